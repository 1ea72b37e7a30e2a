# The README's two commands: `make demo` (main job) and `make test` (the tests).
# Both install the Debian packages first (idempotent), then configure and build.
BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo-output

.PHONY: deps build test demo bench clean

deps:
	bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

demo: build
	$(BUILD)/experiments/bivo demo --output $(DEMO_OUT)

bench: build
	$(BUILD)/benchmarks/bivo_bench

clean:
	rm -rf $(BUILD)
