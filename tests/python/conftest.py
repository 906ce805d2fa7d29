import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = os.path.normpath(os.path.join(ROOT, "..", "shared", "conformance", "cases"))

sys.path.insert(0, os.path.join(ROOT, "generator"))


def case_stems(folder: str, companion: str = "") -> list[str]:
    """The stems of the missions (`*.xml`) in `folder`, sorted; with `companion` (".trace",
    ".scenario"), only those that have that file beside them. No folder: no stems."""
    if not os.path.isdir(folder):
        return []
    return sorted(
        f[:-4]
        for f in os.listdir(folder)
        if f.endswith(".xml") and (not companion or os.path.exists(os.path.join(folder, f[:-4] + companion)))
    )


def conformance_stems():
    return case_stems(CASES)


@pytest.fixture
def repo_root():
    return ROOT
