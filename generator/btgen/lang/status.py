"""Node status, as BehaviorTree.CPP 4.6.2's ``BT::NodeStatus``.

The integer values are 4.6.2's enumerators (``basic_types.h``): a status
stored in a blackboard entry is an integer there, so a script reading one
sees these numbers.
"""

from __future__ import annotations

import enum


class NodeStatus(enum.Enum):
    """The status of a node; ``str()`` gives the bare name (``SUCCESS``)."""

    IDLE = 0
    RUNNING = 1
    SUCCESS = 2
    FAILURE = 3
    SKIPPED = 4

    def __str__(self) -> str:
        return self.name

    @property
    def is_active(self) -> bool:
        """RUNNING, SUCCESS or FAILURE (4.6.2 ``isStatusActive``: not IDLE, not SKIPPED)."""
        return self not in (NodeStatus.IDLE, NodeStatus.SKIPPED)

    @property
    def is_completed(self) -> bool:
        """SUCCESS or FAILURE (4.6.2 ``isStatusCompleted``)."""
        return self in (NodeStatus.SUCCESS, NodeStatus.FAILURE)
