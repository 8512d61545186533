# Two commands for a fresh machine with only Python 3.11+:
#   make demo   - install spurdyn into .venv and run the paper's Fig. 8 case (out/paper-fig8)
#   make test   - install spurdyn with its test extras and run the whole test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test install clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[test]"
	@# pip byte-compiles a regular install but not an editable one; where Python may not
	@# write bytecode itself (PYTHONDONTWRITEBYTECODE), every command would compile the
	@# ~60 modules it imports again (~80 ms a start, docs/performance.md).
	$(BIN)/python -m compileall -q src
	touch $(STAMP)

install: $(STAMP)

demo: install
	$(BIN)/spurdyn run paper-fig8 --force

test: install
	$(BIN)/python -m pytest -q

clean:
	rm -rf $(VENV) out
