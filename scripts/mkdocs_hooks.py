"""MkDocs hooks of the documentation site (mkdocs.yml `hooks:`).

- A page of docs/ that the nav does not list is added under "More pages" (by folder), so a page
  written by someone who did not touch mkdocs.yml is on the site; listing it under its task in
  the nav is still the way to give it a place.
- A link from a page to a file of the repository outside docs/ (`[FORMAT.md](../tests/conformance/FORMAT.md)`)
  is checked: the file must exist (a warning otherwise, so `--strict` fails), and on the site
  the link becomes the path in code, since the site holds only docs/.
"""

from __future__ import annotations

import logging
import os
import re
from typing import Any

log = logging.getLogger("mkdocs.hooks.btgen")

_LINK = re.compile(r"(?<!!)\[(?P<text>[^\]\n]*)\]\((?P<target>\.\./[^)\s#]*)(?P<anchor>#[^)\s]*)?\)")
_FENCE = re.compile(r"^\s*(```|~~~)")


def _listed(nav: Any) -> set[str]:
    found: set[str] = set()
    if isinstance(nav, str):
        found.add(nav)
    elif isinstance(nav, list):
        for item in nav:
            found |= _listed(item)
    elif isinstance(nav, dict):
        for value in nav.values():
            found |= _listed(value)
    return found


def on_config(config: Any) -> Any:
    docs = config["docs_dir"]
    listed = _listed(config["nav"] or [])
    extra: dict[str, list[str]] = {}
    for folder, _dirs, files in sorted(os.walk(docs)):
        for name in sorted(files):
            path = os.path.relpath(os.path.join(folder, name), docs).replace(os.sep, "/")
            if name.endswith(".md") and path not in listed:
                extra.setdefault(os.path.dirname(path) or "", []).append(path)
    if extra and config["nav"] is not None:
        more: list[Any] = list(extra.pop("", []))
        more += [{folder: pages} for folder, pages in sorted(extra.items())]
        config["nav"].append({"More pages": more})
    return config


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    docs = config["docs_dir"]
    repo = os.path.dirname(os.path.abspath(config["config_file_path"]))
    here = os.path.dirname(os.path.join(docs, page.file.src_path))
    out, fenced = [], False
    for line in markdown.split("\n"):
        if _FENCE.match(line):
            fenced = not fenced
        if not fenced:
            line = _LINK.sub(lambda m: _outside(m, here, repo, page.file.src_path), line)
        out.append(line)
    return "\n".join(out)


def _outside(m: re.Match[str], here: str, repo: str, src: str) -> str:
    target = os.path.normpath(os.path.join(here, m.group("target")))
    rel = os.path.relpath(target, repo)
    if rel.startswith("..") or not os.path.exists(target):
        log.warning("Doc file '%s' links to '%s', which is not a file of the repository", src, m.group("target"))
        return m.group(0)
    text = m.group("text")
    shown = f"`{rel}`"
    return shown if text.strip("`") == rel else f"{text} ({shown})"
