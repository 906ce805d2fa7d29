"""The reference interpreter (BehaviorTree.CPP 4.6.2 semantics) and the scenario files that
script the leaves of a mission."""
