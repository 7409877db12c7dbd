# Bootstrap a local virtualenv on a fresh machine, then run tests, the main job, benchmarks.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: test test-all run bench clean venv

venv: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

# Fast suite (slow statistical tests deselected) on both cores (pytest-xdist; each test keeps
# its outputs under its own tmp_path); `make test-all` runs everything. Bytecode is written
# even where the environment sets PYTHONDONTWRITEBYTECODE: the xdist worker that collects
# second then reads the first one's rewritten test modules, and the ~15 CLI subprocesses the
# suite starts load the sources compiled instead of compiling them (clean clone, same code,
# runs alternated: 125 / 140 s CPU with bytecode against 136 / 150 s without).
XDIST := -n 2 --dist worksteal
BYTECODE := PYTHONDONTWRITEBYTECODE=

test: $(STAMP)
	$(VENV)/bin/ruff check --quiet .
	$(BYTECODE) $(PY) -m pytest -q -m "not slow" $(XDIST)

test-all: $(STAMP)
	$(VENV)/bin/ruff check --quiet .
	$(BYTECODE) $(PY) -m pytest -q $(XDIST)

# The default sweep (whole catalogue, DDMA vs TDMA, seed 0): tables in results/default, the
# summary printed, the HTML report, then the shipped gates with the verdict table (scheme x
# case). Rerunning resumes the completed cells of the same code version; --force recomputes
# cells an older code version left (a bare sweep refuses to mix them).
# Bytecode written here too: each of the three commands imports the whole package (a clean
# clone with PYTHONDONTWRITEBYTECODE set compiled its sources in every one, ~1 s apiece).
run: $(STAMP)
	$(BYTECODE) $(VENV)/bin/radar-harness sweep --workers 2 --force --out results/default
	$(BYTECODE) $(VENV)/bin/radar-harness report results/default
	$(BYTECODE) $(VENV)/bin/radar-harness gate results/default

bench: $(STAMP)
	$(BYTECODE) $(PY) -m benchmarks

clean:
	rm -rf $(VENV) build *.egg-info
