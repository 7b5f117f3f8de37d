# robogen — the two commands a newcomer types are `make demo` and `make test`.
# Both create the virtual environment in .venv and install robogen into it.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.robogen-installed
# The suite runs on every core (pytest-xdist), each test file whole on one worker so that its
# module fixtures (built FMUs) are built once; PYTEST_ARGS= runs it in one process.
PYTEST_ARGS ?= -n auto --dist loadfile

.PHONY: all venv test demo bench campaign clean golden runners fuzz

all: test

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

# Reinstall when the project metadata changes. The cross extra brings zig, which builds the
# binaries of the platforms other than the host's (robogen package --platforms).
$(STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test,cross]'
	touch $(STAMP)

# What runs the cross-built binaries in tests/toolchain: wine (Windows) and qemu-user with
# Debian's aarch64 C library (aarch64 Linux). apt-get installs them where it can (root on Debian,
# as in CI); elsewhere, or if apt-get fails, those tests skip and say what is missing.
RUNNERS := wine64 qemu-user libc6-arm64-cross
APT := DEBIAN_FRONTEND=noninteractive apt-get -y -qq --no-install-recommends
runners:
	@if command -v qemu-aarch64 >/dev/null && test -x /usr/lib/wine/wine64 && test -f /usr/aarch64-linux-gnu/lib/libc.so.6; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "installing $(RUNNERS) with apt-get, for the tests that run Windows and aarch64 binaries"; \
	  { $(APT) install $(RUNNERS) >/dev/null 2>&1 || { apt-get -qq update >/dev/null 2>&1 && $(APT) install $(RUNNERS) >/dev/null 2>&1; }; } \
	    || echo "apt-get could not install $(RUNNERS): the tests that run Windows and aarch64 binaries will skip"; \
	else echo "not root or no apt-get: the tests that run Windows and aarch64 binaries will skip (they need $(RUNNERS))"; fi

venv: $(STAMP)

# The benchmarks' peers (bench extra) on top of the test install.
BENCH_STAMP := $(VENV)/.robogen-bench-installed
$(BENCH_STAMP): pyproject.toml | $(STAMP)
	$(PY) -m pip install --quiet -e '.[test,bench]'
	touch $(BENCH_STAMP)

# The campaign tests run after, in a pytest process of their own: their Dask workers are
# processes started from the test process, and started from an xdist worker that had run other
# test files they failed to import robogen.fmu.modeldesc (tests/campaign alone: 44 passed).
test: $(STAMP) runners
	@rc=0; $(PY) -m pytest -q $(PYTEST_ARGS) --ignore=tests/campaign || rc=$$?; \
	$(PY) -m pytest -q tests/campaign || rc=$$?; exit $$rc

demo: $(STAMP)
	$(PY) -m examples.ur5e.demo

# The UR5e campaigns (examples/ur5e/campaign*.toml): the reachability of every grid cell, then the
# command latency over the platform's sample period x the d-model's cycle, each value its own FMU.
UR5E := build/ur5e
CAMPAIGN_FMUS := $(UR5E)/campaign-fmus
PERIODS := 0.1 0.25 0.5 1.0
ROBOGEN := $(PY) -m robogen

campaign: $(STAMP) $(UR5E)/controller.fmu $(UR5E)/dmodel.fmu $(UR5E)/platform.fmu \
          $(PERIODS:%=$(CAMPAIGN_FMUS)/dmodel-cycle-%.fmu) $(PERIODS:%=$(CAMPAIGN_FMUS)/platform-sample-%.fmu)
	$(ROBOGEN) campaign examples/ur5e/campaign.toml -o $(UR5E)/campaign
	$(ROBOGEN) campaign examples/ur5e/campaign_latency.toml -o $(UR5E)/campaign-latency

$(UR5E)/dmodel.fmu: models/ur5e/ur5e.rst | $(STAMP)
	$(ROBOGEN) package $< --time-unit 0.5 -o $@
$(UR5E)/platform.fmu: | $(STAMP)
	$(ROBOGEN) package-py robogen.platforms.ur5e:UR5ePlatform --set sample_period=0.5 -o $@
$(UR5E)/controller.fmu: models/ur5e/plan.toml | $(STAMP)
	$(ROBOGEN) package-py robogen.platforms.controller:PlanController --set plan=$< -o $@
$(CAMPAIGN_FMUS)/dmodel-cycle-%.fmu: models/ur5e/ur5e.rst | $(STAMP)
	$(ROBOGEN) package $< --time-unit $* -o $@
$(CAMPAIGN_FMUS)/platform-sample-%.fmu: | $(STAMP)
	$(ROBOGEN) package-py robogen.platforms.ur5e:UR5ePlatform --set sample_period=$* -o $@

bench: $(BENCH_STAMP)
	@set -e; for b in bench/bench_*.py; do echo "== $$b"; $(PY) $$b; done

# The model fuzzer (docs/fuzzing.md): N random models from SEED through every property; the table,
# then the line `fuzz: N models, C compile failures A, ...`; exit 1 when a model fails a property.
N ?= 200
SEED ?= 1
JOBS ?= 2
FUZZ_ARGS ?=
fuzz: $(STAMP)
	@$(PY) -m robogen.fuzz --count $(N) --seed $(SEED) --jobs $(JOBS) --regressions tests/fuzz/regressions $(FUZZ_ARGS)

# Refresh the golden files of the generated sources (review the diff afterwards).
golden: $(STAMP)
	$(PY) tests/codegen/golden_files.py

clean:
	rm -rf build dist .pytest_cache
