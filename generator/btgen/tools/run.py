"""`btgen run`: run a mission with scripted leaves and print its status trace.

The trace format and the run loop are those of ``tests/conformance/FORMAT.md``.
Mission and scenario problems are reported before any trace line; a problem
found while running (a script error, a value a port cannot take) is reported
after the lines already printed, as ``path:line:col: error: ...``, with exit
status 1.
"""

from __future__ import annotations

import contextlib
import os
import sys

from btgen import cmdline, pipeline
from btgen.diagnostics import print_diagnostics
from btgen.pipeline import options_from_args

EXIT_OK, EXIT_INPUT = 0, 1


def run_command(args) -> int:
    """Entry point of `btgen run MISSION.xml --scenario FILE [--engine interp|cpp]`."""
    engine = getattr(args, "engine", "interp") or "interp"
    substitute = getattr(args, "substitute", None)
    if engine == "cpp":
        from btgen.tools.cppengine import run_cpp

        return run_cpp(args.mission, args.scenario, options_from_args(args))
    if engine != "interp":
        raise cmdline.error(args, engine, f"unknown engine `{engine}` (use interp or cpp)")

    from btgen.interp.engine import run_trace
    from btgen.interp.scenario import load_scenario

    # UserError (mission or scenario) propagates to the command line, which
    # prints it and exits 1: nothing has been printed on stdout yet.
    # The front end only: the interpreter runs what BehaviorTree.CPP would load, including
    # what the C++ back end refuses at compile time (docs/data-side.md: what the C++ back end rejects).
    mission = pipeline.load(args.mission, options_from_args(args))
    print_diagnostics(mission.warnings)
    scenario, warnings = load_scenario(args.scenario, mission)
    print_diagnostics(warnings)

    rules = None
    if substitute is not None:
        from btgen.frontend.substitution import load_rules

        rules = load_rules(substitute, mission.semantics.script_grammar_49)

    out = sys.stdout

    def write(text: str) -> None:
        out.write(text)

    try:
        if rules is not None:
            from btgen.interp import substitute as subst

            subst.run_trace(mission, scenario, rules, write)
        else:
            run_trace(mission, scenario, write)
        out.flush()
    except BrokenPipeError:
        # The reader went away (`btgen run ... | head`): stop quietly.
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, out.fileno())
        except (OSError, ValueError):
            pass
        return EXIT_INPUT
    finally:
        with contextlib.suppress(BrokenPipeError, ValueError):
            out.flush()
    return EXIT_OK
