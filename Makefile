# Two commands for a fresh Debian 12 machine: `make demo` and `make test`.
# ROS Python exists only for /usr/bin/python3, so /usr/bin goes first on PATH.
SHELL := /bin/bash
export PATH := /usr/bin:/bin:$(PATH)

# The catkin workspace lives outside the checkout: a workspace inside it whose
# src/ links back to the package makes rosrun's `find -L` warn about a loop.
WS ?= $(HOME)/.cache/rbx1_nav/ws
ROS := source $(WS)/devel/setup.bash &&
ARGS ?=

DEB_PACKAGES := catkin ros-cmake-modules python3-catkin-pkg python3-setuptools \
  python3-rospy python3-tf2-ros python3-geometry-msgs python3-nav-msgs \
  python3-sensor-msgs python3-rosgraph python3-rosgraph-msgs python3-tf2-msgs \
  python3-rostest python3-roslaunch python3-rosmaster python3-rostopic python3-rosnode python3-rosparam \
  python3-rosbag rosbash librostest-dev libgeometry-msgs-dev libnav-msgs-dev \
  libsensor-msgs-dev libstd-msgs-dev libtf2-ros-dev ros-robot-state-publisher \
  rviz xvfb catkin-lint python3-pytest python3-hypothesis python3-numpy \
  python3-matplotlib python3-pil python3-std-srvs python3-dynamic-reconfigure python3-pytest-xdist \
  ros-message-generation ros-message-runtime python3-genpy python3-gencpp \
  libdynamic-reconfigure-config-init-mutex-dev python3-venv python3-rosservice \
  python3-pip
SUDO := $(if $(filter 0,$(shell id -u)),,sudo)

.PHONY: deps build test unit lint demo bench docs clean

# MuJoCo, for the physics robot (fake_turtlebot.py ~physics): from PyPI, as
# Debian has none, into /usr/bin/python3's site (/usr/local), where the
# nodes find it. rosdep's key is python3-mujoco-pip.
MUJOCO := mujoco==4.0.0

deps: debs
	@/usr/bin/python3 -c 'import mujoco' 2>/dev/null || { \
	  echo "deps: installing $(MUJOCO) from PyPI for the physics robot"; \
	  $(SUDO) /usr/bin/python3 -m pip install -q --break-system-packages '$(MUJOCO)'; }

debs:
	@missing=$$(dpkg-query -W -f='$${Package} $${Status}\n' $(DEB_PACKAGES) 2>/dev/null \
	    | awk '$$NF == "installed" {print $$1}' | sort | comm -13 - <(tr ' ' '\n' <<< "$(DEB_PACKAGES)" | sed '/^$$/d' | sort)); \
	if [ -n "$$missing" ]; then \
	  echo "deps: installing" $$missing; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	else echo "deps: all $(words $(DEB_PACKAGES)) Debian packages present"; fi

# A workspace built from another checkout keeps that checkout's copies
# (install space, generated files) wherever they look newer: start afresh.
build: deps
	@mkdir -p $(WS)/src
	@if [ -L $(WS)/src/rbx1_nav ] && [ "$$(readlink $(WS)/src/rbx1_nav)" != "$(CURDIR)" ]; then \
	  echo "build: $(WS) was built from $$(readlink $(WS)/src/rbx1_nav): starting it afresh"; \
	  rm -rf $(WS)/build $(WS)/devel $(WS)/install; fi
	@ln -sfn $(CURDIR) $(WS)/src/rbx1_nav
	@# catkin finds no package inside another: rbx1_bringup (the launch
	@# files the book starts from it) goes beside rbx1_nav. Its folder is
	@# hidden: roslaunch looks for a launch file's name in every folder of
	@# rbx1_nav but hidden ones, and would find two fake_turtlebot.launch.
	@ln -sfn $(CURDIR)/.rbx1_bringup $(WS)/src/rbx1_bringup
	@echo "build: catkin_make in $(WS) (log: $(WS)/build.log)"
	@cd $(WS) && flock $(WS)/.build.lock catkin_make --force-cmake -DPYTHON_EXECUTABLE=/usr/bin/python3 > $(WS)/build.log 2>&1 \
	  || { tail -40 $(WS)/build.log; exit 1; }
	@echo "build: workspace $(WS) ready; use it with: source $(WS)/devel/setup.bash"

# Tools from PyPI that Debian does not package, in a venv beside the workspace.
VENV := $(WS)/venv
VERMIN := vermin==1.9.2
$(VENV)/.$(VERMIN):
	@python3 -m venv $(VENV) && $(VENV)/bin/pip install -q '$(VERMIN)' && touch '$@'

# ROS Noetic runs Python 3.8: nothing newer anywhere (vermin fails on it).
lint: build $(VENV)/.$(VERMIN)
	$(ROS) catkin_lint -W2 --strict $(WS)/src/rbx1_nav $(WS)/src/rbx1_bringup
	$(VENV)/bin/vermin --target=3.8- --violations --no-tips nodes src bench test docs cfg/*.cfg setup.py

# Unit tests (pytest, no master), every test/rostest/*.test through rostest, and the
# fault suite, in one pytest run of three workers on the two cores: the
# rostests that follow the wall clock one after another in one, the
# two-host fault suite one after another in another (both at normal
# priority), everything else spread over all three at a lower priority
# (test/conftest.py). pytest's summary is the last line.
REPORTS := $(WS)/test_results
test: lint
	@mkdir -p $(REPORTS)
	@$(ROS) python3 -m pytest test/unit test/integration test/faults -q -p no:cacheprovider \
	  -n 3 --dist loadgroup --junitxml=$(REPORTS)/pytest.xml --durations=8

# The unit tests alone; PYTHON=python3.8 runs them as on ROS Noetic.
PYTHON ?= python3
unit:
	$(PYTHON) -m pytest test/unit -q -p no:cacheprovider

# The course on the fake robot at real time, recorded and plotted to course.png.
# Launch args pass through: make demo ARGS="precise:=true rviz:=true"
# roslaunch exits 0 even when the course fails, so launch_status.py runs it
# and exits with the course's status. The launch ends with the course
# (end_launch_on_success.py ends it cleanly after a success).
demo: build
	@$(ROS) set -o pipefail; rosrun rbx1_nav launch_status.py rbx1_nav odom_out_and_back_sim.launch \
	  record:=true bag:=$(CURDIR)/course.bag $(ARGS) 2>&1 | tee $(WS)/demo.log \
	  || { echo "demo: the course did not complete; its error is above"; exit 1; }
	@$(ROS) rosrun rbx1_nav plot_course.py $(CURDIR)/course.bag -o $(CURDIR)/course.png
	@echo "demo: course complete; recorded $(CURDIR)/course.bag, plotted $(CURDIR)/course.png"

# Accuracy, speed, CPU and scale in one run, and the lockstep course files
# idle and beside CPU burners (tables in bench/results/; not a test, but it
# exits 1 if a lockstep figure moves with the load). Sections and sizes:
# make bench BENCH_ARGS="--sections speed --runs 3"
BENCH_ARGS ?=
bench: build
	$(ROS) python3 bench/bench.py $(BENCH_ARGS)

# docs/parameters.md from the nodes' declarations (the same as their --help).
docs: build
	$(ROS) python3 docs/make_parameters.py

clean:
	rm -rf $(WS)
