# Two commands do all set-up on a fresh machine (see README.md):
#   make reproduce   -> every notebook on the embedded simulated data, written to reports/
#   make test        -> unit tests + every notebook in fast mode + every bench once at its smoke size + lint
PY ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
SEED ?= 0
# Seeds over which every reproduced value gets its 95 % confidence interval (see reports/README.md).
SEEDS ?= 5

.PHONY: reproduce test lint lab bench notebooks clean browser measured

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -r environment.txt
	$(BIN)/python -m pip install --quiet --no-deps --no-build-isolation -e .
	touch $(STAMP)

reproduce: $(STAMP)
	$(BIN)/python -m ilocalg reproduce --seed $(SEED) --seeds $(SEEDS)

# The suite in TEST_WORKERS processes (pytest-xdist; one per core of the 2-core CI machine). Each test file runs
# whole in one worker (its module fixtures are built once; tests/conftest.py keeps the claims files together and
# hands the longest files out first). TEST_WORKERS=0 runs it in this process, in name order. The log ends with the
# 25 slowest tests (setup and call), where the suite's time goes (goal: the whole suite under 15 minutes on CI).
TEST_WORKERS ?= 2
test: $(STAMP) lint browser
	$(BIN)/python -m pytest -n $(TEST_WORKERS) --dist loadfile --no-loadscope-reorder --durations=25

# Headless Chromium renders reports/index.html in a test (every figure loads). Installed from the system
# packages only when missing; without it that test skips on a developer machine and fails under CI=true.
browser:
	@command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || \
	  { apt-get update -qq && apt-get install -y -qq chromium; } || \
	  echo "could not install chromium (needs root): the landing-page browser test will skip"

lint: $(STAMP)
	$(BIN)/ruff check ilocalg ilocviz tests benchmarks notebooks
	$(BIN)/python -m ilocalg notebooks --check

# JupyterLab with the project's settings (.jupyter/): a paired notebooks/*.py opens as a notebook, and the
# file browser hides the .ipynb side of each pair (jupyter_server_config.json, hide_globs).
# Open one directly with e.g. `make lab NB=notebooks/07_fusion_iloc_kf.py`.
NB ?= notebooks/
lab: $(STAMP)
	JUPYTER_CONFIG_PATH=$(CURDIR)/.jupyter $(BIN)/jupyter lab $(NB)

# Every benchmark, then the gate: a table (benchmark, measure, measured, goal, pass) of benchmarks/goals.toml
# against this run's measures; exits non-zero when a bench fails or a goal is missed. Timings mean
# something only on an otherwise idle machine.
BENCH_RESULTS := .benchmarks/results.json
bench: $(STAMP)
	rm -f $(BENCH_RESULTS)
	status=0; ILOC_BENCH_RESULTS=$(BENCH_RESULTS) $(BIN)/python -m pytest benchmarks -o python_files='bench_*.py' \
	  -s || status=1; $(BIN)/python benchmarks/gate.py $(BENCH_RESULTS) benchmarks/goals.toml || status=1; \
	  exit $$status

notebooks: $(STAMP)
	$(BIN)/python -m ilocalg notebooks --sync

clean:
	rm -rf reports/* .pytest_cache .ruff_cache

# data/measured_parameters.csv from ../shared/data (the simulators' measured defaults; a few minutes).
measured: $(STAMP)
	$(BIN)/python -m ilocalg measure
