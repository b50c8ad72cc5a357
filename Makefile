# The two set-up commands of the README, and a few helpers. Everything real lives in CMake.
JOBS   ?= $(shell nproc)
BUILD  ?= build/release
ASAN   ?= build/sanitize
FUZZ   ?= build/fuzz
FUZZ_SECONDS ?= 120
FUZZ_SMOKE_SECONDS ?= 12
SCENE  ?= scenes/cornell.json

.PHONY: deps build build-asan demo test test-release test-asan fuzz fuzz-smoke bench bench-report bench-quick gpu-bundle clean

deps:
	bash scripts/install-deps.sh

## The Release build also makes the MPI tools (firstshot-*-mpi, docs/mpi.md), tested under mpirun against the MPI-free
## ones; the sanitizer build below is the default, MPI-free configuration.
build: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DFIRSTSHOT_MPI=ON
	cmake --build $(BUILD) -j $(JOBS)

## The sanitizer build: clang (a second compiler beside the Release build's gcc; its UBSan also checks float-to-int
## overflow), -O1 with line tables and assertions on, no benchmarks.
ASAN_FLAGS := -O1 -g1
build-asan: deps
	CC=clang CXX=clang++ cmake -S . -B $(ASAN) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRSTSHOT_SANITIZE=ON \
	  -DFIRSTSHOT_BENCH=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(ASAN_FLAGS)" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$(ASAN_FLAGS)"
	cmake --build $(ASAN) -j $(JOBS)

## The main job: the shipped Cornell box through the whole pipeline, results under out/.
demo: build
	bash scripts/demo.sh $(BUILD) $(SCENE)

## Every test, in the Release build and again under ASan+UBSan, and each fuzz target for a few seconds.
test: test-release test-asan fuzz-smoke

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-asan: build-asan
	cd $(ASAN) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
	  ctest --output-on-failure -j $(JOBS)

## The libFuzzer targets (clang, ASan+UBSan, tests/fuzz/), each for FUZZ_SECONDS on a scratch copy of its seed
## corpus; fails if one finds a crash, a hang or a huge allocation (docs/robustness.md).
fuzz: deps
	FUZZ_BUILD=$(CURDIR)/$(FUZZ) JOBS=$(JOBS) bash scripts/fuzz.sh $(FUZZ_SECONDS)

## The same for FUZZ_SMOKE_SECONDS per target (6 targets, JOBS at a time: about 40 s on 2 cores), as part of `make test`.
fuzz-smoke: deps
	FUZZ_BUILD=$(CURDIR)/$(FUZZ) JOBS=$(JOBS) bash scripts/fuzz.sh $(FUZZ_SMOKE_SECONDS)

bench: build
	bash bench/run.sh $(BUILD)

## Speed against error: each method's time to 5% and 2% rel. RMSE and MARE against a converged reference, the
## best first-shot method against the best baseline, and the preprocessing accuracy report: CSV, plots, tables and
## out/bench/summary.md under out/bench/, the plots also in docs/figures/ (bench/firstshot_bench.py). Hours: about
## 80 min per scene plus each reference once (cached); e.g. BENCH_ARGS='--max-budget 32 --reps 1' for a shorter run.
BENCH_SCENES ?= cornell many-lights sierpinski-glossy fixture-room office-floor
bench-report: build
	/usr/bin/python3 bench/firstshot_bench.py --build $(BUILD) --figures docs/figures $(BENCH_ARGS) $(BENCH_SCENES)

## A two-minute smoke check of the same harness's plumbing (results under out/bench/quick/; the numbers mean nothing).
bench-quick: build
	/usr/bin/python3 bench/firstshot_bench.py --build $(BUILD) --quick $(BENCH_ARGS) cornell many-lights

## The preprocessor for the GPU machine (docs/gpu.md): firstshot-preprocess and firstshot-fsd-compare built
## in $(GPU_BUILD) with their shared libraries, into .gpu/bundle.tar.xz (ignored by git, carried to the device),
## checked here with nothing but the bundle's libraries; bench/gpu_preprocess.sh runs it there.
GPU_BUILD ?= build/gpu
gpu-bundle:
	JOBS=$(JOBS) bash scripts/gpu_bundle.sh $(GPU_BUILD)

clean:
	rm -rf build out
