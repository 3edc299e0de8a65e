# photolib course: two commands do everything on a fresh machine.
#   make lab   -> .venv with the course extras, JupyterLab on notebooks/00-start.ipynb
#   make test  -> .venv with the test extras, every test (unit, doctest, codegen sync, nbval, grader, browser)
#   make test-fast -> the unit tests and doctests not marked slow or browser (under 90 s on 2 cores)
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
PORT   ?= 8888
IP     ?= 127.0.0.1
# Headless by default: set OPEN_BROWSER=1 to let JupyterLab open a browser tab. (Not BROWSER:
# Python's webbrowser module reads $BROWSER as the command of the browser to start.)
OPEN_BROWSER ?= 0
# Empty token: JupyterLab listens on 127.0.0.1 only and answers /lab without login.
# As root (containers, CI) JupyterLab needs --allow-root, which the lab target adds.
TOKEN  ?=
JOBS   ?= 2
# The lock: exact versions of everything the course installs (pip -c), refreshed by make lock.
LOCK   := constraints.txt

.PHONY: lab test test-fast bench regen assign lock clean help

help:
	@echo "make lab    - install the course into $(VENV) and start JupyterLab (PORT=$(PORT), OPEN_BROWSER=$(OPEN_BROWSER))"
	@echo "make test   - install the test extras into $(VENV) and run every test"
	@echo "make test-fast - ruff and the unit tests and doctests not marked slow or browser;"
	@echo "              no nbval, no browser test (make test runs those)"
	@echo "make bench  - run the benchmarks in benchmarks/ (not part of the tests)"
	@echo "make regen  - regenerate photolib/_generated from photolib/derive and the errata verdict table"
	@echo "make assign - regenerate the student copies in exercises/ from solutions/"
	@echo "make lock   - refresh $(LOCK) with the newest versions pyproject.toml allows"

$(BIN)/python:
	@$(PYTHON) -m venv $(VENV) || { rm -rf $(VENV); \
	  echo "make: '$(PYTHON) -m venv' failed. On Debian/Ubuntu install the venv module first:"; \
	  echo "      sudo apt install python3-venv"; exit 1; }
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.course-installed: pyproject.toml $(LOCK) | $(BIN)/python
	$(BIN)/python -m pip install --quiet -c $(LOCK) -e '.[course]'
	touch $@

$(VENV)/.test-installed: pyproject.toml $(LOCK) | $(BIN)/python
	$(BIN)/python -m pip install --quiet -c $(LOCK) -e '.[test]'
	touch $@ $(VENV)/.course-installed

lab: $(VENV)/.course-installed
	$(BIN)/python -m jupyter lab notebooks/00-start.ipynb \
		--ServerApp.ip=$(IP) --ServerApp.port=$(PORT) --ServerApp.port_retries=0 \
		--ServerApp.root_dir=$(CURDIR) \
		--IdentityProvider.token='$(TOKEN)' --ServerApp.password='' \
		$(if $(filter 1 yes true,$(OPEN_BROWSER)),,--no-browser) \
		$(if $(filter 0,$(shell id -u)),--allow-root)

test: $(VENV)/.test-installed
	$(BIN)/python -m ruff check photolib tests benchmarks conftest.py
	$(BIN)/python -m pytest -q -n $(JOBS) -m "not browser" tests photolib --doctest-modules
	$(BIN)/python -m pytest -q -n $(JOBS) --dist loadfile --nbval --nbval-sanitize-with tests/nbval_sanitize.cfg \
		notebooks/*.ipynb solutions/*.ipynb
	@if ls exercises/*.ipynb >/dev/null 2>&1; then \
		$(BIN)/python -m pytest -q -n $(JOBS) --dist loadfile --nbval-lax exercises/*.ipynb; \
	else echo "no exercise notebooks yet"; fi
	$(BIN)/python -m pytest -q -rs -m browser tests

# The quick loop while editing: the tests marked slow (more than ~2 s each, mostly the grader's
# sandboxed kernels, see tests/grading) and browser are deselected, and the nbval runs are left
# out. pytest prints how many were deselected by marker (tests/conftest.py); the echo says what
# else did not run, also when a test failed.
test-fast: $(VENV)/.test-installed
	$(BIN)/python -m ruff check photolib tests benchmarks conftest.py
	@$(BIN)/python -m pytest -q -n $(JOBS) -m "not slow and not browser" tests photolib --doctest-modules; \
	status=$$?; \
	echo "make test-fast: tests marked slow or browser were deselected (counted above);"; \
	echo "  not run either: strict nbval of notebooks/ and solutions/, lax nbval of exercises/,"; \
	echo "  the real-browser test. 'make test' runs all of them."; \
	exit $$status

bench: $(VENV)/.test-installed
	$(BIN)/python -m benchmarks

regen: $(VENV)/.test-installed
	$(BIN)/python -m photolib.codegen
	$(BIN)/python -m photolib errata --write-table

assign: $(VENV)/.test-installed
	$(BIN)/python -m photolib assign

# A scratch environment gets the newest versions pyproject.toml allows and its freeze becomes the
# lock. Afterwards run make test: where strict nbval fails, the new versions print differently and
# the notebooks' outputs must be re-executed and reviewed before the new lock is committed.
LOCK_VENV := .lock-venv
lock:
	rm -rf $(LOCK_VENV)
	$(PYTHON) -m venv $(LOCK_VENV)
	$(LOCK_VENV)/bin/python -m pip install --quiet --upgrade pip
	$(LOCK_VENV)/bin/python -m pip install --quiet '.[test]'
	{ echo "# The course environment's lock: the exact versions the committed notebook outputs were produced with."; \
	  echo "# make lab and make test install with pip -c $(LOCK); make lock refreshes it (see README)."; \
	  echo "# Generated by 'make lock' on $$(date -u +%Y-%m-%d) (Python $$($(LOCK_VENV)/bin/python -c 'import platform; print(platform.python_version())'), $$(uname -m) $$(uname -s)); do not edit by hand."; \
	  $(LOCK_VENV)/bin/python -m pip freeze --exclude photolib; } > $(LOCK).new
	mv $(LOCK).new $(LOCK)
	rm -rf $(LOCK_VENV) build *.egg-info
	@echo "make lock: $(LOCK) refreshed; now run make test and re-execute notebooks whose outputs changed"

clean:
	rm -rf $(VENV) $(LOCK_VENV) .pytest_cache build *.egg-info
