# Thin wrapper (docs/architecture.md "Layers and their dependencies"). `make demo` and `make test` work on a fresh Debian 12 machine:
# they install missing Debian packages with apt, configure, build, then run.
BUILD ?= build
JOBS  ?= $(shell nproc)
CMAKE_FLAGS ?=
PY := /usr/bin/python3

DEB_PKGS := cmake g++ make pkg-config git clang-format libembree-dev libglm-dev libopenimageio-dev \
            nlohmann-json3-dev libtbb-dev libgtest-dev libcli11-dev libassimp-dev \
            libbenchmark-dev python3-matplotlib python3-numpy pybind11-dev python3-dev
# Optional extras: skimage for the live SSIM cross-check, assimp-testmodels for import tests,
# pandas for DataFrames from python/fovsim (numpy fallback). Not installed: ffmpeg (run videos,
# viz/make_video.py; skipped with a message without it).
DEB_OPT  := python3-skimage assimp-testmodels python3-pandas

SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: all deps deps-bench build demo test bench bench-report clean format update-golden docs docs-check

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

# The demo builds only what it runs: the CLI (its plots are viz/plot_run.py on the CSVs, no
# compiled Python module); `make test` builds the rest (tests, benchmarks, the Python module).
demo: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS) --target fovsim_cli
	$(BUILD)/fovsim run configs/quickstart.json --out results/quickstart  # also writes plots/ (viz/plot_run.py)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 60

bench: deps-bench build
	@for b in $(BUILD)/bench_*; do echo "== $$b"; $$b; done

# The ratios against the real limits (bench/README.md), one run, one thread.
bench-report: deps-bench build
	bench/report.sh $(BUILD)

format:
	clang-format -i $$(git ls-files 'sim/*.cpp' 'sim/*.h' 'tests/*.cpp' 'tests/*.h' 'bench/*.cpp' 'python/*.cpp')

clean:
	rm -rf $(BUILD)

# Regenerates the method parameter tables in docs/methods.md and configs/README.md, and the
# worked numbers of docs/ from their runs (scripts/docs_numbers.py; --slow: also the worked
# examples on shipped configs, a few minutes, which ctest leaves out).
docs: build
	scripts/gen_method_docs.sh $(BUILD)
	$(PY) scripts/docs_numbers.py --update --slow --fovsim $(BUILD)/fovsim

# Checks every worked number of docs/, the slow ones included (ctest's
# Workflow.DocsNumbersReproduce checks only the tiny runs).
docs-check: build
	$(PY) scripts/docs_numbers.py --check --slow --fovsim $(BUILD)/fovsim

# Rewrites the regression goldens from the current build (review the diff before committing).
update-golden: build
	$(BUILD)/test_app --gtest_filter='Golden*' --update-golden

# Single-node Slurm on localhost (slurm-wlm + munge, installed by the script): a small sweep
# as a job array, merged, compared with the local run (docs/sweeps.md "Slurm").
.PHONY: test-slurm
test-slurm: build
	FOVSIM=$(CURDIR)/$(BUILD)/fovsim scripts/slurm/test_slurm.sh

# One instrumented build (Debian's clang; ASan + UBSan + libFuzzer coverage on every fovsim
# library, FOVSIM_FUZZ) in $(SAN_BUILD), shared by `make test-sanitize` and `make fuzz`, so CI
# (.ci/run) compiles the libraries once for both; no benchmarks, no Python module.
SAN_BUILD ?= build-san
SAN_CONFIGURE = CXX=clang++ cmake -S . -B $(SAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFOVSIM_FUZZ=ON -DFOVSIM_BUILD_BENCH=OFF -DFOVSIM_PYTHON=OFF $(CMAKE_FLAGS)

# test-sanitize runs a stated subset of the suite (the whole suite under ASan would push CI
# past its time budget): the core, trace and experiment layers (parsers, params, limits,
# importer, resampling, sweep expansion; test_core, test_trace, test_experiment) and the app's
# CLI tests of bad input (SAN_APP_FILTER), which run the sanitized fovsim
# binary. It builds only those tests and fovsim_cli. Any report fails the target (halt_on_error).
SAN_TESTS ?= test_core test_trace test_experiment
SAN_APP_FILTER ?= Hardening.*:Cli.*
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
.PHONY: test-sanitize
test-sanitize: deps
	$(SAN_CONFIGURE)
	cmake --build $(SAN_BUILD) -j$(JOBS) --target fovsim_cli test_app $(SAN_TESTS)
	@set -e; for t in $(SAN_TESTS); do echo "== $$t (ASan+UBSan)"; \
	  $(SAN_ENV) FOVSIM_SOURCE_DIR=$(CURDIR) $(SAN_BUILD)/$$t; done
	@echo "== test_app --gtest_filter='$(SAN_APP_FILTER)' (ASan+UBSan)"
	$(SAN_ENV) FOVSIM_SOURCE_DIR=$(CURDIR) $(SAN_BUILD)/test_app --gtest_filter='$(SAN_APP_FILTER)'

# libFuzzer targets for the parsers (configs/Params, canonical trace CSV, importer map +
# recording, sweep specs, scene files, images, the Python API's arguments), each run for FUZZ_SECONDS with its committed seed corpus and
# dictionary (tests/fuzz/README.md). New corpus entries and crash inputs stay under
# $(SAN_BUILD)/fuzz/; a crash fails the target and becomes a regression test.
# scene (OBJ/glTF + textures), png (compare's image reader) and args (the argument layer of the
# Python API) had their first runs under ASan/LSan with the suppression file for a leak inside
# OpenImageIO (tests/fuzz/lsan.supp; full stacks so that it matches).
FUZZ_TARGETS ?= params trace_csv importer sweep scene png args
FUZZ_SECONDS ?= 60
FUZZ_OUT := $(SAN_BUILD)/fuzz
.PHONY: fuzz
fuzz: deps
	$(SAN_CONFIGURE)
	cmake --build $(SAN_BUILD) -j$(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@set -e; for f in $(FUZZ_TARGETS); do echo "== fuzz_$$f for $(FUZZ_SECONDS) s"; \
	  mkdir -p $(FUZZ_OUT)/corpus/$$f $(FUZZ_OUT)/crashes/$$f; \
	  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=fast_unwind_on_malloc=0 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/lsan.supp \
	  $(SAN_BUILD)/fuzz_$$f -max_total_time=$(FUZZ_SECONDS) \
	    -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -dict=tests/fuzz/$$f.dict \
	    -artifact_prefix=$(FUZZ_OUT)/crashes/$$f/ $(FUZZ_OUT)/corpus/$$f tests/fuzz/corpus/$$f; done
