"""Benchmark of robogen's front end (parse, resolve, check) on a large generated RoboSim model,
against Lark's own bare LALR parse of the same text in the same process.

The model is written in RoboTool's textual layout (one declaration or transition clause per
line, like the reference models): interfaces, a platform, many state machines (composite
states, junctions, exec transitions, $ inputs and outputs, software operations), a controller
and a module. The script checks that it has no errors, then prints:

  lines, lexical tokens per line,
  median of N runs of parse + check (robogen.semantics.check_texts), and lines/s,
  the medians of the parse alone (robogen.syntax.parser.parse_text: the fast driver of
  robogen.syntax.fastparse over Lark's tables) and of the check alone,
  the median of the same AST built by Lark's own LALR driver (the path of texts the fast
  driver hands back, those with syntax errors),
  median of N runs of Lark's bare parse (robogen.syntax.parser._parser(language).parse(text):
  LALR building a plain tree, no AST, no checks), and the ratios of parse + check and of the
  parse alone to it.

    python bench/bench_frontend.py [--lines N] [--runs N] [--profile]

Nothing is asserted against a time: the figures are printed for a person to read.
"""

from __future__ import annotations

import argparse
import cProfile
import gc
import os
import pstats
import re
import statistics
import sys
import time

from robogen.semantics import check_texts
from robogen.semantics.checker import check
from robogen.semantics.workspace import Workspace
from robogen.syntax.fastparse import FALLBACK
from robogen.syntax.parser import ROBOSIM, _fast_parser, _parser, parse_text, without_gc

PATH = "bench_model.rst"


# ---------------------------------------------------------------------------- the model


def _header() -> list[str]:
    return [
        "package bench",
        "",
        "datatype Reading {",
        "\tvalue: real",
        "\tvalid: boolean",
        "}",
        "",
        "enumeration Mode {",
        "\tidle",
        "\tbusy",
        "\tfailed",
        "}",
        "",
        "interface Sensors {",
        "\tevent sensor: nat",
        "\tevent reading: Reading",
        "\tevent stop",
        "}",
        "",
        "interface Reports {",
        "\tevent report: nat",
        "\tevent alarm",
        "}",
        "",
        "interface Actuators {",
        "\tmove(speed: real, turn: real)",
        "\thalt()",
        "}",
        "",
        "interface Tuning {",
        "\tvar gain: real = 1.5",
        "\tconst limit: nat = 10",
        "}",
        "",
        "robotic platform Robot {",
        "\tuses Sensors",
        "\tuses Reports",
        "\tprovides Actuators",
        "}",
        "",
    ]


def _operation(k: int) -> list[str]:
    return [
        f"operation adjust{k}(amount: real) {{",
        "\trequires Tuning",
        "\tinput context { }",
        "\toutput context {",
        "\t\trequires Actuators",
        "\t}",
        "\tinitial i",
        "\tfinal f",
        "\ttransition t {",
        "\t\tfrom i",
        "\t\tto f",
        "\t\taction gain = gain + amount ; $move(gain, 0.0)",
        "\t}",
        "}",
        "",
        f"interface Adjust{k} {{",
        f"\tadjust{k}(amount: real)",
        "}",
        "",
    ]


