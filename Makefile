# lambert — the two commands a new user needs are `make run` and `make test`.
# Both install missing Debian packages first (scripts/install-deps.sh), then build in Release.

BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
LAMBERT = $(BUILD_DIR)/bin/lambert
BENCH_FLAGS ?=

.PHONY: all deps configure build run test bench sanitize fuzz clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DLAMBERT_BUILD_TESTS=ON -DLAMBERT_BUILD_BENCH=ON $(CMAKE_FLAGS) > /dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j$(JOBS) -- --no-print-directory >&2

# Render the built-in Cornell box to out/cornell.png and print the stats table.
run: build
	@$(LAMBERT) render --scene cornell -o out/cornell.png

# Build everything and run the whole suite through CTest.
test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j$(JOBS)

# Benchmarks: one JSON document on stdout, {"pipeline": …, "dynamic": …, "load": …, "hierarchical": …, "default_method": …,
# "viewer": …, "atlas": …, "lightmap": …, "lightmap_room": …, "lightmap_update": …, "illuminance": …, "distributed": …, "corpus": …, "office": …, "daylight": …, "accuracy": …}, each part also in out/bench/; the micro-benchmarks' table goes to stderr and their JSON to
# out/bench/micro.json. default_method times whole `lambert` processes (Cornell box against a cached path-traced
# reference, RenderPark beside it where ../rpk/src/build/rpk or RENDERPARK is built, buildings to 10^6 faces, the link
# cache); BENCH_FLAGS passes it options, e.g. BENCH_FLAGS=--no-million.
# The corpus part fetches the third-party scenes of bench/corpus/manifest.json into real-scenes/ where the network
# (or LAMBERT_CORPUS_MIRROR) allows, says which it skipped and why, and runs RenderPark beside lambert where
# RENDERPARK names its binary.
# The accuracy part (bench/accuracy_bench.py) measures every output of the default method against the path tracer
# on the accuracy scenes (three Blender-style exports it writes, the corpus's RenderPark and McGuire scenes) and
# writes the table of docs/accuracy.md to out/bench/accuracy.md.
bench: build
	@mkdir -p out/bench
	@$(BUILD_DIR)/bin/micro_bench --benchmark_format=console --benchmark_out_format=json \
	  --benchmark_out=out/bench/micro.json >&2
	@$(BUILD_DIR)/bin/pipeline_bench > out/bench/pipeline.json
	@$(BUILD_DIR)/bin/dynamic_bench > out/bench/dynamic.json
	@$(BUILD_DIR)/bin/load_bench --scenes scenes > out/bench/load.json
	@$(BUILD_DIR)/bin/hierarchical_bench > out/bench/hierarchical.json
	@python3 bench/default_method_bench.py --lambert $(LAMBERT) --vertex-reference $(BUILD_DIR)/bin/vertex_reference \
	  $(BENCH_FLAGS) > out/bench/default_method.json
	@$(BUILD_DIR)/bin/viewer_bench > out/bench/viewer.json
	@python3 bench/corpus_bench.py --lambert $(LAMBERT) --atlas-bench $(BUILD_DIR)/bin/atlas_bench > out/bench/corpus.json
	@$(BUILD_DIR)/bin/atlas_bench > out/bench/atlas.json
	@$(BUILD_DIR)/bin/lightmap_bench > out/bench/lightmap.json
	@python3 bench/lightmap_room_bench.py --lambert $(LAMBERT) > out/bench/lightmap_room.json
	@$(BUILD_DIR)/bin/lightmap_update_bench > out/bench/lightmap_update.json
	@$(BUILD_DIR)/bin/illuminance_bench > out/bench/illuminance.json
	@if command -v mpirun > /dev/null; then python3 bench/distributed_bench.py --lambert $(LAMBERT) > out/bench/distributed.json; \
	  else echo null > out/bench/distributed.json; fi
	@$(BUILD_DIR)/bin/office_bench > out/bench/office.json
	@python3 bench/daylight_bench.py --lambert $(LAMBERT) > out/bench/daylight.json
	@python3 bench/accuracy_bench.py --lambert $(LAMBERT) --vertex-reference $(BUILD_DIR)/bin/vertex_reference \
	  --lightmap-texels $(BUILD_DIR)/bin/lightmap_texels \
	  --corpus real-scenes --markdown out/bench/accuracy.md > out/bench/accuracy.json
	@printf '{"pipeline": ' && cat out/bench/pipeline.json && printf ', "dynamic": ' && cat out/bench/dynamic.json && \
	  printf ', "load": ' && cat out/bench/load.json && printf ', "hierarchical": ' && cat out/bench/hierarchical.json && \
	  printf ', "default_method": ' && cat out/bench/default_method.json && \
	  printf ', "viewer": ' && cat out/bench/viewer.json && printf ', "atlas": ' && cat out/bench/atlas.json && \
	  printf ', "lightmap": ' && cat out/bench/lightmap.json && printf ', "lightmap_room": ' && cat out/bench/lightmap_room.json && \
	  printf ', "lightmap_update": ' && cat out/bench/lightmap_update.json && \
	  printf ', "illuminance": ' && cat out/bench/illuminance.json && printf ', "distributed": ' && cat out/bench/distributed.json && \
	  printf ', "corpus": ' && cat out/bench/corpus.json && printf ', "office": ' && cat out/bench/office.json && \
	  printf ', "daylight": ' && cat out/bench/daylight.json && \
	  printf ', "accuracy": ' && cat out/bench/accuracy.json && printf '}\n'

# The whole suite under AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer, in
# build-sanitize/; the CLI runs the tests start are instrumented too. Any report fails its test.
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1:check_initialization_order=1:strict_init_order=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp
# -O1 -g1 (line tables, all a report's stack needs) compiles in half the time of -O2 -g
# (hierarchical/method.cpp: 23 s against 44 s), which keeps CI under its 45 minutes.
sanitize: deps
	@cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
	  -DLAMBERT_SANITIZE=ON -DLAMBERT_BUILD_BENCH=OFF > /dev/null
	@cmake --build build-sanitize -j$(JOBS) -- --no-print-directory >&2
	@cd build-sanitize && $(SANITIZE_ENV) ctest --output-on-failure -j$(JOBS)

# libFuzzer on every reader (docs/fuzzing.md): clang-14 builds the instrumented library and the
# targets in build-fuzz/, then each runs FUZZ_SECONDS (default 60) on a copy of tests/corpus/<target>;
# findings land in out/fuzz/<target>/ and fail the target. FUZZ_TARGETS="mgf ply" runs only those.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?=
fuzz:
	@scripts/install-deps.sh --fuzz
	@CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLAMBERT_FUZZ=ON \
	  -DLAMBERT_BUILD_TESTS=OFF -DLAMBERT_BUILD_BENCH=OFF > /dev/null
	@cmake --build build-fuzz -j$(JOBS) --target fuzz_targets -- --no-print-directory >&2
	@FUZZ_SECONDS=$(FUZZ_SECONDS) scripts/fuzz.sh build-fuzz/bin $(FUZZ_TARGETS)

clean:
	rm -rf $(BUILD_DIR) build-sanitize build-fuzz out
