# Two entry points that work on a fresh machine: `make demo` and `make test`.
# Each creates its own virtual environment in .venv (override with VENV=...).
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
CASE ?= cases/cycloid_pinhousing.toml
OUT ?= out/demo

.PHONY: demo test test-fast test-wheel lint probe schema venv clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,cad]'
	touch $@

venv: $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/toothfem check $(CASE)
	$(BIN)/toothfem run $(CASE) --out $(OUT)

# ruff (rules in pyproject.toml [tool.ruff]) on the package's four folders, the scripts and
# the tests; mypy on the package as it installs (tools/typecheck.py reads pyproject's package-dir mapping)
lint: $(VENV)/.installed
	$(BIN)/ruff check toothfem geometry fem efficiency benchmarks data tools tests
	$(BIN)/python tools/typecheck.py

# the suite over every core (pytest-xdist; worksteal: an idle worker takes half of the
# other's queue, the slow tests first in the collection: tests/conftest.py), on the FE
# tables kept between sessions (tests/conftest.py: TOOTHFEM_TEST_CACHE=fresh for cold)
test: lint
	$(BIN)/python -m pytest -q -rs -n auto --dist worksteal tests

test-fast: $(VENV)/.installed
	$(BIN)/python -m pytest -q -n auto --dist worksteal -m "not slow" tests

probe: $(VENV)/.installed
	$(BIN)/python benchmarks/adversarial_faults.py --quick

# docs/case_schema.md's tables from the case sections' field metadata (toothfem/case_schema.py):
# each <!-- schema: ... --> block rewritten, the prose between them kept;
# tests/test_case_schema.py fails while the file differs
schema: $(VENV)/.installed
	$(BIN)/python -m toothfem.case_schema docs/case_schema.md

clean:
	rm -rf $(VENV) $(WHEEL_VENV) out build *.egg-info

# the suite against the installed wheel (not the checkout): a regular install in its own
# environment, pytest run from outside the clone with --import-mode=importlib so that the
# clone's folders are not on sys.path (tests/conftest.py checks which toothfem it got)
WHEEL_VENV ?= .venv-wheel
test-wheel:
	rm -rf $(WHEEL_VENV)
	$(PYTHON) -m venv $(WHEEL_VENV)
	$(WHEEL_VENV)/bin/python -m pip install --quiet --upgrade pip
	$(WHEEL_VENV)/bin/python -m pip install --quiet '.[test,cad]'
	cd /tmp && TOOTHFEM_TEST_WHEEL=1 $(CURDIR)/$(WHEEL_VENV)/bin/pytest -q -p no:cacheprovider \
	    -n auto --dist worksteal \
	    --import-mode=importlib --rootdir $(CURDIR) $(CURDIR)/tests
