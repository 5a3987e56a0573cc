# chatterlab: make demo | make test | make build | make bench
MAKEFLAGS += --no-print-directory
BUILD ?= build
JOBS ?= $(shell nproc)
CAMPAIGN ?= experiments/demo

.PHONY: deps build test demo bench format clean

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

bench: deps $(BUILD)/CMakeCache.txt
	@cmake --build $(BUILD) -j $(JOBS) --target chatterlab_bench
	@$(BUILD)/benchmarks/chatterlab_bench

format:
	@clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	@rm -rf $(BUILD)
