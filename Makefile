# conftrack: the two commands of the README.
#   make run   install missing Debian packages, build, run the main job
#   make test  install missing Debian packages, build, run the test suite
#   make check-sanitizers  the same under ASan + UBSan (build-asan/), plus
#              the main job on 5 events and a real TrackML reconstruction
#   make fuzz  build the libFuzzer targets (clang-14) and run each for
#              FUZZ_SECONDS seconds (docs/fuzzing.md)
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
RUN_ARGS ?=
FUZZ_SECONDS ?= 60
FUZZ_BUILD_DIR ?= build-fuzz

.PHONY: run test build deps clean format benchmark check-sanitizers fuzz fuzz-deps

run: build
	./$(BUILD_DIR)/conftrack run $(RUN_ARGS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 1200

build: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD_DIR) -j $(JOBS)

deps:
	@scripts/install-deps.sh

check-sanitizers: deps
	scripts/check-sanitizers.sh build-asan

fuzz: fuzz-deps
	FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_BUILD_DIR=$(FUZZ_BUILD_DIR) JOBS=$(JOBS) \
		scripts/fuzz.sh

fuzz-deps:
	@scripts/install-deps.sh --fuzz

benchmark: build
	./$(BUILD_DIR)/benchmarks/conftrack_benchmarks

format:
	find include src apps tests benchmarks python/src -name '*.[ch]pp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
