"""Recursive enumerations unrolled to a depth bound (robogen.ir.supported.Shapes):
tests/codegen/models/recursive.rct at --enum-depth 2 through the FMU and the reference
interpreter, with hand-calculated results."""

from __future__ import annotations

import pytest

from support.codegen_driver import Instant, Scenario, Tick, build, run_checked
from support.codegen_models import MODELS
from robogen.codegen.api import compile_model
from robogen.diagnostics import RobogenError
from robogen.ir.lower import LoweringOptions

MODEL = MODELS / "recursive.rct"
NIL, CONS = 0, 1


def test_lists_up_to_the_depth_bound_and_a_located_error_beyond(tmp_path):
    """- push 1: l = Cons(1, Nil) = one; 1 list seen
    - push 2: l = Cons(2, Cons(1, Nil)); 2 seen
    - reset, push 1: Cons(1, Nil) again: still 2 seen, equal to one
    - push 5: Cons(5, Cons(1, Nil)): 3 seen
    - push 7: Cons(7, Cons(5, Cons(1, Nil))) nests three Cons, deeper than 2: fmi3Error."""
    ticks = [("push", 1), ("push", 2), ("reset", None), ("push", 1), ("push", 5), ("push", 7)]
    scenario = Scenario([Instant(True, early=(Tick(c, {} if v is None else {f"{c}.value": v}),)) for c, v in ticks],
                        half=False)
    built = build([MODEL], tmp_path / "rec", options=LoweringOptions(enum_depth=2))
    got = run_checked(built, scenario)
    steps = [s.outputs for s in got.steps if "out" in s.outputs]
    assert [(o["same"]["same.value"], o["seen"]["seen.value"]) for o in steps] == [(True, 1), (False, 2), (True, 2), (False, 3)]
    fields = ("out.tag", "out.Cons_1", "out.Cons_2.tag", "out.Cons_2.Cons_1", "out.Cons_2.Cons_2.tag")
    assert [tuple(o["out"][f] for f in fields) for o in steps] == [
        (CONS, 1, NIL, 0, NIL), (CONS, 2, CONS, 1, NIL), (CONS, 1, NIL, 0, NIL), (CONS, 5, CONS, 1, NIL)]
    # the last level holds only literals without a List argument: Nil
    assert "out.Cons_2.Cons_2.Cons_1" not in steps[0]["out"]
    assert got.error is not None and got.error.instant == 5
    assert "a value of recursive::List nested deeper than the depth bound 2 (--enum-depth) at recursive.rct:31" in got.error.where
    config = built.sources["sources/config.h"]
    assert all(f"}} rg_rec_recursive_List{suffix};" in config for suffix in ("", "_1", "_0"))


def test_a_record_that_holds_itself_without_an_enumeration_is_a_located_error(tmp_path):
    path = tmp_path / "tree.rct"
    path.write_text("import sequence_toolkit::*\ndatatype Tree { value: nat kids: Seq(Tree) }\n"
                    "stm M {\n\tvar t: Tree\n\tinitial i\n\tstate S { }\n\ttransition t0 { from i to S }\n}\n")
    with pytest.raises(RobogenError) as exc:
        compile_model([path], tmp_path / "out")
    d = exc.value.diagnostics[0]
    assert "Tree holds itself with no enumeration literal between" in d.message and d.span.line == 4
