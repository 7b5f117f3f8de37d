"""The compiled Python FMUs in real hosts: fmpy's FMU3Slave in this process, and the C host of
host.c in a clean process that dlopen()s the binary with RTLD_LOCAL. Covers the traps of
libpython's scope, sys.path, several instances and several FMUs in one
process, unloading, and Python exceptions turned into fmi3Error with the traceback logged."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
import zipfile

import pytest
from fmpy.fmi1 import FMICallException

from support.pyfmu import Fmu, run_host, unzip
from robogen.pyfmu.build import package

ERROR = 3


def started(path, name="c", **kwargs) -> Fmu:
    fmu = Fmu(path, name, **kwargs)
    fmu.slave.enterInitializationMode(startTime=0.0)
    fmu.slave.exitInitializationMode()
    return fmu


def token(fmu_path) -> str:
    with zipfile.ZipFile(fmu_path) as z:
        return ET.fromstring(z.read("modelDescription.xml")).attrib["instantiationToken"]


# ---- fmpy ------------------------------------------------------------------------------------

def test_fmpy_drives_clocks_and_steps(fmus):
    fmu = started(fmus["counter"])
    fmu.set_clocks("tick")
    assert fmu.clocks("ticked", "alarm") == {"ticked": True, "alarm": False}
    assert fmu.i64("ticked.count", "total") == [1, 1]
    fmu.slave.updateDiscreteStates()
    assert fmu.clocks("ticked") == {"ticked": False}
    fmu.slave.enterStepMode()
    assert fmu.slave.doStep(0.0, 0.5) == (False, False, False, 0.5)
    assert fmu.f64("position") == [0.5]
    fmu.close()


def test_early_return_reaches_the_importer_with_the_event_time(fmus):
    fmu = Fmu(fmus["counter"])
    fmu.set_f64(alarm_time=0.2)
    fmu.slave.enterInitializationMode(startTime=0.0)
    fmu.slave.exitInitializationMode()
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    event, terminate, early, last = fmu.slave.doStep(0.0, 0.5)
    assert (event, early, last) == (True, True, 0.2)
    fmu.slave.enterEventMode()
    assert fmu.active("alarm") == {"alarm"}
    fmu.close()


def test_constant_clock_interval_is_readable(fmus):
    fmu = started(fmus["counter_fast"])
    assert fmu.interval("tick") == (0.25, 1)
    fmu.close()


def test_python_exception_becomes_fmi3error_with_the_traceback_logged(fmus):
    fmu = Fmu(fmus["counter"])
    fmu.set_f64(fail_after=0.7)
    fmu.slave.enterInitializationMode(startTime=0.0)
    fmu.slave.exitInitializationMode()
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    fmu.slave.doStep(0.0, 0.5)
    with pytest.raises(FMICallException) as failure:
        fmu.slave.doStep(0.5, 0.5)
    assert failure.value.status == ERROR
    [(status, category, message)] = [entry for entry in fmu.logs if entry[0] == ERROR]
    assert category == "logStatusError"
    assert message.startswith("fmi3DoStep: Python exception in the FMU")
    assert "Traceback (most recent call last)" in message
    assert "RuntimeError: deliberate failure after t = 0.7" in message
    fmu.slave.freeInstance()  # the host goes on


def test_errors_are_logged_with_logging_off_with_the_place_in_the_models_code(fmus):
    # FMI 3.0: errors reach logMessage whatever loggingOn says; other messages do not
    fmu = Fmu(fmus["counter"], logging=False)
    fmu.set_f64(fail_after=0.2)
    fmu.slave.enterInitializationMode(startTime=0.0)
    fmu.slave.exitInitializationMode()
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    with pytest.raises(FMICallException):
        fmu.slave.doStep(0.0, 0.5)
    [(status, _category, message)] = fmu.logs
    assert status == ERROR
    lines = message.splitlines()
    assert lines[:2] == ["fmi3DoStep: Python exception in the FMU", "Traceback (most recent call last):"]
    assert "robogen/pyfmu" not in message  # only the model's own frames
    # (in this process the model's module is the test's own, imported before the FMU was)
    assert re.fullmatch(r"RuntimeError: deliberate failure after t = 0\.2 \(at (\S+/)?pyfmu_fixture_models\.py:\d+ in do_step\)",
                        lines[-1])
    fmu.slave.freeInstance()


def test_usage_errors_are_logged_without_traceback(fmus):
    fmu = started(fmus["counter"])
    with pytest.raises(FMICallException):
        fmu.i64("ticked.count")  # its clock is inactive
    assert fmu.messages(ERROR) == ["fmi3GetInt64: 'ticked.count' is clocked by 'ticked', which is not active "
                                   "(Event Mode)"]
    fmu.close()


def instantiate_raw(path, guid=None):
    """fmpy's FMU3Slave with the log kept, for instantiations expected to fail."""
    from fmpy import extract, read_model_description
    from fmpy.fmi3 import FMU3Slave

    md = read_model_description(str(path))
    logs: list[tuple[int, str]] = []
    slave = FMU3Slave(guid=guid or md.guid, unzipDirectory=extract(str(path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="x")
    with pytest.raises(Exception, match="Failed to instantiate"):
        slave.instantiate(loggingOn=True, eventModeUsed=True,
                          logMessage=lambda e, status, c, m: logs.append((status, m.decode())))
    return md, logs


def test_failing_instantiation_returns_null_and_logs_why(fmus):
    _, logs = instantiate_raw(fmus["broken_setup"])
    [(status, message)] = logs
    assert status == ERROR and message.startswith("fmi3InstantiateCoSimulation: Python exception in the FMU")
    assert "ValueError: setup cannot find its calibration table" in message
    md, logs = instantiate_raw(fmus["counter"], guid="{not-the-token}")
    assert logs == [(ERROR, f"wrong instantiationToken '{{not-the-token}}'; this FMU's is '{md.guid}'")]


def test_a_clocked_fmu_refuses_event_mode_unused(fmus):
    with pytest.raises(Exception, match="Failed to instantiate"):
        Fmu(fmus["counter"], event_mode=False)


def test_unsupported_functions_log_and_return_error(fmus):
    fmu = started(fmus["counter"])
    with pytest.raises(FMICallException):
        fmu.slave.getFloat32([fmu.vr["position"]])
    with pytest.raises(FMICallException):
        fmu.slave.getFMUState()
    assert fmu.messages(ERROR) == ["fmi3GetFloat32 is not supported by this FMU",
                                   "fmi3GetFMUState is not supported by this FMU"]
    fmu.close()


def test_debug_logging_categories(fmus):
    fmu = started(fmus["counter"])
    fmu.slave.setDebugLogging(True, ["logStatusError"])
    fmu.set_clocks("tick")  # would log under logEvents
    assert fmu.logs == []
    with pytest.raises(FMICallException):
        fmu.slave.setDebugLogging(True, ["logEverything"])
    fmu.slave.setDebugLogging(False, [])
    with pytest.raises(FMICallException):
        fmu.slave.getFloat32([fmu.vr["position"]])
    assert [m for m in fmu.messages() if "getFloat32" in m.lower()] == []  # logging is off
    fmu.close()


def test_event_messages_are_made_only_while_their_category_is_logged(fmus):
    fmu = started(fmus["counter"])
    fmu.slave.setDebugLogging(True, ["logEvents"])
    fmu.set_clocks("tick")
    assert fmu.messages() == ["t=0: input clock tick active"]
    fmu.slave.updateDiscreteStates()
    fmu.slave.setDebugLogging(True, ["logStatusWarning"])  # the slave asks the C side before formatting
    fmu.slave.enterStepMode()
    fmu.slave.doStep(0.0, 0.5)
    fmu.slave.enterEventMode()
    fmu.set_clocks("tick")
    assert fmu.messages() == ["t=0: input clock tick active"]
    fmu.close()


def test_several_instances_and_several_fmus_in_one_process_keep_their_own_state(fmus, tmp_path):
    a = started(fmus["counter"], "a")
    b = started(fmus["counter"], "b")  # same library
    c = started(fmus["counter"], "c", unzip_dir=tmp_path / "copy")  # a second copy of the same binary
    d = started(fmus["counter_fast"], "d")  # another FMU of the same class
    for fmu, bumps in ((a, 1), (b, 2), (c, 3), (d, 4)):
        fmu.set_clocks("bump")
        fmu.set_i64({"bump.amount": bumps})
        fmu.slave.updateDiscreteStates()
    assert [f.i64("total")[0] for f in (a, b, c, d)] == [1, 2, 3, 4]
    for fmu in (a, b, c, d):
        fmu.close()


def test_an_fmu_loads_again_after_its_library_was_closed(fmus):
    first = started(fmus["counter"], "first")
    first.close()  # fmpy's freeInstance also dlclose()s the library
    second = started(fmus["counter"], "second")
    second.set_clocks("tick")
    assert second.i64("total") == [1]
    second.close()


# ---- the C host: dlopen with RTLD_LOCAL, a process without Python ------------------------------

def host_script(fmu_dir, identifier, *calls) -> list[str]:
    return [f"load {fmu_dir}/binaries/x86_64-linux/{identifier}.so", *calls]


def test_c_host_runs_the_fmu_with_rtld_local(fmus, host, tmp_path):
    directory = unzip(fmus["counter"], tmp_path / "counter")
    vr = {v.attrib["name"]: v.attrib["valueReference"]
          for v in ET.parse(directory / "modelDescription.xml").getroot().find("ModelVariables")}
    tok = token(fmus["counter"])
    out = run_host(host, host_script(
        directory, "counter",
        f"instantiate a {tok} {directory}/resources/ 1 1",
        f"instantiate b {tok} {directory}/resources/ 1 1",
        "init 0 0", "init 1 0", "exit_init 0", "exit_init 1",
        f"set_clock 0 {vr['tick']}", f"get_clock 0 {vr['ticked']}", f"get_i64 0 {vr['ticked.count']}",
        f"set_clock 1 {vr['bump']}", f"set_i64 1 {vr['bump.amount']} 40", f"get_i64 1 {vr['total']}",
        "update 0", "update 1", "step_mode 0",
        "do_step 0 0 0.5", f"get_f64 0 {vr['position']}",
        f"set_f64 0 {vr['fail_after']} 0.75", "do_step 0 0.5 0.5",
        "free 0", "free 1",
    ))
    assert "loaded" in out and "instance 0" in out and "instance 1" in out
    assert "clock 1" in out and "int64 1\n" in out and "int64 40\n" in out
    assert "step 0 0 0 0.5" in out and "float64 0.5\n" in out
    # the failure: fmi3Error, the traceback through the logger, the host carries on
    assert re.search(r"log 3 logStatusError: fmi3DoStep: Python exception in the FMU\nTraceback", out)
    assert "RuntimeError: deliberate failure after t = 0.75" in out
    assert out.rstrip().endswith("status 0")  # the frees after the error
    # the model's module came from the FMU's resources (nothing else on sys.path has it)
    assert f"{directory}/resources/python/pyfmu_fixture_models.py" in out


def test_c_host_imports_extension_modules_inside_the_fmu(fmus, host, tmp_path):
    directory = unzip(fmus["uses_numpy"], tmp_path / "numpy")
    tok = token(fmus["uses_numpy"])
    norm_vr = next(v.attrib["valueReference"] for v in
                   ET.parse(directory / "modelDescription.xml").getroot().find("ModelVariables")
                   if v.attrib["name"] == "norm")
    out = run_host(host, host_script(directory, "uses_numpy",
                                     f"instantiate n {tok} {directory}/resources/ 1 0",
                                     "init 0 0", "exit_init 0", "update 0", "step_mode 0", "do_step 0 0 2",
                                     f"get_f64 0 {norm_vr}", "free 0"))
    assert "float64 10\n" in out  # |(3, 4)| * 2


def test_without_promoting_libpython_a_c_host_cannot_import_extension_modules(host, tmp_path):
    """The trap the constructor in shim.c fixes: built without it, _cffi_backend fails to load."""
    fmu = package("pyfmu_fixture_models:TwoInstants", tmp_path / "local.fmu", model_identifier="local_only",
                  promote_libpython=False).path
    directory = unzip(fmu, tmp_path / "local")
    tok = token(fmu)
    out = run_host(host, host_script(directory, "local_only", f"instantiate x {tok} {directory}/resources/ 1 0"))
    assert "undefined symbol: PyExc_" in out
    assert "instance NULL" in out
    assert "log 3 logStatusError: the FMU's Python part failed to start" in out


OTHER_PYTHON_HOST = """
import ctypes, sys
lib = ctypes.CDLL(sys.argv[1])
LOG = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p)
log = LOG(lambda env, status, category, message: print("log", status, message.decode()))
f = lib.fmi3InstantiateCoSimulation
f.restype = ctypes.c_void_p
f.argtypes = [ctypes.c_char_p] * 3 + [ctypes.c_bool] * 4 + [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p, LOG,
                                                           ctypes.c_void_p]
print("instance", f(b"x", sys.argv[2].encode(), sys.argv[3].encode(), False, True, True, False, None, 0, None, log,
                    None))
"""


def other_python() -> str | None:
    """Another CPython minor version on this machine (pyenv keeps several), or None."""
    import shutil
    import sys
    from pathlib import Path

    mine = f"python{sys.version_info.major}.{sys.version_info.minor}"
    candidates = sorted(Path(sys.base_prefix).parent.glob("3.*/bin/python3.*"))
    candidates += [Path(p) for p in (shutil.which("python3.12"), shutil.which("python3.13")) if p]
    for path in candidates:
        if re.fullmatch(r"python3\.\d+", path.name) and path.name != mine and path.is_file():
            return str(path)
    return None


def test_a_host_running_another_python_is_refused(fmus, tmp_path):
    import subprocess

    python = other_python()
    if python is None:
        pytest.skip("no second CPython minor version on this machine")
    directory = unzip(fmus["counter"], tmp_path / "other")
    result = subprocess.run([python, "-c", OTHER_PYTHON_HOST, f"{directory}/binaries/x86_64-linux/counter.so",
                             token(fmus["counter"]), f"{directory}/resources/"],
                            capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"}, timeout=60)
    assert "instance None" in result.stdout
    assert re.search(r"log 3 this FMU was built for Python 3\.\d+; the host runs Python 3\.\d+\.\d+\n", result.stdout)


def test_an_interruption_outside_the_bound_functions_try_is_the_calls_failure_not_a_traceback(fmus, capfd):
    # A host's signal handler can raise at any bytecode of the FMU's Python, also where no try
    # of the bound function covers it: here while the failure of do_step is being reported.
    import gc

    fmu = Fmu(fmus["counter"])
    fmu.set_f64(fail_after=0.2)
    fmu.slave.enterInitializationMode(startTime=0.0)
    fmu.slave.exitInitializationMode()
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    [inst] = [o for o in gc.get_objects() if type(o).__name__ == "_Instance" and hasattr(o, "slave")
              and getattr(o.slave, "instance_name", None) == "instance"]
    raised = []

    def interrupted_while_failing():
        if not raised:
            raised.append(True)
            raise KeyboardInterrupt("SIGINT")

    inst.slave.failed = interrupted_while_failing
    with pytest.raises(FMICallException) as failure:
        fmu.slave.doStep(0.0, 0.5)
    assert failure.value.status == ERROR and raised
    assert "Traceback" not in capfd.readouterr().err
    messages = fmu.messages(ERROR)
    assert messages[0].startswith("fmi3DoStep: Python exception in the FMU")
    assert messages[-1] == "fmi3DoStep: interrupted (SIGINT)"
    fmu.slave.freeInstance()
