"""RoboChart time for free: how many tocks a suspended machine lets pass with nothing to do.

A RoboChart FMU compiled with ``--time skip`` (the default) has no ``tock`` clock: its tocks are
its own, at ``start + k * unit``, and after each event iteration it announces as ``nextEventTime``
the first tock at which anything can happen. The master steps over the tocks in between; the FMU
counts them (``cycles``, the machines' tick counts and ``wait`` counters) without running a
machine, which the ticking FMU would run to no effect.

Which tocks are idle follows from where a machine rests. It rests at a resume point, the target of
a ``Suspend``; a tock runs the block there. That run does nothing when

- the block's statements are ``if``s without ``else`` (deadline checks) whose conditions are
  false, and its guards are false, so that it suspends at the same block again; and
- nothing else changes: no random draw (``Draw``) and no ``$e?x`` binding (``BindIn``) in those
  tests (a stored value or a drawn number changes the state).

A test reads the state (unchanged while idle), the event buffer (unchanged: an arriving event
opens an Event Mode, where the FMU first counts the idle tocks before it, strictly: a tock at
the event's own time is run with the event, since the event's machine may change what the
others' tests read, a shared variable) and time. Time enters
only through comparisons this module recognises, its *atoms*: a quantity that grows or shrinks
with the tocks (``since``, ``sinceEntry``, the tick count ``now``, ``wait_left``, converted, or
plus/minus a literal) compared with a value that does not depend on time. Such a comparison's
outcome (less, equal, greater) is monotone in the number k of tocks from now, so the first k at
which it changes is found by doubling and bisection. If every test is false one tock from now,
the machine is idle until the first k at which an atom changes (never, without atoms); a test
that reads time any other way, or a block of any other shape, makes the machine run at every
tock, as the ticking FMU does. The look-ahead is conservative: waking at a tock where nothing then
happens costs an event iteration, never a difference in the trace.

The generated C (:mod:`robogen.codegen.lookahead_code`) and the reference interpreter
(:meth:`robogen.ir.interp.Interpreter.idle_tocks`) evaluate the same tests and atoms with the
same search, so they announce the same next event times.
"""

from __future__ import annotations

from dataclasses import dataclass

from robogen.ir import model as ir
from robogen.ir.walk import children
from robogen.semantics import types as T

#: the expressions whose value changes with the tocks
TIMED = (ir.Since, ir.SinceEntry, ir.Now, ir.WaitLeft)
#: tests that change the state when evaluated: a resume point that has them is run at every tock
EFFECTS = (ir.Draw, ir.BindIn)
COMPARISONS = ("eq", "ne", "lt", "le", "gt", "ge")
NUMBERS = (T.INT, T.NAT, T.REAL)
#: the most tocks looked ahead (2^40 time units: beyond any run)
HORIZON = 1 << 40


@dataclass(frozen=True)
class Lookahead:
    """A resume point that can be looked ahead of."""

    block: int
    tests: tuple[ir.Expr, ...]  # every condition a run from it evaluates, in order (ifs, then guards)
    atoms: tuple[ir.Bin, ...]  # the comparisons with time in them


def lookaheads(m: ir.Machine) -> dict[int, Lookahead]:
    """The resume points of ``m`` that can be looked ahead of, by block id."""
    out = {}
    for b in sorted(_resume_points(m)):
        la = _lookahead(m.blocks[b])
        if la is not None:
            out[b] = la
    return out


def _resume_points(m: ir.Machine) -> set[int]:
    points = set()
    for b in m.blocks:
        term = b.term
        while isinstance(term, ir.Branch):
            term = term.default
        if isinstance(term, ir.Suspend):
            points.add(term.target)
    return points


def _lookahead(block: ir.Block) -> Lookahead | None:
    tests: list[ir.Expr] = []
    for s in block.stmts:
        if not (isinstance(s, ir.If) and not s.otherwise):
            return None
        tests.append(s.cond)
    term = block.term
    while isinstance(term, ir.Branch):
        tests.extend(c.guard for c in term.cases)
        term = term.default
    if not (isinstance(term, ir.Suspend) and term.target == block.id):
        return None
    atoms: list[ir.Bin] = []
    for t in tests:
        found = _atoms(t)
        if found is None:
            return None
        atoms.extend(a for a in found if a not in atoms)
    return Lookahead(block.id, tuple(tests), tuple(atoms))


def _atoms(test: ir.Expr) -> list[ir.Bin] | None:
    """The atoms of ``test``; None if it has an effect or reads time outside an atom."""
    atoms: list[ir.Bin] = []
    stack: list[object] = [test]
    while stack:
        e = stack.pop()
        if isinstance(e, EFFECTS) or isinstance(e, TIMED):
            return None
        if is_atom(e):
            atoms.append(e)  # type: ignore[arg-type]
            stack.append(e.left if timed(e.right) else e.right)  # type: ignore[attr-defined]  # the side without time
            continue
        stack.extend(children(e))
    return atoms


def is_atom(e: object) -> bool:
    """A comparison of a monotone function of time with a value that does not depend on time."""
    if not (isinstance(e, ir.Bin) and e.op in COMPARISONS and e.left.type in NUMBERS):
        return False
    return (monotone(e.left) and not timed(e.right)) or (monotone(e.right) and not timed(e.left))


def monotone(e: ir.Expr) -> bool:
    """Does ``e`` only grow, or only shrink, as tocks pass (without wrapping in any run)?"""
    if isinstance(e, TIMED):
        return True
    if isinstance(e, ir.Conv):
        return e.type in NUMBERS and e.operand.type in NUMBERS and monotone(e.operand)
    if isinstance(e, ir.Bin) and e.type in NUMBERS and e.op in ("add", "sub"):
        if e.op == "add" and isinstance(e.left, ir.Lit) and monotone(e.right):
            return True
        # a nat minus a literal wraps below it: not monotone
        return isinstance(e.right, ir.Lit) and monotone(e.left) and (e.op == "add" or e.type != T.NAT)
    return False


def timed(e: ir.Expr) -> bool:
    stack: list[object] = [e]
    while stack:
        x = stack.pop()
        if isinstance(x, TIMED):
            return True
        stack.extend(children(x))
    return False


def first_change(sign, horizon: int = HORIZON) -> int:
    """The least k >= 2 at which ``sign(k)`` (-1, 0, 1; monotone in k) differs from ``sign(1)``,
    or ``horizon`` if none is up to it: doubling, then bisection. robogen_machine.h's
    rg_first_change is the same search."""
    first = sign(1)
    low, high = 1, 2
    while high <= horizon and sign(high) == first:
        low, high = high, high * 2
    if high > horizon:
        return horizon
    while high - low > 1:
        mid = low + (high - low) // 2
        if sign(mid) == first:
            low = mid
        else:
            high = mid
    return high


__all__ = ["Lookahead", "lookaheads", "is_atom", "monotone", "timed", "first_change", "HORIZON", "TIMED"]
