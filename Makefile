# Two commands for a newcomer: `make run` and `make test`. Both bootstrap .venv first.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# `make run` installs what serving needs; `make test` adds the `test` extra (pytest, clients,
# Dask). Each install has its own stamp, so `make run` never pulls the test tools.
VENV_STAMP := $(VENV)/.created
RUN_STAMP := $(VENV)/.installed-run
TEST_STAMP := $(VENV)/.installed-test
# An editable install with a package-dir map makes setuptools print an information-only note
# ("Editable installation ... be careful with folders named like your package"); not a problem.
PIP_INSTALL := PYTHONWARNINGS="ignore:Editable installation" $(BIN)/python -m pip install -q

.PHONY: run test docker-test docker-image lint bench profile cov mutate plots fuzz screenshot clean

$(VENV_STAMP):
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	touch $(VENV_STAMP)

$(RUN_STAMP): pyproject.toml $(VENV_STAMP)
	$(PIP_INSTALL) -e .
	touch $(RUN_STAMP)

$(TEST_STAMP): pyproject.toml $(VENV_STAMP)
	$(PIP_INSTALL) -e '.[test]'
	touch $(TEST_STAMP)

run: $(RUN_STAMP)
	$(BIN)/motionsim serve

# The suite in one process (TEST_WORKERS=0, as `pytest` alone). TEST_WORKERS=auto spreads it
# over every core (pytest-xdist, a test file's tests in order in one worker): ~2.5x faster on 2
# cores, but a few tests are not yet isolated from the files another worker runs before them
# (a run of 3 725 had 5 fail), so it is not the default.
TEST_WORKERS ?= 0
test: $(TEST_STAMP)
	$(BIN)/ruff check .
	$(BIN)/pytest -n $(TEST_WORKERS) --dist loadfile

# The image and docker-compose.yml on a real Docker engine (tools/docker_test.py): the base image
# made from Debian packages if missing, the build, the image's health check, then compose's
# `up --build --exit-code-from client` (v2 `docker compose` or v1 `docker-compose`) checked
# for the client's streamed lines, and `down -v`. Bounded: DOCKER_TEST_TIMEOUT_S in all.
DOCKER_TEST_TIMEOUT_S ?= 1500
# Needs only the venv's Python and pip (not motionsim's own install).
docker-test: $(VENV_STAMP)
	$(BIN)/python tools/docker_test.py --timeout-s $(DOCKER_TEST_TIMEOUT_S)

# Its first steps only: the base image if missing, pip's settings for the build, docker build.
docker-image: $(VENV_STAMP)
	$(BIN)/python tools/docker_test.py --image-only --timeout-s $(DOCKER_TEST_TIMEOUT_S)

lint: $(TEST_STAMP)
	$(BIN)/ruff check .
	$(BIN)/python tools/mypy_strict.py

# Bigger fuzz budgets: hypothesis over every parser and codec (>= 10^5 cases, counts in
# fuzz-counts.json) and schemathesis over every operation, stateful phase included.
fuzz: $(TEST_STAMP)
	MOTIONSIM_FUZZ=1 $(BIN)/pytest -p no:cacheprovider -o timeout=3600 -s tests/fuzz tests/integration/test_schemathesis.py

# Every benchmark (each prints its table and writes bench/results/<name>.json), then the
# summary of every target (PASS / SHORT, a report, never a failure) into README's Performance.
bench: $(TEST_STAMP)
	@for f in bench/bench_*.py; do echo "== $$f"; $(BIN)/python $$f || echo "== $$f FAILED"; done
	$(BIN)/python bench/summary.py --readme

# Where the time of each benchmarked path goes (cProfile; `make profile PROFILES=core trio`).
profile: $(TEST_STAMP)
	$(BIN)/python bench/profiles.py $(PROFILES)

# Branch coverage of the whole suite, subprocesses included (pyproject [tool.coverage]).
cov: $(TEST_STAMP)
	rm -f .coverage .coverage.*
	$(BIN)/coverage run -m pytest
	$(BIN)/coverage combine -q
	$(BIN)/coverage report

# Mutation testing of the decision modules (tools/mutation.toml); slow: not part of `make test`.
# `make mutate MODULES=sim/pmac/buffers/rotary.py` for one module.
mutate: $(TEST_STAMP)
	$(BIN)/python -m pip install -q -e '.[test,mutation]'
	$(BIN)/python tools/mutate.py $(MUTATE_ARGS) $(MODULES)

# The README's plots, regenerated from the example scenarios (examples/scenarios/readme_plots.py).
plots: $(RUN_STAMP)
	$(BIN)/python examples/scenarios/readme_plots.py

# The README's dashboard pictures (docs/dashboard-*.png) from a real run in Debian's chromium.
screenshot: $(TEST_STAMP)
	$(BIN)/python -m tests.browser.screenshot docs

clean:
	rm -rf $(VENV) build *.egg-info .mutation .coverage .coverage.*
