# Two commands for a newcomer: `make run` and `make test`. Both bootstrap .venv first.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench cov mutate screenshot clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/motionsim serve

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/pytest

lint: $(STAMP)
	$(BIN)/ruff check .

# Every benchmark (each prints its table and writes bench/results/<name>.json), then the
# summary of every target (PASS / SHORT, a report, never a failure) into README's Performance.
bench: $(STAMP)
	@for f in bench/bench_*.py; do echo "== $$f"; $(BIN)/python $$f || echo "== $$f FAILED"; done
	$(BIN)/python bench/summary.py --readme

# Branch coverage of the whole suite, subprocesses included (pyproject [tool.coverage]).
cov: $(STAMP)
	rm -f .coverage .coverage.*
	$(BIN)/coverage run -m pytest
	$(BIN)/coverage combine -q
	$(BIN)/coverage report

# Mutation testing of the decision modules (tools/mutation.toml); slow: not part of `make test`.
# `make mutate MODULES=sim/pmac/rotary.py` for one module.
mutate: $(STAMP)
	$(BIN)/python -m pip install -q -e '.[test,mutation]'
	$(BIN)/python tools/mutate.py $(MODULES)

# The README's dashboard pictures (docs/dashboard-*.png) from a real run in Debian's chromium.
screenshot: $(STAMP)
	$(BIN)/python -m tests.browser.screenshot docs

clean:
	rm -rf $(VENV) build *.egg-info .mutation .coverage .coverage.*
