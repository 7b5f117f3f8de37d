"""A Python-implemented FMU that fails on request, for the master's failure tests (packaged with
``robogen package-py misbehaving_models:Misbehaving``)."""

from __future__ import annotations

import ctypes
import time

from robogen.pyfmu import Float64, Model


class Misbehaving(Model):
    """``y`` follows time. The step that reaches ``crash_time`` kills the process with SIGSEGV
    (it reads address 0); the step that reaches ``fail_time`` divides by zero; every step sleeps
    ``delay`` seconds of wall time first. A negative time never comes."""

    model_identifier = "misbehaving"
    y = Float64(0.0, causality="output", variability="continuous")
    crash_time = Float64(-1.0, causality="parameter", variability="fixed")
    fail_time = Float64(-1.0, causality="parameter", variability="fixed")
    delay = Float64(0.0, causality="parameter", variability="fixed")

    def do_step(self, t: float, h: float) -> None:
        if self.delay > 0:
            time.sleep(self.delay)
        if self.crash_time >= 0 and t + h >= self.crash_time - 1e-9:
            ctypes.string_at(0)  # SIGSEGV
        if self.fail_time >= 0 and t + h >= self.fail_time - 1e-9:
            self.y = 1.0 / (self.fail_time - self.fail_time)  # ZeroDivisionError: float division by zero
        self.y = t + h
