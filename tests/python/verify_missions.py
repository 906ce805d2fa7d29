"""Missions and a writer shared by the `btgen verify` tests (test_verify.py, test_verify_markov.py)."""

from __future__ import annotations

from pathlib import Path

# Ready, then Grasp (retried once), then Place or nothing: the hand-computed P(SUCCESS) of
# test_verify_markov is 0.9 x (1 - (0.3/0.8)^2) x 0.8 = 0.61875.
GRASP = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Check name="Ready"/>
      <RetryUntilSuccessful num_attempts="2"><Grasp/></RetryUntilSuccessful>
      <Fallback><Place/><AlwaysFailure/></Fallback>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel>
    <Condition ID="Check"/>
    <Action ID="Grasp"/>
    <Action ID="Place"/>
  </TreeNodesModel>
</root>
"""


def write_mission(directory: Path, text: str, name: str = "m.xml") -> str:
    """The mission written into `directory` (a test's tmp_path); its path."""
    path = directory / name
    path.write_text(text, encoding="utf-8")
    return str(path)