def _state(j: int, n: int) -> list[str]:
    """State S{j}: entry and exit actions, three exec transitions to or from it and a junction
    after it; every fifth state is composite, with the translation's EmptyCycle idiom inside.
    The last junction may also stop the machine."""
    lines = [f"\tstate S{j} {{"]
    if j % 5 == 4:
        lines += [
            "\t\tinitial ci",
            "\t\tstate EmptyCycle {",
            "\t\t}",
            "\t\ttransition tc0 {",
            "\t\t\tfrom ci",
            "\t\t\tto EmptyCycle",
            "\t\t}",
            "\t\ttransition tc1 {",
            "\t\t\tfrom EmptyCycle",
            "\t\t\tto EmptyCycle",
            "\t\t\tcondition not $stop",
            "\t\t\taction exec ; level = level * 0.5",
            "\t\t}",
        ]
    lines += [
        "\t\tentry count = count + 1 ; $report!count ; mode = Mode::busy",
        "\t\texit $move(level, 0.0)",
        "\t}",
    ]
    nxt = (j + 1) % n
    lines += [
        f"\ttransition t{j}go {{",
        f"\t\tfrom S{j}",
        f"\t\tto J{j}",
        "\t\texec",
        f"\t\tcondition $sensor?seen /\\ seen > {j % 7 + 1}",
        "\t\taction level = level + 0.25",
        "\t}",
        f"\ttransition t{j}stay {{",
        f"\t\tfrom S{j}",
        f"\t\tto S{j}",
        "\t\texec",
        f"\t\tcondition $sensor?seen /\\ seen <= {j % 7 + 1}",
        "\t\taction seen = 0",
        "\t}",
        f"\ttransition t{j}idle {{",
        f"\t\tfrom S{j}",
        f"\t\tto S{j}",
        "\t\texec",
        "\t\tcondition not $sensor",
        "\t}",
        f"\tjunction J{j}",
    ]
    proceed = "count < limit \\/ mode == Mode::idle"
    if j == n - 1:
        lines += [
            f"\ttransition t{j}stop {{",
            f"\t\tfrom J{j}",
            "\t\tto Stopped",
            "\t\tcondition $stop /\\ since(C) > 100 * cycle",
            "\t}",
        ]
        proceed = f"not ($stop /\\ since(C) > 100 * cycle) /\\ ({proceed})"
    lines += [
        f"\ttransition t{j}next {{",
        f"\t\tfrom J{j}",
        f"\t\tto S{nxt}",
        f"\t\tcondition {proceed}",
        "\t}",
        f"\ttransition t{j}reset {{",
        f"\t\tfrom J{j}",
        "\t\tto S0",
        "\t\tcondition else",
        "\t\taction count = 0 ; $alarm",
        "\t}",
    ]
    return lines


def _machine(k: int, states: int) -> list[str]:
    lines = [
        f"stm Machine{k} {{",
        "\tcycleDef cycle == 1",
        f"\trequires Adjust{k}",
        "\tvar count: nat = 0",
        "\tvar level: real = 0.0",
        "\tvar seen: nat",
        "\tvar mode: Mode = Mode::idle",
        "\tvar last: Reading",
        "\tclock C",
        "\tinput context {",
        "\t\tuses Sensors",
        "\t\trequires Tuning",
        "\t}",
        "\toutput context {",
        "\t\tuses Reports",
        "\t\trequires Actuators",
        "\t\trequires Tuning",
        "\t}",
        "\tinitial i",
    ]
    for j in range(states):
        lines += _state(j, states)
    lines += [
        "\ttransition t0 {",
        "\t\tfrom i",
        "\t\tto S0",
        "\t\taction #C",
        "\t}",
        "\tstate Stopped {",
        f"\t\tentry $halt() ; adjust{k}(-1.0)",
        "\t}",
        "\ttransition trestart {",
        "\t\tfrom Stopped",
        "\t\tto S0",
        "\t\texec",
        "\t\tcondition $reading?last /\\ last.valid",
        "\t}",
        "\ttransition twait {",
        "\t\tfrom Stopped",
        "\t\tto Stopped",
        "\t\texec",
        "\t\tcondition not ($reading?last /\\ last.valid)",
        "\t}",
        "}",
        "",
    ]
    return lines


def generate(target_lines: int, states: int = 20) -> str:
    lines = _header()
    k = 0
    machines: list[int] = []
    footer = 40
    while len(lines) + footer + 16 * len(machines) < target_lines:
        lines += _operation(k) + _machine(k, states)
        machines.append(k)
        k += 1
    lines += ["controller Control {", "\tcycleDef cycle == 1", "\tuses Sensors", "\tuses Reports", "\trequires Actuators",
              "\tprovides Tuning"]  # fmt: skip
    for k in machines:
        lines += [f"\topref op{k} = adjust{k}", f"\tsref m{k} = Machine{k}"]
    # an event end has one connection: the controller's events go to and come from the first machine
    lines += ["\tconnection Control on sensor to m0 on sensor", "\tconnection m0 on report to Control on report"]
    lines += [
        "}",
        "",
        "module System {",
        "\tcycleDef cycle == 1",
        "\trref robot = Robot",
        "\tcref control = Control",
        "\tconnection robot on sensor to control on sensor ( _async )",
        "\tconnection control on report to robot on report ( _async )",
        "}",
    ]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- measuring

_TOKEN = re.compile(r"::\*|::|<->|->|=>|\\/|/\\|==|!=|<=|>=|\[\||\|\]|\(\||\|\)|<\{|[0-9]+\.[0-9]+|\w+|\S")


