import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# Every property test is seeded: hypothesis draws the same examples on every run.
settings.register_profile(
    "polyell",
    derandomize=True,
    deadline=None,
    max_examples=40,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("polyell")


# No test writes into the checkout: every file a test makes goes to a temporary folder.
# The tree is listed (paths, sizes, modification times) before and after the session; the
# caches of the tools themselves and the virtual environment are not part of the checkout.
_ROOT = Path(__file__).resolve().parents[1]
_NOT_THE_CHECKOUT = {
    ".git",
    ".venv",
    ".hypothesis",
    ".pytest_cache",
    ".ruff_cache",
    ".mypy_cache",
    "__pycache__",
    "_build",
    "polyell.egg-info",
}


def _tree() -> dict[str, tuple[int, int]]:
    listing = {}
    for folder, subfolders, files in os.walk(_ROOT):
        subfolders[:] = [d for d in subfolders if d not in _NOT_THE_CHECKOUT]
        for name in files:
            path = Path(folder, name)
            try:
                status = path.stat()
            except OSError:  # removed while listed
                continue
            listing[str(path.relative_to(_ROOT))] = (status.st_size, status.st_mtime_ns)
    return listing


_BEFORE: dict[str, tuple[int, int]] = {}


def pytest_sessionstart(session: pytest.Session) -> None:
    _BEFORE.update(_tree())


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    after = _tree()
    touched = sorted(p for p in after.keys() | _BEFORE.keys() if after.get(p) != _BEFORE.get(p))
    if touched:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
        print(f"\nconftest: the tests wrote into the checkout: {', '.join(touched[:20])}")
