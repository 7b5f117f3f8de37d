"""The C types of a model follow every use of a type (tests/codegen/models/typeuses.rct and
typeusessim.rst): each record type there first appears in one place only - a platform
operation's parameter given a record literal whose fields are records, an output event, a tuple,
an enumeration literal's argument, a sequence, a software operation's parameter, a constant, a
literal inside an expression. The FMUs compile, and what they send is the hand-calculated value
(the interpreter's trace is the same: run_checked)."""

from __future__ import annotations

import pytest

from support.codegen_driver import Tick, build, outputs_by_instant

CAPACITY = 32  # the default --capacity: the length of a sequence's arrays at the boundary


def go(v: float) -> Tick:
    return Tick("go", {"go.value": v})


def twist(lx: float, ly: float, az: float) -> dict:
    return {"cmd_vel.t.linear.x": lx, "cmd_vel.t.linear.y": ly, "cmd_vel.t.linear.z": 0.0,
            "cmd_vel.t.angular.x": 0.0, "cmd_vel.t.angular.y": 0.0, "cmd_vel.t.angular.z": az}


def frame(w: float) -> dict:
    return {"pose.s.a.u": 1.0, "pose.s.a.w": w, "pose.s.b.u": 3.0, "pose.s.b.w": 4.0, "pose.n": 7}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_robochart_values_of_types_first_met_in_each_place(builds, semantics):
    outputs, _ = outputs_by_instant(builds.get("typeuses", semantics), {1: go(1.5), 3: go(-2.0)}, 5)
    assert outputs[0] == outputs[2] == outputs[4] == {}
    for t, v in ((1, 1.5), (3, -2.0)):
        assert outputs[t] == {
            "cmd_vel": twist(v, 2 * v, -v),  # Twist(|linear = Vector3(|x = v, y = 2 * v, ...|), ...|)
            "pose": frame(v),  # Frame(|s = Spin(|a = Axis(|u = 1.0, w = v|), ...|), n = 7|)
            "pair": {"pair._1": 3, "pair._2.px": v, "pair._2.py": -v},  # (|3, Point(|px = v, py = -v|)|)
            "drive": {"drive.tag": 1, "drive.Drive_1.along.px": v, "drive.Drive_1.along.py": 0.0},  # Drive is literal 1
            "path": {"path.value.elements.dx": [1, -3] + [0] * (CAPACITY - 2),
                     "path.value.elements.dy": [2, 4] + [0] * (CAPACITY - 2), "path.value.size": 2},
            "force": {"force.value": v - 2},  # relay(Wrench(|f = Force(|fx = v|), k = -2|)): w.f.fx + w.k
            "home": {"home.value": 0.5 + v},  # origin.p.ox + v
            "spot": {"spot.value": 2 * v},  # Spot(|at = Loc(|lx = v|)|).at.lx * 2
        }


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_robosim_operation_call_and_event_output_of_nested_records(builds, semantics):
    outputs, _ = outputs_by_instant(builds.get("typeusessim", semantics), {1: go(1.5), 2: go(-2.0)}, 4)
    # the cycle that samples go decides t1 (an exec transition); its action runs at the start of
    # the next cycle: the outputs of go at t come at t + 1
    assert outputs[0] == outputs[1] == {}
    for t, v in ((2, 1.5), (3, -2.0)):
        assert outputs[t] == {"cmd_vel": twist(v, 2 * v, -v), "pose": frame(v), "force": {"force.value": v - 2}}


GUST = """package gust
datatype Axis { u: real w: real }
datatype Gust { a: Axis k: nat }
function speed(g: Gust): real { }
interface Io { event go: real event out: real }
stm M {
\tuses Io
\tvar v: real = 0.0
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger go?v action out!speed(Gust(|a = Axis(|u = v, w = 2.0|), k = 3|)) }
}
"""
GUST_C = """static double rg_user_speed(rg_rec_gust_Gust g)
{
    return g.a.u * g.a.w + (double)g.k;
}
"""


def test_a_record_met_only_in_a_user_function_signature_and_a_literal(tmp_path):
    model, c_file = tmp_path / "gust.rct", tmp_path / "gust.c"
    model.write_text(GUST)
    c_file.write_text(GUST_C)
    built = build([model], tmp_path / "w", machine="M", functions=c_file)
    python = {"speed": lambda g: g["a"]["u"] * g["a"]["w"] + g["k"]}
    outputs, _ = outputs_by_instant(built, {1: go(1.5)}, 2, functions=python)
    assert outputs == {0: {}, 1: {"out": {"out.value": 6.0}}}  # 1.5 * 2.0 + 3
