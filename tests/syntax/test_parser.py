"""robogen.syntax.parser: what the grammars accept, the trees they build, and the syntax errors
they report (golden messages with exact line and column)."""

from __future__ import annotations

import pytest
from support.frontend import REFERENCE, corpus_files, reference_files, relative_ids, walk

from robogen.diagnostics import RobogenError, SourceMap, render
from robogen.syntax import ast
from robogen.syntax.parser import MAX_NESTING, keywords, language_of, parse_file, parse_text

# ---------------------------------------------------------------------------- helpers


def N(*parts: str) -> ast.Name:
    return ast.Name(parts)


def I(value: int) -> ast.IntLit:  # noqa: E743 - reads like the literal it builds
    return ast.IntLit(value)


def Bin(op: str, left: ast.Expr, right: ast.Expr) -> ast.Binary:
    return ast.Binary(op, left, right)


def Not(e: ast.Expr) -> ast.Unary:
    return ast.Unary("not", e)


def Neg(e: ast.Expr) -> ast.Unary:
    return ast.Unary("-", e)


def Ref(*parts: str) -> ast.TypeRef:
    return ast.TypeRef(N(*parts))


NAT = Ref("nat")


def condition(text: str, path: str = "m.rct") -> ast.Expr:
    """The AST of ``text`` parsed as a transition condition."""
    f = parse_text(f"stm S {{ transition t {{ from a to b condition {text} }} }}", path)
    transition = f.items[0].members[0]
    assert isinstance(transition, ast.Transition)
    return transition.condition


def action(text: str, path: str = "m.rct") -> ast.Stmt:
    f = parse_text(f"stm S {{ transition t {{ from a to b action {text} }} }}", path)
    return f.items[0].members[0].action


def syntax_errors(text: str, path: str = "m.rct") -> list[tuple[int, int, str]]:
    with pytest.raises(RobogenError) as exc:
        parse_text(text, path)
    return [(d.span.line, d.span.column, d.message) for d in exc.value.diagnostics]


def rendered(text: str, path: str = "m.rct") -> str:
    with pytest.raises(RobogenError) as exc:
        parse_text(text, path)
    return "\n".join(render(d, SourceMap({path: text})) for d in exc.value.diagnostics)


# ---------------------------------------------------------------------------- the real models


@pytest.mark.shared
@pytest.mark.parametrize("path", reference_files(), ids=relative_ids(reference_files(), REFERENCE))
def test_every_reference_model_parses(path):
    f = parse_file(path)
    assert f.path == str(path)
    assert f.items, "a reference model declares something"


@pytest.mark.shared
def test_the_reference_models_are_all_found():
    # the conformance corpus: RoboChart originals, normalised RoboChart, RoboSim translation
    assert len(reference_files()) == 16
    assert {p.suffix for p in reference_files()} == {".rct", ".rst"}


@pytest.mark.parametrize("path", corpus_files(), ids=lambda p: p.name)
def test_every_node_of_the_own_corpus_has_a_consistent_span(path):
    """Spans start and end on tokens, agree with their offsets, cover balanced brackets, and
    a named node's name span holds its name."""
    text = path.read_text(encoding="utf-8")
    line_starts = [0] + [i + 1 for i, ch in enumerate(text) if ch == "\n"]
    for node in walk(parse_file(path)):
        span = node.span
        assert span is not None and span.offset >= 0, node
        covered = text[span.offset : span.end_offset]
        assert covered and not covered[0].isspace() and not covered[-1].isspace(), (node, covered)
        assert line_starts[span.line - 1] + span.column - 1 == span.offset
        if not _has_range(node):
            for opening, closing in ("()", "{}", "[]"):
                assert covered.count(opening) == covered.count(closing), (type(node).__name__, covered)
        if isinstance(node, ast.Named) and node.name_span is not None:
            assert text[node.name_span.offset : node.name_span.end_offset].lstrip("^") == node.name


def _has_range(node: ast.Node) -> bool:
    """Ranges like [a, b) legitimately pair different brackets; so do strings holding brackets."""
    return any(isinstance(n, (ast.Range, ast.StringLit)) for n in walk(node))


def test_language_follows_the_extension():
    assert language_of("a/b.rct") == "robochart"
    assert language_of("a/b.RST") == "robosim"
    assert language_of("b.rsim") == "robosim"
    assert language_of("b.txt") is None
    assert parse_text("", "x.rsim").language == "robosim"


# ---------------------------------------------------------------------------- lexical rules


def test_keywords_win_only_on_whole_words():
    assert condition("stateX /\\ index /\\ toX /\\ exists1x /\\ notes") == Bin(
        "/\\", Bin("/\\", Bin("/\\", Bin("/\\", N("stateX"), N("index")), N("toX")), N("exists1x")), N("notes")
    )


