"""robogen.semantics.workspace: packages, imports and global names across the files of a
workspace, and the loading of files and folders."""

from __future__ import annotations

import pytest
from support.frontend import at, brief

from robogen.diagnostics import RobogenError, Span
from robogen.semantics import check_paths, check_texts
from robogen.semantics.workspace import collect_model_paths, load

MACHINE_BODY = "initial i state A { } transition t { from i to A }"


def check(texts: dict[str, str]) -> list[tuple]:
    """(path, severity, line, column, message) of every diagnostic."""
    return [(d.span.path if d.span else None, *brief(d)) for d in check_texts(texts).diagnostics]


def test_names_resolve_across_files_through_packages_and_imports():
    texts = {
        "types.rct": "package geo::types\ntype Id\nenumeration Dir { n s }",
        "machine.rct": (
            "package geo::robot\nimport geo::types::*\nimport geo::types::Dir\n"
            f"stm S {{ var a: Id var b: geo::types::Id var d: Dir = geo::types::Dir::n {MACHINE_BODY} }}"
        ),
        "system.rct": "package geo\ncontroller C { sref s = geo::robot::S }",
        "loose.rct": "interface Everywhere { event e }",  # no package: visible in every file
        "user.rct": f"package other\nstm U {{ uses Everywhere {MACHINE_BODY} }}",
    }
    assert check(texts) == []


def test_unknown_and_bad_imports():
    """An import that finds nothing is a warning: RoboTool does not check imports (K12)."""
    texts = {
        "a.rct": "package a\ntype T",
        "m.rct": "import nope::*\nimport a\nimport a::Nope\nimport b::T\nimport a::T",
    }
    m = texts["m.rct"]
    assert check(texts) == [
        ("m.rct", "warning", *at(m, "nope"), "no package 'nope' in this workspace: the import brings nothing"),
        ("m.rct", "error", *at(m, "a\n"), "import 'a' must name a package and a declaration (pkg::Name or pkg::*)"),
        ("m.rct", "warning", *at(m, "a::Nope"), "package 'a' declares no 'Nope': the import brings nothing"),
        ("m.rct", "warning", *at(m, "b::T"), "no package 'b' in this workspace: the import brings nothing"),
    ]


def test_an_import_of_a_missing_package_leaves_the_names_of_the_file_unresolved_not_the_file():
    texts = {
        "chem.rct": "package det::chem\nenumeration Chem { innocuous toxic }",
        "m.rct": f"package det::main\nimport chem::*\nstm S {{ var c: det::chem::Chem = det::chem::Chem::toxic {MACHINE_BODY} }}",
    }
    assert check(texts) == [("m.rct", "warning", *at(texts["m.rct"], "chem::*"),
                             "no package 'chem' in this workspace: the import brings nothing (did you mean 'det::chem'?)")]


def test_qualified_names_name_a_package_and_a_declaration_of_the_right_kind():
    texts = {
        "a.rct": "package a\ntype T\ninterface I { event e }",
        "m.rct": f"package m\nstm S {{ var x: z::T var y: a::I uses a::T uses a::J {MACHINE_BODY} }}",
    }
    m = texts["m.rct"]
    assert check(texts) == [
        ("m.rct", "error", *at(m, "z::T"), "unknown package 'z' in 'z::T'"),
        ("m.rct", "error", *at(m, "a::I"), "'a::I' is an interface, not a type"),
        ("m.rct", "error", *at(m, "a::T"), "'a::T' is a type, not an interface"),
        ("m.rct", "error", *at(m, "a::J"), "package 'a' declares no interface 'J'"),
    ]


def test_ambiguous_and_unimported_names():
    texts = {
        "a.rct": "package a\ntype T",
        "b.rct": "package b\ntype T",
        "c.rct": f"package c\nimport a::*\nimport b::*\nstm S {{ var x: T {MACHINE_BODY} }}",
        "d.rct": f"package d\nstm S {{ var x: T {MACHINE_BODY} }}",
        "e.rct": f"package a::sub\nstm S {{ var x: T {MACHINE_BODY} }}",
    }
    assert check(texts) == [
        ("c.rct", "error", *at(texts["c.rct"], "T "), "'T' is ambiguous here: a::T, b::T"),
        ("d.rct", "error", *at(texts["d.rct"], "T "), "'T' is not imported here, and several packages declare it: a::T, b::T"),
        # RoboTool's translations rely on this: the closest package wins, with a warning
        ("e.rct", "warning", *at(texts["e.rct"], "T "), "'T' is not imported here; using 'a::T'"),
    ]
    notes = [n.message for d in check_texts(texts).diagnostics for n in d.notes]
    assert "add 'import a::T' (or '::*') to the file" in notes


