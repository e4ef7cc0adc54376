# blurloc: setup, reproduce, test. Each target is idempotent and runs setup itself.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
QUICK ?= 0

.PHONY: setup reproduce test lint docs benchmarks clean

setup: $(STAMP)

$(STAMP): requirements.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r requirements.txt
	touch $(STAMP)

## Run every notebook in order with papermill into build/ (figures into figures/). QUICK=1: small sizes.
reproduce: setup
	$(BIN)/blurloc run-notebooks $(if $(filter 1 true yes,$(QUICK)),--quick,)

test: setup
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks
	$(BIN)/python -m pytest -q

## The book: README, docs/ and the executed notebooks as a static site in build/site (offline).
docs: setup $(VENV)/.docs-installed
	$(BIN)/python docs/stage_book.py build/book-src
	NO_MKDOCS_2_WARNING=1 $(BIN)/python -m mkdocs build --clean --quiet

$(VENV)/.docs-installed: requirements-docs.txt $(STAMP)
	$(BIN)/python -m pip install --quiet -r requirements-docs.txt
	touch $@

## The cheap benchmarks (no rendered stand-in, 1-3 min each), tables into figures/.
BENCHMARKS_CHEAP := bench_deblur bench_deblur_folder bench_video_deblur bench_synth
benchmarks: setup
	set -e; for name in $(BENCHMARKS_CHEAP); do $(BIN)/python benchmarks/$$name.py; done

lint: setup
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks

clean:
	rm -rf build results data/standin-quick
