"""The pre-commit hook (.pre-commit-hooks.yaml) in a fresh repository, through `pre-commit try-repo`
(PyPI's pre-commit, pinned in requirements-test.txt): a broken mission fails the hook with its
`path:line:col` line, a good one passes.

`language: python`: pre-commit builds the hook's environment by `pip install` of this checkout
(try-repo copies it, uncommitted changes included), so it needs PyPI for btgen's dependencies and
setuptools, and no other network. It takes 25 s on an idle 2-core machine and 90 s on a busy one
(the environment is built anew for each run), so it runs when BTGEN_TEST_PRECOMMIT=1 (CI sets it:
scripts/test.sh).
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GOOD = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Say text="hi"/>
  </BehaviorTree>
</root>
"""
NODES = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Action ID="Say"><input_port name="text"/></Action>
  </TreeNodesModel>
</root>
"""

pytestmark = pytest.mark.skipif(
    os.environ.get("BTGEN_TEST_PRECOMMIT") != "1", reason="builds a pre-commit environment: BTGEN_TEST_PRECOMMIT=1"
)


def _git(cwd: Path, *args: str) -> None:
    subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True)


def test_hook_in_a_fresh_repository(tmp_path):
    pre_commit = shutil.which("pre-commit") or os.path.join(os.path.dirname(sys.executable), "pre-commit")
    assert os.path.exists(pre_commit), "pre-commit is in requirements-test.txt"
    repo = tmp_path / "robot"
    (repo / "trees").mkdir(parents=True)
    (repo / "trees" / "nodes.xml").write_text(NODES)
    (repo / "trees" / "good.xml").write_text(GOOD)
    (repo / "trees" / "bad.xml").write_text(GOOD.replace("<Say ", "<Sya "))
    (repo / "README.md").write_text("robot\n")
    _git(repo, "init", "-q", ".")
    _git(repo, "add", ".")
    env = dict(os.environ, PRE_COMMIT_HOME=str(tmp_path / "cache"), GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t")
    env.pop("PYTHONPATH", None)  # the hook runs the btgen installed in its own environment

    def try_repo(*files: str) -> subprocess.CompletedProcess:
        which = ["--files", *files] if files else ["--all-files"]
        return subprocess.run(
            [pre_commit, "try-repo", str(ROOT), "btgen-check", *which],
            cwd=repo,
            env=env,
            capture_output=True,
            text=True,
            check=False,
            timeout=600,
        )

    r = try_repo()
    assert r.returncode == 1, r.stdout + r.stderr
    assert "trees/bad.xml:3:5: error: unknown node `Sya`" in r.stdout
    assert "good.xml" not in r.stdout.split("btgen check...")[-1]
    r = try_repo("trees/good.xml", "README.md")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "btgen check" in r.stdout and "Passed" in r.stdout
