"""robogen.fuzz: the generator is reproducible and its models are well formed, the shrinker keeps
a failure while it removes what does not matter, regression files round-trip, and a small fixed
budget of models passes every property (the CI budget of `make fuzz`, under a minute)."""

from __future__ import annotations

import io
import re

import pytest

from robogen.fuzz import regressions
from robogen.fuzz.features import DEFAULT, FEATURES, features
from robogen.fuzz.model import generate
from robogen.fuzz.properties import Budget, Failure, check_model
from robogen.fuzz.runner import Settings, run
from robogen.fuzz.shrink import shrink, variants
from robogen.semantics import check_texts
from robogen.syntax import ast, printer
from robogen.syntax.parser import parse_text

SUMMARY = re.compile(r"fuzz: (\d+) models, C compile failures (\d+), differences (\d+), internal errors (\d+), "
                     r"print/parse differences (\d+), not supported (\d+)")


def test_a_seed_gives_one_model_and_another_seed_another():
    a, b = printer.file(generate("7.3", DEFAULT).file), printer.file(generate("7.3", DEFAULT).file)
    assert a == b
    assert printer.file(generate("7.4", DEFAULT).file) != a
    # switches are part of the model's identity: without sets, no Set( in any model
    assert all("Set(" not in printer.file(generate(f"7.{i}", DEFAULT - {"sets"}).file) for i in range(20))


def test_generated_models_print_parse_and_check_without_errors():
    languages = set()
    for i in range(40):
        g = generate(f"11.{i}", DEFAULT)
        text = printer.file(g.file)
        assert parse_text(text, g.path) == g.file, g.seed
        model = check_texts({g.path: text})
        assert not model.errors, (g.seed, [d.render() for d in model.errors])
        languages.add(g.language)
        assert g.file.language == g.language and g.path.endswith(".rst" if g.language == "robosim" else ".rct")
    assert languages == {"robochart", "robosim"}


def test_the_features_table():
    assert DEFAULT == {f.name for f in FEATURES if f.default}
    assert all(f.why_off for f in FEATURES if not f.default)  # every switch that is off says why
    assert features(["quantifiers"], ["sets"]) == (DEFAULT | {"quantifiers"}) - {"sets"}
    with pytest.raises(ValueError, match="no feature 'nope'"):
        features(["nope"])
    # what code generation on main supports is on: issue 23's functions and front end
    assert {"generic_functions", "postcondition_functions", "recursive_enums", "literal_types", "abstract_operations",
            "old_syntax", "filter_from", "function_updates", "matrix_ops", "nested_collections", "comprehensions",
            "quantifiers", "iter_dconcat", "union_inter", "strings_in_collections", "constant_expressions"} <= DEFAULT


SHRINKABLE = """\
stm S {
	var x: int = 1, y: int = 2
	event e
	initial i
	state A { entry x = x + 1 ; y = 3 }
	state B { entry wait(2) ; y = y * 2 }
	transition t0 { from i to A }
	transition t1 { from A to B trigger e condition x > 1 action y = 0 }
	transition t2 { from B to A condition y > 2 }
}
"""


def test_the_shrinker_keeps_the_failure_and_drops_the_rest():
    """The failure: a wait statement that still checks. The smallest such model keeps one state
    with the wait, the initial node and its transition."""
    original = parse_text(SHRINKABLE, "s.rct")

    def fails(f: ast.File) -> bool:
        text = printer.file(f)
        return "wait(" in text and not check_texts({"s.rct": text}).errors

    small = shrink(original, fails, seconds=60)
    text = printer.file(small)
    assert fails(small) and len(text) < len(SHRINKABLE) / 2
    assert "transition t1" not in text and "y = 3" not in text
    assert any(isinstance(v, ast.File) for v in variants(small))


def test_a_regression_file_holds_the_model_its_failure_and_its_functions(tmp_path):
    g = next(g for g in (generate(f"5.{i}", DEFAULT) for i in range(200)) if any(f.c_body for f in g.functions))
    failure = Failure("differential", "difference", "stepwise, scenario 2: record 7:\n  FMU (...)")
    path = regressions.write(tmp_path, g, failure, DEFAULT - {"vectors"})
    assert path.name == f"differential_difference_{g.seed.replace('.', '_')}{path.suffix}"
    head = path.read_text().splitlines()
    assert head[0] == f"// robogen fuzz regression: property differential (difference), seed {g.seed}"
    assert head[1] == "// features: -vectors"
    r = regressions.read(path)
    assert (r.prop, r.kind, r.seed) == ("differential", "difference", g.seed)
    assert (r.generated.file.package, r.generated.file.imports, r.generated.file.items) == (g.file.package, g.file.imports, g.file.items)
    # the functions implemented in C keep their bodies; those defined by a postcondition are in the text
    assert r.generated.functions == tuple(f for f in g.functions if f.c_body is not None) and r.generated.language == g.language


def test_a_model_that_code_generation_refuses_is_not_supported_not_a_failure(tmp_path):
    """A located "not supported" error stops the model without failing it: the inverse of a matrix
    (refused: README, Known limits) in an otherwise good RoboSim machine."""
    text = ("stm S { cycleDef cycle == 1 var m: matrix(real, 2, 2) = [| 1.0, 2.0; 3.0, 4.0 |] initial i state A { }\n"
            "transition t0 { from i to A action m = inverse(m) } transition t1 { from A to A exec } }\n")
    g = generate("1.0", DEFAULT)
    from dataclasses import replace
    model = replace(g, language="robosim", file=parse_text(text, "t.rst"), functions=())
    out = check_model(model, tmp_path, Budget())
    assert out.failure is None and out.passed == ["print", "check"]
    assert out.unsupported == "the inverse of a matrix"


@pytest.mark.slow
def test_a_small_fixed_budget_passes_every_property(tmp_path):
    """The CI budget: two dozen models of seed 3 through every property, the first under the
    sanitizers too; the table ends with the summary line, all four failure counts 0."""
    out = io.StringIO()
    settings = Settings(seed=3, count=24, on=DEFAULT, jobs=2, sanitize_every=24, shrink_seconds=0,
                        budget=Budget(scenarios=3, instants=10), work=tmp_path)
    report = run(settings, out)
    text = out.getvalue()
    last = text.strip().splitlines()[-1]
    match = SUMMARY.fullmatch(last)
    assert match is not None, last
    assert match.group(1) == "24" and match.groups()[1:5] == ("0", "0", "0", "0"), text
    assert not report.failed, text
    assert sum("sanitize" in o.passed for o in report.outcomes) == 1
    assert all("differential" in o.passed or o.unsupported for o in report.outcomes)
    assert sum(1 for o in report.outcomes if o.unsupported) <= 1, text  # "not supported" stays rare (under 1% in `make fuzz` runs)
