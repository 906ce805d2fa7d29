"""Stage 2, the IR: lowering a checked mission to the frozen program (the node table, the
resolved blackboard slots and the compiled scripts) that the back ends emit."""
