"""Python-implemented FMI 3.0 Co-Simulation FMUs (cffi embedding mode).

Declare a subclass of :class:`Model` (see :mod:`robogen.pyfmu.model`), then package it with
``robogen package-py MODULE:CLASS -o NAME.fmu`` (:mod:`robogen.pyfmu.build`).
"""

from robogen.pyfmu.model import (
    Boolean, Clock, Float64, FmiUsageError, Int32, Int64, Model, Setting, Step, String, Update,
)

__all__ = [
    "Boolean", "Clock", "Float64", "FmiUsageError", "Int32", "Int64", "Model", "Setting", "Step", "String", "Update",
]
