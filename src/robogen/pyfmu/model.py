"""Declaring a Python-implemented FMI 3.0 Co-Simulation FMU.

A model is a subclass of :class:`Model` whose class body declares its variables::

    class Counter(Model):
        model_identifier = "counter"
        tick = Clock(kind="constant", causality="input", interval="period")
        period = Setting(0.5, "interval of the constant clock 'tick' [s]")
        count = Int64(0, causality="output", variability="discrete", clock="tick")

        def react(self, clocks):
            if "tick" in clocks:
                self.count += 1

Value references follow declaration order (``time`` is 0). The FMI names default to the
attribute names; ``name=`` gives dotted names such as ``movediscrete.target_X``. Reading a
declared attribute gives the current value (a Clock gives whether it is active); assigning one
writes the value directly, without the FMI access rules that :mod:`robogen.pyfmu.slave`
enforces on the importer's calls.

The hooks a model overrides (all optional) are listed on :class:`Model`. The hooks run inside
the FMU, called by :class:`robogen.pyfmu.slave.Slave`; an exception in a hook becomes
``fmi3Error`` with the traceback in a log message.

Settings (:class:`Setting`) are packaging-time constants: they may change the model
description (a constant clock's interval), so ``robogen package-py --set NAME=VALUE`` fixes them
when the FMU is written and the FMU applies the same values at run time.
"""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Iterable, Mapping

CAUSALITIES = ("parameter", "calculatedParameter", "input", "output", "local")
VARIABILITIES = ("constant", "fixed", "tunable", "discrete", "continuous")
INITIALS = ("exact", "approx", "calculated")
CLOCK_KINDS = ("constant", "triggered")  # the kinds robogen's Python FMUs implement


class DeclarationError(Exception):
    """A variable declaration that FMI 3.0 does not allow (raised when the class is defined)."""


class FmiUsageError(Exception):
    """The importer used the FMU in a way it does not allow: a call in the wrong state, a bad
    argument, an invalid parameter value. Raised by the runtime or by model hooks, it becomes
    fmi3Error with this message (no traceback) in the log."""


class Var:
    """A declared scalar variable. Subclasses fix the FMI type."""

    type_name: ClassVar[str] = ""
    python_type: ClassVar[type] = object
    default_start: ClassVar[Any] = None

    def __init__(
        self,
        start: Any = None,
        *,
        name: str | None = None,
        causality: str = "local",
        variability: str | None = None,
        initial: str | None = None,
        clock: str | None = None,
        description: str = "",
        unit: str | None = None,
        depends_on: Iterable[str] | None = None,
    ) -> None:
        self.attr = ""
        self.name = name or ""
        self.vr = -1
        self.start = start
        self.causality = causality
        self.variability = variability
        self.initial = initial
        self.clock = clock
        self.description = description
        self.unit = unit
        self.depends_on = None if depends_on is None else tuple(depends_on)

    # -- declaration --------------------------------------------------------------------------

    def __set_name__(self, owner: type, attr: str) -> None:
        self.attr = attr
        self.name = self.name or attr

    def complete_declaration(self) -> None:
        """Fill in FMI defaults and reject combinations the standard forbids (called by
        ``Model.__init_subclass__`` for the variables a class declares)."""
        where = f"variable '{self.name}'"
        if self.causality not in CAUSALITIES:
            raise DeclarationError(f"{where}: causality must be one of {', '.join(CAUSALITIES)}")
        if self.variability is None:
            if self.causality in ("parameter", "calculatedParameter"):
                self.variability = "fixed"
            elif self.clock is not None or self.type_name != "Float64":
                self.variability = "discrete"
            else:
                self.variability = "continuous"
        if self.variability not in VARIABILITIES:
            raise DeclarationError(f"{where}: variability must be one of {', '.join(VARIABILITIES)}")
        if self.variability == "continuous" and self.type_name != "Float64":
            raise DeclarationError(f"{where}: only Float64 variables can be continuous")
        if self.clock is not None and self.variability not in ("discrete", "tunable"):
            raise DeclarationError(f"{where}: a clocked variable must be discrete or tunable")
        if self.causality in ("parameter", "calculatedParameter") and self.variability not in ("fixed", "tunable"):
            raise DeclarationError(f"{where}: a parameter must be fixed or tunable")
        if self.initial is None:
            if self.causality == "parameter" or self.variability == "constant":
                self.initial = "exact"
            elif self.causality in ("calculatedParameter", "output", "local"):
                self.initial = "calculated"
        if self.initial is not None and self.initial not in INITIALS:
            raise DeclarationError(f"{where}: initial must be one of {', '.join(INITIALS)}")
        if self.causality == "input" and self.initial is not None:
            raise DeclarationError(f"{where}: an input has no 'initial' attribute")
        if self.needs_start and self.start is None:
            self.start = self.default_start
        if self.start is not None:
            self.start = self.coerce(self.start)

    @property
    def needs_start(self) -> bool:
        """Inputs and exact/approx variables carry a start value in the XML."""
        return self.causality == "input" or self.initial in ("exact", "approx")

    def coerce(self, value: Any) -> Any:
        if not isinstance(value, self.python_type) or isinstance(value, bool) != (self.python_type is bool):
            raise TypeError(f"{self.name}: expected {self.type_name}, got {type(value).__name__} {value!r}")
        return value

    # -- access from model code -----------------------------------------------------------------

    def __get__(self, obj: "Model | None", owner: type) -> Any:
        if obj is None:
            return self
        return obj.variable_values[self.name]

    def __set__(self, obj: "Model", value: Any) -> None:
        obj.variable_values[self.name] = self.coerce(value)

    def initial_value(self) -> Any:
        return self.start if self.start is not None else self.default_start


