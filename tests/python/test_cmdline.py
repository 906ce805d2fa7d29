"""Mistakes on the command line are bad input like any other: `<command-line>:1:COL: error: ...`
on stderr, COL where the offending argument starts, exit status 1 (argparse exits 2), never a
traceback, and nothing written."""

import os
import subprocess
import sys

import pytest

from btgen import cmdline
from btgen.cli import main
from conftest import ROOT

PICK = os.path.join(ROOT, "missions", "PickPlaceBall.xml")


def _col(argv, i):
    """Column of argv[i] in the arguments joined by spaces."""
    return 1 + sum(len(a) + 1 for a in argv[:i])


@pytest.mark.parametrize(
    "argv, at, message",
    [
        (["compile", "--btcpp", "9.9", PICK], 2, "argument --btcpp: invalid choice: '9.9'"),
        (["validate", "--btcpp=4.9.0", PICK], 1, "argument --btcpp: invalid choice: '4.9.0'"),
        (["validate", PICK, "--frobnicate"], 2, "unrecognized arguments: --frobnicate"),
        (["frobnicate"], 0, "argument COMMAND: invalid choice: 'frobnicate'"),
        (["bench", PICK, "--ticks", "ten"], 3, "argument --ticks: invalid int value: 'ten'"),
        (["compile", PICK, "-o"], 2, "argument -o/--output-dir: expected one argument"),
        (["validate"], 1, "the following arguments are required: MISSION.xml"),  # past the end
        (["bench", PICK, "--ticks", "0"], 2, "--ticks must be at least 1, not 0"),
        (["explore", "--assert", "sometimes X", PICK], 1, "--assert: unknown property"),
        (["explore", "--clock-ms", "-5", PICK], 1, "--clock-ms cannot be negative"),
        (["graph", PICK, "-o", "x.png"], 3, "-o x.png: the output is a .svg or a .dot file"),
        (["graph", PICK, "-o", "x.dot", "--tick", "2"], 4, "--tick needs --trace"),
        (["graph", PICK, "-o", "x.dot", "--record", "2"], 4, "--record needs --btlog"),
    ],
)
def test_bad_option_is_a_located_error(argv, at, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        rc = main(argv)
    except SystemExit as e:
        rc = e.code
    err = capsys.readouterr().err
    first = err.splitlines()[0]
    assert rc == 1, err
    assert first.startswith(f"<command-line>:1:{_col(argv, at)}: error: {message}"), first
    assert "Traceback" not in err
    assert all(line.startswith(f"<command-line>:1:{_col(argv, at)}: ") for line in err.splitlines()), err
    assert os.listdir(tmp_path) == []


def test_location_helpers():
    argv = ["compile", "m.xml", "--namespace", "a b"]
    assert str(cmdline.loc_of(argv, "--namespace")) == "<command-line>:1:15"
    assert str(cmdline.loc_of(argv, "a b")) == "<command-line>:1:27"
    assert str(cmdline.loc_of(argv, None)) == "<command-line>:1:31"
    assert str(cmdline.loc_of([], "x")) == "<command-line>:1:1"
    assert str(cmdline.loc_of(["run", "--engine=cpp"], "cpp")) == "<command-line>:1:5"
    assert cmdline.token_of("argument -o/--output: expected one argument") == ("-o", "--output")
    assert str(cmdline.loc_of(["x", "--output", "y"], ("-o", "--output"))) == "<command-line>:1:3"
    assert cmdline.token_of("unrecognized arguments: --x y") == ("--x",)
    assert cmdline.token_of("the following arguments are required: M") == ()


@pytest.mark.parametrize(
    "module, argv",
    [("btgen.tools.synth", ["ten"]), ("btgen.compiler", ["--deps"]), ("btgen.tools.mcu", ["--nope"])],
)
def test_module_entry_points_exit_1(module, argv):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "generator"))
    p = subprocess.run([sys.executable, "-m", module, *argv], capture_output=True, text=True, env=env, check=False)
    assert p.returncode == 1, p.stderr
    assert p.stderr.startswith("<command-line>:1:"), p.stderr
    assert "Traceback" not in p.stderr
