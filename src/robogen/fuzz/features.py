"""The generator's feature switches: each construct family the model fuzzer can generate, on or off.

The default set is what code generation supports on ``main``. A switch that is off names the
reason, and, for a construct another branch of issue 23 is implementing, that branch's area: the
lead turns it on (``--with NAME``, or here) once the branch is merged. Turning a switch off never
changes what the generator draws for the other constructs' *decisions*, only whether the
construct itself appears, so the same seed still gives a comparable model.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Feature:
    name: str
    default: bool
    what: str  # what the generator produces when it is on
    why_off: str = ""  # why it is off by default (empty when on)


FEATURES: tuple[Feature, ...] = (
    # ---- languages and structure
    Feature("robochart", True, "RoboChart (.rct) models"),
    Feature("robosim", True, "RoboSim (.rst) models"),
    Feature("modules", True, "modules with a robotic platform, controllers and connections (else a lone state machine)"),
    Feature("composite_states", True, "composite states, nested up to two levels"),
    Feature("junctions", True, "junctions with an `else` branch"),
    Feature("finals", True, "final nodes"),
    Feature("probabilistic", True, "probabilistic junctions (RoboChart)"),
    Feature("operations", True, "software operations (opref, calls from actions)"),
    Feature("platform_operations", True, "platform operations (output clocks)"),
    Feature("shared_variables", True, "variables provided by the controller or the platform"),
    Feature("platform_variables", True, "RoboSim: platform variables read ($x) and written ($x = e)"),
    Feature("machine_connections", True, "connections between the machines of a controller"),
    Feature("mult", True, "bidirectional connections ([ mult ])"),
    Feature("broadcast", True, "_broadcast events (RoboChart)"),
    Feature("time", True, "RoboChart clocks, since, sinceEntry, wait, deadlines"),
    Feature("user_functions", True, "functions declared by their contract, implemented in C (--functions)"),
    # ---- types and expressions
    Feature("records", True, "datatypes, record literals, field selection and update"),
    Feature("tuples", True, "products, tuple literals and projection"),
    Feature("enum_args", True, "enumeration literals with arguments"),
    Feature("sets", True, "sets of scalars and records, the set toolkit"),
    Feature("sequences", True, "sequences of scalars and records, the sequence toolkit"),
    Feature("vectors", True, "vectors, vector arithmetic"),
    Feature("matrices", True, "matrices, transpose, matrix products"),
    Feature("function_values", True, "lambdas and function-typed variables"),
    Feature("function_updates", True, "function variables updated by the toolkit (f = override(f, {(| k, v |)}))"),
    Feature("strings", True, "string variables, literals and events"),
    Feature("lets", True, "let and if expressions, casts"),
    Feature("matrix_ops", True, "transpose of matrices"),
    # ---- issue 23, on main: functions (helper 'functions'), the front end (helper 'frontend')
    Feature("generic_functions", True, "user functions with type variables (?X)"),
    Feature("postcondition_functions", True, "functions defined by `postcondition result == e`, without a C file"),
    Feature("recursive_enums", True, "enumerations whose literals carry the enumeration"),
    Feature("literal_types", True, "record, tuple and tagged types used only in expressions, events or operation "
            "parameters (else the machine also declares a variable of each)"),
    Feature("abstract_operations", True, "operations without nodes, called by a machine"),
    Feature("old_syntax", True, "RoboTool's syntax before 2020-10: a bare `trigger` for the empty trigger"),
    Feature("filter_from", True, "filters that bind the sender (`x = from`)"),
    # ---- issue 23, on main: collections of collections, quantifiers, comprehensions (helper 'collections')
    Feature("nested_collections", True, "Seq(Seq(T)), collections of records whose fields hold collections"),
    Feature("comprehensions", True, "set comprehensions and ranges as values"),
    Feature("quantifiers", True, "forall, exists, exists1 over finite sets"),
    Feature("iter_dconcat", True, "the toolkit's iter and dconcat"),
    Feature("union_inter", True, "the toolkit's Union and Inter (sets of sets)"),
    Feature("strings_in_collections", True, "sets and sequences of strings"),
    Feature("constant_expressions", True, "constants of scalar, vector and matrix types whose value is any expression "
            "(off: literals, other constants and + - *)"),
)

BY_NAME = {f.name: f for f in FEATURES}
DEFAULT: frozenset[str] = frozenset(f.name for f in FEATURES if f.default)


def features(with_: list[str] | tuple[str, ...] = (), without: list[str] | tuple[str, ...] = ()) -> frozenset[str]:
    """The default set with ``with_`` switched on and ``without`` switched off (names checked)."""
    for name in (*with_, *without):
        if name not in BY_NAME:
            raise ValueError(f"no feature '{name}' (features: {', '.join(sorted(BY_NAME))})")
    return (DEFAULT | frozenset(with_)) - frozenset(without)


__all__ = ["Feature", "FEATURES", "BY_NAME", "DEFAULT", "features"]
