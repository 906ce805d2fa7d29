"""The mission language every stage shares: the node catalogue, the checked model, values,
statuses, the scripting language and the blackboard rules of BehaviorTree.CPP 4.6.2."""