def tokens(text: str) -> int:
    """Lexical tokens (comments removed; multi-character operators count once)."""
    text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", text, flags=re.S)
    return len(_TOKEN.findall(text))


CPU: dict[int, float] = {}  # id(fn) -> median CPU time of the process, beside the wall time


def median_time(fn, runs: int) -> float:
    """Median wall time of ``runs`` calls (the median CPU time of this process is kept in CPU:
    on a shared machine it is the steadier figure)."""
    times, cpu = [], []
    for _ in range(runs):
        gc.collect()
        start, start_cpu = time.perf_counter(), time.process_time()
        fn()
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    CPU[id(fn)] = statistics.median(cpu)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--lines", type=int, default=20_000, help="size of the generated model (default 20000)")
    parser.add_argument("--runs", type=int, default=7, help="runs per measurement (median; default 7)")
    parser.add_argument("--profile", action="store_true", help="also print a cProfile of one parse + check")
    args = parser.parse_args()

    text = generate(args.lines)
    n_lines = text.count("\n")
    n_tokens = tokens(text)
    model = check_texts({PATH: text})
    if model.errors:
        for d in model.errors[:10]:
            print(d.render(), file=sys.stderr)
        print(f"the generated model has {len(model.errors)} errors", file=sys.stderr)
        return 1
    fast = _fast_parser(ROBOSIM)  # tables loaded before timing
    lark, transformer = fast.lark, fast.lark.options.transformer
    bare = _parser(ROBOSIM)
    transformer.begin(PATH, text)
    fast_used = fast.parse(text) is not FALLBACK
    transformer.end()

    def lark_ast():
        with without_gc():
            transformer.begin(PATH, text)
            lark.parse(text)
            transformer.end()

    load = os.getloadavg()[0]
    full_fn = lambda: check_texts({PATH: text})  # noqa: E731
    bare_fn = lambda: bare.parse(text)  # noqa: E731
    full = median_time(full_fn, args.runs)
    parse_fn = lambda: parse_text(text, PATH)  # noqa: E731
    parsed = median_time(parse_fn, args.runs)
    tree = parse_text(text, PATH)
    checked = median_time(lambda: check(Workspace([tree])), args.runs)
    lark_driver = median_time(lark_ast, args.runs)
    lark = median_time(bare_fn, args.runs)

    print(f"model: {n_lines} lines, {n_tokens} tokens ({n_tokens / n_lines:.2f} tokens/line), "
          f"{len(model.scopes)} machines and operations, 0 errors, {len(model.warnings)} warnings")  # fmt: skip
    print(f"runs: {args.runs} (medians); load average {load:.2f} at the start, {os.getloadavg()[0]:.2f} at the end")
    print(f"robogen parse + check: {full * 1000:8.1f} ms  {n_lines / full:10,.0f} lines/s"
          f"  (CPU {CPU[id(full_fn)] * 1000:.1f} ms, {n_lines / CPU[id(full_fn)]:,.0f} lines/s)")  # fmt: skip
    print(f"  parse (AST built during the LALR parse, {'fast driver' if fast_used else 'Lark driver: FAST PATH NOT USED'}): "
          f"{parsed * 1000:8.1f} ms")  # fmt: skip
    print(f"  check (resolution, types, rules, analyses): {checked * 1000:8.1f} ms")
    print(f"the same AST by Lark's own LALR driver (texts with syntax errors): {lark_driver * 1000:8.1f} ms")
    print(f"Lark bare LALR parse (plain tree): {lark * 1000:8.1f} ms  {n_lines / lark:10,.0f} lines/s"
          f"  (CPU {CPU[id(bare_fn)] * 1000:.1f} ms)")  # fmt: skip
    print(f"ratio parse + check / bare Lark parse: {full / lark:.2f} (CPU {CPU[id(full_fn)] / CPU[id(bare_fn)]:.2f})")
    print(f"ratio parse / bare Lark parse: {parsed / lark:.2f} (CPU {CPU[id(parse_fn)] / CPU[id(bare_fn)]:.2f})")
    print(f"target 20,000 lines/s for parse + check: {'met' if n_lines / full >= 20_000 else 'NOT met'}")

    if args.profile:
        profile = cProfile.Profile()
        profile.enable()
        check_texts({PATH: text})
        profile.disable()
        pstats.Stats(profile).sort_stats("cumulative").print_stats(30)
    return 0


if __name__ == "__main__":
    sys.exit(main())
