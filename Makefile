# Two commands do all set-up on a fresh machine (see README.md):
#   make reproduce   -> every notebook on the embedded simulated data, written to reports/
#   make test        -> unit tests + every notebook in fast mode + lint
PY ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
SEED ?= 0
# Seeds over which every reproduced value gets its 95 % confidence interval (see reports/README.md).
SEEDS ?= 5

.PHONY: reproduce test lint lab bench notebooks clean

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -r environment.txt
	$(BIN)/python -m pip install --quiet --no-deps --no-build-isolation -e .
	touch $(STAMP)

reproduce: $(STAMP)
	$(BIN)/python -m ilocalg reproduce --seed $(SEED) --seeds $(SEEDS)

test: $(STAMP) lint
	$(BIN)/python -m pytest

lint: $(STAMP)
	$(BIN)/ruff check ilocalg ilocviz tests benchmarks notebooks
	$(BIN)/python -m ilocalg notebooks --check

lab: $(STAMP)
	$(BIN)/jupyter lab notebooks/

bench: $(STAMP)
	$(BIN)/python -m pytest benchmarks -o python_files='bench_*.py' -s

notebooks: $(STAMP)
	$(BIN)/python -m ilocalg notebooks --sync

clean:
	rm -rf reports/* .pytest_cache .ruff_cache
