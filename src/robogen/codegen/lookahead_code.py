"""The look-ahead of a RoboChart FMU compiled with ``--time skip``, as C (robogen.ir.lookahead).

For machine i, ``rg_wake_<i>(inst)`` gives the number of tocks from the last one counted to the
first at which the machine may do something (at least 1; ``RG_NEVER`` for none until an event
comes). At each resume point that can be looked ahead of, a probe (``rg_probe_<i>_<b>``) evaluates
the block's tests one tock from now, and each atom (``rg_atom_<i>_<j>``: a comparison of a
monotone function of time with a value that does not depend on time) gives its outcome -1, 0, 1 k
tocks from now, for the search of robogen_machine.h's ``rg_first_change``. Expressions are the
machine's own, emitted by its :class:`~robogen.codegen.c.Emitter` with the machine's tick count
and wait counter shifted for the evaluation and restored after it.
"""

from __future__ import annotations

from robogen.codegen.c import Emitter, c_comment
from robogen.codegen.cnames import ctype
from robogen.ir import model as ir
from robogen.ir.dump import expr as show
from robogen.ir.lookahead import lookaheads


def lookahead_code(fmu: ir.Fmu, em: Emitter, line_comments: bool) -> list[str]:
    """The C functions of machine ``em.m``'s look-ahead, ``rg_wake_<i>`` last."""
    m, i = em.m, em.m.index
    found = lookaheads(m)
    atoms: dict[ir.Bin, int] = {}
    functions: list[str] = []
    cases: list[str] = []
    for b, la in found.items():
        block = m.blocks[b]
        where = f" ({fmu.place(block.span)})" if line_comments and block.span is not None else ""
        functions.append(_probe(em, b, la.tests, f"b{b}: {block.label}{where}"))
        lines = [f"    case {b}: /* the resume point b{b}, {c_comment(block.label)} */",
                 f"        if (rg_probe_{i}_{b}(inst)) return 1;"]
        for a in la.atoms:
            if a not in atoms:
                atoms[a] = len(atoms)
                functions.append(_atom(em, atoms[a], a))
            lines.append(f"        wake = rg_first_change(inst, rg_atom_{i}_{atoms[a]}, wake);")
        lines.append("        break;")
        cases += lines
    functions.append("\n".join([
        f"/* Tocks from the last one counted to the first at which {c_comment(m.name)} may do something (at least 1),",
        " * RG_NEVER if none comes before an event (robogen.ir.lookahead). */",
        f"static uint64_t rg_wake_{i}(rg_instance *inst)",
        "{",
        f"    rg_machine_{i} *m = &inst->s.data.m{i};",
        "    uint64_t wake = RG_NEVER;",
        "    if (m->in_cycle) return 1;",
        "    switch (m->pc) {",
        *cases,
        "    default: /* a resume point that cannot be looked ahead of: it runs at every tock */",
        "        return 1;",
        "    }",
        "    return rg_lookahead_fault(&inst->s.data) ? 1 : wake;",
        "}",
    ]))
    return functions


def _prologue(i: int, k: str) -> list[str]:
    return [
        "    rg_model_data *d = &inst->s.data;",
        f"    rg_machine_{i} *m = &d->m{i};",
        f"    rg_tock_shift saved = rg_shift_tocks(&m->ticks, &m->wait_left, {k});",
    ]


def _probe(em: Emitter, b: int, tests: tuple[ir.Expr, ...], what: str) -> str:
    i = em.m.index
    lines = [f"/* {c_comment(what)}: is a test true one tock from now (or in error)? */",
             f"static bool rg_probe_{i}_{b}(rg_instance *inst)", "{", *_prologue(i, "1"), "    bool any = false;"]
    for t in tests:
        lines.append(f"    any = any || ({em.expr(t)});  /* {c_comment(show(t))} */")
    lines += ["    rg_unshift_tocks(&m->ticks, &m->wait_left, saved);",
              "    return rg_lookahead_fault(d) || any;", "}"]
    return "\n".join(lines)


def _atom(em: Emitter, j: int, a: ir.Bin) -> str:
    i = em.m.index
    t = ctype(a.left.type)
    return "\n".join([
        f"/* {c_comment(show(a))}: how its sides compare k tocks from now (-1, 0, 1) */",
        f"static int rg_atom_{i}_{j}(rg_instance *inst, uint64_t k)", "{", *_prologue(i, "k"),
        f"    {t} left = {em.expr(a.left)};",
        f"    {t} right = {em.expr(a.right)};",
        "    rg_unshift_tocks(&m->ticks, &m->wait_left, saved);",
        "    (void)d;",
        "    return (left > right) - (left < right);",
        "}",
    ])


__all__ = ["lookahead_code"]
