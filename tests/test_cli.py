from __future__ import annotations

import json
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
        (["analyze", "--direction", "1,1"], "add --normalize to scale it"),
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


def test_json_output_is_valid_and_complete(capsys):
    assert main(["analyze", "--json", "--no-mvie"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["rank"] == 2
    assert round(data["ellipsoids"]["chiacchio"]["limits"][1], 3) == 35.284
    assert data["scores"]["mvie"]["defined"] is False
    assert data["scores"]["chiacchio"]["inscribed_scale"] > 1


def test_json_at_a_singularity_writes_null_not_nan(capsys):
    assert main(["analyze", "--json", "--q", "pi/6,0,0"]) == 0
    text = capsys.readouterr().out
    assert "NaN" not in text
    data = json.loads(text)
    assert data["ellipsoids"]["yoshikawa"]["defined"] is False
    assert data["scores"]["yoshikawa"]["coverage"] is None


def test_robot_file_and_limits_override(tmp_path, capsys):
    robot = tmp_path / "arm.toml"
    robot.write_text("planar = { lengths = [1, 1], masses = [1, 1] }\ntau_max = [5, 5]\n")
    assert main(["analyze", "--robot", str(robot), "--q", "0.3,0.4", "--no-mvie"]) == 0
    assert "rank M = 2 of m = 2" in capsys.readouterr().out
    assert main(["analyze", "--robot", "chiacchio2000", "--tau-max", "1,1,1", "--no-mvie"]) == 0


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["analyze", "--robot", "kuka"], "name: expected one of ['chiacchio2000', 'kinova'"),
        (["analyze", "--robot", "missing.toml"], "expected an existing TOML file"),
        (["study", "missing.toml", "--out", "x"], "expected an existing TOML file"),
    ],
)
def test_bad_robot_or_study(capsys, argv, fragment):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err and len(err.strip().splitlines()) == 1


def test_study_command(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'
        '[compare]\nmvie = false\n[output]\nformats = ["png"]\ndpi = 40\n'
    )
    assert main(["study", str(spec), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    assert "wrote" in capsys.readouterr().out
    assert (tmp_path / "out" / "sets_p.png").exists()


def test_help_everywhere(capsys):
    for argv in (["--help"], ["analyze", "--help"], ["study", "--help"]):
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == 0
    assert "--out" in capsys.readouterr().out


def only_line(capsys) -> str:
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.endswith("\n"), err
    return err


def test_an_internal_error_is_one_line_that_asks_for_a_report(capsys, monkeypatch):
    import polyell.cli as cli

    def broken(args):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(cli, "_analyze", broken)
    assert main(["analyze"]) == 2
    err = only_line(capsys)
    assert err.startswith("polyell: error: internal error, ZeroDivisionError: float division")
    assert "please report it" in err


@pytest.mark.parametrize(("command", "resume"), [("analyze", False), ("study", True)])
def test_ctrl_c_is_one_line_and_exit_130(capsys, monkeypatch, tmp_path, command, resume):
    import polyell.cli as cli

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, f"_{command}", interrupted)
    argv = ["analyze"] if command == "analyze" else ["study", "s.toml", "--out", str(tmp_path)]
    assert main(argv) == 130
    err = only_line(capsys)
    assert (
        err == "polyell: interrupted" + ("; run the same command again to resume" * resume) + "\n"
    )


def test_an_error_after_a_note_is_still_one_line(capsys):
    # --normalize notes the scaled direction; --mesh into a missing folder then fails
    argv = [
        "analyze",
        "--direction",
        "2,0",
        "--normalize",
        "--no-mvie",
        "--mesh",
        "/nonexistent/x.obj",
    ]
    assert main(argv) == 2
    assert only_line(capsys).startswith("polyell: error: ")


def test_line_breaks_in_a_message_stay_on_one_line(capsys, tmp_path):
    folder = tmp_path / "two\nlines.toml"
    folder.mkdir()
    assert main(["study", str(folder), "--out", str(tmp_path / "o")]) == 2
    assert "two\\nlines.toml" in only_line(capsys)
    with pytest.raises(SystemExit) as info:
        main(["analyze", "extra\nargument"])
    assert info.value.code == 2
    assert "extra\\nargument" in only_line(capsys)


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["study", "{tmp}", "--out", "{tmp}/o"], "a folder"),
        (["study", "{tmp}/latin1.toml", "--out", "{tmp}/o"], "is not UTF-8"),
        (["study", "{tmp}/deep.toml", "--out", "{tmp}/o"], "nested deeper than the parser"),
        (["analyze", "--robot", "{tmp}/deep.toml"], "nested deeper than the parser"),
        (["analyze", "--robot", "{tmp}"], "describing a robot, got"),
        (["study", "{tmp}/grid.toml", "--out", "{tmp}/o", "--scheduler", "tcp://a:b"], "tcp://"),
        (["study", "{tmp}/grid.toml", "--out", "{tmp}/o", "--scheduler", "tcp://[::1"], "[::1"),
    ],
)
def test_files_and_addresses_that_cannot_be_used(capsys, tmp_path, argv, fragment):
    (tmp_path / "latin1.toml").write_bytes('title = "\u00e9"\n'.encode("latin-1"))
    (tmp_path / "deep.toml").write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    (tmp_path / "grid.toml").write_text('[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 1\n')
    assert main([a.format(tmp=tmp_path) for a in argv]) == 2
    err = only_line(capsys)
    assert err.startswith("polyell: error: ") and fragment in err


def test_joint_velocity_options_take_a_leading_minus_and_are_bounded(capsys):
    # qd_min is at most 0: "--qd-min -1,-2,-3" must not read as an option (found by the
    # third independent check); speeds beyond any drive name --qd
    assert main(["analyze", "--capacity", "velocity", "--qd-min", "-1,-2,-3"]) == 0
    assert "qd_min: -1, -2, -3" in capsys.readouterr().out
    q = ["--robot", "panda", "--q", "0,0,0,-1.5,0,1.5,0"]
    assert main(["analyze", *q, "--qd", "1e20,0,0,0,0,0,0"]) == 2
    assert "--qd: expected joint velocities of at most 1e+06 rad/s" in capsys.readouterr().err


def test_direction_by_name_takes_a_leading_minus(capsys):
    # issue 32: "--direction -y" reads as --direction=-y, the same numbers as 0,-1
    assert main(["analyze", "--json", "--no-mvie", "--no-outer", "--direction", "-y"]) == 0
    by_name = json.loads(capsys.readouterr().out)
    assert main(["analyze", "--json", "--no-mvie", "--no-outer", "--direction=0,-1"]) == 0
    assert by_name == json.loads(capsys.readouterr().out)
    assert by_name["direction"] == [0.0, -1.0]
    assert main(["analyze", "--direction", "z"]) == 2
    err = only_line(capsys)
    assert err.startswith("polyell: error: --direction: ") and "task rows (x, y)" in err
