"""robogen against RoboTool's own test corpus (a local checkout of UoY-RoboStar/robochart-tests).

Each project folder of ``robochart/``, ``robosim/`` and ``robochart-fail/`` is one workspace: all
its model files are loaded together, as RoboTool's integration test loads a project. For every
workspace the script runs robogen's check in-process (``robogen.semantics.check_paths``); with
``--package``, every workspace that checks with 0 errors is also packaged, one FMU per module (or,
when it has no module, per state machine; when it has neither, once without a name, to record what
robogen says, and the workspace is counted apart as having nothing to package) into a temporary
folder and validated (``robogen.codegen.api.package_model``). Where the only errors are functions
the model declares without a body, the script gives them one (returning their type's zero) in a
``--functions`` file, as a user would, retries, and counts those targets apart. A ``RobogenError`` is a located user
error (its first message is recorded); any other exception is an internal error, i.e. a robogen bug.

Each workspace runs in its own subprocess with a time limit, so a hang or a crash costs one row.

What RoboTool expects: with ``--robotool-tests FILE`` (RoboTool's ``IntegrationTest.xtend``) the
expectation of each listed project is read from that file at run time: "ok" (no errors) or the
exact error messages, the model file and the element class they must be reported on. Projects it
does not list default to "ok" under robochart/ and robosim/ and "fail" under robochart-fail/.

A failing project counts as rejected "with the right rule" when some robogen error in the file
RoboTool names mentions every name that RoboTool's message names (quoted names, or else its
identifiers that are not all lower case: events, machines, operations), either in the message or
on the reported source line, and, for connection/transition errors, sits on such a line.

    python bench/robotool_corpus.py PATH_TO_robochart-tests [--package] [--jobs N] [--json OUT]
        [--robotool-tests IntegrationTest.xtend] [--timeout SECONDS] [--only SUBSTRING]

Nothing is asserted: the table and summary are for a person (or the JSON for a script) to read.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import traceback
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

GROUPS = ("robochart", "robosim", "robochart-fail")
ELEMENT_KEYWORDS = {"CONNECTION": "connection", "TRANSITION": "transition"}


# ---------------------------------------------------------------------------- RoboTool's expectations


def read_expectations(path: Path) -> dict[str, dict]:
    """workspace ('group/name') -> {'ok': bool, 'errors': [{'file', 'element', 'message'}]}."""
    text = path.read_text(encoding="utf-8")
    out: dict[str, dict] = {}
    for body in re.split(r"@Test\b", text)[1:]:
        body = re.split(r"\bdef\b", body)[1]  # the test method only, not the helpers after it
        where = re.search(r'top_dir\s*\+\s*"([^"]+)"', body)
        if not where:
            continue
        strings = dict(re.findall(r'val\s+(\w+)\s*=\s*"((?:[^"\\]|\\.)*)"', body))
        errors = []
        for call in re.findall(r"TestRoboChartModelError\(([^)]*)\)", body):
            args = [a.strip() for a in call.split(",")]
            element = args[2].split(".")[-1]
            for arg in args[3:]:
                if arg.startswith('"'):
                    continue  # an Xtext issue code, e.g. ...Diagnostic.Linking
                errors.append({"file": strings.get(args[1], args[1]), "element": element,
                               "message": strings.get(arg, arg)})
        if errors or "TestRoboChartModel(dir)" in body:
            out[where.group(1)] = {"ok": not errors, "errors": errors}
    return out


def key_names(message: str) -> list[str]:
    quoted = re.findall(r"(?<!\w)'([^'\s]+)'", message)  # not the ' of "Couldn't"
    if quoted:
        return quoted
    words = re.findall(r"[A-Za-z_]\w*", message)
    return sorted({w for w in words if w != w.lower()})


def names_the_same(expected: dict, err: dict) -> bool:
    """A robogen error in RoboTool's file that names what RoboTool's message names."""
    if Path(err["path"] or "").name != expected["file"]:
        return False
    keyword = ELEMENT_KEYWORDS.get(expected["element"])
    if keyword and keyword not in err["line_text"]:
        return False
    text = err["message"] + " " + err["line_text"]
    return all(re.search(rf"\b{re.escape(k)}\b", text) for k in key_names(expected["message"]))


def right_rule(expected: list[dict], errors: list[dict]) -> bool:
    """Every error RoboTool expects has a matching robogen error."""
    return all(any(names_the_same(exp, err) for err in errors) for exp in expected)


# ---------------------------------------------------------------------------- one workspace (subprocess)


def _located(diag) -> dict:
    span = diag.span
    line_text = ""
    if span is not None:
        try:
            line_text = Path(span.path).read_text(encoding="utf-8").splitlines()[span.line - 1].strip()
        except (OSError, IndexError, UnicodeDecodeError):
            pass
    where = f"{span.path}:{span.line}:{span.column}: " if span is not None else ""
    return {"path": span.path if span else None, "message": diag.message, "line_text": line_text,
            "text": where + diag.message}


def _internal(exc: BaseException) -> str:
    frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    at = f" [{Path(frame.filename).name}:{frame.lineno}]" if frame else ""
    return f"{type(exc).__name__}: {exc}{at}"


_MUST_DEFINE = "the file must define: "


def _package(workspace: str, tmp: Path, entry: dict, **target) -> None:
    """package_model, and where the only errors are functions the model leaves without a body,
    again with a --functions file that gives each one a body returning the zero of its type: the
    user's part, as the issue's measure allows (``entry["functions"]`` names them)."""
    from robogen.codegen.api import package_model
    from robogen.codegen.generate import CodegenOptions
    from robogen.diagnostics import RobogenError

    try:
        package_model([workspace], tmp / "out.fmu", **target)
        return
    except RobogenError as exc:
        notes = [n.message for d in exc.diagnostics for n in d.notes if n.message.startswith(_MUST_DEFINE)]
        if not notes or len(notes) != len(exc.diagnostics):
            raise
        prototypes = [n[len(_MUST_DEFINE):].removesuffix(" { ... }") for n in notes]
    (tmp / "functions.c").write_text("".join(_zero_body(p) for p in prototypes), encoding="utf-8")
    package_model([workspace], tmp / "out.fmu", codegen=CodegenOptions(functions=tmp / "functions.c"), **target)
    entry["functions"] = [p.split("rg_user_", 1)[1].split("(", 1)[0] for p in prototypes]


def _zero_body(prototype: str) -> str:
    """``static T rg_user_f(A a, B b)`` with a body that uses its parameters and returns T's zero."""
    result = prototype.removeprefix("static ").split(" rg_user_", 1)[0]
    params = prototype.split("(", 1)[1].rstrip(")")
    uses = "".join(f" (void){p.split()[-1]};" for p in params.split(", ") if p != "void")
    return f"{prototype}\n{{{uses} static {result} zero; return zero; }}\n"


