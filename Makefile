# conftrack: the two commands of the README.
#   make run   install missing Debian packages, build, run the main job
#   make test  install missing Debian packages, build, run the test suite
#   make check-sanitizers  the same under ASan + UBSan (build-asan/; without
#              the 13 longest TrackML chain tests), plus
#              the main job on 5 events and a real TrackML reconstruction
#   make fuzz  build the libFuzzer targets (clang-14) and run each for
#              FUZZ_SECONDS seconds (docs/fuzzing.md)
#   make test-slurm  start a one-node Slurm cluster here (root), run a
#              sharded study on it and compare with one process
#              (docs/cluster.md)
#   make benchmark-merge  time `conftrack merge` of 100 shards of a
#              10,000-event muon study
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
RUN_ARGS ?=
FUZZ_SECONDS ?= 60
FUZZ_BUILD_DIR ?= build-fuzz

.PHONY: run test build deps clean format benchmark benchmark-merge check-sanitizers fuzz fuzz-deps test-slurm

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

test-slurm: build
	@scripts/install-deps.sh --slurm
	tests/slurm/slurm_cluster_test.sh $(BUILD_DIR)/conftrack

benchmark-merge: build
	benchmarks/merge_benchmark.sh $(BUILD_DIR)/conftrack

benchmark: build
	./$(BUILD_DIR)/benchmarks/conftrack_benchmarks

format:
	find include src apps tests benchmarks python/src -name '*.[ch]pp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
