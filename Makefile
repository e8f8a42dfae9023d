# Top-level entry points. `make` builds everything; `make demo` and `make test` are the README's
# quick start. `make demo` builds only the relief CLI (its plugins are linked in), not the tests
# and benchmarks; `make package` makes the Debian packages (docs/packaging.md).
BUILD ?= build
JOBS ?= $(shell nproc)
CONFIG ?= Release

.PHONY: all build deps demo test bench package clean format

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CONFIG)

build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

demo: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target relief
	@mkdir -p out
	$(BUILD)/bin/relief render -o out/demo.png

test: deps
	@$(MAKE) --no-print-directory build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: deps
	@$(MAKE) --no-print-directory build
	$(BUILD)/bin/bench_raster

# relief_<version>_<arch>.deb (CLI, man page, docs) and relief-dev_... (libraries, headers, CMake
# package) in $(BUILD).
package: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target relief relief_man
	cd $(BUILD) && cpack -G DEB

format:
	git ls-files '*.cpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) out
