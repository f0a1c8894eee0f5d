# Two commands from a fresh clone: `make demo` and `make test`. Each sets everything up first.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
INSTALLED := $(VENV)/.turtle_traj-installed
INTERFACES := $(VENV)/.turtle_traj-interfaces
INTERFACE_FILES := $(shell find interfaces -type f -not -name '*.pyc')

.PHONY: setup test check demo bench lint docs clean

# Our own modules' bytecode, as they are now (0.1 s when up to date).
setup: $(INTERFACES)
	@$(PY) -m compileall -q -j 0 src > /dev/null

$(PY):
	$(PYTHON) -m venv $(VENV)

# Re-install only when the project metadata changed. uv (from PyPI) installs the ~220 packages
# in parallel: a fresh venv in about 12 s here against 41 s with pip (no caches); pip is the
# fallback.
# Bytecode is written at install (uv writes none by default): where PYTHONDONTWRITEBYTECODE is
# set, as on this machine, Python never caches it, and each of the suite's processes compiled
# numpy, rclpy and the messages again, 0.65 s of CPU for a command-line call alone.
$(INSTALLED): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet --disable-pip-version-check uv
	$(VENV)/bin/uv pip install --quiet --compile-bytecode --python $(PY) -e '.[dev,interfaces,physics]' \
	  || $(PY) -m pip install --quiet --disable-pip-version-check -e '.[dev,interfaces,physics]'
	touch $@

# Rebuild the interface packages only when one of their files changed.
$(INTERFACES): $(INSTALLED) $(INTERFACE_FILES)
	interfaces/build.sh $(VENV)
	$(PY) -m compileall -q -j 0 $(VENV)/lib > /dev/null
	touch $@

# Three workers, a test file each at a time: the subprocess-heavy files mostly wait (on DDS
# discovery and real-time drawings), so with two the suite used one core of two (101% CPU,
# 185-199 s quiet); with three, 145 s quiet and 240 s under two busy loops (medians of paired
# runs; each worker claims its own ROS_DOMAIN_ID). One quiet run in 17 was red at three: a bag's
# real-time replay drew its circle 0.185 m off, because a publish() had waited 333 ms on Fast
# DDS's shared-memory health check (our profile now sends by UDP only: bench/transport_bench.py).
# The files go out in the order tests/conftest.py gives them, the slowest first, so the workers
# finish together: xdist's default reorders them by their count of tests, and the two-host file
# (a minute) started 85 s in, its worker done 25-35 s before the other. PYTEST_ARGS adds
# options (`--durations=20`).
test: setup
	$(PY) -m pytest -q -rs -n 3 --dist loadfile --no-loadscope-reorder $(PYTEST_ARGS)

# Between edits: every test but the system tests (programs, namespaces, a browser, colcon),
# one test at a time to each worker.
check: setup
	$(PY) -m pytest -q -n 2 --dist load -m 'not system' $(PYTEST_ARGS)

demo: setup
	$(PY) -m turtle_traj.apps.demo

bench: setup
	for script in bench/*_bench.py; do $(PY) $$script || exit 1; done

# ruff, and import-linter's contracts: packages import downwards, the simulator knows no
# trajectories, the core and the web server load no ROS. Cyclomatic complexity (radon's ranks,
# through xenon): at most B in the control core and the node, at most C anywhere.
lint: setup
	$(VENV)/bin/ruff check src tests bench ros/turtle_traj/setup.py ros/turtle_traj/launch
	$(VENV)/bin/lint-imports --no-logo  # the architecture: the contracts in pyproject.toml
	$(VENV)/bin/xenon --max-absolute B src/turtle_traj/core/control src/turtle_traj/node
	$(VENV)/bin/xenon --max-absolute C src

# The documentation site (Sphinx, MyST Markdown): warnings are errors, so a broken
# cross-reference or a reference table that no longer builds fails. No network is used.
docs: setup
	$(VENV)/bin/sphinx-build -q -E -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf $(VENV) output docs/_build
