"""Where btgen's non-Python files are: templates, schemas, runtime, CMake package.

In a checkout they are the repository's top-level folders (`templates/`,
`schema/`, `runtime/`, `cmake/`, `bench/`), two levels above this package.
In a wheel, setup.py's build step copies the same folders to `btgen/_data/`
inside the installed package. Every module asks here; nothing else builds a
path to them.
"""

from __future__ import annotations

from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent

# The folders setup.py maps into the wheel (relative to the repository root),
# with the glob of the files each contributes.
DATA_FILES = (
    ("templates", "*.j2"),
    ("schema", "*.xsd"),
    ("runtime/include", "**/*.hpp"),
    ("runtime/src", "**/*.cpp"),
    ("cmake", "*.cmake"),
    ("bench", "bench_main.cpp"),
)
INSTALLED_DATA = "_data"


def data_root() -> Path:
    """The folder holding templates/, schema/, runtime/, cmake/ and bench/."""
    installed = PACKAGE_DIR / INSTALLED_DATA
    if (installed / "templates").is_dir():
        return installed
    return PACKAGE_DIR.parents[1]


ROOT = data_root()
TEMPLATE_DIR = ROOT / "templates"
SCHEMA_DIR = ROOT / "schema"
RUNTIME_INCLUDE = ROOT / "runtime" / "include"
RUNTIME_SRC = ROOT / "runtime" / "src"
CMAKE_DIR = ROOT / "cmake"
BENCH_DIR = ROOT / "bench"


def installed() -> bool:
    """True when running from a built wheel rather than from a checkout."""
    return ROOT == PACKAGE_DIR / INSTALLED_DATA
