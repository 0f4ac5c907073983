# Two entry points a new user needs; each sets up its own virtual environment.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-grounding lint clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,fast,llm,export,dask]"
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

## test-grounding: the heavy optional path (extras grounding + clip: torch, sentence-transformers,
## open_clip) in its own environment .venv-grounding, then the grounding tests. The PyPI builds
## pinned in .ci/grounding-constraints.txt are installed with pip's local wheel folders and
## config ignored: a CPU-only torch wheel lying on disk does not work with PyPI's torchvision.
GVENV := .venv-grounding
GSTAMP := $(GVENV)/.installed
GPIP := env -u PIP_FIND_LINKS PIP_CONFIG_FILE=/dev/null $(GVENV)/bin/pip

$(GSTAMP): pyproject.toml .ci/grounding-constraints.txt
	$(PY) -m venv $(GVENV)
	$(GPIP) install --quiet --upgrade pip
	$(GPIP) install --quiet -c .ci/grounding-constraints.txt -e ".[dev,export,grounding,clip]"
	touch $(GSTAMP)

test-grounding: $(GSTAMP)
	$(GVENV)/bin/python -m pytest -q tests/test_grounding.py \
		tests/test_benchmarks.py::test_grounding_quick \
		"tests/test_examples.py::test_example_runs[09_asset_library.py]"

lint: $(STAMP)
	$(BIN)/ruff check src tests examples benchmarks

clean:
	rm -rf $(VENV) .venv-core $(GVENV) out .pytest_cache .ruff_cache
