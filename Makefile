# navlab: `make repro` sets up and regenerates every report (default profile); `make test` runs the tests.
PY      ?= python3.11
VENV    := .venv
BIN     := $(VENV)/bin
STAMP   := $(VENV)/.installed

.PHONY: setup data repro test test-fast lab clean-venv

setup: $(STAMP)

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --disable-pip-version-check -r environment.txt
	$(BIN)/python -m pip install -q --disable-pip-version-check --no-deps -e .
	touch $(STAMP)

data: setup
	$(BIN)/python -m navlab data build

# dvc.yaml and params.resolved.yaml are generated (navlab.pipeline.dvc_yaml); the `data` stage builds data/.
repro: setup
	$(BIN)/python -m navlab pipeline write
	PATH=$(abspath $(BIN)):$$PATH $(BIN)/dvc repro

# The whole suite, as CI runs it: unit and property tests, every notebook in `smoke`, the browser check,
# `params check` over every profile, and `pipeline check` (dvc.lock describes the tree).
test: setup
	PATH=$(abspath $(BIN)):$$PATH $(BIN)/python -m pytest

# For development: the same without the notebook runs, the browser and the lock check (which fails after
# any code change until `dvc repro` has run): minutes, not a quarter hour.
test-fast: setup
	PATH=$(abspath $(BIN)):$$PATH $(BIN)/python -m pytest -m "not notebook and not browser and not provenance"

lab: setup
	$(BIN)/python -m navlab lab

clean-venv:
	rm -rf $(VENV)
