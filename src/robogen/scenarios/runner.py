"""``robogen test FILES_OR_FOLDERS [--junit report.xml] [--results DIR]``: scenarios as tests.

Every scenario file given, and every ``*.toml`` with ``[[expect]]`` in a folder given (searched
recursively), is run on its model (``model = ...`` in the file, built with its ``[options]``,
cached) and its expectations checked (:mod:`robogen.scenarios.expect`). One line per expectation,
located at its ``[[expect]]`` in the scenario file, ``PASS`` or ``FAIL`` with what was found; a
scenario that cannot run (a bad file, a model with errors) is reported with its located errors.
Then a table: per scenario, the expectations passed and failed, the errors and the time.

Exit status: 0 when every expectation of every scenario holds, 1 otherwise (a failure or an
error), 2 for a usage error.
"""

from __future__ import annotations

import argparse
import sys
import time
import tomllib
from datetime import datetime, timezone
from pathlib import Path

from robogen.diagnostics import RobogenError, SourceMap, Span, render_all
from robogen.outputs import output_file
from robogen.scenarios import junit


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("paths", nargs="+", metavar="FILE_OR_FOLDER", help="scenario files, or folders searched for them")
    parser.add_argument("--junit", metavar="REPORT.xml", help="also write the outcomes as JUnit XML (for CI systems)")
    parser.add_argument("--results", metavar="DIR", help="keep each scenario's results CSV and events log in DIR")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--reference", action="store_true",
                       help="run the scenarios on the reference interpreter (robogen.ir.interp) instead of the FMUs")
    which.add_argument("--compare", action="store_true",
                       help="run each scenario on the FMU and on the reference interpreter; report the first difference")


def scenario_files(paths: list[str]) -> list[Path]:
    """The scenario files to run: those named, and those with [[expect]] in the folders named."""
    found: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            found += [f for f in sorted(p.rglob("*.toml")) if _has_expectations(f)]
        elif p.is_file():
            found.append(p)
        else:
            raise RobogenError.at(f"no such file or folder: {p}", Span.of_path(str(p)))
    if not found:
        raise RobogenError.at(f"no scenario with expectations ([[expect]]) in {', '.join(paths)}", Span.of_path(paths[0]))
    return list(dict.fromkeys(found))


def _has_expectations(path: Path) -> bool:
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return True  # run it: its error is reported where it is
    return "expect" in data and "instances" not in data


def run_one(path: Path, results: Path | None, how: str = "fmu") -> junit.Suite:
    """Run the scenario at ``path`` and check its expectations; print a line for each. ``how``:
    "fmu", "reference" (the reference interpreter) or "compare" (both; one more expectation: the
    two runs agree)."""
    from robogen.cosim.scenario import load_scenario
    from robogen.scenarios.build import model_fmu
    from robogen.scenarios.expect import Outcome, check, expectations
    from robogen.scenarios.run import INSTANCE, fmu_description, model_options, model_paths, run_scenario

    started = time.perf_counter()
    suite = junit.Suite(str(path), str(path.parent), datetime.now(timezone.utc))
    try:
        scenario = load_scenario(path)
        paths = model_paths(scenario, None)
        md = fmu_description(model_fmu(paths, model_options(scenario, None)).fmu)
        expected = expectations(scenario, md)
        if not expected:
            raise RobogenError.at("the scenario has no expectations: add [[expect]] entries", Span.point(str(path)))
    except RobogenError as exc:
        return _error(suite, exc, "the scenario cannot run", started)
    output = events = None
    if results is not None:
        results.mkdir(parents=True, exist_ok=True)
        output, events = results / f"{path.stem}.csv", results / f"{path.stem}.events.jsonl"
    try:
        done = run_scenario(path, paths, output=output, events=events, keep_rows=True, warn=lambda d: None,
                            reference=how == "reference")
        outcomes = [Outcome(None, True, "", Span.point(str(path)), "the run ends without error")]
        outcomes += check(expected, done.result, INSTANCE)
        if how == "compare":
            outcomes.append(_compare(path, paths, done))
    except RobogenError as exc:
        message = "; ".join(d.message for d in exc.diagnostics)
        outcomes = [Outcome(None, False, message, Span.point(str(path)), "the run ends without error")]
        outcomes += [Outcome(e, False, "not checked: the run failed", e.span, e.text) for e in expected]
    seconds = time.perf_counter() - started
    for o in outcomes:
        line = f"{o.span}: {'PASS' if o.passed else 'FAIL'}  {o.text}" + ("" if o.passed else f": {o.detail}")
        print(line)
        suite.output += line + "\n"
        suite.cases.append(junit.Case(f"{o.span.line}: {o.text}", seconds / len(outcomes),
                                      None if o.passed else f"{o.text}: {o.detail}", detail=line))
    suite.seconds = seconds
    return suite


def _compare(path: Path, paths: list[str], done):
    """The outcome of running the scenario on the reference interpreter too: the rows agree."""
    from robogen.scenarios.expect import Outcome
    from robogen.scenarios.reference import first_difference
    from robogen.scenarios.run import run_scenario

    text = "the FMU and the reference interpreter give the same results"
    try:
        other = run_scenario(path, paths, keep_rows=True, warn=lambda d: None, reference=True)
    except RobogenError as exc:
        return Outcome(None, False, "the reference interpreter's run failed: " + "; ".join(d.message for d in exc.diagnostics),
                       Span.point(str(path)), text)
    found = first_difference(done.result.columns, done.result.rows, other.result.rows)
    return Outcome(None, found is None, found or "", Span.point(str(path)), text)


def _error(suite: junit.Suite, exc: RobogenError, what: str, started: float) -> junit.Suite:
    text = render_all(exc.diagnostics, SourceMap())
    print(text, file=sys.stderr)
    first = exc.diagnostics[0]
    suite.seconds = time.perf_counter() - started
    suite.cases.append(junit.Case(what, suite.seconds, error=f"{first.span}: {first.message}" if first.span else first.message,
                                  detail=text))
    print(f"{suite.name}: ERROR  {what}")
    return suite


def table(suites: list[junit.Suite]) -> str:
    """Per scenario: the expectations passed and failed, the errors (the times are in the JUnit
    report: the table is the same from run to run)."""
    rows = [("scenario", "passed", "failed", "errors")]
    for s in suites:
        failed = sum(c.failure is not None for c in s.cases)
        errors = sum(c.error is not None for c in s.cases)
        rows.append((s.name, str(len(s.cases) - failed - errors), str(failed), str(errors)))
    totals = [sum(int(r[i]) for r in rows[1:]) for i in (1, 2, 3)]
    rows.append(("total", *map(str, totals)))
    width = [max(len(r[i]) for r in rows) for i in range(4)]
    return "\n".join("  ".join(c.ljust(width[i]) if i == 0 else c.rjust(width[i]) for i, c in enumerate(r)).rstrip()
                     for r in rows)


def run(args: argparse.Namespace) -> int:
    files = scenario_files(args.paths)
    results = Path(args.results) if args.results else None
    how = "reference" if args.reference else "compare" if args.compare else "fmu"
    suites = [run_one(path, results, how) for path in files]
    print(table(suites))
    if args.junit:
        print(f"wrote {junit.write(output_file(args.junit, inputs=files, option='--junit'), suites)}", file=sys.stderr)
    bad = any(c.failure is not None or c.error is not None for s in suites for c in s.cases)
    return 1 if bad else 0
