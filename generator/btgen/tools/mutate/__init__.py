"""`btgen mutate MISSION --tests DIR`: how good a scenario suite is, by mutation.

Each mutant is one small edit of the mission file (operators.py), loaded with the checks of
`btgen validate` (a mutant that does not load is discarded, with the reason). The suite's
scenarios (`DIR/scenarios/*.scenario`, as `btgen tests` writes them, or the `*.scenario`
files of DIR itself, as `btgen explore -o` writes them) run on the original and on each
mutant on btgen's interpreter; what is compared is what `btgen diff` observes (each leaf call
with its inputs and result, each write of the main tree's blackboard, run-time errors, the
root's results), tick by tick. A mutant is killed when some scenario's observed run differs.

A survivor goes to `btgen diff`'s product search (tools/diff/product.py, `Differ`) between the
original and the mutant: *equivalent* only when that search is exhaustive; a difference
comes back as a shortest scenario that kills the mutant (replayed here before it is shown:
it must kill it); a search stopped by the tick bound or the state budget is *undecided*,
never equivalent. Equivalent mutants are left out of the score:
`killed K of N non-equivalent mutants (E equivalent, U undecided)`, N counting the undecided.
"""

from btgen.tools.mutate.command import mutate_command

__all__ = ["mutate_command"]
