"""Benchmark of the code generator and of the FMUs it writes, on the UR5e d-model.

Prints medians over several runs (never asserted anywhere):
  (a) compile + package time of models/ur5e/ur5e.rst (check, lower, generate, C compile, zip,
      validate), in-process, with its parts (target: at most 1 s);
  (b) cycles per second of the UR5e FMU driven through the FMI API by a small C harness compiled
      here (dlopen the .so; per cycle: SetClock(cycle) and the story's inputs, GetClock and the
      movediscrete arguments, UpdateDiscreteStates, EnterStepMode, DoStep, EnterEventMode), in
      both semantics (target: at least 1,000,000);
  (c) the same cycles driven from Python with raw FMI calls (robogen's cffi binding), and the
      reference interpreter (robogen.ir.interp) running the same inputs; their ratio.

The inputs repeat the UR5e story every 6 cycles: idle, command (0, 23, 1), feasible, moving,
moveCompleted, robotStopped.

    python bench/bench_codegen.py [--quick]
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

from fmpy import read_model_description

from robogen import toolchain
from robogen.codegen.api import build_fmu, compile_model, lower_paths, package_model
from robogen.cosim.fmi3 import Binding, Library, ffi, value_array, vr_array
from robogen.fmu.headers import include_dir
from robogen.ir.interp import Interpreter
from robogen.ir.lower import LoweringOptions

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "models" / "ur5e" / "ur5e.rst"
QUICK = "--quick" in sys.argv
RUNS = 3 if QUICK else 5

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c99 */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "fmi3FunctionTypes.h"

#define GET(name) fmi3##name##TYPE *name; { void *s = dlsym(lib, "fmi3" #name); \
    if (!s) { fprintf(stderr, "no fmi3" #name "\n"); return 2; } memcpy(&name, &s, sizeof s); }
#define OK(call) do { if ((call) > fmi3Warning) { fprintf(stderr, "%s failed\n", #call); return 3; } } while (0)

int main(int argc, char **argv)
{
    void *lib;
    fmi3Instance inst;
    long n, i;
    fmi3ValueReference vr[9];
    fmi3Clock on = fmi3ClockActive, active;
    fmi3Boolean need, term, nominals, values, defined, event, early;
    fmi3Float64 next, last;
    fmi3Int64 command[3] = {0, 23, 1}, args[3];
    fmi3ValueReference command_args[3], move_args[3];
    struct timespec t0, t1;
    long moves = 0;
    if (argc != 13) { fprintf(stderr, "usage: lib token cycles vr_cycle vr_command vr_command_x vr_feasible "
                                      "vr_completed vr_stopped vr_move vr_move_x interval\n"); return 2; }
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 2; }
    {
        GET(InstantiateCoSimulation) GET(EnterInitializationMode) GET(ExitInitializationMode) GET(SetClock)
        GET(GetClock) GET(SetInt64) GET(GetInt64) GET(UpdateDiscreteStates) GET(EnterStepMode) GET(DoStep)
        GET(EnterEventMode) GET(FreeInstance)
        double h = atof(argv[12]);
        n = atol(argv[3]);
        for (i = 0; i < 8; ++i) vr[i] = (fmi3ValueReference)atol(argv[4 + i]);
        for (i = 0; i < 3; ++i) { command_args[i] = vr[2] + (fmi3ValueReference)i; move_args[i] = vr[7] + (fmi3ValueReference)i; }
        inst = InstantiateCoSimulation("bench", argv[2], NULL, fmi3False, fmi3False, fmi3True, fmi3False, NULL, 0,
                                       NULL, NULL, NULL);
        if (!inst) { fprintf(stderr, "instantiation failed\n"); return 2; }
        OK(EnterInitializationMode(inst, fmi3False, 0.0, 0.0, fmi3False, 0.0));
        OK(ExitInitializationMode(inst));
        clock_gettime(CLOCK_MONOTONIC, &t0);
        for (i = 0; i < n; ++i) {
            if (i > 0) {
                OK(EnterStepMode(inst));
                OK(DoStep(inst, (double)(i - 1) * h, h, fmi3True, &event, &term, &early, &last));
                OK(EnterEventMode(inst));
            }
            OK(SetClock(inst, &vr[0], 1, &on));
            switch (i % 6) {
            case 1: OK(SetClock(inst, &vr[1], 1, &on)); OK(SetInt64(inst, command_args, 3, command, 3)); break;
            case 2: OK(SetClock(inst, &vr[3], 1, &on)); break;
            case 4: OK(SetClock(inst, &vr[4], 1, &on)); break;
            case 5: OK(SetClock(inst, &vr[5], 1, &on)); break;
            default: break;
            }
            do {
                OK(GetClock(inst, &vr[6], 1, &active));
                if (active) { OK(GetInt64(inst, move_args, 3, args, 3)); moves += args[1] == 23; }
                OK(UpdateDiscreteStates(inst, &need, &term, &nominals, &values, &defined, &next));
            } while (need);
        }
        clock_gettime(CLOCK_MONOTONIC, &t1);
        FreeInstance(inst);
    }
    printf("%ld %.9f %ld\n", n, (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec), moves);
    return 0;
}
"""


