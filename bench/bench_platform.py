"""Benchmark of the Python-implemented FMUs (robogen.pyfmu) and the UR5e platform FMU, each
against a peer run in the same process. Prints medians and ratios (never asserted anywhere):

  1. packaging: wall time of `robogen package-py` for the platform and the controller FMUs
  2. 100 s of simulated motion (24,000 physics steps at 1/240 s): the platform FMU driven
     through fmpy's FMU3Slave like a master (sample clock every 0.5 s, the scenario's 16
     movediscrete commands, early returns honoured, joint positions read at every communication
     point) vs a bare PyBullet loop doing the same physics (same URDF, motors and joint targets,
     joint states read every 0.5 s). Target ratio <= 1.3.
  3. per-call overhead: fmi3GetFloat64 of one value and an empty fmi3DoStep, through the same
     ctypes functions, on a Python FMU (the platform) vs a C FMU (robogen's C test FMU 'ticker')

    python bench/bench_platform.py [--quick]
"""

from __future__ import annotations

import ctypes
import importlib.util
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import fmpy
import pybullet
from fmpy.fmi3 import FMU3Slave

from robogen.platforms import scene
from robogen.platforms.kinematics import HOME, IK_SEED, MAX_JOINT_SPEED, MAX_JOINT_TORQUE, grid_pose, inverse, nearest_equivalent
from robogen.platforms.plan import load_plan
from robogen.platforms.urdf import ur5e_urdf
from robogen.pyfmu.build import package

ROOT = Path(__file__).resolve().parent.parent
QUICK = "--quick" in sys.argv
REPEAT = 3 if QUICK else 5
STOP = 100.0
SAMPLE = 0.5
PHYSICS_STEP = 1.0 / 240.0
EVENTS = ("feasibleMoveDiscreteCommand", "nonfeasibleMoveDiscreteCommand", "moveCompleted", "robotStopped",
          "collision")


def median(values):
    return statistics.median(values)


# ---- 1. packaging ----------------------------------------------------------------------------

def bench_packaging(folder: Path) -> dict[str, Path]:
    built = {}
    for label, spec, settings in [
        ("platform", "robogen.platforms.ur5e:UR5ePlatform", ["sample_period=0.5"]),
        ("controller", "robogen.platforms.controller:PlanController",
         [f"plan={ROOT / 'models' / 'ur5e' / 'plan.toml'}"]),
    ]:
        times = []
        for k in range(REPEAT):
            t0 = time.perf_counter()
            built[label] = package(spec, folder / f"{label}{k}.fmu", settings).path
            times.append(time.perf_counter() - t0)
        print(f"  package-py {label:10s}: median {median(times):.2f} s over {REPEAT} "
              f"(min {min(times):.2f}, max {max(times):.2f})")
    return built


# ---- 2. 100 s of motion ------------------------------------------------------------------------

class RawFmu:
    """The platform through fmpy's FMU3Slave, hot calls on the raw ctypes functions."""

    def __init__(self, path: Path, directory: str) -> None:
        md = fmpy.read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        #: the non-clocked Float64 outputs (readable after any step): what a master reads in one call
        self.float_outputs = [v.name for v in md.modelVariables
                              if v.type == "Float64" and v.causality == "output" and v.variability == "continuous"]
        self.slave = FMU3Slave(guid=md.guid, unzipDirectory=directory, modelIdentifier=md.coSimulation.modelIdentifier,
                               instanceName="bench")
        self.dll = self.slave.dll

    def array(self, names):
        return (ctypes.c_uint32 * len(names))(*(self.vr[n] for n in names))


def run_fmu(path: Path, directory: str, commands) -> tuple[float, int, int]:
    f = RawFmu(path, directory)
    s, dll = f.slave, f.dll
    s.instantiate(loggingOn=False, eventModeUsed=True, earlyReturnAllowed=True)
    s.enterInitializationMode(startTime=0.0, stopTime=STOP)
    s.exitInitializationMode()
    component = s.component
    sample_vr, md_vr = f.array(["sample"]), f.array(["movediscrete"])
    targets_vr = f.array(["movediscrete.target_X", "movediscrete.target_Y", "movediscrete.target_Z"])
    events_vr, q_vr = f.array(EVENTS), f.array([f"q{i}" for i in range(6)])
    on = (ctypes.c_bool * 1)(True)
    clocks, q = (ctypes.c_bool * len(EVENTS))(), (ctypes.c_double * 6)()
    targets = (ctypes.c_int64 * 3)()
    flags = [ctypes.c_bool() for _ in range(5)]
    next_time, last = ctypes.c_double(), ctypes.c_double()
    event, terminate, early = ctypes.c_bool(), ctypes.c_bool(), ctypes.c_bool()
    pending = list(commands)
    early_returns = 0
    t = 0.0
    t0 = time.perf_counter()
    while True:
        if abs(t / SAMPLE - round(t / SAMPLE)) < 1e-9:
            dll.fmi3SetClock(component, sample_vr, 1, on)
        if pending and abs(pending[0][0] - t) < 1e-9:
            _, cell = pending.pop(0)
            dll.fmi3SetClock(component, md_vr, 1, on)
            targets[:] = cell
            dll.fmi3SetInt64(component, targets_vr, 3, targets, 3)
        dll.fmi3GetClock(component, events_vr, len(EVENTS), clocks)
        dll.fmi3GetFloat64(component, q_vr, 6, q, 6)
        dll.fmi3UpdateDiscreteStates(component, *(ctypes.byref(x) for x in flags[:5]), ctypes.byref(next_time))
        dll.fmi3EnterStepMode(component)
        if t >= STOP - 1e-9:
            break
        target = min((math.floor(t / SAMPLE + 1e-9) + 1) * SAMPLE, STOP)
        dll.fmi3DoStep(component, ctypes.c_double(t), ctypes.c_double(target - t), True, ctypes.byref(event),
                       ctypes.byref(terminate), ctypes.byref(early), ctypes.byref(last))
        early_returns += early.value
        t = last.value
        dll.fmi3EnterEventMode(component)
    wall = time.perf_counter() - t0
    steps = (ctypes.c_int64 * 1)()
    dll.fmi3GetInt64(component, f.array(["physics_steps"]), 1, steps, 1)
    s.terminate()
    s.freeInstance()
    return wall, steps[0], early_returns