def test_a_caret_escapes_a_keyword_and_is_not_part_of_the_name():
    assert condition("^state == ^exec") == Bin("==", N("state"), N("exec"))
    f = parse_text("interface I { event ^exec }", "m.rst")
    assert f.items[0].members[0] == ast.EventDecl("exec")


def test_robosim_keywords_are_names_in_robochart_and_reserved_in_robosim():
    text = "stm input { var output: nat, context: nat, cycle: nat, exec: nat }"
    assert [v.name for v in parse_text(text, "m.rct").items[0].members[0].vars] == ["output", "context", "cycle", "exec"]
    assert {"input", "output", "context", "cycle", "exec", "cycleDef"} <= keywords("robosim")
    assert not {"input", "output", "context", "cycle", "exec", "cycleDef"} & keywords("robochart")
    assert {"stm", "state", "transition", "from", "to", "since", "sinceEntry", "Set", "Seq"} <= keywords("robochart")
    assert syntax_errors(text, "m.rst") == [
        (1, 5, "'input' is a reserved word and cannot be used as a name (write ^input to escape it)"),
        (1, 17, "'output' is a reserved word and cannot be used as a name (write ^output to escape it)"),
        (1, 30, "'context' is a reserved word and cannot be used as a name (write ^context to escape it)"),
        (1, 44, "'cycle' is a reserved word and cannot be used as a name (write ^cycle to escape it)"),
        (1, 56, "'exec' is a reserved word and cannot be used as a name (write ^exec to escape it)"),
    ]


def test_numbers_strings_and_comments():
    f = parse_text(
        """// a line comment
        stm S { /* a block
        comment */ var r: real = 0.5, n: nat = 42, s: string = "say \\"hi\\"", t: string = 'it\\'s' }"""
    )
    values = [v.init for v in f.items[0].members[0].vars]
    assert values == [ast.RealLit("0.5"), I(42), ast.StringLit('say "hi"'), ast.StringLit("it's")]
    assert values[0].value == 0.5


def test_set_and_seq_types_accept_a_space_before_the_parenthesis():
    f = parse_text("stm S { var a: Set (nat), b: Seq(Set( nat )) }")
    assert [v.type for v in f.items[0].members[0].vars] == [ast.SetType(NAT), ast.SeqType(ast.SetType(NAT))]


def test_deadline_opener_is_one_token():
    # `x<{1}` lexes as x followed by a deadline opener, which a condition cannot take; with a
    # space, `x < {1}` compares x with a set.
    assert condition("x < {1}") == Bin("<", N("x"), ast.SetLit((I(1),)))
    assert syntax_errors("stm S { transition t { from a to b condition x<{1} } }")[0][:2] == (1, 47)


def test_not_equal_is_one_token_after_a_dollar_name():
    assert condition("$e!=v", "m.rst") == Bin("!=", ast.Dollar("e"), N("v"))


def test_wildcard_import_and_qualified_names():
    f = parse_text("package a::b\nimport c::d::*\nimport c::E\nstm S { var x: c::d::T }")
    assert f.package == N("a", "b")
    assert f.imports == (ast.Import(N("c", "d"), True), ast.Import(N("c", "E"), False))
    assert f.items[0].members[0].vars[0].type == Ref("c", "d", "T")


# ---------------------------------------------------------------------------- precedence

