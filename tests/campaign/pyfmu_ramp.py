"""A Python-implemented FMU for the campaign tests (packaged with
``robogen package-py pyfmu_ramp:Ramp``): ``y = gain * t`` at the end of every step."""

from __future__ import annotations

from robogen.pyfmu import Float64, Model


class Ramp(Model):
    model_identifier = "ramp"
    gain = Float64(1.0, causality="parameter", variability="fixed")
    y = Float64(0.0, causality="output")

    def do_step(self, t: float, h: float) -> None:
        self.y = self.gain * (t + h)
