# fairspline: the two commands of the quick start are `make run` and `make test`.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
# Ninja for every CMake tree configured from here (this one, the fuzz and sanitizer builds, and
# the trees make test's consumer and pip tests configure): it compiles a target's sources while
# the library they link is still being built, where Make waits. A clean build took 264 s
# instead of 301 s on 2 cores. An existing tree keeps the generator it was made with.
export CMAKE_GENERATOR ?= $(if $(shell command -v ninja 2>/dev/null),Ninja,Unix Makefiles)
CLI := $(BUILD_DIR)/apps/cli/fairspline
EXAMPLE ?= examples/li-example1.csv

# Fuzzing (libFuzzer, clang) and sanitizers (ASan + UBSan) each have their own build directory.
FUZZ_DIR ?= build-fuzz
FUZZ_OPT ?= -O1
# make test's fuzz smoke: its own build at -O0 (compile time matters more than executions/s).
FUZZ_SMOKE_DIR ?= build-fuzz-smoke
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := fuzz_csv fuzz_json fuzz_fit fuzz_server
ASAN_DIR ?= build-asan
SANITIZE_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
SANITIZE_ENV := ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

.PHONY: all deps configure build run test bench format format-check clean fuzz fuzz-build \
  fuzz-smoke-build sanitize stress

all: build

deps:
	@scripts/install-deps

$(BUILD_DIR)/CMakeCache.txt:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

configure: $(BUILD_DIR)/CMakeCache.txt

build: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Only the command (with the library and web server it links), not the tests, benchmarks or
# Python module: the first curve comes sooner. `make test` builds the rest in the same tree.
run: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target fairspline_cli
	@mkdir -p out
	$(CLI) fit $(EXAMPLE) -f svg -o out/example.svg --summary
	@echo "wrote out/example.svg"

# The suite includes fuzz.replay.* (every committed fuzz input, any compiler) and the fuzz smoke
# fuzz.smoke.* (each libFuzzer target for 10 s, 40 s in all, alongside the other tests): when
# clang can link a libFuzzer target, fuzz-smoke-build builds $(FUZZ_SMOKE_DIR) first (incremental
# after the first time); otherwise they report as skipped. FUZZ_SMOKE=0 leaves them out.
FUZZ_SMOKE ?= 1
test: build fuzz-smoke-build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) $(if $(filter 1,$(FUZZ_SMOKE)),,-E '^fuzz\.smoke\.')

fuzz-smoke-build:
	@if [ "$(FUZZ_SMOKE)" != 1 ]; then echo "fuzz smoke: off (FUZZ_SMOKE=$(FUZZ_SMOKE))"; \
	elif tests/fuzz/have-libfuzzer; then \
	  $(MAKE) --no-print-directory fuzz-build FUZZ_DIR=$(FUZZ_SMOKE_DIR) FUZZ_OPT=-O0; \
	else echo "fuzz smoke: clang with libFuzzer not found; fuzz.smoke.* will be skipped"; fi

bench: build
	cmake --build $(BUILD_DIR) -j $(JOBS) --target fairspline_bench
	$(BUILD_DIR)/bench/fairspline_bench --benchmark_min_time=0.2
	/usr/bin/python3 bench/compare_scipy.py --cli $(CLI)

# `make stress STRESS_COUNT=N`: the optimizers' stress program (tools/stress; docs/hardening.md,
# "Stress suite"): N cases, each fitted by every iterative method; failing inputs in out/stress.
# Then data balls on 600 noisy samples of smooth curves (docs/hardening.md, "Noisy samples").
STRESS_COUNT ?= 100000
STRESS_SEED ?= 18
stress: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target fairspline_stress fairspline_python
	$(BUILD_DIR)/tools/stress/fairspline_stress --seed $(STRESS_SEED) --count $(STRESS_COUNT) \
	  --out out/stress --summary-json out/stress/summary.json
	/usr/bin/python3 tools/stress/noisy_shapes.py --build $(BUILD_DIR) --seed $(STRESS_SEED) \
	  --count 600 --save out/stress/noisy

# `make fuzz FUZZ_SECONDS=N`: builds the libFuzzer targets of tests/fuzz with clang in
# $(FUZZ_DIR) (library instrumented, ASan + UBSan) and runs each for N seconds on its committed
# seed corpus tests/fuzz/corpus/<target> (read only) plus a writable corpus in $(FUZZ_DIR).
# A crash stops with the reproducer's path: add it to tests/fuzz/corpus/<target>/ (make test
# replays every file there) and fix the bug. See docs/fuzzing.md.
fuzz-build: deps
	CC=clang CXX=clang++ cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFAIRSPLINE_FUZZ=ON \
	  -DFAIRSPLINE_FUZZ_OPT=$(FUZZ_OPT)
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(FUZZ_TARGETS)

fuzz: fuzz-build
	tests/fuzz/run-fuzz.sh $(FUZZ_DIR) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# `make sanitize`: the whole test suite built with ASan + UBSan (g++) in $(ASAN_DIR). Python
# loads the extension module into the uninstrumented /usr/bin/python3, so py.pytest runs with
# the sanitizer runtimes preloaded and without leak detection (CPython itself does not free
# everything at exit); every other test runs with leak detection on.
sanitize: deps
	cmake -S . -B $(ASAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  "-DCMAKE_CXX_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_EXE_LINKER_FLAGS=$(SANITIZE_FLAGS)" \
	  "-DCMAKE_SHARED_LINKER_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_MODULE_LINKER_FLAGS=$(SANITIZE_FLAGS)"
	cmake --build $(ASAN_DIR) -j $(JOBS)
	$(SANITIZE_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS) -E '^py\.pytest$$'
	LD_PRELOAD="$$(g++ -print-file-name=libasan.so) $$(g++ -print-file-name=libubsan.so)" \
	  ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
	  ctest --test-dir $(ASAN_DIR) --output-on-failure -R '^py\.pytest$$'

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

format-check:
	clang-format --dry-run --Werror $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR) out
