# chatterlab: make demo | make test | make build | make bench | make sanitize
MAKEFLAGS += --no-print-directory
BUILD ?= build
JOBS ?= $(shell nproc)
CAMPAIGN ?= experiments/demo

.PHONY: deps build test demo bench sanitize format clean

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null

build: deps $(BUILD)/CMakeCache.txt
	@cmake --build $(BUILD) -j $(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

demo: build
	@if [ "$(CAMPAIGN)" = experiments/demo ] && { [ ! -f $(CAMPAIGN)/campaign.yaml ] || \
	    [ experiments/demo.synth.yaml -nt $(CAMPAIGN)/campaign.yaml ]; }; then \
	  rm -rf $(CAMPAIGN) && $(BUILD)/chatterlab synth experiments/demo.synth.yaml --out $(CAMPAIGN); fi
	@$(BUILD)/chatterlab report $(CAMPAIGN) --out reports/demo
	@echo "Report written to reports/demo/index.html and reports/demo/report.pdf"

# The suite under AddressSanitizer and UndefinedBehaviorSanitizer, with Eigen's assertions on
# (a Debug build: no NDEBUG; -O1 keeps it fast enough), in its own folder
# (docs/testing.md#the-sanitizer-build). GCC: clang 14's ASan stopped at start-up in a test
# binary (docs/testing.md). Not yet part of CI.
ASAN_BUILD ?= build-asan
$(ASAN_BUILD)/CMakeCache.txt:
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g" \
	  -DCHATTERLAB_SANITIZE=ON -DCHATTERLAB_WERROR=OFF -DCHATTERLAB_BENCHMARKS=OFF >/dev/null

sanitize: deps $(ASAN_BUILD)/CMakeCache.txt
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp \
	  ctest --output-on-failure -j $(JOBS)

bench: deps $(BUILD)/CMakeCache.txt
	@cmake --build $(BUILD) -j $(JOBS) --target chatterlab_bench
	@$(BUILD)/benchmarks/chatterlab_bench

format:
	@clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	@rm -rf $(BUILD)
