# Two entry points a new user needs; each sets up its own virtual environment.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test lint clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,llm,export,dask]"
	$(BIN)/pip install --quiet -e examples/plugin
	touch $(STAMP)

## demo: generate 8 layouts (JSON + PNG) of the bundled bedroom plan into out/bedroom
demo: $(STAMP)
	$(BIN)/forcelayout generate bedroom -n 8 --seed 0 --out out/bedroom

## test: lint, check the core alone (no extras), and run the whole test suite
test: $(STAMP) core-check
	$(BIN)/ruff check src tests examples benchmarks
	$(BIN)/python -m pytest -q

## core-check: `import forcelayout` in an environment with the core dependencies only
core-check:
	$(PY) -m venv .venv-core
	.venv-core/bin/pip install --quiet .
	cd /tmp && $(CURDIR)/.venv-core/bin/python $(CURDIR)/tests/core_only.py

lint: $(STAMP)
	$(BIN)/ruff check src tests examples benchmarks

clean:
	rm -rf $(VENV) .venv-core out .pytest_cache .ruff_cache