def median_time(fn, runs: int = RUNS) -> float:
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


# ---------------------------------------------------------------------------- (a)


def bench_package(folder: Path) -> None:
    print("(a) compile + package models/ur5e/ur5e.rst (in-process, median of %d)" % RUNS)
    count = iter(range(1000))

    def package():
        package_model([str(MODEL)], folder / f"ur5e-{next(count)}.fmu")

    package()  # warm caches (grammar tables, imports)
    total = median_time(package)
    work = folder / "parts"
    front = median_time(lambda: lower_paths([str(MODEL)]))
    generate = median_time(lambda: compile_model([str(MODEL)], work))
    build = median_time(lambda: build_fmu(work, folder / "parts.fmu", validate=False))
    validate = median_time(lambda: build_fmu(work, folder / "parts.fmu", validate=True)) - build
    print(f"    total {total:.3f} s (target <= 1 s): check + lower {front:.3f} s, generate + write sources "
          f"{generate - front:.3f} s, C compile + zip {build:.3f} s, validate {validate:.3f} s")


# ---------------------------------------------------------------------------- (b)


class Ur5eFmu:
    """The UR5e FMU built with one semantics, unzipped, with the value references the benches use."""

    def __init__(self, folder: Path, semantics: str):
        self.options = LoweringOptions(semantics=semantics)
        archive, compiled = package_model([str(MODEL)], folder / f"ur5e-{semantics}.fmu", options=self.options)
        self.fmu = compiled.fmu
        self.dir = folder / f"ur5e-{semantics}"
        with zipfile.ZipFile(archive) as z:
            z.extractall(self.dir)
        md = read_model_description(str(self.dir / "modelDescription.xml"))
        self.token = md.guid
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.so = self.dir / "binaries" / "x86_64-linux" / f"{md.coSimulation.modelIdentifier}.so"
        self.interval = float(self.fmu.clock_interval)

    def harness_args(self) -> list[str]:
        names = ["cycle", "moveDiscreteCommand", "moveDiscreteCommand.target_X", "feasibleMoveDiscreteCommand",
                 "moveCompleted", "robotStopped", "movediscrete", "movediscrete.target_X"]
        return [str(self.vr[n]) for n in names]