def run_workspace(workspace: str, package: bool) -> dict:
    """Check (and package) one workspace; the path is relative to the current directory."""
    from robogen.ir.boundary import boundaries
    from robogen.diagnostics import RobogenError
    from robogen.semantics import check_paths

    result: dict = {"workspace": workspace, "errors": [], "warnings": 0, "internal": None, "package": []}
    started = time.perf_counter()
    try:
        model = check_paths([workspace])
    except RobogenError as exc:
        result["errors"] = [_located(d) for d in exc.diagnostics]
        return result
    except Exception as exc:  # noqa: BLE001 - any other exception is a robogen bug
        result["internal"] = "check: " + _internal(exc)
        return result
    result["errors"] = [_located(d) for d in model.errors]
    result["warnings"] = len(model.warnings)
    result["check_seconds"] = round(time.perf_counter() - started, 3)
    if not package or model.errors:
        return result
    modules, machines = boundaries(model)  # each named by a label that selects it alone
    targets = [("module", m.label) for m in modules]
    if not targets:
        targets = [("machine", s.label) for s in machines]
    for kind, name in targets or [("default", None)]:  # nothing to name: let robogen say what it does
        entry = {"kind": kind, "name": name or "(no module or machine)", "status": "ok", "message": ""}
        with tempfile.TemporaryDirectory(prefix="robotool-corpus-") as tmp:
            try:
                _package(workspace, Path(tmp), entry, **({kind: name} if name else {}))
            except RobogenError as exc:
                first = exc.diagnostics[0] if exc.diagnostics else None
                # a workspace without a module or a machine (only types, functions, operations)
                # has nothing to package: counted apart, with robogen's message
                entry.update(status="error" if name else "nothing", message=_located(first)["text"] if first else str(exc))
            except Exception as exc:  # noqa: BLE001
                entry.update(status="internal", message=_internal(exc))
            entry["message"] = entry["message"].replace(tmp, "<tmp>")  # stable across runs
        result["package"].append(entry)
    return result


