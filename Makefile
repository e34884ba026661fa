# trikedyn: `make run` and `make test` set up .venv on first use, then run.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= trikedyn-output
STAMP := $(VENV)/.installed

.PHONY: run test test-all bench morris-seeds docs fuzz lint clean

$(STAMP): pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	$(BIN)/python -m compileall -q src/trikedyn  # the bytecode a wheel's install writes: every command starts sooner
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/trikedyn reproduce --out $(OUT) --force

test: $(STAMP)  # one test process per core (pytest-xdist); a test file's tests stay in one process; not the slow tier
	$(BIN)/python -m pytest -q -n auto --dist loadfile -m "not slow"

test-all: $(STAMP)  # every test, the slow tier too (a real Dask cluster, the paper study searched twice, ...)
	$(BIN)/python -m pytest -q -n auto --dist loadfile

fuzz: $(STAMP)
	TRIKEDYN_FUZZ_EXAMPLES=$${FUZZ_EXAMPLES:-12500} $(BIN)/python -m pytest -q -p no:cacheprovider tests/fuzz

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet commonroad-vehicle-models  # the peer, for the bench only
	$(BIN)/python benchmarks/run.py

morris-seeds: $(STAMP)  # issue 19: the Morris ranking of the assumed values against the seed (about 3 min)
	$(BIN)/python benchmarks/morris_seeds.py

docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/python -m mkdocs build --strict

lint: $(STAMP)
	$(BIN)/ruff check src tests

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache build/site