PRECEDENCE = [
    # binders extend as far right as possible
    ("forall x: nat @ a /\\ b", ast.Binder("forall", (ast.Decl("x", NAT),), None, Bin("/\\", N("a"), N("b")))),
    (
        "a /\\ (exists x: nat | x > 1 @ b \\/ c)",
        Bin("/\\", N("a"), ast.Binder("exists", (ast.Decl("x", NAT),), Bin(">", N("x"), I(1)), Bin("\\/", N("b"), N("c")))),
    ),
    ("a iff b => c", Bin("iff", N("a"), Bin("=>", N("b"), N("c")))),
    ("a iff b iff c", Bin("iff", Bin("iff", N("a"), N("b")), N("c"))),
    ("a => b => c", Bin("=>", Bin("=>", N("a"), N("b")), N("c"))),
    ("a => b \\/ c", Bin("=>", N("a"), Bin("\\/", N("b"), N("c")))),
    ("a \\/ b /\\ c", Bin("\\/", N("a"), Bin("/\\", N("b"), N("c")))),
    ("not a /\\ b", Bin("/\\", Not(N("a")), N("b"))),
    ("not x == y", Not(Bin("==", N("x"), N("y")))),
    ("not not a", Not(Not(N("a")))),
    ("a == b /\\ c < d", Bin("/\\", Bin("==", N("a"), N("b")), Bin("<", N("c"), N("d")))),
    ("a < b == c", Bin("==", Bin("<", N("a"), N("b")), N("c"))),
    ("x in s /\\ y", Bin("/\\", Bin("in", N("x"), N("s")), N("y"))),
    ("x + 1 in s", Bin("in", Bin("+", N("x"), I(1)), N("s"))),
    # the, let and if bind looser than arithmetic and tighter than comparison
    ("the x: nat | p @ x == 1", Bin("==", ast.Binder("the", (ast.Decl("x", NAT),), N("p"), N("x")), I(1))),
    ("let k == 1, j == 2 @ k + j", ast.Let((ast.LetDef("k", I(1)), ast.LetDef("j", I(2))), Bin("+", N("k"), N("j")))),
    ("x == if c then 1 else 2 end", Bin("==", N("x"), ast.IfExpr(N("c"), I(1), I(2)))),
    ("x + 1 as real", ast.Cast("as", Bin("+", N("x"), I(1)), Ref("real"))),
    ("x is nat == true", Bin("==", ast.Cast("is", N("x"), NAT), ast.BoolLit(True))),
    ("a - b - c", Bin("-", Bin("-", N("a"), N("b")), N("c"))),
    ("a + b * c", Bin("+", N("a"), Bin("*", N("b"), N("c")))),
    ("a * b / c % d", Bin("%", Bin("/", Bin("*", N("a"), N("b")), N("c")), N("d"))),
    ("a * b cat c", Bin("*", N("a"), Bin("cat", N("b"), N("c")))),
    ("a ^ b cat c", Bin("cat", Bin("^", N("a"), N("b")), N("c"))),
    ("- a ^ b", Bin("^", Neg(N("a")), N("b"))),
    ("- - a", Neg(Neg(N("a")))),
    ("- r.f", Neg(ast.Field(N("r"), "f"))),
    ("r.f.g", ast.Field(ast.Field(N("r"), "f"), "g")),
    ("r.f[1]", ast.Index(ast.Field(N("r"), "f"), (I(1),))),
    ("f(x)[2]", ast.Index(ast.Call(N("f"), (N("x"),)), (I(2),))),
    ("m[i, j]", ast.Index(N("m"), (N("i"), N("j")))),
    ("p::f(x, y)", ast.Call(N("p", "f"), (N("x"), N("y")))),
    ("E::a == E::b(1)", Bin("==", N("E", "a"), ast.Call(N("E", "b"), (I(1),)))),
    ("(a \\/ b) /\\ c", Bin("/\\", Bin("\\/", N("a"), N("b")), N("c"))),
]


@pytest.mark.parametrize("text, tree", PRECEDENCE, ids=[t for t, _ in PRECEDENCE])
def test_precedence(text, tree):
    assert condition(text) == tree


ATOMS = [
    ("<a, b + 1> == s", Bin("==", ast.SeqLit((N("a"), Bin("+", N("b"), I(1)))), N("s"))),
    ("<> == s", Bin("==", ast.SeqLit(()), N("s"))),
    ("(a, b)", ast.Range(N("a"), N("b"), False, False)),
    ("(a, b]", ast.Range(N("a"), N("b"), False, True)),
    ("[a, b]", ast.Range(N("a"), N("b"), True, True)),
    ("[a, b)", ast.Range(N("a"), N("b"), True, False)),
    ("{}", ast.SetLit(())),
    ("{a, b}", ast.SetLit((N("a"), N("b")))),
    ("{a to b}", ast.SetRange(N("a"), N("b"))),
    ("{x: nat}", ast.SetComprehension((ast.Decl("x", NAT),), None, None)),
    ("{x: nat | x > 1 @ x * 2}", ast.SetComprehension((ast.Decl("x", NAT),), Bin(">", N("x"), I(1)), Bin("*", N("x"), I(2)))),
    ("{x: nat @ x}", ast.SetComprehension((ast.Decl("x", NAT),), None, N("x"))),
    ("(| a, 1 |)", ast.TupleLit((N("a"), I(1)))),
    ("R(| f = 1, g = a |)", ast.RecordLit(N("R"), (ast.FieldValue("f", I(1)), ast.FieldValue("g", N("a"))))),
    ("[| 1, 2 |]", ast.VectorLit(((I(1), I(2)),))),
    ("[| 1, 2; 3, 4 |]", ast.VectorLit(((I(1), I(2)), (I(3), I(4))))),
    ("inverse(transpose(m))", ast.MatrixOp("inverse", ast.MatrixOp("transpose", N("m")))),
    ("since(C) > 1", Bin(">", ast.Since("C"), I(1))),
    ("sinceEntry(A::B) > 1", Bin(">", ast.SinceEntry(N("A", "B")), I(1))),
    ("result /\\ true \\/ false", Bin("\\/", Bin("/\\", ast.Keyword("result"), ast.BoolLit(True)), ast.BoolLit(False))),
    ("1.25 > 3", Bin(">", ast.RealLit("1.25"), I(3))),
]


@pytest.mark.parametrize("text, tree", ATOMS, ids=[t for t, _ in ATOMS])
def test_atoms(text, tree):
    assert condition(text) == tree


