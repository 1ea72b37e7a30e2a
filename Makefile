# The README's two commands: `make demo` (main job) and `make test` (the tests).
# Both install the Debian packages first (idempotent), then configure and build.
# Hardening (docs/reliability.md): `make sanitize` (clang, ASan + UBSan, every test) and
# `make fuzz` (the libFuzzer targets, FUZZ_SECONDS each).
BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo-output
# Extra configure arguments, e.g. CMAKE_ARGS=-DCMAKE_COMPILE_WARNING_AS_ERROR=ON (CI).
CMAKE_ARGS ?=
SAN_BUILD ?= build-sanitize
FUZZ_SECONDS ?= 30
# Extra ctest arguments of `make sanitize`, e.g. SAN_CTEST_ARGS="-R Hardening" for a subset.
SAN_CTEST_ARGS ?=
# One clang build serves the sanitized test suite, the fuzz targets and the portability
# check: -O1 keeps it fast to build and run, asserts stay on (Eigen's bounds checks),
# warnings are errors, benchmarks are left out.
SAN_FLAGS = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -fsanitize=fuzzer-no-link
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1 \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

.PHONY: deps deps-sanitizer build test demo bench clean sanitize-build sanitize fuzz

deps:
	bash scripts/install-deps.sh

deps-sanitizer:
	bash scripts/install-deps.sh --sanitizer

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)
	cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

demo: build
	$(BUILD)/experiments/bivo demo --output $(DEMO_OUT)

bench: build
	$(BUILD)/benchmarks/bivo_bench

sanitize-build: deps-sanitizer
	cmake -S . -B $(SAN_BUILD) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
	  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" \
	  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
	  -DCMAKE_COMPILE_WARNING_AS_ERROR=ON -DBIVO_BENCHMARKS=OFF -DBIVO_FUZZ=ON $(CMAKE_ARGS)
	cmake --build $(SAN_BUILD) -j$(JOBS)

sanitize: sanitize-build
	cd $(SAN_BUILD) && $(SAN_ENV) ctest --output-on-failure -j$(JOBS) $(SAN_CTEST_ARGS)

fuzz: sanitize-build
	$(SAN_ENV) bash scripts/run-fuzzers.sh $(SAN_BUILD) $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD) $(SAN_BUILD)
