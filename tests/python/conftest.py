import os
import socket
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# The recorded BehaviorTree.CPP 4.6.2 cases the repository holds (tests/conformance/README.md):
# every test of them runs on a plain clone.
CASES = os.path.join(ROOT, "tests", "conformance", "btcpp-4.6.2")
# The project's shared conformance folder beside the checkout, when present, only adds the stems
# the repository does not hold. BTGEN_SHARED_CASES names another folder (a folder that does not
# exist: none, as on a plain clone).
SHARED_CASES = os.environ.get("BTGEN_SHARED_CASES") or os.path.normpath(
    os.path.join(ROOT, "..", "shared", "conformance", "cases")
)

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


def conformance_stems(companion: str = "") -> list[str]:
    """The repository's 4.6.2 cases, plus those of the shared folder it does not hold."""
    return sorted(set(case_stems(CASES, companion)) | set(case_stems(SHARED_CASES, companion)))


def case_file(stem: str, ext: str) -> str:
    """The path of a conformance case's `.xml`, `.scenario` or `.trace`: the repository's copy
    when it holds the stem, else the shared folder's."""
    if os.path.exists(os.path.join(CASES, stem + ".xml")):
        return os.path.join(CASES, stem + ext)
    return os.path.join(SHARED_CASES, stem + ext)


@pytest.fixture
def repo_root():
    return ROOT


def free_port_pair() -> int:
    """A port P with P and P + 1 free on 127.0.0.1 (Groot2 uses both)."""
    for _ in range(50):
        with socket.socket() as a:
            a.bind(("127.0.0.1", 0))
            port = a.getsockname()[1]
            if port >= 65534:
                continue
            with socket.socket() as b:
                try:
                    b.bind(("127.0.0.1", port + 1))
                except OSError:
                    continue
            return port
    raise RuntimeError("no two consecutive free ports on 127.0.0.1")


# ------------------------------------------------------------------ skips in CI
# In CI (CI=1/true, as .ci/run is run) a test may skip only for a reason on this list; any other
# skip fails the test, so a missing tool or package cannot turn tests off unnoticed. Each entry:
# the start of the skip's reason, and why that skip is right even in CI. The list is printed at
# the end of every run.
CI_SKIP_ALLOWED: tuple[tuple[str, str], ...] = (
    ("one mission is enough", "test_groot2.py: a protocol test parametrized by mission runs on one of them"),
    ("the names are monitored.xml's", "test_groot2.py: blackboard names only monitored.xml has"),
    (
        "no BehaviorTree.CPP 4.6.2 to build against",
        "test_migration.py: the library's headers are neither on PyPI nor in Debian (BTGEN_BTCPP_PREFIX)",
    ),
    (
        "no Nav2 sources to build its plugins (NAV2_MIRROR)",
        "test_gtests_nav2.py: Nav2's plugins are built from a local navigation2 mirror, which CI has not "
        "(docs/tests.md records the runs on 4.6.2 and 4.10.0)",
    ),
    ("does not fit the board: ", "test_mcu.py: the cases DOES_NOT_FIT names, each with its reason"),
    (
        "set BTGEN_VERIFY_AGREE=N",
        "test_verify.py: the long agreement run of verify and explore on N random missions, run by hand "
        "(docs/verify.md states the count)",
    ),
    (
        "the C++ back end cannot compile it yet: ",
        "test_diff_regressions.py: a regression case whose mission the C++ back end refuses, with its message",
    ),
    (
        "set BTGEN_MUTATE_FULL=1",
        "test_mutate.py: the mutation runs of the shipped missions and the Nav2 trees (minutes; "
        "docs/tests.md records their scores and times)",
    ),
    (
        "BTGEN_NAV2_TREES=all",
        "test_nav2_trees.py: the ten default trees with a Nav2 Decorator reading ROS 2 on both engines, one C++ "
        "build each, run by hand (docs/nav2.md states the count; CI runs a tree of ours with all five Decorators)",
    ),
    (
        "set BTGEN_REAL_PROJECTS=all",
        "test_check_real.py: MoveIt Pro's example workspace, 296 files checked twice (114 s wall on the busy "
        "shared 2-core machine), run by hand (docs/check.md states its counts; CI checks the three other "
        "MoveIt Pro projects)",
    ),
)


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("1", "true", "yes")


def _skip_reason(report) -> str:
    longrepr = report.longrepr
    reason = longrepr[2] if isinstance(longrepr, tuple) and len(longrepr) == 3 else str(longrepr)
    return reason[len("Skipped: ") :] if reason.startswith("Skipped: ") else reason


