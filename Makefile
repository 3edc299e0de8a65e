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

.PHONY: lab test test-fast bench regen assign lock clean help hub-install hub test-hub binder test-binder site test-site

help:
	@echo "make lab    - install the course into $(VENV) and start JupyterLab (PORT=$(PORT), OPEN_BROWSER=$(OPEN_BROWSER))"
	@echo "make test   - install the test extras into $(VENV) and run every test"
	@echo "make test-fast - ruff and the unit tests and doctests not marked slow or browser;"
	@echo "              no nbval, no browser test (make test runs those)"
	@echo "make bench  - run the benchmarks in benchmarks/ (not part of the tests)"
	@echo "make regen  - regenerate photolib/_generated from photolib/derive and the errata verdict table"
	@echo "make assign - regenerate the student copies in exercises/ from solutions/"
	@echo "make lock   - refresh $(LOCK) with the newest versions pyproject.toml allows"
	@echo "make site   - the course website from the executed notebooks into $(SITE_OUT)/html (no network)"
	@echo "make test-site - build the website and test it in headless Chromium (TOC, figures, search, links)"
	@echo "make hub-install - JupyterHub into $(VENV), configurable-http-proxy into deploy/jupyterhub"
	@echo "make hub    - the class's one-server JupyterHub on http://$(IP):$(HUB_PORT) (as root)"
	@echo "make test-hub - the hub's end-to-end test (root: two student accounts, collect, grade, return)"

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
	$(BIN)/python -m ruff check photolib tests benchmarks site conftest.py
	$(BIN)/python -m pytest -q -n $(JOBS) -m "not browser and not hub and not binder and not site" tests photolib --doctest-modules
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
	$(BIN)/python -m ruff check photolib tests benchmarks site conftest.py
	@$(BIN)/python -m pytest -q -n $(JOBS) -m "not slow and not browser and not hub and not binder and not site" tests photolib --doctest-modules; \
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
	$(LOCK_VENV)/bin/python -m pip install --quiet '.[test,hub,site]'
	{ echo "# The course environment's lock: the exact versions the committed notebook outputs were produced with."; \
	  echo "# make lab and make test install with pip -c $(LOCK); make lock refreshes it (see README)."; \
	  echo "# Generated by 'make lock' on $$(date -u +%Y-%m-%d) (Python $$($(LOCK_VENV)/bin/python -c 'import platform; print(platform.python_version())'), $$(uname -m) $$(uname -s)); do not edit by hand."; \
	  $(LOCK_VENV)/bin/python -m pip freeze --exclude photolib; } > $(LOCK).new
	mv $(LOCK).new $(LOCK)
	rm -rf $(LOCK_VENV) build *.egg-info
	@echo "make lock: $(LOCK) refreshed; now run make test and re-execute notebooks whose outputs changed"

# The course as a website (site/build_site.py): the executed chapters, the glossary and the
# student copies as static HTML with Sphinx, myst-nb and sphinx-book-theme (the site extra, PyPI)
# and MathJax (site/package-lock.json, npm registry). Nothing is executed and nothing is
# downloaded when the site is built or viewed.
SITE_OUT ?= build/site
$(VENV)/.site-installed: pyproject.toml $(LOCK) | $(BIN)/python
	$(BIN)/python -m pip install --quiet -c $(LOCK) -e '.[test,site]'
	touch $@ $(VENV)/.test-installed $(VENV)/.course-installed

site/node_modules/mathjax/es5/tex-mml-chtml.js: site/package.json site/package-lock.json
	cd site && npm ci --no-audit --no-fund --silent
	touch $@

site: $(VENV)/.site-installed site/node_modules/mathjax/es5/tex-mml-chtml.js
	$(BIN)/python site/build_site.py --out $(SITE_OUT)

test-site: $(VENV)/.site-installed site/node_modules/mathjax/es5/tex-mml-chtml.js
	$(BIN)/python -m pytest -q -rs -m site tests/site