DOLLAR = [
    ("$e", ast.Dollar("e")),
    ("$ e ? x", ast.DollarInput("e", "x", None)),
    ("$e?x : p(x)", ast.DollarInput("e", "x", ast.Call(N("p"), (N("x"),)))),
    ("$e?x : (x > 1) /\\ b", Bin("/\\", ast.DollarInput("e", "x", Bin(">", N("x"), I(1))), N("b"))),
    ("$e.3", ast.DollarValue("e", I(3))),
    ("not $a \\/ $b", Bin("\\/", Not(ast.Dollar("a")), ast.Dollar("b"))),
    ("$x + 1 > cycle", Bin(">", Bin("+", ast.Dollar("x"), I(1)), ast.Keyword("cycle"))),
]


@pytest.mark.parametrize("text, tree", DOLLAR, ids=[t for t, _ in DOLLAR])
def test_robosim_dollar_expressions(text, tree):
    assert condition(text, "m.rst") == tree


def test_statements():
    assert action("a = 1 ; b = 2 <{ 3 } ; (c = 4 ; skip)") == ast.Seq(
        (
            ast.Assign(N("a"), I(1)),
            ast.StmtDeadline(ast.Assign(N("b"), I(2)), I(3)),
            ast.Seq((ast.Assign(N("c"), I(4)), ast.Skip())),
        )
    )
    assert action("r.f[1].g = x") == ast.Assign(ast.Field(ast.Index(ast.Field(N("r"), "f"), (I(1),)), "g"), N("x"))
    assert action("if c then op(1) else e!(x + 1) end") == ast.IfStmt(
        N("c"),
        ast.CallStmt(ast.Call(N("op"), (I(1),))),
        ast.Communicate(ast.Communication("e", "!", value=Bin("+", N("x"), I(1))), False),
    )
    assert action("e ; e.v ; e?x ; send e ; send e.1 ; wait(2) ; #C") == ast.Seq(
        (
            ast.Communicate(ast.Communication("e"), False),
            ast.Communicate(ast.Communication("e", ".", value=N("v")), False),
            ast.Communicate(ast.Communication("e", "?", var="x"), False),
            ast.Communicate(ast.Communication("e"), True),
            ast.Communicate(ast.Communication("e", ".", value=I(1)), True),
            ast.Wait(I(2)),
            ast.ClockReset("C"),
        )
    )
    assert action("$out!size(s) ; $out ; $out.v ; $op(1, 2) ; $x = 3 ; exec", "m.rst") == ast.Seq(
        (
            ast.DollarOutput("out", "!", ast.Call(N("size"), (N("s"),))),
            ast.DollarOutput("out", "", None),
            ast.DollarOutput("out", ".", N("v")),
            ast.DollarCall("op", (I(1), I(2))),
            ast.DollarAssign("x", I(3)),
            ast.Exec(),
        )
    )


def test_function_values_are_called_and_cast_to_any_type():
    """RoboTool's CallExp: the callee is any atom; 'as' and 'is' take a whole type (K2, K3)."""
    lam = ast.Binder("lambda", (ast.Decl("x", NAT),), None, Bin("+", N("x"), I(1)))
    assert condition("(lambda x: nat @ x + 1)(1) == 2") == Bin("==", ast.Call(lam, (I(1),)), I(2))
    cast = ast.Cast("as", ast.Call(N("override"), (N("f"), N("g"))), ast.FunctionType(ast.ProductType((NAT, NAT)), NAT))
    assert condition("(override(f, g) as (nat * nat) -> nat)(0, 1)") == ast.Call(cast, (I(0), I(1)))
    assert condition("x as nat -> nat") == ast.Cast("as", N("x"), ast.FunctionType(NAT, NAT))
    assert condition("r is A <-> B == b") == Bin("==", ast.Cast("is", N("r"), ast.RelationType(Ref("A"), Ref("B"))), N("b"))
    assert condition("f(1)(2)") == ast.Call(ast.Call(N("f"), (I(1),)), (I(2),))


def test_a_synchronisation_statement_carries_any_atom_or_call():
    """RoboTool's `value=CallExp` after '.' without 'send' (K13); a plain name stays `e.v`."""
    def sync(value: ast.Expr) -> ast.Communicate:
        return ast.Communicate(ast.Communication("e", ".", value=value), False)

    assert action("e.E::lit ; e . 3 ; e.(x + 1) ; e.E::c(1) ; e.f(x) ; e.v") == ast.Seq((
        sync(N("E", "lit")),
        sync(I(3)),
        sync(Bin("+", N("x"), I(1))),
        sync(ast.Call(N("E", "c"), (I(1),))),
        sync(ast.Call(N("f"), (N("x"),))),
        sync(N("v")),
    ))  # fmt: skip
    assert action("r.f = 1") == ast.Assign(ast.Field(N("r"), "f"), I(1))


