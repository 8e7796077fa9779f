# Two entry points on a fresh machine with only Python 3.10+:
#   make demo   builds the FMU and runs the default scenario, writing results/
#   make test   runs the test suite
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: venv demo test bench fmu clean

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

test: $(STAMP)
	$(PY) -m pytest -q -ra

bench: $(STAMP)
	$(PY) benchmarks/bench_frequency.py
	$(PY) benchmarks/bench_time.py

clean:
	rm -rf $(VENV) dist build results *.egg-info
