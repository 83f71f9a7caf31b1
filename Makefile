# Thin wrapper (DESIGN §1). `make demo` and `make test` work on a fresh Debian 12 machine:
# they install missing Debian packages with apt, configure, build, then run.
BUILD ?= build
JOBS  ?= $(shell nproc)
CMAKE_FLAGS ?=
PY := /usr/bin/python3

DEB_PKGS := cmake g++ make pkg-config git libembree-dev libglm-dev libopenimageio-dev \
            nlohmann-json3-dev libtbb-dev libgtest-dev libcli11-dev libassimp-dev \
            libbenchmark-dev python3-matplotlib python3-numpy
# Optional extras: skimage for the live SSIM cross-check, assimp-testmodels for import tests.
DEB_OPT  := python3-skimage assimp-testmodels

SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: all deps deps-bench build demo test bench bench-report clean format update-golden docs

all: build

deps:
	@missing=""; for p in $(DEB_PKGS) $(DEB_OPT); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -q --no-install-recommends $$missing; \
	fi

# Benchmark-only extras (not in `deps`): OpenCV for bench_methods' cv::warpPolar comparison
# (optional in CMakeLists.txt). A fresh install re-runs cmake on an existing build dir so
# find_package(OpenCV) sees it.
DEB_BENCH := libopencv-dev

deps-bench:
	@missing=""; for p in $(DEB_BENCH); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -q --no-install-recommends $$missing && \
	  if [ -f $(BUILD)/CMakeCache.txt ]; then cmake $(BUILD); fi; \
	fi

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS)

demo: build
	$(BUILD)/fovsim run configs/quickstart.json --out results/quickstart
	@if $(PY) -c "import matplotlib" 2>/dev/null; then \
	  $(PY) viz/plot_run.py results/quickstart; fi

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 60

bench: deps-bench build
	@for b in $(BUILD)/bench_*; do echo "== $$b"; $$b; done

# The ratios against the real limits (issue 19; bench/README.md), one run, one thread.
bench-report: deps-bench build
	bench/report.sh $(BUILD)

format:
	clang-format -i $$(git ls-files 'sim/*.cpp' 'sim/*.h' 'tests/*.cpp' 'bench/*.cpp')

clean:
	rm -rf $(BUILD)

# Regenerates the method parameter tables in docs/methods.md and configs/README.md.
docs: build
	scripts/gen_method_docs.sh $(BUILD)

# Rewrites the regression goldens from the current build (review the diff before committing).
update-golden: build
	$(BUILD)/test_app --gtest_filter='Golden*' --update-golden

# Single-node Slurm on localhost (slurm-wlm + munge, installed by the script): a small sweep
# as a job array, merged, compared with the local run (docs/sweeps.md "Slurm").
.PHONY: test-slurm
test-slurm: build
	FOVSIM=$(CURDIR)/$(BUILD)/fovsim scripts/slurm/test_slurm.sh