def test_unknown_names_of_every_kind():
    text = "\n".join([
        "module M { rref p = NoPlatform cref c = NoController }",
        "controller C { sref s = NoMachine opref o = NoOperation }",
        f"stm S {{ uses NoInterface var x: NoType {MACHINE_BODY} }}",
        f"stm T {{ var y: S {MACHINE_BODY} }}",
    ])  # fmt: skip
    assert check({"m.rct": text}) == [
        ("m.rct", "error", *at(text, "NoPlatform"), "unknown robotic platform 'NoPlatform'"),
        ("m.rct", "error", *at(text, "NoController"), "unknown controller 'NoController'"),
        ("m.rct", "error", *at(text, "NoMachine"), "unknown state machine 'NoMachine'"),
        ("m.rct", "error", *at(text, "NoOperation"), "unknown operation 'NoOperation'"),
        ("m.rct", "error", *at(text, "NoInterface"), "unknown interface 'NoInterface'"),
        ("m.rct", "error", *at(text, "NoType"), "unknown type 'NoType'"),
        ("m.rct", "error", *at(text, "S initial"), "'S' is a state machine, not a type"),
    ]


def test_duplicate_top_level_declarations():
    """RoboTool's UniqueQualifiedName check (RoboChartValidator.checkUniqueness) warns "... is not
    unique" when the project exports two objects of one class under one qualified name, in a
    package or not, in one file or two; declarations of other kinds (a machine and a type S)
    do not clash, since every lookup asks for a kind."""
    texts = {
        "a.rct": f"package p\nstm S {{ {MACHINE_BODY} }}\ntype S\ninterface J {{ }}",
        "b.rct": "package p\ninterface S { }\ninterface J { }",
        "c.rct": "type Free",
        "d.rct": "type Free",
    }
    assert check(texts) == [
        ("b.rct", "warning", 3, 11, "'J' is not unique: an interface of that name is declared twice in package 'p'; "
                                    "a file that declares one uses its own, the other files the first"),
        ("d.rct", "warning", 1, 6, "'Free' is not unique: a type of that name is declared twice in the files without a "
                                   "package; a file that declares one uses its own, the other files the first"),
    ]
    first = check_texts(texts).diagnostics[0].notes[0]
    assert first.message == "'J' is first declared here"
    assert (first.span.path, first.span.line, first.span.column) == ("a.rct", 4, 11)


SHADOW_A = """interface I {
\tevent go
}
stm A {
\tuses I
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger go }
}
"""
SHADOW_B = """interface I {
\tevent stop
}
stm B {
\tuses I
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger stop }
}
controller C {
\tuses I
\tsref b = B
\tconnection C on stop to b on stop
}
"""


@pytest.mark.parametrize("package", ["", "package p\n"])
def test_a_name_declared_in_the_same_file_shadows_its_declaration_in_another_file(package):
    """Xtext links a name to the resource's own elements before the global index: b.rct's machine
    and controller use b.rct's interface I (with event stop), not a.rct's (with go), though
    a.rct comes first; the duplicate stays a warning. A file that does not declare I uses the
    first (c.rct: a.rct's, so stop is unknown there)."""
    c = package + "stm M {\n\tuses I\n\tinitial i\n\tstate S { }\n\ttransition t0 { from i to S }\n" \
                  "\ttransition t1 { from S to S trigger stop }\n}\n"
    texts = {"a.rct": package + SHADOW_A, "b.rct": package + SHADOW_B, "c.rct": c}
    shift = 1 if package else 0
    assert [d[:4] for d in check(texts)] == [
        ("b.rct", "warning", 1 + shift, 11),  # 'I' is not unique
        ("c.rct", "error", 6 + shift, 38),  # unknown event 'stop'
    ]
    model = check_texts({"a.rct": package + SHADOW_A, "b.rct": package + SHADOW_B})
    assert not model.errors


def test_a_function_does_not_hide_a_type_of_the_same_name():
    """Types and functions are separate name spaces, as in RoboTool's scopes."""
    texts = {
        "m.rct": "function real(x: nat): nat { }\ntype nat2\nfunction nat2(x: nat): nat2 { }\n"
                 f"stm S {{ var r: real = 1.5 var n: nat = real(2) var m: nat2 = nat2(1) {MACHINE_BODY} }}",
    }
    assert check(texts) == []