def test_qualified_input_variables_and_empty_filters():
    """`e?P::x` (RoboTool: `[Variable|QualifiedName]`) and `e[||]` (an optional predicate)."""
    assert action("e?P::x ; send e[||]?x") == ast.Seq((
        ast.Communicate(ast.Communication("e", "?", "x", var_qualifier=("P",)), False),
        ast.Communicate(ast.Communication("e", "?", "x", filter=ast.Filter(None, None, None)), True),
    ))  # fmt: skip
    f = parse_text("stm S { transition t { from a to b trigger e [| |] ? P::Q::x } }")
    trigger = f.items[0].members[0].trigger
    assert trigger == ast.Communication("e", "?", "x", filter=ast.Filter(None, None, None), var_qualifier=("P", "Q"))
    assert (trigger.filter.span.column, trigger.filter.span.end_column) == (46, 51)  # [| |]


def test_a_communication_statement_takes_a_filter_without_send():
    """RoboTool's `'send'? Communication`: the filter does not need the keyword."""
    def comm(kind: str, var=None, value=None, predicate=None) -> ast.Communicate:
        return ast.Communicate(ast.Communication("e", kind, var, value, ast.Filter(None, None, predicate)), False)

    s = action("e[| x > 1 |]!x ; e[||]?y ; e [| p |] ; e[|q|].E::lit")
    assert s == ast.Seq((
        comm("!", value=N("x"), predicate=Bin(">", N("x"), I(1))),
        comm("?", var="y"),
        comm("", predicate=N("p")),
        comm(".", value=N("E", "lit"), predicate=N("q")),
    ))  # fmt: skip
    first = s.stmts[0]
    assert (first.span.column, first.span.end_column) == (43, 57)  # e[| x > 1 |]!x
    assert (first.comm.filter.span.column, first.comm.filter.span.end_column) == (44, 55)


def test_the_empty_tuple():
    """RoboTool's `'(|' (values+=Expression ...)? '|)'`: a tuple may have no component."""
    assert condition("(||) == (| |)") == Bin("==", ast.TupleLit(()), ast.TupleLit(()))
    empty = condition("(||) == x").left
    assert (empty.span.column, empty.span.end_column) == (46, 50)


def test_vector_and_matrix_sizes_are_atoms():
    f = parse_text("stm S { var v: vector(nat, (N)), m: matrix(real, P::K, (2)) }")
    v, m = (x.type for x in f.items[0].members[0].vars)
    assert v == ast.VectorType(NAT, N("N"))
    assert m == ast.MatrixType(Ref("real"), N("P", "K"), I(2))


DOLLAR_ATOMS = [
    # (statement, tree): $ forms are values of outputs, and names after $ may be qualified (K7)
    ("$Out1!$x", ast.DollarOutput("Out1", "!", ast.Dollar("x"))),
    ("$Out.$In", ast.DollarOutput("Out", ".", ast.Dollar("In"))),
    ("$I::e!$P::x", ast.DollarOutput("e", "!", ast.Dollar("x", ("P",)), ("I",))),
    ("$I::x = $v[2]", ast.DollarAssign("x", ast.Index(ast.Dollar("v"), (I(2),)), ("I",))),
    ("$P::op($r.f)", ast.DollarCall("op", (ast.DollarValue("r", N("f")),), ("P",))),
    ("x = $e?I::y : $ok", ast.Assign(N("x"), ast.DollarInput("e", "y", ast.Dollar("ok"), var_qualifier=("I",)))),
    ("x = f($a) + $b.$c", ast.Assign(N("x"), Bin("+", ast.Call(N("f"), (ast.Dollar("a"),)), ast.DollarValue("b", ast.Dollar("c"))))),
    # RoboTool's CallExp over a $ atom: a call of what $f denotes
    ("x = $f(1) + $P::g()", ast.Assign(N("x"), Bin("+", ast.Call(ast.Dollar("f"), (I(1),)), ast.Call(ast.Dollar("g", ("P",)), ())))),
    ("$Out!$f($x)", ast.DollarOutput("Out", "!", ast.Call(ast.Dollar("f"), (ast.Dollar("x"),)))),
]


@pytest.mark.parametrize("text, tree", DOLLAR_ATOMS, ids=[t for t, _ in DOLLAR_ATOMS])
def test_robosim_dollar_forms_are_atoms(text, tree):
    assert action(text, "m.rst") == tree


