"""Mistakes on the command line, reported like mistakes in a file.

A bad option, a bad option value, a missing or unknown argument is bad input like any other:
it is printed as ``<command-line>:1:COL: error: message`` (the way compilers name their command
line), where COL is the column where the offending argument starts in the arguments joined by
spaces, and the command exits with status 1.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
from typing import NoReturn, Optional, Union

from btgen.diagnostics import Loc, UserError, did_you_mean

COMMAND_LINE = "<command-line>"
EXIT_INPUT = 1

# argparse's messages that quote the offending value, and the ones that name an option
_QUOTED_VALUE = re.compile(r"(?:invalid choice|invalid \S+ value|ambiguous option): '([^']*)'")
_UNRECOGNIZED = re.compile(r"unrecognized arguments: (\S+)")
_ARGUMENT = re.compile(r"^argument ([^:]+):")


def loc_of(argv: Sequence[str], token: Union[str, Sequence[str], None]) -> Loc:
    """Where `token` (or the first of several names of one option) starts on the command line:
    the first argument equal to it, or an option `token=...`, or one ending in `=token`; past the
    last argument when there is none (a missing argument is missing there)."""
    tokens = (token,) if isinstance(token, str) else tuple(token or ())
    for t in tokens:
        col = 1
        for arg in argv:
            if t and (arg == t or arg.startswith(t + "=") or (arg.startswith("-") and arg.endswith("=" + t))):
                return Loc(COMMAND_LINE, 1, col)
            col += len(arg) + 1
    return Loc(COMMAND_LINE, 1, sum(len(a) + 1 for a in argv) + 1 if argv else 1)


def token_of(message: str) -> tuple[str, ...]:
    """The argument an argparse message is about (an option's names), when it names one."""
    for pattern in (_QUOTED_VALUE, _UNRECOGNIZED):
        m = pattern.search(message)
        if m:
            return (m.group(1),)
    m = _ARGUMENT.match(message)
    if m:
        return tuple(m.group(1).split("/"))
    return ()


def error(args: argparse.Namespace, token: Optional[str], message: str) -> UserError:
    """A command's own check of its options failed (`--tick needs --trace`): the error to
    raise, located at `token`."""
    argv = getattr(args, "argv", None)
    return UserError.at(loc_of(sys.argv[1:] if argv is None else argv, token), message)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose mistakes are located errors with exit status 1, then a note
    naming the help to read."""

    command = ""  # btgen's command being parsed, when the arguments name one (cli.main)
    argv: Sequence[str] = ()  # the arguments being parsed

    def parse_args(self, args=None, namespace=None):
        Parser.argv = list(sys.argv[1:] if args is None else args)
        ns = super().parse_args(args, namespace)
        ns.argv = Parser.argv
        return ns

    def _commands(self) -> dict[str, argparse.ArgumentParser]:
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                return dict(action.choices)
        return {}

    def _options_of_command(self) -> list[str]:
        """The option names the command being parsed takes (this parser's, or, for the top
        parser reporting what a command left over, the command's)."""
        parser = self._commands().get(Parser.command, self)
        return [o for o in parser._option_string_actions if o.startswith("--")]

    def _explained(self, message: str) -> str:
        """The message with a did-you-mean for a misspelt command, choice or option (in place
        of argparse's list of every choice, which `--help` shows), or naming the commands that
        take an option this one does not."""
        m = re.search(r"invalid choice: '([^']*)' (\(choose from (.*)\))$", message)
        if m:
            guess = did_you_mean(m.group(1), re.findall(r"'([^']*)'", m.group(3)))
            return message[: m.start(2)] + f"(did you mean `{guess}`?)" if guess else message
        m = _UNRECOGNIZED.search(message)
        if m and m.group(1).startswith("--"):
            word = m.group(1).split("=", 1)[0]
            guess = did_you_mean(word, self._options_of_command())
            if guess:
                return f"{message} (did you mean `{guess}`?)"
            takers = [name for name, p in self._commands().items() if word in p._option_string_actions]
            if takers and Parser.command:
                if word == "--namespace":
                    takers.append("build-info")
                shown = ", ".join(f"`btgen {t}`" for t in takers)
                return f"{message} (`btgen {Parser.command}` does not take {word}, which only {shown} take)"
        return message

    def error(self, message: str) -> NoReturn:
        message = self._explained(message)
        loc = loc_of(Parser.argv, token_of(message))
        print(f"{loc}: error: {message}", file=sys.stderr)
        if self.prog.startswith("btgen"):
            # A command's own parser, or the top one reporting what the command left over
            # (`unrecognized arguments`): the help to read is the command's.
            command = self.prog.split()[-1] if " " in self.prog else Parser.command
            hint = f"btgen {command} --help" if command else "btgen --help"
        else:
            hint = f"{self.prog} --help"
        print(f"{loc}: note: try '{hint}'", file=sys.stderr)  # a diagnostic too: every line is one
        raise SystemExit(EXIT_INPUT)
