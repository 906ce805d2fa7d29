"""Every command's help: each option says what it does, one spelling of each metavar, only the
options that change what the command does; a misspelt command or option gets a did-you-mean."""

import argparse
import os
import subprocess
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "generator"))

from btgen.cli import build_parser, main
from btgen.compiler import build_info_parser


def commands() -> dict[str, argparse.ArgumentParser]:
    top = build_parser()
    sub = next(a for a in top._actions if isinstance(a, argparse._SubParsersAction))
    found = {name: p for name, p in sub.choices.items() if name != "build-info"}
    found["build-info"] = build_info_parser()
    return found


COMMANDS = commands()


def test_every_command_is_walked():
    assert set(COMMANDS) >= {"validate", "compile", "run", "explore", "cover", "upgrade-check", "bench", "init"}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_option_and_argument_has_a_help_text(name):
    missing = [
        "/".join(a.option_strings) or a.dest
        for a in COMMANDS[name]._actions
        if not isinstance(a, argparse._HelpAction) and not (a.help or "").strip()
    ]
    assert missing == [], f"btgen {name}: no help for {missing}"


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_value_has_a_metavar(name):
    # argparse's default metavar is the dest in capitals (`--ticks TICKS`, `mission`): each
    # value is named for what it holds instead.
    for a in COMMANDS[name]._actions:
        if a.nargs == 0 or isinstance(a, argparse._HelpAction):
            continue
        assert a.metavar, f"btgen {name} {'/'.join(a.option_strings) or a.dest}: no metavar"


def test_one_metavar_per_option_and_for_a_mission():
    seen: dict[str, set] = {}
    for p in COMMANDS.values():
        for a in p._actions:
            if a.nargs == 0 or isinstance(a, argparse._HelpAction):
                continue
            key = a.option_strings[-1] if a.option_strings else ("mission" if "mission" in a.dest else a.dest)
            seen.setdefault(key, set()).add(a.metavar)
    assert seen["mission"] == {"MISSION.xml"}
    assert seen["--ticks"] == {"N"}
    assert seen["--scenario"] == {"FILE.scenario"}
    # what -o writes differs by command (FILE.svg|FILE.dot, FILE.xml, FILE.scenario)
    assert all(m.startswith("FILE.") for m in seen.pop("--output"))
    for key, metavars in seen.items():
        assert len(metavars) == 1, f"{key} is spelt {sorted(metavars)}"


def _options(name):
    return {o for a in COMMANDS[name]._actions for o in a.option_strings}


def test_namespace_and_capacities_only_where_they_mean_something():
    assert {n for n in COMMANDS if "--namespace" in _options(n)} == {"compile", "build-info"}
    sized = {n for n in COMMANDS if "--string-capacity" in _options(n)}
    assert sized == {"validate", "analyze", "explore", "verify", "cover", "run", "compile", "bench", "build-info"}
    assert sized == {n for n in COMMANDS if "--queue-capacity" in _options(n)}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_help_prints_and_exits_0(name, capsys):
    with pytest.raises(SystemExit) as e:
        main([name, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: btgen {name}")
    assert "`btgen compile`:" not in out  # build-info described as itself


def run(*args, cwd=ROOT):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "generator"))
    return subprocess.run(
        [sys.executable, "-m", "btgen", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False
    )


def test_misspelt_command_gets_did_you_mean():
    p = run("valdate", "missions/LabTour.xml")
    assert p.returncode == 1
    assert p.stderr.splitlines()[0] == (
        "<command-line>:1:1: error: argument COMMAND: invalid choice: 'valdate' (did you mean `validate`?)"
    )


def test_misspelt_option_gets_did_you_mean():
    p = run("validate", "missions/LabTour.xml", "--modles", "m.xml")
    assert p.returncode == 1
    assert p.stderr.splitlines()[0] == (
        "<command-line>:1:31: error: unrecognized arguments: --modles m.xml (did you mean `--models`?)"
    )
    p = run("run", "missions/LabTour.xml", "--scenario", "s", "--engine", "cp")
    assert "invalid choice: 'cp' (did you mean `cpp`?)" in p.stderr


def test_an_option_of_another_command_says_which_takes_it():
    p = run("validate", "missions/LabTour.xml", "--namespace", "robot")
    assert p.returncode == 1
    assert (
        "(`btgen validate` does not take --namespace, which only `btgen compile`, `btgen build-info` take)"
        in p.stderr.splitlines()[0]
    )


def test_init_names_the_project_and_refuses_in_command_line_style(tmp_path):
    p = run("init", "my-robot", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout == "btgen init: wrote the project `my_robot` into my-robot (next: read my-robot/README.md)\n"
    assert (tmp_path / "my-robot" / "README.md").read_text().startswith("# my-robot\n")
    p = run("init", "my-robot", cwd=tmp_path)
    assert p.returncode == 1
    assert p.stderr.splitlines()[0] == (
        "<command-line>:1:6: error: my-robot is not empty: `btgen init` writes a new project"
    )