# ---------------------------------------------------------------------------- the driver


def discover(root: Path) -> list[str]:
    found = []
    for group in GROUPS:
        base = root / group
        if base.is_dir():
            found += [f"{group}/{p.name}" for p in sorted(base.iterdir(), key=lambda p: p.name.lower()) if p.is_dir()]
    return found


def run_isolated(root: Path, workspace: str, package: bool, timeout: float) -> dict:
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", workspace] + (["--package"] if package else [])
    try:
        done = subprocess.run(cmd, check=False, cwd=root, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"workspace": workspace, "errors": [], "warnings": 0, "package": [],
                "internal": f"timeout after {timeout:g} s"}
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        tail = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return {"workspace": workspace, "errors": [], "warnings": 0, "package": [],
                "internal": f"worker exit {done.returncode}: {tail}"}
    return json.loads(lines[-1])


def expectation(workspace: str, listed: dict[str, dict]) -> dict:
    if workspace in listed:
        return dict(listed[workspace], listed=True)
    return {"ok": not workspace.startswith("robochart-fail/"), "errors": [], "listed": False}


def clip(text: str, width: int) -> str:
    text = " ".join(text.split())
    return text if len(text) <= width else text[: width - 1] + "…"


def report(rows: list[dict], package: bool, listed: bool) -> None:
    """One line per workspace; file paths are shown relative to the workspace."""
    print(f"{'workspace':46} {'RoboTool':12} {'robogen check':100} {'package' if package else ''}".rstrip())
    for r in rows:
        exp, here = r["expect"], r["workspace"] + "/"
        want = ("expect ok" if exp["ok"] else "expect fail") + ("*" if listed and not exp["listed"] else "")
        if r["internal"]:
            got = "INTERNAL " + r["internal"]
        else:
            got = f"{len(r['errors'])}E {r['warnings']}W" + (f" {r['errors'][0]['text']}" if r["errors"] else "")
        pkg = ""
        if r["package"]:
            good = sum(p["status"] == "ok" for p in r["package"])
            bad = next((p for p in r["package"] if p["status"] != "ok"), None)
            pkg = f"{good}/{len(r['package'])}" + (f" {bad['status']}: {bad['name']}: {bad['message']}" if bad else "")
            given = sorted({f for p in r["package"] for f in p.get("functions", ())})
            pkg += f" (--functions: {', '.join(given)})" if given else ""
        print(f"{r['workspace']:46} {want:12} {clip(got.replace(here, ''), 100):100} {clip(pkg.replace(here, ''), 200)}".rstrip())
        for e in exp["errors"]:
            print(f"{'':46} {'':12} RoboTool: {e['file']} {e['element']}: {e['message']}")
    if listed:
        print("* not named in IntegrationTest.xtend; expectation from the folder")