def test_transition_clauses():
    f = parse_text(
        "stm S { transition t { from a to b trigger e[| x = from | x != me |]?v #C # D <{ 5 } condition else action skip } }"
    )
    assert f.items[0].members[0] == ast.Transition(
        "t",
        "a",
        "b",
        trigger=ast.Communication(
            "e", "?", var="v", filter=ast.Filter("x", ast.Keyword("from"), Bin("!=", N("x"), N("me")))
        ),
        resets=(ast.ClockReset("C"), ast.ClockReset("D")),
        deadline=I(5),
        condition_else=True,
        action=ast.Skip(),
    )
    f = parse_text("stm S { transition t { from a to b exec condition $go action exec } }", "m.rst")
    assert f.items[0].members[0] == ast.Transition(
        "t", "a", "b", exec=True, condition=ast.Dollar("go"), action=ast.Exec()
    )
    f = parse_text("stm S { transition t { from p to b probability 0.25 } }")
    assert f.items[0].members[0].probability == ast.RealLit("0.25")


def test_declarations():
    f = parse_text(
        """
        type ID
        datatype R { a: nat b: Set(ID) }
        enumeration E { x y(nat, real) }
        interface I { op(a: nat, b: real) [terminates] event e: nat * boolean var v: nat = 1, w: real const k: nat clock C }
        function f(x: ?X): Seq(?X) { precondition true postcondition result == <x> }
        """
    )
    assert f.items == (
        ast.GivenType("ID"),
        ast.Record("R", (ast.FieldDecl("a", NAT), ast.FieldDecl("b", ast.SetType(Ref("ID"))))),
        ast.Enumeration("E", (ast.EnumLiteral("x"), ast.EnumLiteral("y", (NAT, Ref("real"))))),
        ast.Interface(
            "I",
            (
                ast.OpSig("op", (ast.Param("a", NAT), ast.Param("b", Ref("real"))), True),
                ast.EventDecl("e", ast.ProductType((NAT, Ref("boolean")))),
                ast.VarList(False, (ast.VarDecl("v", NAT, I(1)), ast.VarDecl("w", Ref("real")))),
                ast.VarList(True, (ast.VarDecl("k", NAT),)),
                ast.ClockDecl("C"),
            ),
        ),
        ast.FunctionDef(
            "f",
            (ast.Param("x", ast.TypeVar_("X")),),
            ast.SeqType(ast.TypeVar_("X")),
            (ast.Precondition(ast.BoolLit(True)), ast.Postcondition(Bin("==", ast.Keyword("result"), ast.SeqLit((N("x"),))))),
        ),
    )


def test_type_expressions():
    f = parse_text("stm S { var a: nat * Set(real) * ?X -> nat <-> boolean, b: vector(real, 3), c: matrix(int, n, 2), d: (nat -> nat) -> nat }")
    a, b, c, d = (v.type for v in f.items[0].members[0].vars)
    assert a == ast.FunctionType(
        ast.ProductType((NAT, ast.SetType(Ref("real")), ast.TypeVar_("X"))), ast.RelationType(NAT, Ref("boolean"))
    )
    assert b == ast.VectorType(Ref("real"), I(3))
    assert c == ast.MatrixType(Ref("int"), N("n"), I(2))
    assert d == ast.FunctionType(ast.FunctionType(NAT, NAT), NAT)


def test_module_and_connections():
    f = parse_text(
        """module M { rref p = q::P cref c = C
             connection p on e
               to c on f ( _async ) [ mult ]
             connection c on g to p on h }"""
    )
    module = f.items[0]
    assert module.members[:2] == (ast.Reference("p", "rref", N("q", "P")), ast.Reference("c", "cref", N("C")))
    assert module.members[2] == ast.Connection("p", "e", "c", "f", asynchronous=True, bidirectional=True)
    assert module.members[3] == ast.Connection("c", "g", "p", "h")
    assert [s.line for s in module.members[2].spans] == [2, 2, 3, 3]


def test_robosim_machine_parts():
    f = parse_text(
        "stm S { cycleDef cycle == 1 input context { uses I event e: nat requires J } output context { } initial i }",
        "m.rst",
    )
    assert f.items[0].members == (
        ast.CycleDef(Bin("==", ast.Keyword("cycle"), I(1))),
        ast.Context("input", (ast.InterfaceRef("uses", N("I")), ast.EventDecl("e", NAT), ast.InterfaceRef("requires", N("J")))),
        ast.Context("output", ()),
        ast.Initial("i"),
    )


def test_the_pulse_machine_of_the_corpus_has_the_expected_shape(repo_root):
    f = parse_file(repo_root / "tests" / "models" / "valid" / "pulse.rst")
    pulse = next(i for i in f.items if isinstance(i, ast.StateMachine))
    assert [type(m).__name__ for m in pulse.members] == [
        "CycleDef", "VarList", "Context", "Context", "Initial", "State", "State",
        "Transition", "Transition", "Transition", "Transition",
    ]  # fmt: skip
    run = pulse.members[6]
    assert run == ast.State(
        "Run",
        (
            ast.StateAction(
                "entry",
                ast.Seq((ast.Assign(N("k"), Bin("+", N("k"), I(1))), ast.DollarOutput("tick", "!", N("k")))),
            ),
        ),
    )
    assert pulse.members[9] == ast.Transition("t2", "Idle", "Idle", exec=True, condition=Not(ast.Dollar("go")))
    assert (run.span.line, run.span.column, run.span.end_line) == (25, 2, 25)


