# clap_unified: two commands set everything up on a fresh machine.
#   make book   -> .venv from environment.lock, package installed, executed book in book/_build/html
#   make test   -> same set-up, then lint, the book built, unit tests + doctests (with a browser
#                  test of the built book), and pytest --nbval over every chapter
# Both are idempotent: the second run only redoes what changed.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
UV_VERSION := 0.13.9
STAMP  := $(VENV)/.installed
export UV_PYTHON_DOWNLOADS := never
export OPEN3D_DISABLE_WEB_VISUALIZER := true
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# The library multiplies many small matrices: OpenBLAS's worker threads cost more than
# they give there (3-10x slower on a busy 2-core machine). Results do not depend on it.
export OPENBLAS_NUM_THREADS ?= 1

.PHONY: all book test lint unit nbval bench lock system clean

all: book

# Debian packages (libusb-1.0-0 for open3d; chromium and its driver for the browser test).
# Installs only when root and missing.
system:
	@bash .ci/install-system-packages.sh

$(STAMP): environment.lock pyproject.toml .ci/install-system-packages.sh
	@bash .ci/install-system-packages.sh
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	@$(VENV)/bin/uv --version >/dev/null 2>&1 || $(PY) -m pip install --quiet --disable-pip-version-check "uv==$(UV_VERSION)"
	$(VENV)/bin/uv pip sync --quiet --python $(PY) --compile-bytecode environment.lock
	$(VENV)/bin/uv pip install --quiet --python $(PY) --no-deps --no-build-isolation -e .
	@touch $(STAMP)

venv: $(STAMP)

book: $(STAMP)
	$(VENV)/bin/jupyter-book build -W -n --keep-going book/

lint: $(STAMP)
	$(VENV)/bin/ruff check clap_unified tests bench

unit: $(STAMP)
	$(PY) -m pytest -q tests clap_unified

nbval: $(STAMP)
	$(PY) -m pytest -q --nbval book/chapters

# The book is built first (executed, warnings as errors) so that the browser test
# (tests/test_book_browser.py) checks the pages a reader gets.
test: $(STAMP)
	$(VENV)/bin/ruff check clap_unified tests bench
	$(VENV)/bin/jupyter-book build -W -n --keep-going book/
	$(PY) -m pytest -q tests clap_unified
	$(PY) -m pytest -q --nbval book/chapters

bench: $(STAMP)
	@for f in bench/bench_*.py; do echo "== $$f"; $(PY) $$f || exit 1; done

# Regenerate the lock (exact pins with hashes, no index URLs). Needs network to PyPI.
lock:
	@$(VENV)/bin/uv --version >/dev/null 2>&1 || { $(PYTHON) -m venv $(VENV) && $(PY) -m pip install --quiet "uv==$(UV_VERSION)"; }
	$(VENV)/bin/uv pip compile pyproject.toml --extra book --extra test \
	  --python-version 3.11.7 --generate-hashes --no-header --no-emit-index-url -o environment.lock

clean:
	rm -rf book/_build .pytest_cache
