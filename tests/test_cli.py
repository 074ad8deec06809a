import subprocess
import sys

from ilocalg.workflow.cli import build_parser, main


def test_help_lists_the_commands():
    out = subprocess.run([sys.executable, "-m", "ilocalg", "--help"], capture_output=True, text=True)
    assert out.returncode == 0
    for cmd in ("reproduce", "evaluate", "notebooks"):
        assert cmd in out.stdout


def test_reproduce_options_parse():
    args = build_parser().parse_args(["reproduce", "--fast", "--only", "00", "--seed", "3"])
    assert (args.fast, args.only, args.seed, args.jobs) == (True, "00", 3, 2)
    assert build_parser().parse_args(["reproduce", "--jobs", "1"]).jobs == 1


def test_reproduce_rejects_zero_jobs_in_one_line(tmp_path, capsys):
    assert main(["reproduce", "--jobs", "0", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err == "error: jobs must be >= 1, got 0\n"


def test_reproduce_with_no_matching_notebook_fails(tmp_path, capsys):
    assert main(["reproduce", "--only", "no-such-notebook", "--out", str(tmp_path)]) == 2
    assert "no notebooks match" in capsys.readouterr().err


def test_notebook_pairs_are_in_step_and_stripped():
    assert main(["notebooks", "--check"]) == 0
