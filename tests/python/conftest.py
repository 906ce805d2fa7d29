import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = os.path.normpath(os.path.join(ROOT, "..", "shared", "conformance", "cases"))

sys.path.insert(0, os.path.join(ROOT, "generator"))


def conformance_stems():
    if not os.path.isdir(CASES):
        return []
    return sorted(f[:-4] for f in os.listdir(CASES) if f.endswith(".xml"))


@pytest.fixture
def repo_root():
    return ROOT