def test_the_core_package_declares_the_primitive_types():
    text = f"import core::*\nstm S {{ var a: core::nat var b: boolean var c: string var d: int var e: real {MACHINE_BODY} }}"
    assert check({"m.rct": text}) == []


# ---------------------------------------------------------------------------- loading


def test_folders_are_searched_recursively_in_a_stable_order(tmp_path):
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "z.rst").write_text("")
    (tmp_path / "a.rct").write_text("")
    (tmp_path / "notes.txt").write_text("")
    (tmp_path / "c.rsim").write_text("")
    found = collect_model_paths([tmp_path, tmp_path / "a.rct"])
    assert [p.removeprefix(str(tmp_path)) for p in found] == ["/a.rct", "/b/z.rst", "/c.rsim"]


@pytest.mark.parametrize(
    "name, message",
    [
        ("missing.rct", "no such file or directory: {path}"),
        ("notes.txt", "not a model file: {path} (expected a .rct (RoboChart), .rst or .rsim (RoboSim) file)"),
    ],
)
def test_paths_that_hold_no_model_are_reported(tmp_path, name, message):
    (tmp_path / "notes.txt").write_text("hello")
    (tmp_path / "empty-folder").mkdir()
    path = tmp_path / name
    with pytest.raises(RobogenError) as exc:
        collect_model_paths([path])
    assert [d.message for d in exc.value.diagnostics] == [message.format(path=path)]
    model = check_paths([path])
    assert [brief(d) for d in model.diagnostics] == [("error", message.format(path=path))]


def test_an_empty_folder_is_an_empty_project_or_for_robogen_check_an_error(tmp_path):
    """RoboTool loads an empty project folder without complaint (K14): a warning, located at the
    folder (a span of the path alone); but a script that runs `robogen check` on a folder would
    believe its models checked, so there (empty_is_error) it is an error."""
    (tmp_path / "empty-folder").mkdir()
    path = tmp_path / "empty-folder"
    message = f"no model files (.rct, .rst, .rsim) in directory {path}"
    assert collect_model_paths([path]) == []
    model = check_paths([path])
    assert [brief(d) for d in model.diagnostics] == [("warning", 0, 0, message)]
    assert model.files == ()
    with pytest.raises(RobogenError) as exc:
        collect_model_paths([path], empty_is_error=True)
    (d,) = exc.value.diagnostics
    assert (d.message, d.span) == (message, Span.of_path(str(path)))
    assert [brief(d) for d in check_paths([path], empty_is_error=True).diagnostics] == [("error", 0, 0, message)]


def test_a_file_with_a_syntax_error_is_left_out_and_the_others_still_checked(tmp_path):
    (tmp_path / "bad.rct").write_text("stm {")
    (tmp_path / "good.rct").write_text(f"stm S {{ var x: Quux {MACHINE_BODY} }}")
    workspace = load([tmp_path])
    assert [f.path for f in workspace.files] == [str(tmp_path / "good.rct")]
    model = check_paths([tmp_path])
    assert [(d.span.path.rsplit("/", 1)[1], d.message) for d in model.diagnostics] == [
        ("bad.rct", "unexpected '{'; expected a name"),
        ("good.rct", "unknown type 'Quux'"),
    ]


def test_undecodable_and_binary_files(tmp_path):
    (tmp_path / "latin1.rct").write_bytes("// caf\xe9\nstm S { }".encode("latin-1"))
    (tmp_path / "nul.rst").write_bytes(b"stm S {\n\x00 }")
    model = check_paths([tmp_path])
    assert [brief(d) for d in model.diagnostics] == [
        ("error", 1, 7, "not valid UTF-8 text (byte 0xe9 at offset 6); models must be UTF-8"),
        ("error", 2, 1, "file contains NUL bytes; is it a binary file, not a model?"),
    ]


def test_a_byte_order_mark_is_allowed(tmp_path):
    (tmp_path / "bom.rct").write_bytes(b"\xef\xbb\xbf" + f"stm S {{ {MACHINE_BODY} }}".encode())
    assert check_paths([tmp_path]).diagnostics == ()


def test_an_empty_file_is_a_warning(tmp_path):
    (tmp_path / "empty.rct").write_text("// nothing here\n")
    assert [brief(d) for d in check_paths([tmp_path]).diagnostics] == [("warning", 1, 1, "the file is empty: it declares nothing")]


def test_a_qualified_name_also_finds_the_declaration_of_the_same_file_first():
    b = "package p\n" + SHADOW_B.replace("uses I", "uses p::I")
    assert [d[:4] for d in check({"a.rct": "package p\n" + SHADOW_A, "b.rct": b})] == [("b.rct", "warning", 2, 11)]