class Float64(Var):
    type_name = "Float64"
    python_type = float
    default_start = 0.0

    def coerce(self, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{self.name}: expected Float64, got {type(value).__name__} {value!r}")
        return float(value)


class _Integer(Var):
    python_type = int
    default_start = 0
    bits: ClassVar[int] = 64

    def coerce(self, value: Any) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            else:
                raise TypeError(f"{self.name}: expected {self.type_name}, got {type(value).__name__} {value!r}")
        low, high = -(1 << (self.bits - 1)), (1 << (self.bits - 1)) - 1
        if not low <= value <= high:
            raise OverflowError(f"{self.name}: {value} is out of the {self.type_name} range")
        return int(value)


class Int32(_Integer):
    type_name = "Int32"
    bits = 32


class Int64(_Integer):
    type_name = "Int64"
    bits = 64


class Boolean(Var):
    type_name = "Boolean"
    python_type = bool
    default_start = False

    def coerce(self, value: Any) -> bool:
        if not isinstance(value, bool):
            raise TypeError(f"{self.name}: expected Boolean, got {type(value).__name__} {value!r}")
        return value


class String(Var):
    type_name = "String"
    python_type = str
    default_start = ""


class Clock(Var):
    """A clock. ``kind`` is its ``intervalVariability``: ``constant`` (periodic input clock,
    ``interval`` in seconds or the name of a :class:`Setting`, ``shift`` likewise) or
    ``triggered`` (input or output). Output clocks must be triggered. ``depends_on`` names the
    input clocks and inputs that can activate an output clock (its ModelStructure dependencies).
    """

    type_name = "Clock"
    python_type = bool
    default_start = False

    def __init__(
        self,
        *,
        kind: str = "triggered",
        causality: str = "input",
        interval: float | str | None = None,
        shift: float | str = 0.0,
        name: str | None = None,
        description: str = "",
        depends_on: Iterable[str] | None = None,
    ) -> None:
        super().__init__(None, name=name, causality=causality, variability="discrete", description=description,
                         depends_on=depends_on)
        self.kind = kind
        self.interval = interval
        self.shift = shift

    def complete_declaration(self) -> None:
        where = f"clock '{self.name}'"
        if self.kind not in CLOCK_KINDS:
            raise DeclarationError(f"{where}: kind must be one of {', '.join(CLOCK_KINDS)}")
        if self.causality not in ("input", "output", "local"):
            raise DeclarationError(f"{where}: a clock's causality is input, output or local")
        if self.causality != "input" and self.kind != "triggered":
            raise DeclarationError(f"{where}: output and local clocks must be triggered")
        if self.kind == "constant" and self.interval is None:
            raise DeclarationError(f"{where}: a constant clock needs an interval")
        if self.kind == "triggered" and self.interval is not None:
            raise DeclarationError(f"{where}: a triggered clock has no interval")
        self.initial = "calculated" if self.causality == "output" else None

    @property
    def needs_start(self) -> bool:
        return False

    @property
    def periodic(self) -> bool:
        return self.kind == "constant"

    def __get__(self, obj: "Model | None", owner: type) -> Any:
        if obj is None:
            return self
        return self.name in obj.active_clocks

    def __set__(self, obj: "Model", value: Any) -> None:
        raise AttributeError(f"clock '{self.name}' is activated with raise_clock(), not assigned")


class Setting:
    """A packaging-time constant of the model class (see the module docstring).

    ``Setting(0.5, "...")`` has a default, whose type the values must have; ``Setting(str,
    "...")``, a type instead of a value, has none, and packaging needs ``--set NAME=VALUE``.
    Reading it on the class or an instance gives its value (None while a required one has none);
    ``Model.configured`` makes a subclass with other values.

    A number may be limited: ``gt``/``ge`` (greater than / at least) and ``lt``/``le`` (less
    than / at most); any setting to ``choices``. ``robogen package-py --set`` refuses a value
    outside them, and the default must lie inside. A setting that names a constant clock's
    interval must be positive, one that names its shift at least 0, without saying so.
    """

    def __init__(self, default: Any, description: str = "", *, gt: float | None = None, ge: float | None = None,
                 lt: float | None = None, le: float | None = None, choices: Iterable[Any] | None = None) -> None:
        self.required = isinstance(default, type)
        self.kind: type = default if self.required else type(default)
        self.default = None if self.required else default
        self.description = description
        self.attr = ""
        self.limits: list[tuple[str, float, str]] = [(op, bound, "") for op, bound in
                                                     (("gt", gt), ("ge", ge), ("lt", lt), ("le", le)) if bound is not None]
        self.choices = tuple(choices) if choices is not None else None

    def __set_name__(self, owner: type, attr: str) -> None:
        self.attr = attr

    def __get__(self, obj: Any, owner: type) -> Any:
        return self.default

    def require(self, op: str, bound: float, reason: str) -> None:
        """A limit the model's structure implies (e.g. a clock interval's ``gt 0``)."""
        if (op, bound, reason) not in self.limits:
            self.limits.append((op, bound, reason))

    def check(self, value: Any) -> None:
        """Raise ValueError if ``value`` breaks a limit or is not one of the choices."""
        for op, bound, reason in self.limits:
            test, sign = _LIMITS[op]
            if not test(value, bound):
                raise ValueError(f"{value!r} is not {sign} {bound!r}" + (f" ({reason})" if reason else ""))
        if self.choices is not None and value not in self.choices:
            raise ValueError(f"{value!r} is not one of {', '.join(repr(c) for c in self.choices)}")

    def parse(self, text: str) -> Any:
        """The value of ``--set NAME=TEXT``, of the setting's type and within its limits."""
        value = self._parse(text)
        self.check(value)
        return value

    def _parse(self, text: str) -> Any:
        kind = self.kind
        if kind is bool:
            if text.lower() in ("1", "true", "yes", "on"):
                return True
            if text.lower() in ("0", "false", "no", "off"):
                return False
            raise ValueError(f"expected true or false, got {text!r}")
        if kind is float:
            value = float(text)
            if not math.isfinite(value):
                raise ValueError(f"expected a finite number, got {text!r}")
            return value
        if kind is int:
            return int(text)
        return text


_LIMITS = {"gt": (operator.gt, ">"), "ge": (operator.ge, ">="), "lt": (operator.lt, "<"), "le": (operator.le, "<=")}


@dataclass(frozen=True)
class Step:
    """What ``Model.do_step`` returns when it does not simply reach ``t + h``.

    ``time`` is where the model stopped (``t + h`` or earlier: an early return, allowed only when
    ``Model.early_return_allowed``); ``event`` asks the importer for Event Mode at that time.
    """

    time: float
    event: bool = False
    terminate: bool = False


@dataclass(frozen=True)
class Update:
    """What ``Model.update_discrete_states`` returns when it has something to say."""

    need_update: bool = False
    terminate: bool = False
    next_event_time: float | None = None


class Model:
    """Base class of a Python-implemented FMU. Subclasses declare variables and override hooks:

    - ``setup()``: after instantiation; ``self.resource_path`` (the FMU's ``resources/`` folder,
      or None) and the settings are known.
    - ``enter_initialization_mode()``, ``exit_initialization_mode()``: parameters are final at
      the latter.
    - ``react(clocks)``: compute the reactions of the current event instant to the input clocks
      activated in it (``clocks``, a frozenset of names; empty for an instant caused by time or
      by ``Step(event=True)``): raise output clocks, write clocked outputs. Called once the
      instant's inputs are set, before any output of the instant is read, and again if more
      input clocks arrive after outputs were read (with only the new ones).
    - ``update_discrete_states() -> Update | None``: close the instant. The runtime then
      deactivates every clock.
    - ``do_step(t, h) -> Step | None``: advance from ``t`` to ``t + h`` (None means reached).
    - ``update_outputs()``: compute outputs on demand: the runtime calls it before the
      importer reads an output or local while ``self.outputs_stale`` is true (set it where the
      outputs change, clear it here). Cheaper than overriding ``get``: a Get call is then served
      from the values in one lookup.
    - ``get(name)`` / ``set(name, value)``: value access by FMI name; override to compute
      outputs on demand per variable or to react to a parameter.
    - ``terminate()``, ``free()``: release resources (``free`` also runs before a reset).

    The framework keeps two attributes on every instance, read by the slave (and by a subclass
    that computes its outputs in bulk): ``variable_values``, the values of the variables by name
    (the storage the declared attributes read and write), and ``active_clocks``, the names of the
    clocks active in the current event instant. A variable may not take either name.
    """

    model_identifier: ClassVar[str] = ""
    model_name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    might_return_early: ClassVar[bool] = False
    default_experiment: ClassVar[Mapping[str, float]] = {}

    _variables: ClassVar[tuple[Var, ...]] = ()
    _by_name: ClassVar[dict[str, Var]] = {}
    _settings: ClassVar[dict[str, Setting]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        variables: dict[str, Var] = {}
        settings: dict[str, Setting] = {}
        for value in vars(cls).values():
            if isinstance(value, Var):
                try:
                    value.complete_declaration()
                except DeclarationError as exc:
                    raise DeclarationError(f"{cls.__name__}: {exc}") from None
        for klass in reversed(cls.__mro__):
            for attr, value in vars(klass).items():
                if isinstance(value, Var):
                    variables.pop(attr, None)
                    variables[attr] = value
                elif isinstance(value, Setting):
                    settings[attr] = value
        by_name: dict[str, Var] = {}
        for vr, var in enumerate(variables.values(), start=1):
            if var.name in by_name or var.name == "time":
                raise DeclarationError(f"{cls.__name__}: the FMI name '{var.name}' is declared twice")
            var.vr = vr
            by_name[var.name] = var
        cls._variables = tuple(variables.values())
        cls._by_name = by_name
        cls._settings = settings
        cls._check_references()
        cls._check_settings()

    @classmethod
    def _check_references(cls) -> None:
        for var in cls._variables:
            if var.clock is not None:
                target = cls._by_name.get(var.clock)
                if not isinstance(target, Clock):
                    raise DeclarationError(f"{cls.__name__}.{var.name}: clocks='{var.clock}' is not a declared clock")
            for dep in var.depends_on or ():
                if dep not in cls._by_name:
                    raise DeclarationError(f"{cls.__name__}.{var.name}: depends on undeclared '{dep}'")
            if isinstance(var, Clock):
                for value, op, what in ((var.interval, "gt", "interval"), (var.shift, "ge", "shift")):
                    if isinstance(value, str):
                        if value not in cls._settings:
                            raise DeclarationError(f"{cls.__name__}.{var.name}: '{value}' is not a Setting")
                        cls._settings[value].require(op, 0, f"the {what} of clock '{var.name}'")

    @classmethod
    def _check_settings(cls) -> None:
        """Limits are numbers on number settings; the defaults the class declares lie within them."""
        for attr, setting in vars(cls).items():
            if not isinstance(setting, Setting) or isinstance(setting, _SettingValue):
                continue
            if setting.limits and setting.kind not in (int, float):
                raise DeclarationError(f"{cls.__name__}.{attr}: only a number setting can have limits")
            if not setting.required:
                try:
                    setting.check(setting.default)
                except ValueError as exc:
                    raise DeclarationError(f"{cls.__name__}.{attr}: the default {exc}") from None

    # -- class-level queries --------------------------------------------------------------------

    @classmethod
    def variables(cls) -> tuple[Var, ...]:
        return cls._variables

    @classmethod
    def variable(cls, name: str) -> Var:
        return cls._by_name[name]

    @classmethod
    def settings(cls) -> dict[str, Setting]:
        return dict(cls._settings)

    @classmethod
    def configured(cls, values: Mapping[str, Any]) -> type["Model"]:
        """A subclass with the given setting values (already parsed), or ``cls`` itself."""
        if not values:
            return cls
        unknown = [k for k in values if k not in cls._settings]
        if unknown:
            raise KeyError(unknown[0])
        namespace: dict[str, Any] = {k: _SettingValue(cls._settings[k], v) for k, v in values.items()}
        namespace["__module__"] = cls.__module__
        return type(cls.__name__, (cls,), namespace)

    @classmethod
    def clock_seconds(cls, value: float | str) -> float:
        """A clock's interval or shift in seconds (resolving a Setting name)."""
        return float(getattr(cls, value)) if isinstance(value, str) else float(value)

    @classmethod
    def package_resources(cls) -> dict[str, bytes]:
        """Extra files for the FMU's ``resources/`` folder, by name; called by package-py.

        Raise :class:`robogen.diagnostics.RobogenError` for bad input (e.g. a data file).
        """
        return {}

    # -- instance -------------------------------------------------------------------------------

    def __init__(self, *, instance_name: str = "", resource_path: Path | None = None,
                 logger: Any = None) -> None:
        self.instance_name = instance_name
        self.resource_path = resource_path
        self.time = 0.0
        self.start_time = 0.0
        self.stop_time: float | None = None
        self.early_return_allowed = False
        self._logger = logger
        self.variable_values: dict[str, Any] = {v.name: v.initial_value() for v in self._variables if not isinstance(v, Clock)}
        self.active_clocks: set[str] = set()

    #: Whether :meth:`update_outputs` must run before the importer reads outputs (see the class).
    outputs_stale: bool = False

    def get(self, name: str) -> Any:
        return self.variable_values[name]

    def set(self, name: str, value: Any) -> None:
        self.variable_values[name] = self._by_name[name].coerce(value)

    def raise_clock(self, name: str) -> None:
        """Activate an output (or local) clock in the current event instant."""
        var = self._by_name.get(name)
        if not isinstance(var, Clock) or var.causality == "input":
            raise ValueError(f"'{name}' is not an output clock of {type(self).__name__}")
        self.active_clocks.add(name)

    def clock_active(self, name: str) -> bool:
        return name in self.active_clocks

    def log(self, message: str, category: str = "logEvents", status: int = 0) -> None:
        """Send a message through the importer's logMessage callback (if logging is on)."""
        if self._logger is not None:
            self._logger(status, category, message)

    def logging(self, category: str = "logEvents", status: int = 0) -> bool:
        """Whether :meth:`log` would pass a message of this category and status on to the
        importer: test it before formatting a message at every step or event."""
        enabled = getattr(self._logger, "enabled", None)
        return self._logger is not None and (enabled is None or enabled(status, category))

    # -- hooks (documented on the class) ----------------------------------------------------------

    def setup(self) -> None:
        pass

    def enter_initialization_mode(self) -> None:
        pass

    def exit_initialization_mode(self) -> None:
        pass

    def react(self, clocks: frozenset[str]) -> None:
        pass

    def update_discrete_states(self) -> Update | None:
        return None

    def do_step(self, t: float, h: float) -> Step | None:
        return None

    def update_outputs(self) -> None:
        self.outputs_stale = False

    def terminate(self) -> None:
        pass

    def free(self) -> None:
        pass


class _SettingValue(Setting):
    """A Setting whose value was chosen at packaging time."""

    def __init__(self, declared: Setting, value: Any) -> None:
        super().__init__(value, declared.description)
