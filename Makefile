# vdbappear: `make demo` and `make test` work on a fresh Debian 12 machine (as root, or with sudo):
# each installs the missing Debian packages, configures, builds, then runs.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
CMAKE_FLAGS ?=
JOBS ?= $(shell nproc)
# Unity builds (CMake's CMAKE_UNITY_BUILD): eight sources of a target compiled as one, so that the
# OpenVDB templates they share are parsed and instantiated once; a build from scratch takes about half
# the time (on 2 cores, 2026-11-29: make test's 14 min against about 26 before; the sanitizer build's
# about 25 min, where 61 of its 321 unbatched steps had taken 9.6 min). UNITY=OFF when editing one file
# at a time.
UNITY ?= ON

.PHONY: all deps configure build install test sanitize-build test-sanitize fuzz demo bench bench-render bench-scale bench-training bench-mpi lobes similarity lightgrid optimize modularity subsurface displacement interop clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DCMAKE_UNITY_BUILD=$(UNITY) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The tools, libvdbappear (CMake package, pkg-config), man pages and bash completion under PREFIX
# (docs/library.md); never /usr, where Debian's libopenvdb-tools keeps its own vdb_render.
PREFIX ?= /usr/local
install: build
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

test: build
	@ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

# The whole suite built with clang, AddressSanitizer and UndefinedBehaviorSanitizer (its own build
# folder), with the libFuzzer harnesses: any report fails the test that triggered it
# (docs/reliability.md).
SANITIZE_DIR ?= build-sanitize
SANITIZER_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0
sanitize-build: deps
	@cmake -S . -B $(SANITIZE_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DVDBAPPEAR_SANITIZE=address,undefined -DVDBAPPEAR_FUZZ=ON -DCMAKE_UNITY_BUILD=$(UNITY) >/dev/null
	@cmake --build $(SANITIZE_DIR) -j $(JOBS)

# Left out under the sanitizers: the tests of tests/sanitize_skip.txt, whose cost there is sample volume
# (each over 20 s, 20 to 100 times its time in make test); the code they drive runs in the lighter tests
# that the file names for each.
SANITIZE_SKIP = ^($(shell sed -e 's/\#.*//' -e 's/[[:space:]]*$$//' -e '/^$$/d' tests/sanitize_skip.txt | paste -sd'|'))( |$$)
test-sanitize: sanitize-build
	@$(SANITIZER_ENV) ctest --test-dir $(SANITIZE_DIR) --output-on-failure -j $(JOBS) -E '$(SANITIZE_SKIP)'

# Coverage-guided fuzzing of every reader with the harnesses of tests/fuzz (FUZZ_SECONDS each,
# two at a time): fuzz-out/report.md.
FUZZ_SECONDS ?= 600
fuzz: sanitize-build
	@scripts/fuzz.py --build $(SANITIZE_DIR) --out fuzz-out --seconds $(FUZZ_SECONDS)

demo: build
	@scripts/demo.sh $(BUILD_DIR)

bench: build
	@scripts/bench_downsample.py --build $(BUILD_DIR)

# Media larger than memory (issue 28): time and peak memory against active voxels at 256^3, 512^3,
# 1024^3 (the whole read of 1024^3 takes 21.5 GB) and 1792^3 (1.06 billion active voxels, a 15.7 GB
# file made and removed), with OpenVDB's vdb_lod as the peer; vdb_lobe_cluster in slabs up to 1024^3.
# About 65 minutes on 2 cores (--sizes 256,512,1024: about 30).
bench-scale: build
	@scripts/bench_scale.py --build $(BUILD_DIR)

# vdb_render against Blender Cycles (installs Debian's blender for itself when missing).
bench-render: build
	@scripts/bench_render.py --build $(BUILD_DIR)

# vdb_render on 1 and 2 MPI ranks: strong scaling, communication, imbalance and the scaling model
# of docs/scaling.md (bench-out/mpi_report.md).
bench-mpi: build
	@scripts/bench_mpi.py --build $(BUILD_DIR)

# The weight optimisation's training renders: restricted-mean noise and seconds per set (bench/training_set_bench.cpp).
# BASELINE_LIB=DIR: the same benchmark with another build's libvdbappear.so (DIR holds it; its public types must
# match this build's), the two runs alternating, for a before/after in one run (docs/rendering.md 7).
bench-training: build
	@mkdir -p bench-out
	@for round in 1 2; do \
		$(BUILD_DIR)/bin/training_set_bench --benchmark_out=bench-out/training_set_bench_$$round.json \
			--benchmark_out_format=json || exit 1; \
		if [ -n "$(BASELINE_LIB)" ]; then LD_LIBRARY_PATH="$(BASELINE_LIB)" $(BUILD_DIR)/bin/training_set_bench \
			--benchmark_out=bench-out/training_set_bench_baseline_$$round.json --benchmark_out_format=json || exit 1; \
		else break; fi; \
	done

# Multi-lobe fits: error against lobe count (twill, velvet) and renders against full resolution.
lobes: build
	@scripts/lobe_experiment.py --build $(BUILD_DIR)

# Similarity relations: speed-up at equal quality against alpha, order 5 against order 1, throughput.
similarity: build
	@scripts/similarity_experiment.py --build $(BUILD_DIR)

# SH light grids: scaling with the number of lights, interpolation along a line, renders with 512 lights.
lightgrid: build
	@scripts/lightgrid_experiment.py --build $(BUILD_DIR)

# Optimised lobe weights (vdb_optimize_weights) on the paper's cases, judged under held-out lighting.
optimize: build
	@scripts/optimize_experiment.py --build $(BUILD_DIR)

# One optimisation of stacked exemplar blocks serving two assembled models (vdb_exemplar_stack, §7).
modularity: build
	@scripts/modularity_experiment.py --build $(BUILD_DIR)

# Translucent objects by the dipole (issue 22): the physical check against vdb_render's path tracing.
subsurface: build
	@scripts/subsurface_experiment.py --build $(BUILD_DIR)

# Displacement-map prefiltering (issue 23): reference, naive, multi-lobe and full models of three
# procedural surfaces, a ball and a torus at two scales and at each one's scale in the chapter
# (Table 4.3), under direct light and global illumination; equal time; storage. At the n15 rates
# (the default) it takes more than five hours on 2 cores: run from a fresh clone (2026-12-01), its
# models' precomputation alone took 4.9 hours, the renders besides (docs/displacement.md §9). Run
# again, it goes on where an interrupted run stopped (--resume): what is up to date in
# displacement-out/ is kept.
displacement: build
	@scripts/displacement_experiment.py --build $(BUILD_DIR) --resume

# VDBs from Blender and Houdini (issue 26): the kept foreign files rendered by vdb_render and by Blender
# Cycles with the same grids, lights and camera; mean and worst 8x8 tile against the issue's gates.
interop: build
	@scripts/interop_experiment.py --build $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) $(SANITIZE_DIR) demo-out bench-out lobes-out similarity-out lightgrid-out optimize-out modularity-out subsurface-out displacement-out interop-out fuzz-out media

include scripts/media.mk
