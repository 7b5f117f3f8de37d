"""Fixtures of the code generator's tests (see model_builds)."""

from support.model_builds import builds, built  # noqa: F401 - fixtures
