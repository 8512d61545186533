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
UV     := $(VENV)/uv/bin/uv

.PHONY: demo test check install clean

# Two workers; tests that share a module fixture go to one of them (tests/conftest.py).
# Bytecode is written (as compileall does for src below) so that the assertion rewriting of
# the ~50 test files, done by each worker, is done once.
PYTEST := PYTHONDONTWRITEBYTECODE= $(BIN)/python -m pytest -q -n 2 --dist loadgroup

# The installer is uv (from the package index, by the pip Python comes with, into .venv/uv):
# it fetches and unpacks the ~50 wheels in parallel and links them from its cache, where
# pip took half a minute for the same (docs/performance.md, "`make demo` installed with
# uv"). Where uv cannot be had, the venv gets pip and pip installs as before.
$(BIN)/python:
	$(PYTHON) -m venv --without-pip $(VENV)
	PIP_ROOT_USER_ACTION=ignore $(PYTHON) -m pip install --quiet --target $(VENV)/uv uv || { \
	    echo "make: uv could not be installed; installing with pip" >&2; \
	    $(BIN)/python -m ensurepip --upgrade --default-pip >/dev/null && \
	    $(BIN)/python -m pip install --quiet --upgrade pip; }

# install_with ARGS: uv's pip interface where uv is, else the venv's pip. uv does not
# byte-compile what it installs (pip does, all ~6,000 modules: about 30 s of CPU); the
# modules a command imports are compiled at its first import instead.
# uv's install failing (its index unreachable, say) falls back on pip as well.
install_with = if [ -x $(UV) ] && $(UV) pip install --quiet --python $(BIN)/python $(1); then :; else \
	echo "make: installing with pip" >&2; \
	$(BIN)/python -m pip --version >/dev/null 2>&1 || $(BIN)/python -m ensurepip --default-pip >/dev/null; \
	$(BIN)/python -m pip install --quiet $(1); fi

# The demo needs the package alone; the tests add their extras (pytest, Hypothesis, xdist,
# Selenium: a sixth of a fresh install's time, docs/performance.md).
$(RUN_STAMP): pyproject.toml | $(BIN)/python
	$(call install_with,-e .)
	@# An editable install is not byte-compiled by pip or uv; where Python may not write
	@# bytecode itself (PYTHONDONTWRITEBYTECODE), every command would compile the ~60
	@# modules it imports again (~80 ms a start, docs/performance.md).
	$(BIN)/python -m compileall -q src
	touch $(RUN_STAMP)

$(STAMP): $(RUN_STAMP)
	$(call install_with,-e ".[test]")
	touch $(STAMP)

install: $(STAMP)

# Bytecode is written (as for the tests below) so that the libraries' modules the run
# imports, which uv left uncompiled, are compiled once, here, not at every later command.
demo: $(RUN_STAMP)
	PYTHONDONTWRITEBYTECODE= $(BIN)/spurdyn run paper-fig8 --force

test: install
	$(PYTEST) --durations=30

check: install
	$(PYTEST) -m "not slow"

clean:
	rm -rf $(VENV) out