def joint_targets(commands) -> list[tuple[float, tuple[float, ...]]]:
    """The joint solutions the platform computes for the commands (outside the timed loop)."""
    out, q = [], HOME
    for t, cell in commands:
        result = inverse(*grid_pose(*cell), seeds=(IK_SEED, q))
        q = nearest_equivalent(result.q, q)
        out.append((t, q))
    return out


def run_bare(urdf: Path, targets, include_setup: bool = False, stretches: bool = False) -> tuple[float, int]:
    """The same physics without the FMU: PyBullet calls only. The wall time covers the loop, or
    also connecting, loading the URDF and disconnecting (``include_setup``, to compare with a whole
    co-simulation, which frees its platform's client). ``stretches``: each 0.5 s of physics in one
    PyBullet call where that is the same physics (``scene.step_stretch``, as the platform steps
    where it watches nothing), instead of a call a physics step."""
    t_setup = time.perf_counter()
    cid = pybullet.connect(pybullet.DIRECT)
    pybullet.setTimeStep(PHYSICS_STEP, physicsClientId=cid)
    pybullet.setGravity(0, 0, -scene.GRAVITY, physicsClientId=cid)
    robot = pybullet.loadURDF(str(urdf), useFixedBase=True, physicsClientId=cid,
                              flags=pybullet.URDF_USE_INERTIA_FROM_FILE | pybullet.URDF_USE_SELF_COLLISION
                              | pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT)
    plane = pybullet.createMultiBody(0.0, pybullet.createCollisionShape(pybullet.GEOM_PLANE, physicsClientId=cid),
                                     physicsClientId=cid)
    for link in (-1, 0):
        pybullet.setCollisionFilterPair(plane, robot, -1, link, 0, physicsClientId=cid)

    def command(q):
        for j in range(6):
            pybullet.setJointMotorControl2(robot, j, pybullet.POSITION_CONTROL, targetPosition=q[j], targetVelocity=0.0,
                                           force=MAX_JOINT_TORQUE[j], positionGain=scene.POSITION_GAIN,
                                           velocityGain=scene.VELOCITY_GAIN, maxVelocity=MAX_JOINT_SPEED,
                                           physicsClientId=cid)

    for j in range(6):
        pybullet.resetJointState(robot, j, HOME[j], 0.0, physicsClientId=cid)
    command(HOME)
    pending = list(targets)
    per_interval = round(SAMPLE / PHYSICS_STEP)
    steps = 0
    t0 = t_setup if include_setup else time.perf_counter()
    for k in range(round(STOP / SAMPLE)):
        if pending and abs(pending[0][0] - k * SAMPLE) < 1e-9:
            command(pending.pop(0)[1])
        if stretches:
            scene.step_stretch(cid, PHYSICS_STEP, per_interval)
        else:
            for _ in range(per_interval):
                pybullet.stepSimulation(physicsClientId=cid)
        steps += per_interval
        pybullet.getJointStates(robot, range(6), physicsClientId=cid)
    end = time.perf_counter()
    pybullet.disconnect(physicsClientId=cid)
    if include_setup:  # the disconnect too
        end = time.perf_counter()
    return end - t0, steps


