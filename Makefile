# MultiBots: `make run` reproduces the paper's experiment, `make test` runs every test.
# Both install what they need: a virtual environment in .venv, the Rust build in target/.

SHELL := /bin/bash
PYTHON ?= python3
VENV := $(CURDIR)/.venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
EXT_STAMP := $(VENV)/.ext-built
TOOLS_STAMP := $(VENV)/.tools-installed
OUT ?= out/paper
RUST_SOURCES := $(shell find crates -name '*.rs' -o -name Cargo.toml 2>/dev/null) Cargo.toml
export VIRTUAL_ENV := $(VENV)
export PATH := $(VENV)/bin:$(PATH)

.PHONY: help run test test-rust test-python bench lint develop browser clean schema fuzz

schema: ## regenerate docs/schema/*.json and the field tables of docs/scenario-format.md
	cargo run -q -p multibots-core --example schema

help: ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

run: $(EXT_STAMP) ## run the paper's 30-run experiment: table, results.csv and figures in out/paper
	$(PY) -m multibots paper --out $(OUT)
	$(PY) -m multibots layout --out $(OUT)/layout.png

test: develop browser ## run every test: cargo, pytest (engine, CLI, viewer in Chromium)
	@echo "== the engine's tests (cargo, profile test-fast)"
	cargo test --profile test-fast --workspace --exclude multibots-py --exclude multibots-bench --lib --tests
	cargo test --profile test-fast -p multibots-core --doc
	@echo "== the package's tests (pytest)"
	$(PY) -m pytest -q

FUZZ_MINUTES ?= 10
fuzz: develop ## fuzz scenario, layout and replay files and CLI flags (Hypothesis) for FUZZ_MINUTES minutes, fresh seeds each round
	@end=$$(( $$(date +%s) + 60 * $(FUZZ_MINUTES) )); round=0; \
	while [ $$(date +%s) -lt $$end ]; do \
	  round=$$((round + 1)); seed=$$(od -An -N4 -tu4 /dev/urandom | tr -d ' '); \
	  echo "fuzz round $$round, seed $$seed"; \
	  MULTIBOTS_FUZZ=fuzz $(PY) -m pytest -q -p no:cacheprovider tests/fuzz --hypothesis-seed=$$seed || exit 1; \
	done

bench: develop ## benchmarks: criterion and Python scripts; figures go to docs/benchmarks.md
	cargo bench -p multibots-bench --bench step -- --quick
	$(PY) benchmarks/run_all.py

lint: develop ## clippy, rustfmt, ruff, the generated schema and docs, and the stubs against the binary
	cargo clippy --workspace --all-targets -- -D warnings
	cargo fmt --all -- --check
	cargo run -q -p multibots-core --example schema -- --check
	$(PY) -m ruff check .
	cd python && $(PY) -m mypy.stubtest multibots._core

develop: $(EXT_STAMP) $(TOOLS_STAMP) ## build the engine and install the package into .venv, with the test and lint extras

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q 'maturin>=1.7,<2'
	touch $@

# The engine alone, with what `make run` needs; cargo shows its progress.
$(EXT_STAMP): $(STAMP) $(RUST_SOURCES) pyproject.toml
	@echo "== building the engine (Rust, release; a few minutes the first time)"
	cd $(CURDIR) && maturin develop --release
	touch $@

# The test and lint extras (pytest, Playwright, Ray, ...), for `make test` and `make lint`.
$(TOOLS_STAMP): $(STAMP) pyproject.toml | $(EXT_STAMP)
	@echo "== installing the test and lint tools (the test and lint extras of pyproject.toml)"
	$(PY) -c "import sys; t = __import__('tomllib' if sys.version_info >= (3, 11) else 'tomli'); \
	  d = t.load(open('pyproject.toml', 'rb'))['project']['optional-dependencies']; \
	  print('\n'.join(x for e in ('test', 'lint') for x in d[e]))" > $(VENV)/tools.txt
	$(PY) -m pip install -q -r $(VENV)/tools.txt
	touch $@

browser: ## install Debian's chromium for the browser tests, if missing
	@command -v chromium >/dev/null 2>&1 || { \
	  echo "installing Debian's chromium"; \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null); }

clean: ## remove build output and the virtual environment
	rm -rf target .venv out
