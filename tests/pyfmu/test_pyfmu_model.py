"""Declaring a Python FMU: value references, FMI defaults, rejected declarations, settings."""

from __future__ import annotations

import pytest

from pyfmu_fixture_models import Counter
from robogen.pyfmu import Boolean, Clock, Float64, Int32, Int64, Model, Setting, String
from robogen.pyfmu.model import DeclarationError


def test_value_references_follow_declaration_order_after_time():
    names = [v.name for v in Counter.variables()]
    assert names[:5] == ["tick", "bump", "bump.amount", "ticked", "ticked.count"]
    assert [v.vr for v in Counter.variables()] == list(range(1, len(names) + 1))


def test_fmi_defaults_per_causality():
    assert (Counter.variable("speed").variability, Counter.variable("speed").initial) == ("tunable", "exact")
    assert (Counter.variable("alarm_time").variability, Counter.variable("alarm_time").initial) == ("fixed", "exact")
    position = Counter.variable("position")
    assert (position.variability, position.initial, position.start) == ("continuous", "calculated", None)
    total = Counter.variable("total")
    assert (total.variability, total.initial) == ("discrete", "calculated")  # Int64 cannot be continuous
    amount = Counter.variable("bump.amount")
    assert (amount.variability, amount.initial, amount.start, amount.clock) == ("discrete", None, 1, "bump")
    assert Counter.variable("flag").start is False and Counter.variable("small").start == 7


@pytest.mark.parametrize("declare, message", [
    (lambda: Int64(causality="output", variability="continuous"), "only Float64"),
    (lambda: Float64(causality="output", variability="continuous", clock="c"), "discrete or tunable"),
    (lambda: Clock(kind="constant", causality="output", interval=1.0), "must be triggered"),
    (lambda: Clock(kind="constant", causality="input"), "needs an interval"),
    (lambda: Clock(kind="triggered", causality="input", interval=1.0), "has no interval"),
    (lambda: Clock(kind="countdown", causality="input"), "kind must be"),
    (lambda: Float64(1.0, causality="input", initial="exact"), "no 'initial'"),
    (lambda: Float64(causality="parameter", variability="discrete"), "fixed or tunable"),
])
def test_declarations_the_standard_forbids_are_rejected(declare, message):
    with pytest.raises(DeclarationError, match=message):
        class Bad(Model):  # noqa: F841
            x = declare()


def test_references_must_name_declared_clocks_and_settings():
    with pytest.raises(DeclarationError, match="not a declared clock"):
        class A(Model):  # noqa: F841
            x = Int64(causality="output", clock="nowhere")
    with pytest.raises(DeclarationError, match="not a Setting"):
        class B(Model):  # noqa: F841
            c = Clock(kind="constant", interval="undefined_setting")
    with pytest.raises(DeclarationError, match="declared twice"):
        class C(Model):  # noqa: F841
            a = Float64(name="x")
            b = Float64(name="x")


def test_values_are_checked_against_the_fmi_type():
    assert Int32(causality="input").coerce(5.0) == 5
    with pytest.raises(OverflowError):
        Int32(name="i", causality="input").coerce(2**31)
    with pytest.raises(TypeError):
        Boolean(name="b", causality="input").coerce(1)
    with pytest.raises(TypeError):
        Float64(name="f", causality="input").coerce("1.0")
    with pytest.raises(TypeError):
        String(name="s", causality="input").coerce(3)


def test_settings_parse_by_the_type_of_their_default_and_configure_a_subclass():
    assert Setting(0.5).parse("0.25") == 0.25
    assert Setting(True).parse("off") is False
    assert Setting(3).parse("4") == 4
    with pytest.raises(ValueError):
        Setting(0.5).parse("inf")
    fast = Counter.configured({"period": 0.25})
    assert fast.period == 0.25 and Counter.period == 0.5
    assert fast.clock_seconds(fast.variable("tick").interval) == 0.25
    assert issubclass(fast, Counter) and [v.vr for v in fast.variables()] == [v.vr for v in Counter.variables()]


def test_a_setting_declared_by_its_type_has_no_default_until_configured():
    required = Setting(float, "a period")
    assert required.required and required.default is None and required.parse("0.25") == 0.25
    assert not Setting(0.5).required

    class Timed(Counter):
        offset = Setting(float, "an offset [s]")

    assert Timed.offset is None and Timed.configured({"offset": 1.5}).offset == 1.5


def test_model_code_reads_and_writes_values_through_attributes():
    m = Counter()
    m.setup()
    m.total = 41
    m.total += 1
    assert m.get("total") == 42 and m.count == 0
    assert m.ticked is False
    m.raise_clock("ticked")
    assert m.ticked is True and m.clock_active("ticked")
    with pytest.raises(ValueError, match="not an output clock"):
        m.raise_clock("tick")
    with pytest.raises(AttributeError):
        m.ticked = True