def bench_c(fmus: dict[str, Ur5eFmu], folder: Path) -> None:
    source = folder / "bench_cycles.c"
    source.write_text(HARNESS)
    program = folder / "bench_cycles"
    toolchain.run_compiler([*toolchain.CFLAGS, "-O2", "-I", str(include_dir()), str(source), "-o", str(program), "-ldl"],
                    "the benchmark harness")
    cycles = 300_000 if QUICK else 2_000_000
    print(f"(b) the UR5e FMU driven from C through the FMI API, {cycles:,} cycles (median of {RUNS})")
    for semantics, f in fmus.items():
        rates = []
        for _ in range(RUNS):
            out = subprocess.run([str(program), str(f.so), f.token, str(cycles), *f.harness_args(), repr(f.interval)],
                                 capture_output=True, text=True, check=True).stdout.split()
            n, seconds, moves = int(out[0]), float(out[1]), int(out[2])
            assert moves == 2 * (n // 6) + (1 if n % 6 > 2 else 0) + (1 if n % 6 > 1 else 0), moves
            rates.append(n / seconds)
        rate = statistics.median(rates)
        print(f"    {semantics:10s} {rate:14,.0f} cycles/s  ({1e6 / rate:.3f} us per cycle; target >= 1,000,000 cycles/s)")


# ---------------------------------------------------------------------------- (c)


def python_fmu_cycles(f: Ur5eFmu, n: int) -> int:
    """Raw FMI calls through the cffi binding, as the C harness makes them. Returns the moves seen."""
    lib = Library(str(f.so))
    inst = Binding(lib, "bench")
    inst.fmi3InstantiateCoSimulation(f.token, None, eventModeUsed=True)
    c, h = lib.lib, inst.handle
    vr = f.vr
    cycle, command, feasible = vr_array([vr["cycle"]]), vr_array([vr["moveDiscreteCommand"]]), vr_array([vr["feasibleMoveDiscreteCommand"]])
    completed, stopped, move = vr_array([vr["moveCompleted"]]), vr_array([vr["robotStopped"]]), vr_array([vr["movediscrete"]])
    command_args = vr_array([vr[f"moveDiscreteCommand.target_{a}"] for a in "XYZ"])
    move_args = vr_array([vr[f"movediscrete.target_{a}"] for a in "XYZ"])
    on, active = value_array("Clock", 1), value_array("Clock", 1)
    on[0] = True
    command_values, args = ffi.new("int64_t[]", [0, 23, 1]), value_array("Int64", 3)
    b, d = ffi.new("bool[6]"), ffi.new("double[1]")
    ticks = {2: feasible, 4: completed, 5: stopped}
    inst.fmi3EnterInitializationMode(None, 0.0, None)
    inst.fmi3ExitInitializationMode()
    moves, t, step = 0, 0.0, f.interval
    for i in range(n):
        if i > 0:
            assert c.fmi3EnterStepMode(h) <= 1
            assert c.fmi3DoStep(h, t, step, True, b, b + 1, b + 2, d) <= 1
            t += step
            assert c.fmi3EnterEventMode(h) <= 1
        assert c.fmi3SetClock(h, cycle, 1, on) <= 1
        phase = i % 6
        if phase == 1:
            assert c.fmi3SetClock(h, command, 1, on) <= 1
            assert c.fmi3SetInt64(h, command_args, 3, command_values, 3) <= 1
        elif phase in ticks:
            assert c.fmi3SetClock(h, ticks[phase], 1, on) <= 1
        while True:
            assert c.fmi3GetClock(h, move, 1, active) <= 1
            if active[0]:
                assert c.fmi3GetInt64(h, move_args, 3, args, 3) <= 1
                moves += args[1] == 23
            assert c.fmi3UpdateDiscreteStates(h, b, b + 1, b + 2, b + 3, b + 4, d) <= 1
            if not b[0]:
                break
    inst.fmi3FreeInstance()
    return moves


def interpreter_cycles(f: Ur5eFmu, n: int) -> int:
    """The reference interpreter on the same inputs."""
    it = Interpreter(f.fmu)
    it.exit_initialization()
    payload = {"moveDiscreteCommand.target_X": 0, "moveDiscreteCommand.target_Y": 23, "moveDiscreteCommand.target_Z": 1}
    ticks = {2: "feasibleMoveDiscreteCommand", 4: "moveCompleted", 5: "robotStopped"}
    moves = 0
    for i in range(n):
        phase = i % 6
        if phase == 1:
            it.latch("moveDiscreteCommand", payload)
        elif phase in ticks:
            it.latch(ticks[phase])
        periodic = True
        while True:
            shown = it.evaluate(periodic)
            periodic = False
            move = shown.outputs.get("movediscrete")
            if move is not None:
                moves += move["movediscrete.target_Y"] == 23
            if not it.update():
                break
    return moves


def bench_python(fmus: dict[str, Ur5eFmu]) -> None:
    n = 6_000 if QUICK else 30_000
    print(f"(c) the same inputs from Python, {n:,} cycles (median of {RUNS}): raw FMI calls vs the reference interpreter")
    for semantics, f in fmus.items():
        assert python_fmu_cycles(f, 60) == interpreter_cycles(f, 60) == 20  # the same story on both
        fmu_time = median_time(lambda: python_fmu_cycles(f, n))
        interp_time = median_time(lambda: interpreter_cycles(f, n))
        print(f"    {semantics:10s} FMU from Python {n / fmu_time:10,.0f} cycles/s, interpreter {n / interp_time:10,.0f} "
              f"cycles/s: the FMU is {interp_time / fmu_time:.1f}x faster")


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-codegen-") as tmp:
        folder = Path(tmp)
        bench_package(folder)
        fmus = {s: Ur5eFmu(folder, s) for s in ("exhaustive", "stepwise")}
        bench_c(fmus, folder)
        bench_python(fmus)


if __name__ == "__main__":
    main()
