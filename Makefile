# conftrack: the two commands of the README.
#   make run   install missing Debian packages, build, run the main job
#   make test  install missing Debian packages, build, run the test suite
#   make check-sanitizers  the same under ASan + UBSan (build-asan/), plus
#              the main job on 5 events and a real TrackML reconstruction
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
RUN_ARGS ?=

.PHONY: run test build deps clean format benchmark check-sanitizers

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

benchmark: build
	./$(BUILD_DIR)/benchmarks/conftrack_benchmarks

format:
	find include src apps tests benchmarks -name '*.[ch]pp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
