"""robogen.ir.dump and the IR's places: the canonical text names no file, the printers of
generated files name a model file relative to the workspace root."""

from __future__ import annotations

from pathlib import Path

from robogen.codegen.api import lower_paths
from robogen.diagnostics import Span
from robogen.ir import model as ir
from robogen.ir.dump import dump

MODELS = Path(__file__).resolve().parent.parent / "codegen" / "models"


def test_a_message_writes_its_places_with_the_printer_given():
    text = ir.Text(("deadlock in state 'S' (", ir.At(Span.point("/w/m/a.rst", 7)), "): stuck at ", ir.At(None)))
    assert text.render(lambda span: "HERE" if span else "NOWHERE") == "deadlock in state 'S' (HERE): stuck at NOWHERE"


def test_places_are_relative_to_the_workspace_root():
    fmu = ir.Fmu("M", "M", "robosim", "exhaustive", "cycle", 1, 1, ("/w/models/a.rst", "/w/models/lib/b.rst"), None,
                 root="/w/models")
    assert fmu.place(Span.point("/w/models/lib/b.rst", 12)) == "lib/b.rst:12"
    assert fmu.place(None) == "?"
    assert fmu.source_names == ["a.rst", "lib/b.rst"]


def test_the_dump_is_path_free_and_shows_the_lines_of_places():
    fmu, _ = lower_paths([MODELS / "timers.rct"])  # deadlines: messages that name transitions and statements
    text = dump(fmu)
    assert "timers.rct" not in text and str(MODELS) not in text
    assert "deadline missed" in text and "(line 43)" in text