def bench_motion(platform: Path, folder: Path) -> None:
    commands = [(c.time, c.target) for c in load_plan(ROOT / "models" / "ur5e" / "plan.toml").events(until=STOP)]
    directory = fmpy.extract(str(platform), str(folder / "platform-x"))
    urdf = folder / "ur5e.urdf"
    urdf.write_text(ur5e_urdf())
    targets = joint_targets(commands)
    fmu_times, bare_times = [], []
    for _ in range(REPEAT):  # interleaved, so both see the same machine load
        wall, steps, early_returns = run_fmu(platform, directory, commands)
        fmu_times.append(wall)
        bare_wall, bare_steps = run_bare(urdf, targets)
        bare_times.append(bare_wall)
    fmu_m, bare_m = median(fmu_times), median(bare_times)
    print(f"  100 s of motion, {len(commands)} commands, {steps} physics steps in the FMU, {bare_steps} bare; "
          f"{early_returns} early returns")
    print(f"  platform FMU via FMU3Slave : median {fmu_m:.3f} s  ({fmu_m / steps * 1e6:.1f} us per physics step)")
    print(f"  bare PyBullet loop         : median {bare_m:.3f} s  ({bare_m / bare_steps * 1e6:.1f} us per physics step)")
    print(f"  ratio FMU / bare           : {fmu_m / bare_m:.2f}  (target <= 1.3)")


# ---- 3. per-call overhead ----------------------------------------------------------------------

def load_c_fmus(folder: Path) -> Path:
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", ROOT / "tests" / "cosim" / "fmus" / "build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build_all(folder, ["ticker"])["ticker"]


def per_call(path: Path, directory: str, output: str, h: float, n: int) -> tuple[float, float, float, int]:
    """Seconds per fmi3GetFloat64 of ``output``, per fmi3DoStep of ``h``, per fmi3GetFloat64 of
    all the non-clocked Float64 outputs in one call; how many those are."""
    f = RawFmu(path, directory)
    s, dll = f.slave, f.dll
    s.instantiate(loggingOn=False, eventModeUsed=True, earlyReturnAllowed=False)
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    s.updateDiscreteStates()
    s.enterStepMode()
    component, vr, value = s.component, f.array([output]), (ctypes.c_double * 1)()
    get = dll.fmi3GetFloat64
    t0 = time.perf_counter()
    for _ in range(n):
        get(component, vr, 1, value, 1)
    get_time = (time.perf_counter() - t0) / n
    m = len(f.float_outputs)
    vrs, values = f.array(f.float_outputs), (ctypes.c_double * m)()
    t0 = time.perf_counter()
    for _ in range(n):
        get(component, vrs, m, values, m)
    batch_time = (time.perf_counter() - t0) / n
    event, terminate, early, last = ctypes.c_bool(), ctypes.c_bool(), ctypes.c_bool(), ctypes.c_double()
    step, t = dll.fmi3DoStep, 0.0
    t0 = time.perf_counter()
    for _ in range(n):
        step(component, ctypes.c_double(t), ctypes.c_double(h), True, ctypes.byref(event), ctypes.byref(terminate),
             ctypes.byref(early), ctypes.byref(last))
        t = last.value
    step_time = (time.perf_counter() - t0) / n
    s.terminate()
    s.freeInstance()
    return get_time, step_time, batch_time, m


def per_call_figures(platform: Path, folder: Path, n: int) -> None:
    """Print the per-call costs of the platform FMU against the C test FMU (medians of REPEAT runs of n calls)."""
    ticker = load_c_fmus(folder / "c-fmus")
    py_dir = fmpy.extract(str(platform), str(folder / "calls-py"))
    c_dir = fmpy.extract(str(ticker), str(folder / "calls-c"))
    # The platform's step is shorter than its physics step, so fmi3DoStep does no physics.
    py = [per_call(platform, py_dir, "q0", PHYSICS_STEP / 1000, n) for _ in range(REPEAT)]
    c = [per_call(ticker, c_dir, "phase", PHYSICS_STEP / 1000, n) for _ in range(REPEAT)]
    for label, k in (("fmi3GetFloat64 (1 value)", 0), ("fmi3DoStep (no physics)", 1)):
        py_m, c_m = median(r[k] for r in py), median(r[k] for r in c)
        print(f"  {label:26s}: Python FMU {py_m * 1e6:6.2f} us, C FMU {c_m * 1e6:6.2f} us, ratio {py_m / c_m:5.1f}, "
              f"overhead {(py_m - c_m) * 1e6:.2f} us per call")
    one, batch, m = median(r[0] for r in py), median(r[2] for r in py), py[0][3]
    print(f"  fmi3GetFloat64 ({m} values, one call): Python FMU {batch * 1e6:6.2f} us, {batch / one:4.1f}x one value: "
          f"the shim's entry is paid once per call, each further value costs {(batch - one) / (m - 1) * 1e6:.2f} us")


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-platform-") as tmp:
        folder = Path(tmp)
        print("1. packaging (robogen package-py)")
        built = bench_packaging(folder)
        print("2. 100 s of UR5e motion: platform FMU vs bare PyBullet (same run)")
        bench_motion(built["platform"], folder)
        print("3. per-call overhead: Python FMU vs C FMU (same ctypes calls, same run)")
        per_call_figures(built["platform"], folder, 20_000 if QUICK else 100_000)
    return 0


if __name__ == "__main__":
    sys.exit(main())
