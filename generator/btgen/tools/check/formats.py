"""`btgen check --format text|json|sarif|junit|github`: the findings for people and for CI servers.

- text: `path:line:col: severity: message [CODE]`, then one summary line; nothing when clean.
- json: `{"files": [...], "findings": [{path, line, column, code, name, severity, message}]}`.
- sarif: SARIF 2.1.0 for code scanning (GitHub, GitLab, Azure): one run whose `artifacts` list every
  file checked, whose driver lists every rule of the table, and whose results carry `ruleId`,
  `level` and a `physicalLocation` with line and column (paths relative to `%SRCROOT%`, the current
  folder).
- junit: JUnit XML (the schema of Jenkins' xunit plugin, which GitLab reads too): one test case per
  file checked, a `<failure>` per error, the warnings in `<system-out>`.
- github: GitHub Actions workflow commands (`::error file=...,line=...,col=...,title=CODE::message`),
  which the runner shows as annotations on the pull request.
"""

from __future__ import annotations

import json
import os
from urllib.parse import quote
from xml.sax.saxutils import escape, quoteattr

from btgen.diagnostics import one_line
from btgen.tools.check.codes import RULES
from btgen.tools.check.runner import Finding, Report
from btgen.version import __version__

FORMATS = ("text", "json", "sarif", "junit", "github")
SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def text(report: Report) -> str:
    if not report.findings:
        return ""
    lines = [str(f) for f in report.findings]
    warnings = len(report.findings) - report.errors
    files = len({f.path for f in report.findings})
    lines.append(
        f"btgen check: {_plural(report.errors, 'error')}, {_plural(warnings, 'warning')} in "
        f"{_plural(files, 'file')} ({_plural(len(report.files), 'file')} checked)"
    )
    return "\n".join(lines) + "\n"


def as_json(report: Report) -> str:
    doc = {
        "version": __version__,
        "files": [{"path": p, "kind": report.kinds[p]} for p in report.files],
        "findings": [
            {
                "path": f.path,
                "line": f.line,
                "column": f.col,
                "code": f.code,
                "name": f.rule.name,
                "severity": f.severity,
                "message": f.message,
            }
            for f in report.findings
        ],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _uri(path: str) -> str:
    rel = os.path.relpath(path) if os.path.isabs(path) else os.path.normpath(path)
    return quote(rel.replace(os.sep, "/"), safe="/-_.~")


def sarif(report: Report) -> str:
    rules = [r for r in RULES if r.code != "C001"]
    index = {r.code: i for i, r in enumerate(rules)}
    artifacts = sorted(set(report.files) | {f.path for f in report.findings})
    art_index = {p: i for i, p in enumerate(artifacts)}
    doc = {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "btgen",
                        "version": __version__,
                        "semanticVersion": __version__,
                        "rules": [
                            {
                                "id": r.code,
                                "name": r.name,
                                "shortDescription": {"text": r.summary},
                                "fullDescription": {"text": (r.summary + ". " + r.why).strip()},
                                "defaultConfiguration": {"level": r.severity, "enabled": r.default},
                                "help": {
                                    "text": " ".join(
                                        x
                                        for x in (r.summary + ".", r.why, f"Examples: btgen's docs/rules/{r.code}.md.")
                                        if x
                                    )
                                },
                            }
                            for r in rules
                        ],
                    }
                },
                "originalUriBaseIds": {"%SRCROOT%": {"uri": _srcroot()}},
                "artifacts": [{"location": {"uri": _uri(p), "uriBaseId": "%SRCROOT%"}} for p in artifacts],
                "columnKind": "unicodeCodePoints",
                "results": [
                    {
                        "ruleId": f.code,
                        "ruleIndex": index[f.code],
                        "level": f.severity,
                        "message": {"text": one_line(f.message)},
                        "locations": [
                            {
                                "physicalLocation": {
                                    "artifactLocation": {
                                        "uri": _uri(f.path),
                                        "uriBaseId": "%SRCROOT%",
                                        "index": art_index[f.path],
                                    },
                                    "region": {"startLine": f.line, "startColumn": f.col},
                                }
                            }
                        ],
                    }
                    for f in report.findings
                ],
            }
        ],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _srcroot() -> str:
    cwd = os.getcwd().replace(os.sep, "/")
    return "file://" + quote(cwd if cwd.startswith("/") else "/" + cwd, safe="/-_.~:") + "/"


def junit(report: Report) -> str:
    by_file: dict[str, list[Finding]] = {p: [] for p in report.files}
    for f in report.findings:
        by_file.setdefault(f.path, []).append(f)
    failures = sum(1 for fs in by_file.values() if any(f.severity == "error" for f in fs))
    out = ['<?xml version="1.0" encoding="UTF-8"?>']
    out.append(f'<testsuites name="btgen check" tests="{len(by_file)}" failures="{failures}" errors="0">')
    out.append(f'  <testsuite name="btgen check" tests="{len(by_file)}" failures="{failures}" errors="0" skipped="0">')
    for path in sorted(by_file):
        fs = by_file[path]
        out.append(f"    <testcase name={quoteattr(path)} classname={quoteattr(_classname(path))}>")
        for f in fs:
            if f.severity == "error":
                out.append(
                    f"      <failure type={quoteattr(f.code)} message={quoteattr(one_line(f.message))}>"
                    f"{escape(str(f))}</failure>"
                )
        warnings = [str(f) for f in fs if f.severity != "error"]
        if warnings:
            out.append(f"      <system-out>{escape(chr(10).join(warnings))}</system-out>")
        out.append("    </testcase>")
    out.append("  </testsuite>")
    out.append("</testsuites>")
    return "\n".join(out) + "\n"


def _classname(path: str) -> str:
    folder = os.path.dirname(os.path.normpath(path)).replace(os.sep, ".").strip(".")
    return "btgen.check" + ("." + folder if folder else "")


def _escape_data(s: str) -> str:
    return s.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(s: str) -> str:
    return _escape_data(s).replace(":", "%3A").replace(",", "%2C")


def github(report: Report) -> str:
    out = []
    for f in report.findings:
        level = "error" if f.severity == "error" else "warning"
        props = f"file={_escape_property(f.path)},line={f.line},col={f.col},title={_escape_property(f.code)}"
        out.append(f"::{level} {props}::{_escape_data(one_line(f.message))}")
    return "".join(line + "\n" for line in out)


RENDER = {"text": text, "json": as_json, "sarif": sarif, "junit": junit, "github": github}
