# robogen — the two commands a newcomer types are `make demo` and `make test`.
# Both create the virtual environment in .venv and install robogen into it.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.robogen-installed
PYTEST_ARGS ?=

.PHONY: all venv test demo bench clean golden

all: test

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

# Reinstall when the project metadata changes.
$(STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

venv: $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q $(PYTEST_ARGS)

demo: $(STAMP)
	$(PY) -m examples.ur5e.demo

bench: $(STAMP)
	@set -e; for b in bench/bench_*.py; do echo "== $$b"; $(PY) $$b; done

# Refresh the golden files of the generated sources (review the diff afterwards).
golden: $(STAMP)
	$(PY) tests/codegen/golden_files.py

clean:
	rm -rf build dist .pytest_cache