# ---------------------------------------------------------------------------- spans


def test_spans_cover_parentheses_and_keywords():
    text = "stm S { transition t { from a to b condition (x \\/ y) /\\ z action if (a) then skip end } }"
    f = parse_text(text)
    t = f.items[0].members[0]
    covered = lambda node: text[node.span.offset : node.span.end_offset]  # noqa: E731
    assert covered(t.condition) == "(x \\/ y) /\\ z"
    assert covered(t.condition.left) == "(x \\/ y)"
    assert covered(t.action) == "if (a) then skip end"
    assert covered(t) == text[8:-2]
    assert covered(f.items[0]) == text


def test_spans_of_empty_bodies():
    text = "package p\nstm S { }\nenumeration E { }\nstm T { state A { } transition t { from a to b action x = <> } }\noperation o() { }"
    f = parse_text(text)
    covered = lambda node: text[node.span.offset : node.span.end_offset]  # noqa: E731
    assert [covered(i) for i in f.items] == [
        "stm S { }", "enumeration E { }", "stm T { state A { } transition t { from a to b action x = <> } }", "operation o() { }",
    ]  # fmt: skip
    assert covered(f.items[2].members[0]) == "state A { }"
    assert covered(f.items[2].members[1].action.value) == "<>"
    assert covered(f) == text


# ---------------------------------------------------------------------------- syntax errors

SYNTAX_ERRORS = [
    # (text, line, column, message)
    ("stm S { var x: nat = }", 1, 22, "unexpected '}'; expected an expression"),
    (
        "stm S {\n  initial i",
        2,
        12,
        "unexpected end of file; expected one of '}', '_broadcast', 'clock', 'const', 'event', 'final', 'initial', "
        "'junction', ... (8 more)",
    ),
    ("stm S { initial i ~ }", 1, 19, "unexpected character '~'"),
    ("stm S { initial i \x07 }", 1, 19, "unexpected character U+0007"),
    ("stm state { }", 1, 5, "'state' is a reserved word and cannot be used as a name (write ^state to escape it)"),
    ("stm S { var x: nat initial i state A { entry if x > 1 then x = 1 } }", 1, 66, "unexpected '}'; expected 'end', ';' or 'else'"),
    ("stm S { var s: string = \"abc }", 1, 25, 'unterminated string: no closing " on this line'),
    ("stm S {\n/* never closed\n}", 2, 1, "unterminated comment: '/*' has no matching '*/'"),
    ("stm S { var x: real = .5 }", 1, 23, "unexpected '.'; expected an expression"),
    ("stm S { var x: Set nat }", 1, 20, "unexpected name 'nat'; expected '('"),
    ("datatype R { a: nat, b: nat }", 1, 20, "unexpected ','; expected '}' or a name"),
    ("module M { connection a on b to c }", 1, 35, "unexpected '}'; expected 'on'"),
    ("stm S { var x: nat = 1 var y: = 2 }", 1, 31, "unexpected '='; expected '(', '?', 'Seq', 'Set', 'matrix', 'vector' or a name"),
    ("interface I { event e }\nstm", 2, 4, "unexpected end of file; expected a name"),
    (
        "stm S { event e initial i state A { entry e!x + 1 } }",
        1,
        47,
        "unexpected '+'; expected one of '}', '(', '.', ';', '<{', '[', 'during', 'entry', ... (7 more)",
    ),
    ("stm S { var t: nat = (| 1, |) }", 1, 28, "unexpected '|)'; expected an expression"),
    ("stm S { var x: nat = 1 + 2 > }", 1, 30, "unexpected '}'; expected an expression"),
    ("stm S { var x: nat = x\n\n\t\t< }", 3, 5, "unexpected '}'; expected an expression"),
    (
        "stm S { transition t { from a to b trigger e exec } }",
        1,
        46,
        "unexpected name 'exec'; expected '}', '!', '#', '.', '<{', '?', '[|', 'action' or 'condition'",
    ),
]


@pytest.mark.parametrize("text, line, column, message", SYNTAX_ERRORS, ids=[m for *_, m in SYNTAX_ERRORS])
def test_syntax_error(text, line, column, message):
    assert syntax_errors(text) == [(line, column, message)]


def test_exec_is_robosim_only():
    assert syntax_errors("stm S { transition t { from a to b exec } }") == [
        (1, 36, "unexpected name 'exec'; expected '}', '#', '<{', 'action', 'condition', 'probability' or 'trigger'")
    ]


CLAUSE_ORDER = "the clauses of a transition come in this order: from, to, trigger (or exec, or probability), #clock resets, <{deadline}, condition, action"


