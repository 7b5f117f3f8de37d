"""Fixtures of the IR's tests: the compiled test models and the drivers that run them on the FMU
and on the reference interpreter (tests/support, shared with the code generator's tests)."""

from support.model_builds import builds, built  # noqa: F401 - fixtures
