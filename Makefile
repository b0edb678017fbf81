# The two entry points of the README. Each installs what is missing, configures and builds.
BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo-out

.PHONY: all deps test-deps configure build demo test sanitize fuzz bench clean

all: build

deps:
	@bash scripts/install-deps.sh

# What only the tests need beside the build's packages (Blender, for the add-on's test).
test-deps:
	@bash scripts/install-deps.sh --tests

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# Runs the whole pipeline on the bundled example data; results go to $(DEMO_OUT)/.
demo: build
	@bash examples/demo.sh $(BUILD)/sdm $(DEMO_OUT)

# Builds and runs every test.
test: test-deps build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer.
sanitize: deps
	@cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDM_SANITIZE=ON >/dev/null
	@cmake --build build-asan -j $(JOBS)
	@cd build-asan && ASAN_OPTIONS=detect_leaks=0 ctest --output-on-failure -j $(JOBS)

# libFuzzer on every reader under ASan + UBSan (clang; build-fuzz/): FUZZ_SECONDS per reader (60).
fuzz: deps
	@bash scripts/fuzz.sh

bench: build
	@$(BUILD)/sdm bench

clean:
	rm -rf $(BUILD) build-asan build-fuzz $(DEMO_OUT)