# A class on one server (deploy/jupyterhub, docs/instructors.md "Run a class"): the course once
# more, with JupyterHub from PyPI, in an environment of its own (HUB_VENV) that every student's
# server runs (jupyterhub-singleuser). Its Python must be one the students may execute: where
# PYTHON's is not (pyenv's under /root), deploy/jupyterhub/hub-python copies it to .hub-python.
# The proxy comes from the npm registry at the versions of deploy/jupyterhub/package-lock.json.
HUB_DIR    := deploy/jupyterhub
HUB_PORT   ?= 8000
HUB_VENV   ?= .hub-venv
HUB_PYTHON ?= $(PYTHON)
$(HUB_VENV)/.hub-installed: pyproject.toml $(LOCK)
	@test -x $(HUB_VENV)/bin/python || { py=$$($(HUB_DIR)/hub-python $$(command -v $(HUB_PYTHON)) $(CURDIR)/.hub-python) && \
	  $$py -m venv $(HUB_VENV); } || { rm -rf $(HUB_VENV); \
	  echo "make: no environment for the hub from $(HUB_PYTHON) (python3-venv installed?)"; exit 1; }
	$(HUB_VENV)/bin/python -m pip install --quiet --upgrade pip
	$(HUB_VENV)/bin/python -m pip install --quiet -c $(LOCK) -e '.[course,hub]'
	touch $@
$(HUB_DIR)/node_modules/.bin/configurable-http-proxy: $(HUB_DIR)/package-lock.json
	@command -v npm >/dev/null 2>&1 || { echo "make: npm not found (apt install npm); no configurable-http-proxy"; exit 1; }
	npm ci --prefix $(HUB_DIR) --no-audit --no-fund --loglevel=error
	touch $@

hub-install: $(HUB_VENV)/.hub-installed $(HUB_DIR)/node_modules/.bin/configurable-http-proxy

hub: hub-install
	@if [ "$$(id -u)" != 0 ]; then echo "make hub: run as root (one system user per student)"; exit 1; fi
	PHOTOLIB_HUB_IP=$(IP) PHOTOLIB_HUB_PORT=$(HUB_PORT) PHOTOLIB_HUB_PYTHON=$(CURDIR)/$(HUB_VENV)/bin/python \
		$(HUB_VENV)/bin/jupyterhub -f $(HUB_DIR)/jupyterhub_config.py

# The test skips (saying why) where it is not root or the proxy could not be installed.
test-hub: $(VENV)/.test-installed $(HUB_VENV)/.hub-installed
	-@$(MAKE) --no-print-directory $(HUB_DIR)/node_modules/.bin/configurable-http-proxy
	PHOTOLIB_HUB_PYTHON=$(CURDIR)/$(HUB_VENV)/bin/python \
		$(BIN)/python -m pytest -q -rs -s -p no:xdist -m hub tests/hub

# Binder: binder/requirements.txt is the lock (every pin of constraints.txt), binder/postBuild
# installs the course on top; tests/test_binder.py checks it is in sync with the lock and
# (make test-binder) builds it in a fresh venv and runs chapter 00 under strict nbval.
binder/requirements.txt: $(LOCK)
	{ echo "# Binder's environment: the lock ($(LOCK)), generated by 'make binder'; do not edit."; \
	  echo "# binder/postBuild then installs the course itself (pip install --no-deps -e .)."; \
	  grep -v '^#' $(LOCK); } > $@
binder: binder/requirements.txt

test-binder: $(VENV)/.test-installed binder/requirements.txt
	$(BIN)/python -m pytest -q -rs -s -p no:xdist -m binder tests/test_binder.py

clean:
	rm -rf $(VENV) $(LOCK_VENV) $(HUB_VENV) .hub-python .pytest_cache build *.egg-info .hub-state $(HUB_DIR)/node_modules
