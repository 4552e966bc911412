# Two commands do everything on a fresh Debian 12 machine (as root, or with sudo):
#   make demo   install what is missing, then render the most complete scene headless to out/
#               (make report: the visual course report in out/report/index.html)
#   make test   install what is missing, then run ruff and the whole test suite on lavapipe
SHELL := /bin/bash
VENV := .venv
BIN := $(VENV)/bin
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)
APT_PACKAGES := python3 python3-venv mesa-vulkan-drivers libvulkan1 libglfw3 xvfb xauth \
                vulkan-validationlayers glslc vulkan-tools xdotool chromium libassimp5 assimp-utils
STAMP := $(VENV)/.installed
export XDG_RUNTIME_DIR ?= /tmp

.PHONY: setup apt demo report report-screenshot test fuzz lint references bench clean docs

setup: apt $(STAMP)

apt:
	@missing=""; for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "apt: installing$$missing"; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing >/dev/null; \
	fi

$(STAMP): pyproject.toml
	python3 -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[test]'
	touch $@

demo: setup
	@mkdir -p out
	$(BIN)/wgpurender render assets/scenes/final.toml -o out/final.png
	@echo "In a window: $(BIN)/wgpurender demo assets/scenes/final.toml (orbit camera, live reload; see README)"
	@echo "The course on one page: make report (or $(BIN)/wgpurender report -o out/report), then open out/report/index.html"

# The visual course report: every step on both paths, their difference, timings and code, and the accuracy measured
# in the run (about a minute on lavapipe with 2 cores).
report: setup
	@mkdir -p out
	$(BIN)/wgpurender report -o out/report

# docs/img/report.png, the README's picture of the report: a fresh report, then headless Chromium's screenshot of
# the 3d step (both renders, the heatmap, the metrics and the code of both paths side by side).
report-screenshot: report
	cd tests && ../$(BIN)/python browser.py ../out/report/index.html ../docs/img/report.png 3d 1100x1240

test: setup
	$(BIN)/ruff check .
	$(BIN)/pytest -q -n 2  # two workers (pytest-xdist): the suite is mostly processes waiting on lavapipe and subprocesses

# The long fuzz run (>= 10,000 cases, counts by outcome printed and written to out/fuzz-report.json) and the long
# soak. lavapipe limited to 1 thread, so a shared machine stays usable; it takes about an hour.
fuzz: setup
	@mkdir -p out
	WGPURENDER_FUZZ=long WGPURENDER_FUZZ_REPORT=out/fuzz-report.json LP_NUM_THREADS=1 \
	  $(BIN)/python -m pytest -q -p no:cacheprovider tests/fuzz tests/test_soak.py

# Re-render assets/reference/*.png with the raw-Vulkan path (validation on); never with the wgpu path.
references: setup
	WGPURENDER_VALIDATION=1 $(BIN)/python -m wgpurender.raw_path.make_references

lint: setup
	$(BIN)/ruff check .

clean:
	rm -rf $(VENV) out .pytest_cache

# The generated docs: the package graph in docs/architecture.md and the course map (tests check both are current).
docs: setup
	$(BIN)/python tests/test_layering.py --write
	$(BIN)/python -m wgpurender.course_map > docs/course-map.md
