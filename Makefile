# Two commands for a fresh machine with only Python 3.11+:
#   make demo   - install spurdyn (without the test extras) into .venv and run the paper's
#                 Fig. 8 case (out/paper-fig8)
#   make test   - install spurdyn with its test extras and run the whole test suite (what CI
#                 runs) on both cores (pytest-xdist), printing its 30 slowest tests
# and for the inner loop:
#   make check  - the fast tier: the same less the tests marked `slow` (pyproject.toml)
# Times: docs/performance.md, "The test suite's time".
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
RUN_STAMP := $(VENV)/.installed-run

.PHONY: demo test check install clean

# Two workers; tests that share a module fixture go to one of them (tests/conftest.py).
# Bytecode is written (as compileall does for src below) so that the assertion rewriting of
# the ~50 test files, done by each worker, is done once.
PYTEST := PYTHONDONTWRITEBYTECODE= $(BIN)/python -m pytest -q -n 2 --dist loadgroup

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# The demo needs the package alone; the tests add their extras (pytest, Hypothesis, xdist,
# Selenium: a sixth of a fresh install's time, docs/performance.md).
$(RUN_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e .
	@# pip byte-compiles a regular install but not an editable one; where Python may not
	@# write bytecode itself (PYTHONDONTWRITEBYTECODE), every command would compile the
	@# ~60 modules it imports again (~80 ms a start, docs/performance.md).
	$(BIN)/python -m compileall -q src
	touch $(RUN_STAMP)

$(STAMP): $(RUN_STAMP)
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $(STAMP)

install: $(STAMP)

demo: $(RUN_STAMP)
	$(BIN)/spurdyn run paper-fig8 --force

test: install
	$(PYTEST) --durations=30

check: install
	$(PYTEST) -m "not slow"

clean:
	rm -rf $(VENV) out
