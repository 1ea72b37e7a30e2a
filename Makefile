# The README's two commands: `make demo` (main job) and `make test` (the tests).
# Both install the Debian packages first (`make deps`, idempotent), then configure and build;
# `make build` alone only configures and builds.
# Hardening (docs/reliability.md): `make sanitize` (clang, ASan + UBSan, every test) and
# `make fuzz` (the libFuzzer targets, FUZZ_SECONDS each); CI: `make fuzz-ci` (a clang build of
# only the fuzz targets and the readers they link, each run FUZZ_CI_SECONDS).
BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo-output
# Extra configure arguments, e.g. CMAKE_ARGS=-DCMAKE_COMPILE_WARNING_AS_ERROR=ON (CI).
CMAKE_ARGS ?=
# Ninja for a new build folder (it compiles a target's files while the libraries they need
# still link; Make waits); a folder configured before keeps its generator.
generator = $(if $(wildcard $(1)/CMakeCache.txt),,-G Ninja)
SAN_BUILD ?= build-sanitize
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 30
FUZZ_CI_SECONDS ?= 20
# Extra ctest arguments of `make sanitize`, e.g. SAN_CTEST_ARGS="-R Hardening" for a subset.
SAN_CTEST_ARGS ?=
# One clang build serves the sanitized test suite, the fuzz targets and the portability
# check: -O1 keeps it fast to build and run, asserts stay on (Eigen's bounds checks),
# warnings are errors, benchmarks are left out, and so is the Python module (an ASan-built
# extension cannot be imported by the uninstrumented interpreter).
SAN_FLAGS = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -fsanitize=fuzzer-no-link
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1 \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

# The clang configuration shared by `make sanitize` (whole project) and `make fuzz-ci`
# (fuzz targets only); $(1) is the build folder.
san_configure = cmake -S . -B $(1) $(call generator,$(1)) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
	  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" \
	  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
	  -DCMAKE_COMPILE_WARNING_AS_ERROR=ON -DBIVO_BENCHMARKS=OFF -DBIVO_PYTHON=OFF -DBIVO_FUZZ=ON $(CMAKE_ARGS)

.PHONY: deps deps-sanitizer build test demo bench clean sanitize-build sanitize fuzz fuzz-ci format-check

deps:
	bash scripts/install-deps.sh

deps-sanitizer:
	bash scripts/install-deps.sh --sanitizer

build:
	cmake -S . -B $(BUILD) $(call generator,$(BUILD)) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)
	cmake --build $(BUILD) -j$(JOBS)

test: deps
	$(MAKE) build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# The demo needs only the command line: the tests, benchmarks and Python module wait for `make test`.
demo: deps
	cmake -S . -B $(BUILD) $(call generator,$(BUILD)) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)
	cmake --build $(BUILD) -j$(JOBS) --target bivo
	$(BUILD)/experiments/bivo demo --output $(DEMO_OUT)

# Every tracked C++ file formatted as .clang-format says (CI runs it).
format-check: deps-sanitizer
	git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run -Werror

bench: build
	$(BUILD)/benchmarks/bivo_bench

sanitize-build: deps-sanitizer
	$(call san_configure,$(SAN_BUILD))
	cmake --build $(SAN_BUILD) -j$(JOBS)

sanitize: sanitize-build
	cd $(SAN_BUILD) && $(SAN_ENV) ctest --output-on-failure -j$(JOBS) $(SAN_CTEST_ARGS)

fuzz: sanitize-build
	$(SAN_ENV) bash scripts/run-fuzzers.sh $(SAN_BUILD) $(FUZZ_SECONDS)

# CI's fuzz step, after `make test`: the seeds come from the default build's bivo_fuzz_seeds,
# the clang build compiles only the fuzz targets and the libraries they link (about 25 files),
# each target runs FUZZ_CI_SECONDS from the seeds and the stored regressions; fails on any finding.
fuzz-ci: deps-sanitizer
	cmake --build $(BUILD) -j$(JOBS) --target bivo_fuzz_seeds
	$(call san_configure,$(FUZZ_BUILD))
	cmake --build $(FUZZ_BUILD) -j$(JOBS) --target bivo_fuzz_targets
	$(SAN_ENV) FUZZ_SEEDS_BIN=$(BUILD)/tests/fuzz/bivo_fuzz_seeds \
	  bash scripts/run-fuzzers.sh $(FUZZ_BUILD) $(FUZZ_CI_SECONDS)

clean:
	rm -rf $(BUILD) $(SAN_BUILD) $(FUZZ_BUILD)
