"""Size and time of a fresh install of polyell, with and without extras.

For each requested install: a new virtual environment under a temporary folder,
``pip install --no-cache-dir SOURCE[extras]`` timed (download, build and install, the
network included), then the packages it holds (``pip list``, pip itself not counted) and
the size of its site-packages (``du``).  With ``--run-default-job`` the README's Quick start
command (``polyell study studies/chiacchio2000.toml --out DIR``) runs in the fresh
environment, to show that the install is enough for it.  One install each: the time
depends on the network and the package index's caches, so take it as an order of
magnitude; the counts and sizes are exact for the versions resolved that day.

Usage::

    python tests/benchmarks/install_size.py [--source DIR] [--extras "" studies robots ...]
        [--run-default-job]

``--source`` defaults to this checkout; it is copied (without ``.venv``, ``.git`` and build
outputs) so that building the wheel writes nothing into the working tree.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_SKIP = {".venv", ".git", "__pycache__", "build", "results", "_build", ".pytest_cache"}


def _copy_source(source: Path, into: Path) -> Path:
    """A copy of the package source without virtual environments or build outputs."""

    def ignore(folder: str, names: list[str]) -> list[str]:
        return [n for n in names if n in _SKIP or n.endswith(".egg-info")]

    target = into / "src"
    shutil.copytree(source, target, ignore=ignore)
    return target


def _du_mib(path: Path) -> float:
    out = subprocess.run(["du", "-sk", str(path)], capture_output=True, text=True, check=True)
    return int(out.stdout.split()[0]) / 1024


def measure(source: Path, extras: str, work: Path, run_default_job: bool) -> dict[str, object]:
    """Install ``source[extras]`` into a new environment under ``work``; what it took."""
    env = work / ("venv-" + (extras.replace(",", "-") or "default"))
    subprocess.run([sys.executable, "-m", "venv", str(env)], check=True)
    python = env / "bin" / "python"
    spec = f"{source}[{extras}]" if extras else str(source)
    started = time.perf_counter()
    subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--no-cache-dir", spec], check=True
    )
    seconds = time.perf_counter() - started
    listed = subprocess.run(
        [str(python), "-m", "pip", "list", "--format=json"],
        capture_output=True,
        text=True,
        check=True,
    )
    packages = [p["name"] for p in json.loads(listed.stdout) if p["name"] != "pip"]
    site = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    result: dict[str, object] = {
        "extras": extras or "(none)",
        "packages": len(packages),
        "site_packages_mib": round(_du_mib(Path(site))),
        "install_seconds": round(seconds, 1),
        "names": sorted(packages),
    }
    if run_default_job:
        out = work / f"job-{extras or 'default'}"
        job = subprocess.run(
            [
                str(env / "bin" / "polyell"),
                "study",
                "studies/chiacchio2000.toml",
                "--out",
                str(out),
            ],
            cwd=source,
            capture_output=True,
            text=True,
        )
        result["default_job_exit"] = job.returncode
        if job.returncode:
            result["default_job_stderr"] = job.stderr[-2000:]
    return result


def main(argv: list[str] | None = None) -> int:
    """Measure each requested install and print one JSON record per install."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source", type=Path, default=ROOT)
    parser.add_argument("--extras", nargs="*", default=[""], help='"" for the default install')
    parser.add_argument("--run-default-job", action="store_true")
    parser.add_argument("--keep", action="store_true", help="keep the environments")
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="polyell-install-"))
    try:
        source = _copy_source(args.source.resolve(), work)
        for extras in args.extras:
            record = measure(source, extras, work, args.run_default_job)
            print(json.dumps(record), flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