def ci_skip_allowed(reason: str) -> bool:
    return any(reason.startswith(prefix) for prefix, _why in CI_SKIP_ALLOWED)


def _refuse_skip(report) -> None:
    reason = _skip_reason(report)
    if ci_skip_allowed(reason):
        return
    report.outcome = "failed"
    report.longrepr = (
        f"skipped in CI ({reason}), and that reason is not on the allow-list "
        "(CI_SKIP_ALLOWED in tests/python/conftest.py): install what the test needs, or add the "
        "reason to the list with why the skip is right"
    )


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if report.skipped and in_ci() and not hasattr(report, "wasxfail"):
        _refuse_skip(report)


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    outcome = yield
    report = outcome.get_result()
    if report.skipped and in_ci():  # a module skipped as a whole (pytest.importorskip, allow_module_level)
        _refuse_skip(report)


def pytest_terminal_summary(terminalreporter):
    terminalreporter.section("skips allowed in CI (tests/python/conftest.py, CI_SKIP_ALLOWED)")
    for prefix, why in CI_SKIP_ALLOWED:
        terminalreporter.write_line(f"- {prefix!r}: {why}")
    skipped = terminalreporter.stats.get("skipped", [])
    if skipped:
        terminalreporter.write_line(f"{len(skipped)} skipped here" + (", all on the list" if in_ci() else ""))


# ---------------------------------------------------------------- markers (pyproject.toml)
# `scripts/test.sh --quick` runs `pytest -m "not slow and not sanitize and not qemu"`: what a
# contributor runs in minutes. The marks are given here, by file, test and parameter, so that
# the one list says what the quick path leaves out (CI, `scripts/test.sh`, runs everything).
_FILE_MARKS = {
    # random missions, whole corpora built as C++, packages and copies of the checkout
    "test_diff_random.py": ("slow", "cpp"),
    "test_analyze_random.py": ("slow",),
    "test_fuzz_frontend.py": ("slow",),
    "test_package.py": ("slow", "cpp"),
    "test_hostile.py": ("slow", "cpp"),
    "test_real_files.py": ("slow", "cpp"),
    "test_conformance_cpp.py": ("slow", "cpp"),
    "test_conformance_cpp_410.py": ("slow", "cpp"),
    "test_diff_sanitize.py": ("sanitize", "cpp"),
    "test_mcu.py": ("qemu", "cpp"),
    "test_bench.py": ("slow", "cpp"),  # -O2 benchmark builds
    "test_groot2.py": ("slow", "cpp"),  # monitored executors built, servers started
    # C++ builds of a few missions each: in the quick path
    "test_compiler.py": ("cpp",),
    "test_migration.py": ("cpp",),
    "test_leaf_hooks.py": ("cpp",),
    "test_bare_metal_text.py": ("cpp",),
}
# (file, test name prefix): marks of single tests
_TEST_MARKS = (
    ("test_plain_clone.py", "test_a_copy_of_the_tracked_files", ("slow",)),
    ("test_plain_clone.py", "test_a_shared_folder_adds_stems", ("slow",)),
    ("test_catch_on_halt.py", "test_random_missions", ("slow", "cpp")),
    ("test_edges_462.py", "test_cpp_", ("slow", "cpp")),
    ("test_edges_462.py", "test_interpreter_matches_462_on_random_edges", ("slow",)),
    # both engines on a corpus of probes, a C++ build each (9 of the quick path's 29 minutes)
    ("test_dynamic.py", "test_probe_", ("slow", "cpp")),
    ("test_dynamic.py", "test_value_of_changing_type_into_static_entry", ("slow", "cpp")),
    ("test_atomic.py", "test_sigkill_at_random_moments", ("slow",)),
    ("test_limits.py", "test_65535_nodes_build_and_run", ("slow", "cpp")),
)


def pytest_collection_modifyitems(config, items):
    for item in items:
        name = os.path.basename(str(item.fspath))
        marks = list(_FILE_MARKS.get(name, ()))
        for file, prefix, more in _TEST_MARKS:
            if name == file and item.name.startswith(prefix):
                marks.extend(more)
        params = getattr(getattr(item, "callspec", None), "params", {})
        if str(params.get("sanitize", "")) == "1":
            marks.append("sanitize")
        if params.get("engine") == "cpp" or "compiler" in params:
            marks.append("cpp")
            # a build per case (the regressions) or per compiler and case: the full run's
            if name == "test_diff_regressions.py" or "compiler" in params:
                marks.append("slow")
        for mark in dict.fromkeys(marks):
            item.add_marker(getattr(pytest.mark, mark))
