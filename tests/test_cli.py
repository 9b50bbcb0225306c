from __future__ import annotations

import subprocess
import sys

import pytest

from polyell.cli import main


def test_main_job_prints_the_paper_numbers(capsys):
    assert main(["analyze"]) == 0
    out = capsys.readouterr().out
    assert "chiacchio  [-43.401, 35.284]" in out
    assert "semi-axes [m/s^2]: 45.163, 28.595" in out
    assert "semi-axes [m/s^2]: 31.323, 18.341" in out
    assert "Polytope (eq. 15): dimension 2, 6 vertices, 6 facets" in out


def test_singular_configuration_reports_the_undefined_classic_ellipsoid(capsys):
    assert main(["analyze", "--q", "pi/6,0,0", "--direction=-0.5,0.8660254037844386"]) == 0
    out = capsys.readouterr().out
    assert "(singular configuration)" in out
    assert "Ellipsoid 'yoshikawa': undefined here." in out
    assert "chiacchio  [-70.922, 52.69]" in out


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["analyze", "--q", "1,2"], "q: expected an array of joint angles [rad] with shape (3,)"),
        (["analyze", "--tau-max", "1,-1,1"], "tau_max: expected strictly positive"),
        (["analyze", "--direction", "1,1"], "unit direction vectors"),
    ],
)
def test_bad_input_is_one_line_and_exit_code_2(capsys, argv, fragment):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("polyell: error: ") and fragment in err
    assert len(err.strip().splitlines()) == 1


def test_unparsable_numbers_are_an_argparse_error(capsys):
    with pytest.raises(SystemExit) as info:
        main(["analyze", "--q", "__import__('os')"])
    assert info.value.code == 2
    assert "expression of numbers, pi" in capsys.readouterr().err


def test_module_entry_point_runs():
    result = subprocess.run(
        [sys.executable, "-m", "polyell", "analyze"], capture_output=True, text=True, check=True
    )
    assert "[-57.305, 53.7]" in result.stdout