def summarise(rows: list[dict], package: bool) -> dict:
    valid = [r for r in rows if r["expect"]["ok"]]
    fail = [r for r in rows if not r["expect"]["ok"]]
    checked = [r for r in valid if not r["errors"] and not r["internal"]]
    rejected = [r for r in fail if r["errors"]]
    right = [r for r in rejected if r["expect"]["errors"] and right_rule(r["expect"]["errors"], r["errors"])]
    s = {"valid": len(valid), "valid_checked": len(checked), "fail": len(fail), "fail_rejected": len(rejected),
         "fail_right_rule": len(right), "workspaces_with_internal_errors": sum(
             bool(r["internal"]) or any(p["status"] == "internal" for p in r["package"]) for r in rows)}
    if package:
        def packaged(r: dict) -> bool:
            return bool(r["package"]) and all(p["status"] == "ok" for p in r["package"])

        nothing = [r for r in checked if r["package"] and all(p["status"] == "nothing" for p in r["package"])]
        checked = [r for r in checked if r not in nothing]
        targets = [p for r in checked for p in r["package"]]
        accepted_fail = [r for r in fail if not r["errors"] and not r["internal"]]
        s.update(package_workspaces=len(checked), package_workspaces_ok=sum(map(packaged, checked)),
                 package_targets=len(targets), package_targets_ok=sum(p["status"] == "ok" for p in targets),
                 package_internal=sum(p["status"] == "internal" for r in rows for p in r["package"]),
                 fail_accepted_and_packaged=sum(map(packaged, accepted_fail)), package_nothing=len(nothing),
                 package_targets_with_functions=sum(p["status"] == "ok" and bool(p.get("functions")) for p in targets))
    print()
    print(f"valid workspaces that check with 0 errors: {s['valid_checked']}/{s['valid']}")
    print(f"failing projects rejected: {s['fail_rejected']}/{s['fail']}, with RoboTool's rule: {s['fail_right_rule']}/{s['fail']}")
    if package:
        pct = 100 * s["package_workspaces_ok"] / max(1, s["package_workspaces"])
        print(f"valid workspaces that check and whose every module packages and validates: "
              f"{s['package_workspaces_ok']}/{s['package_workspaces']} ({pct:.0f}%); "
              f"their modules/machines: {s['package_targets_ok']}/{s['package_targets']}")
        print(f"valid workspaces that check and have nothing to package (no module, no state machine): {s['package_nothing']}")
        print(f"modules/machines that package only with a --functions file for functions the model leaves without a body: "
              f"{s['package_targets_with_functions']}")
        print(f"failing projects robogen accepts that also package: {s['fail_accepted_and_packaged']}; "
              f"internal errors while packaging: {s['package_internal']}")
    print(f"workspaces with an internal error (check, package or worker): {s['workspaces_with_internal_errors']}")
    return s


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("root", nargs="?", help="a checkout of UoY-RoboStar/robochart-tests")
    p.add_argument("--package", action="store_true", help="package every module of workspaces that check")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="workspaces run at once")
    p.add_argument("--json", metavar="OUT", help="write every result (all messages) as JSON")
    p.add_argument("--robotool-tests", metavar="FILE", help="RoboTool's IntegrationTest.xtend")
    p.add_argument("--timeout", type=float, default=900.0, help="seconds per workspace (default 900)")
    p.add_argument("--only", metavar="SUBSTRING", help="only workspaces whose name contains this")
    p.add_argument("--worker", metavar="WORKSPACE", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        print(json.dumps(run_workspace(args.worker, args.package)))
        return 0
    if not args.root:
        p.error("the path to robochart-tests is required")
    root = Path(args.root).resolve()
    workspaces = [w for w in discover(root) if not args.only or args.only in w]
    if not workspaces:
        p.error(f"no project folders under {root}/{{{','.join(GROUPS)}}}")
    listed = read_expectations(Path(args.robotool_tests)) if args.robotool_tests else {}
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        rows = list(pool.map(lambda w: run_isolated(root, w, args.package, args.timeout), workspaces))
    for r in rows:
        r["expect"] = expectation(r["workspace"], listed)
    report(rows, args.package, bool(listed))
    summary = summarise(rows, args.package)
    if args.json:
        Path(args.json).write_text(json.dumps({"summary": summary, "workspaces": rows}, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
