# Two entry points that work on a fresh machine: `make demo` and `make test`.
# Each creates its own virtual environment in .venv (override with VENV=...).
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
CASE ?= cases/cycloid_pinhousing.toml
OUT ?= out/demo

.PHONY: demo test test-fast lint probe venv clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,cad]'
	touch $@

venv: $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/toothfem check $(CASE)
	$(BIN)/toothfem run $(CASE) --out $(OUT)

# ruff (rules in pyproject.toml [tool.ruff]) on the four source folders (ruff does not
# follow the toothfem/{geometry,fem,efficiency} symlinks), mypy on the package
lint: $(VENV)/.installed
	$(BIN)/ruff check toothfem geometry fem efficiency
	$(BIN)/mypy

test: lint
	$(BIN)/python -m pytest -q -rs tests

test-fast: $(VENV)/.installed
	$(BIN)/python -m pytest -q -m "not slow" tests

probe: $(VENV)/.installed
	$(BIN)/python benchmarks/adversarial_faults.py --quick

clean:
	rm -rf $(VENV) out build *.egg-info
