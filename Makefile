# fairspline: the two commands of the quick start are `make run` and `make test`.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CLI := $(BUILD_DIR)/apps/cli/fairspline
EXAMPLE ?= examples/li-example1.csv

.PHONY: all deps configure build run test bench format format-check clean

all: build

deps:
	@scripts/install-deps

$(BUILD_DIR)/CMakeCache.txt:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

configure: $(BUILD_DIR)/CMakeCache.txt

build: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	@mkdir -p out
	$(CLI) fit $(EXAMPLE) -f svg -o out/example.svg --summary
	@echo "wrote out/example.svg"

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/bench/fairspline_bench --benchmark_min_time=0.2
	/usr/bin/python3 bench/compare_scipy.py --cli $(CLI)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

format-check:
	clang-format --dry-run --Werror $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR) out
