# Two commands on a fresh machine (each builds .venv when it is missing):
#   make repro   runs the pipeline (`dvc repro`) on params.yaml
#   make test    runs the test suite in its three layers: unit (default), integration, slow
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
export PATH := $(CURDIR)/$(BIN):$(PATH)
export MLFLOW_DISABLE_TELEMETRY := true
export DVC_NO_ANALYTICS := true
export MLFLOW_TRACKING_URI ?= sqlite:///$(CURDIR)/mlflow.db

.PHONY: repro test test-fast bench lint

# The report test renders in headless Chromium (Debian's package; no browser download).
CHROMIUM := /usr/bin/chromium
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

$(VENV)/.installed: pyproject.toml constraints.txt
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet torch==2.13.0
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[dev,bench]'
	touch $@

repro: $(VENV)/.installed
	dvc repro

$(CHROMIUM):
	$(SUDO) apt-get update -qq
	DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq chromium

# Three disjoint layers, cheapest first, so a broken unit fails in a minute (README, Set-up).
test: $(VENV)/.installed $(CHROMIUM)
	pytest -q
	pytest -q -m integration
	pytest -q -m slow

test-fast: $(VENV)/.installed
	pytest -q

bench: $(VENV)/.installed
	for b in bench/bench_*.py; do python $$b || exit 1; done

lint: $(VENV)/.installed
	ruff check .
	ruff format --check .