def test_transition_clauses_out_of_order():
    with pytest.raises(RobogenError) as exc:
        parse_text("stm S {\n  transition t { from a to b\n    condition true\n    trigger e } }")
    (d,) = exc.value.diagnostics
    assert (d.span.line, d.span.column, d.message) == (4, 5, "unexpected 'trigger'; expected '}' or 'action'")
    assert [n.message for n in d.notes] == [CLAUSE_ORDER]
    assert syntax_errors("stm S { transition t { to b from a } }") == [(1, 24, "unexpected 'to'; expected 'from'")]
    assert syntax_errors("stm S { transition t { from a to b action skip condition true } }") == [
        (1, 48, "unexpected 'condition'; expected '}', ';' or '<{'")
    ]


def test_hints_for_operators_of_other_languages():
    def notes(text):
        with pytest.raises(RobogenError) as exc:
            parse_text(text)
        return [n.message for d in exc.value.diagnostics for n in d.notes]

    assert notes("stm S { var b: boolean = x || y }") == ["'or' is written \\/"]
    assert notes("stm S { var b: boolean = x && y }") == ["'and' is written /\\"]
    assert notes("stm S { var b: boolean = !x }") == ["negation is written 'not'"]
    assert notes("stm S { transition t { from a to b action x := 1 } }") == ["assignment is written '='"]
    assert notes("stm S { transition t { from a to b action x = 1; } }") == ["';' separates statements: there is none after the last one"]


def test_every_reserved_word_used_as_a_name_is_reported():
    assert syntax_errors("stm S { var state: nat, transition: nat }") == [
        (1, 13, "'state' is a reserved word and cannot be used as a name (write ^state to escape it)"),
        (1, 25, "'transition' is a reserved word and cannot be used as a name (write ^transition to escape it)"),
    ]


def test_a_syntax_error_renders_with_a_caret_under_the_token():
    assert rendered("stm S {\n\tinitial i\n\tstate A { entry x = = 1 }\n}") == (
        "m.rct:3:22: error: unexpected '='; expected an expression\n"
        "    3 |     state A { entry x = = 1 }\n"
        "      |                         ^"
    )
    assert rendered("stm S { var state: nat }") == (
        "m.rct:1:13: error: 'state' is a reserved word and cannot be used as a name (write ^state to escape it)\n"
        "    1 | stm S { var state: nat }\n"
        "      |             ^~~~~"
    )


def test_binary_content_is_reported_not_parsed():
    assert syntax_errors("stm S {\n  ab\x00cd }") == [(2, 5, "file contains NUL bytes; is it a binary file, not a model?")]


def nested_calls(depth: int) -> str:
    """`f(f(...f(1)...))`: ``depth`` calls, each inside the one before."""
    return "f(" * depth + "1" + ")" * depth


def test_nesting_deeper_than_the_limit_is_an_error_not_a_crash():
    # reported at the outermost call too deep: the fifth from the outside
    assert syntax_errors(f"stm S {{ var x: nat = {nested_calls(MAX_NESTING + 5)} }}") == [
        (1, 30, f"nested too deeply: robogen accepts at most {MAX_NESTING} levels of nested expressions, statements, types or states")
    ]
    states = "state A { " * (MAX_NESTING + 1) + "}" * (MAX_NESTING + 1)
    assert syntax_errors(f"stm S {{ {states} }}")[0][2].startswith("nested too deeply")
    parens = "(" * (MAX_NESTING + 1) + "1" + ")" * (MAX_NESTING + 1)
    assert syntax_errors(f"stm S {{ var x: nat = {parens} }}")[0][2].startswith("nested too deeply")
    right = "1 + (" * MAX_NESTING + "1" + ")" * MAX_NESTING  # each sum inside parentheses: two levels
    assert syntax_errors(f"stm S {{ var x: nat = {right} }}")[0][2].startswith("nested too deeply")
    parse_text(f"stm S {{ var x: nat = {nested_calls(MAX_NESTING)} }}")  # the limit itself is fine


FLAT = [
    # a flat chain of operators is one level of nesting, however long (only real nesting counts)
    " + ".join(f"x{i}" for i in range(1000)),
    " /\\ ".join(f"x{i} > {i}" for i in range(1000)),
    " \\/ ".join(f"a{i} /\\ b{i} == {i} + y * 2 - z" for i in range(1000)),
    "(" * (MAX_NESTING - 2) + " * ".join(["x"] * 1000) + ")" * (MAX_NESTING - 2) + " + 1" * 1000,
]


@pytest.mark.parametrize("text", FLAT, ids=["sum", "conjunction", "mixed levels", "chains at the limit"])
def test_a_flat_expression_of_a_thousand_operands_is_not_nested(text):
    e = condition(text)
    first, links = ast.chain(e)
    assert len(links) >= 999 and not isinstance(first, ast.Binary)
