# Top-level entry points. `make` builds; `make demo` and `make test` are the README's quick start.
BUILD ?= build
JOBS ?= $(shell nproc)
CONFIG ?= Release

.PHONY: all build deps demo test bench clean format

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CONFIG)

build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

demo: deps
	@$(MAKE) --no-print-directory build
	@mkdir -p out
	@$(BUILD)/bin/relief render -o out/demo.png 

test: deps
	@$(MAKE) --no-print-directory build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: deps
	@$(MAKE) --no-print-directory build
	$(BUILD)/bin/bench_raster

format:
	git ls-files '*.cpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) out
