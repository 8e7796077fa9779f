# Two entry points on a fresh machine with only Python 3.10+:
#   make demo   builds the FMU and runs the default scenario, writing results/
#   make test   lint (ruff check, ruff format --check) and the whole test suite (what .ci/run calls)
# and make test-fast: the same without the tests marked slow.
# The suite runs on WORKERS processes (pytest-xdist; make test WORKERS=0 runs it in the one process of pytest).
PYTHON ?= python3
WORKERS ?= 2
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: venv demo lint test test-fast bench fmu clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP)

venv: $(STAMP)

fmu: $(STAMP)
	$(PY) build_fmu.py

demo: $(STAMP)
	$(PY) examples/demo.py --out results

lint: $(STAMP)
	$(PY) -m ruff check .
	$(PY) -m ruff format --check .

test: lint
	$(PY) -m pytest -q -ra --durations=15 -n $(WORKERS)

test-fast: lint
	$(PY) -m pytest -q -ra --durations=15 -n $(WORKERS) -m "not slow"

bench: $(STAMP)
	$(PY) benchmarks/bench_frequency.py
	$(PY) benchmarks/bench_time.py

clean:
	rm -rf $(VENV) dist build results *.egg-info
