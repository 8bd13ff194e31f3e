# tubempm: material point method for thin-walled tubes under lateral compression.
# SPDX-License-Identifier: MIT
#   make            build bin/tubempm (release)         make test     debug build + all tests
#   make run        default scene + its plot            make help     all targets
.DEFAULT_GOAL := all
MAKEFLAGS += --no-builtin-rules

ifeq ($(origin FC),default)
  FC := gfortran
endif
BUILD ?= release
PYTHON ?= python3
CASE ?= namelists/default.nml

FFLAGS_common  := -std=f2008 -fimplicit-none -Wall -Wextra -Wimplicit-interface \
                  -Wno-compare-reals -fopenmp
FFLAGS_release := -O2 -g
# native: this machine's instruction set (AVX2, FMA); results differ at round-off (tests/check_native.py, run by make bench)
FFLAGS_native  := -O2 -g -march=native
# debug (make test): every run-time check and the floating-point traps, at -O2: the checks and
# traps make it the debug build, and the suite runs faster than at -Og (the same arithmetic as
# release: no -ffast-math, no FMA contraction); for a debugger, FFLAGS_debug with -Og. -Wno-maybe-uninitialized because gfortran flags every deferred-length string built by
# concatenation as "may be used uninitialized" (about 40 false positives); a real uninitialised
# real is caught at run time instead (-finit-real=snan with the invalid trap)
FFLAGS_debug   := -O2 -g -fcheck=all -fbacktrace -ffpe-trap=invalid,zero,overflow \
                  -finit-real=snan -finit-integer=-99999999 -Wno-maybe-uninitialized
# the sanitizer profile (make test BUILD=asan): AddressSanitizer and UndefinedBehaviorSanitizer
# in the Fortran and the C code
SANITIZE       := -fsanitize=address,undefined -fno-omit-frame-pointer
FFLAGS_asan    := -Og -g $(SANITIZE)
CFLAGS_asan    := -g $(SANITIZE)
HDF5_FFLAGS ?= $(shell pkg-config --cflags hdf5 2>/dev/null)
HDF5_LIBS   ?= $(shell pkg-config --libs-only-L hdf5 2>/dev/null) -lhdf5_fortran -lhdf5
CFLAGS_shim := -O2 -std=c99 -Wall -Wextra $(CFLAGS_$(BUILD))

BLD     ?= build/$(BUILD)
# the sources: src/ and every folder below it (one folder per layer, docs/architecture.md);
# the objects and modules of a build sit side by side in $(BLD), found by file name (vpath)
rwildcard = $(foreach d,$(wildcard $(1:=/*)),$(call rwildcard,$d,$2) $(filter $(subst *,%,$2),$d))
SRC     := $(sort $(call rwildcard,src,*.f90))
CSRC    := $(sort $(call rwildcard,src,*.c))
LIBOBJ  := $(patsubst %.f90,$(BLD)/%.o,$(notdir $(filter-out %/tubempm.f90,$(SRC)))) \
           $(patsubst %.c,$(BLD)/%.o,$(notdir $(CSRC)))
vpath %.f90 $(sort $(dir $(SRC)))
vpath %.c $(sort $(dir $(CSRC)))
TESTSRC := $(wildcard tests/test_*.f90)
TESTS   := $(patsubst tests/%.f90,$(BLD)/%,$(TESTSRC))
FC_ALL  := $(FC) $(FFLAGS_common) $(FFLAGS_$(BUILD))

.PHONY: all deps test run clean help check-namelists check-paraview bench bench-cost study stability figures \
        cfl-accuracy validate-honeycomb \
        fuzz fuzz-scenes fe-reference test-slurm design-example

# HDF5 flags come from pkg-config when make reads this file, so everything that compiles runs
# in a sub-make started after `deps` has installed what was missing (a fresh machine).
# the builds use both cores of the machine (or fewer): -j$(JOBS), unless make is given its own -j
JOBS ?= $(shell n=$$(nproc 2>/dev/null || echo 1); [ $$n -gt 2 ] && n=2; echo $$n)
JFLAG = $(if $(filter -j%,$(MAKEFLAGS)),,-j$(JOBS))
all: deps
	@$(MAKE) --no-print-directory $(JFLAG) $(if $(filter release,$(BUILD)),bin/tubempm,$(BLD)/tubempm)

## deps: install what is missing (Debian packages, Python packages); silent when all is there
deps:
	@bash tools/install-deps.sh

bin/tubempm: $(BLD)/tubempm | bin
	cp $< $@.tmp && mv -f $@.tmp $@    # a new file: runs of the old binary go on

bin:
	mkdir -p $@

$(BLD):
	mkdir -p $@

$(BLD)/%.o: %.f90 | $(BLD)
	$(FC_ALL) $(HDF5_FFLAGS) -J$(BLD) -c -o $@ $<

$(BLD)/%.o: %.c | $(BLD)
	$(CC) $(CFLAGS_shim) -c -o $@ $<

$(BLD)/tubempm: $(LIBOBJ) $(BLD)/tubempm.o
	$(FC_ALL) -o $@ $^ $(HDF5_LIBS)

$(BLD)/testing.o: tests/testing.f90 | $(BLD)
	$(FC_ALL) -J$(BLD) -c -o $@ $<

# the test helpers that need the library (must_setup)
$(BLD)/testing_sim.o: tests/testing_sim.f90 $(BLD)/testing.o $(LIBOBJ) | $(BLD)
	$(FC_ALL) $(HDF5_FFLAGS) -J$(BLD) -c -o $@ $<

$(BLD)/test_%: tests/test_%.f90 $(BLD)/testing.o $(BLD)/testing_sim.o $(LIBOBJ) | $(BLD)
	$(FC_ALL) $(HDF5_FFLAGS) -I$(BLD) -J$(BLD)/tmod_$* -o $@ $< $(BLD)/testing.o \
	  $(BLD)/testing_sim.o $(LIBOBJ) $(HDF5_LIBS)

$(BLD)/tmod_%:
	mkdir -p $@

$(TESTS): $(BLD)/test_%: | $(BLD)/tmod_%

# Module dependencies are generated from the sources, never listed by hand.
$(BLD)/deps.mk: $(SRC) tools/f90deps.awk | $(BLD)
	awk -f tools/f90deps.awk $(SRC) | sed 's|build/|$(BLD)/|g' > $@

ifneq ($(MAKECMDGOALS),clean)
ifneq ($(MAKECMDGOALS),help)
-include $(BLD)/deps.mk
endif
endif

## test: debug build (-fcheck=all, FP traps), then every test program and script;
##       BUILD=asan: the same with the sanitizer build (-fsanitize=address,undefined)
TEST_BUILD := $(if $(filter asan,$(BUILD)),asan,debug)
test: deps
	@$(MAKE) --no-print-directory $(JFLAG) BUILD=$(TEST_BUILD) build/$(TEST_BUILD)/tubempm \
	  test-programs
	@bash tools/run-tests.sh build/$(TEST_BUILD)

test-programs: $(TESTS)

## test-slurm: as root, install Slurm and munge where missing (tools/install-deps.sh --slurm),
##             start a one-node cluster in a temporary folder, run a small sweep through it and
##             locally, compare, cancel a task and re-submit (tests/slurm/; about a minute:
##             63 s with the packages' install, docs/batch.md)
test-slurm: all
	@bash tools/install-deps.sh --slurm
	@bash tests/slurm/run.sh bin/tubempm

## run: build, run CASE (default namelists/default.nml), then plot it
run: all
	bin/tubempm $(CASE)
	$(PYTHON) -m plots.plot_case --case $(CASE)

## bench: the native build's results against the release build's (tests/check_native.py), the
##        release build, then the fixed benchmark scenes (4-6 min, run it on an idle machine);
##        table and plot in docs/bench/ (BENCH_FLAGS=--quick: up to 1e5 particles only), and
##        --check's throughput (tools/advice_tables.py writes src/advice/mpm_bench_table.inc)
BENCH_BLD := $(if $(filter command line,$(origin BLD)),$(BLD),build/release)
bench: deps
	$(PYTHON) -m tests.check_native out/bench/check_native
	@$(MAKE) --no-print-directory BUILD=release BLD=$(BENCH_BLD) $(BENCH_BLD)/bench
	$(PYTHON) -m tools.bench --exe $(BENCH_BLD)/bench --out docs/bench $(BENCH_FLAGS)
	$(PYTHON) -m tools.advice_tables --bench --cost    # --check's wall-time estimate and model

## bench-cost: the wall-time model's measurements (about 80 min on one thread; never part of
##        make test): every shipped namelist's first 1.5e7 particle-steps and the whole run of
##        those whose contact or foam changes (tools/bench.py --cost, docs/bench/cost_<stamp>.csv), then
##        the fit of its terms (tools/advice_tables.py --cost writes src/advice/mpm_cost_table.inc)
bench-cost: all
	@$(MAKE) --no-print-directory BUILD=release BLD=$(BENCH_BLD) $(BENCH_BLD)/bench
	$(PYTHON) -m tools.bench --exe $(BENCH_BLD)/bench --cost --out docs/bench
	$(PYTHON) -m tools.advice_tables --cost    # --check's wall-time model

$(BLD)/bench: tools/bench.f90 $(LIBOBJ) | $(BLD) $(BLD)/tmod_bench
	$(FC_ALL) $(HDF5_FFLAGS) -I$(BLD) -J$(BLD)/tmod_bench -o $@ $< $(LIBOBJ) $(HDF5_LIBS)

## study: the refinement study (LEVEL=quick: under 10 min on 2 cores; LEVEL=full: 223 runs,
##        2.8 CPU h, about 85 min on 2 free cores; LEVEL=all: more); runs in out/study/ (resumable),
##        table and figures in docs/study/ (quick: out/study-quick/); BACKEND=slurm runs them
##        as a Slurm job array, BATCH_FLAGS="--partition P --time T --account A" (docs/batch.md)
LEVEL ?= quick
BACKEND ?= local
study: all
	$(PYTHON) -m tools.study --level $(LEVEL) --backend $(BACKEND) $(BATCH_FLAGS)
	$(PYTHON) -m plots.plot_study --level $(LEVEL)
	$(PYTHON) -m tools.advice_tables --study
	@$(MAKE) --no-print-directory all    # --check's advice table may have changed

## figures: regenerate the study's figures (docs/study/) from the committed table and curves,
##          and --check's advice table (tools/advice_tables.py writes src/advice/mpm_advice_table.inc;
##          rebuilt when it changed); the stability study's figures (docs/stability/) from its
##          committed tables
figures: deps
	$(PYTHON) -m plots.plot_study --level full
	$(PYTHON) -m plots.plot_stability --level full
	$(PYTHON) -m tools.advice_tables --study
	@$(MAKE) --no-print-directory all

## cfl-accuracy: the accuracy limit of the automatic time step: an elastic impact per basis x
##               scheme at 1 and 2 particles per cell, the cfl stepped down until its energy is
##               within 1 % (tools/cfl_accuracy.py, about 8 min on two cores; runs reused from
##               build/cfl_accuracy/), into docs/stability/cfl_accuracy_*.csv and the compiled table
cfl-accuracy: all
	$(PYTHON) -m tools.cfl_accuracy
	$(PYTHON) -m tools.advice_tables --stability

## validate-honeycomb: honeycomb cells (regular and re-entrant) against Gibson & Ashby's E1, nu12
##                     and plastic collapse stress, and against CalculiX on the same mesh
##                     (installs calculix-ccx where missing; tools/honeycomb_validation.py, about
##                     50 CPU min, one run at a time): docs/honeycomb/gibson_ashby.csv; runs in
##                     build/honeycomb_validation/ (reused when unchanged)
validate-honeycomb: all
	@bash tools/install-deps.sh --ccx
	OMP_NUM_THREADS=1 $(PYTHON) -m tools.honeycomb_validation

## fe-reference: the CalculiX reference of the study's crush (installs calculix-ccx where
##               missing; about 20 CPU min, one thread): first the committed coarse curve
##               against ccx on this machine (tests/test_fe_reference.py --ccx), then decks,
##               curves and convergence in
##               docs/fe_reference/, runs in out/fe_reference/ (reused when the deck is unchanged),
##               then the comparison with the study's crush curves (docs/fe_reference/crush_fe.png);
##               then the square tube crushed laterally (about 15 CPU min more: decks, curves,
##               convergence, tubempm's namelists/sections/square_tube.nml against them,
##               docs/fe_reference/square_*; runs in out/fe_reference/square/; and at four
##               platen speeds, square_speed.csv, about 5 CPU min);
##               then the sheared ring, bonded and loose (about 6 CPU min more: decks, curves and
##               tubempm's runs against them, docs/fe_reference/shear_*; runs in out/fe_reference/shear/);
##               then fe-dynamic
fe-reference: deps
	@bash tools/install-deps.sh --ccx
	$(PYTHON) -m tests.test_fe_reference --ccx out/fe_reference/check
	$(PYTHON) -m tools.fe_reference.fe_reference
	$(PYTHON) -m plots.plot_fe_reference
	$(PYTHON) -m tools.fe_reference.square_reference
	$(MAKE) --no-print-directory all BUILD=release
	OMP_NUM_THREADS=1 bin/tubempm --quiet namelists/sections/square_tube.nml
	$(PYTHON) -m tools.fe_reference.square_reference --compare out/square_tube/history.csv --write
	$(PYTHON) -m plots.plot_fe_square
	$(PYTHON) -m tools.fe_reference.square_speed
	$(PYTHON) -m tools.fe_reference.shear_reference
	$(PYTHON) -m plots.plot_fe_shear
	@$(MAKE) --no-print-directory fe-dynamic

## fe-dynamic: the dynamic FE references of the impact and wave (the project's explicit FE code
##             tools/fe_reference/xfe.f90, gfortran -O2; about 70 CPU min, one thread): meshes
##             n_t = 2-16 (the wave 2-32), convergence, the CalculiX cross-checks, tubempm's
##             errors against them (docs/fe_reference/README.md#dynamic-references); runs in
##             out/fe_dynamic/ (reused)
.PHONY: fe-dynamic
fe-dynamic: all
	@bash tools/install-deps.sh --ccx
	OMP_NUM_THREADS=1 $(PYTHON) -m tools.fe_reference.fe_dynamic
	OMP_NUM_THREADS=1 $(PYTHON) -m tools.fe_reference.ccx_dynamic
	OMP_NUM_THREADS=1 $(PYTHON) -m tools.fe_reference.compare_dynamic --study

## design-example: design charts of tube absorbers (docs/design.md): seven quasi-static crushes
##                 (steel and aluminium at D/t 15, 25, 35; a nested pair), about 2.5 min on two
##                 cores; charts and table in out/design_example/; BACKEND=slurm, BATCH_FLAGS
design-example: all
	$(PYTHON) -m tools.design_example --backend $(BACKEND) $(BATCH_FLAGS)

## stability: the stability study of docs/stability.md (release build, one run at a time, one
##            thread): LEVEL=quick (default, < 10 min; tables and figures in out/stability-quick/)
##            or LEVEL=full (docs/stability/); runs in build/stability/ (reused when unchanged);
##            then the automatic cfl's and --check's cfl limits from docs/stability/
##            (tools/advice_tables.py writes src/method/mpm_time_step_table.inc and
##            src/advice/mpm_stability_table.inc); BACKEND=slurm and BATCH_FLAGS as for study
stability: all
	$(PYTHON) -m tools.stability --level $(LEVEL) --backend $(BACKEND) $(BATCH_FLAGS)
	$(PYTHON) -m plots.plot_stability --level $(LEVEL)
	$(PYTHON) -m tools.advice_tables --stability
	@$(MAKE) --no-print-directory all    # the cfl limits may have changed

## check-paraview: install Debian's ParaView (pvbatch, xvfb) if missing, then open a run's
##                 particles.xdmf with ParaView's default reader and check every array
check-paraview: deps
	@bash tools/install-deps.sh --paraview
	@$(MAKE) --no-print-directory BUILD=debug build/debug/tubempm
	@TUBEMPM=build/debug/tubempm bash tests/test_paraview.sh $$(mktemp -d)

## check-namelists: bin/tubempm --check on every file in namelists/
check-namelists: all
	@for f in namelists/*.nml; do bin/tubempm --check --quiet $$f > /dev/null || exit 1; echo "ok  $$f"; done

## fuzz: mutate the shipped namelists N times (default 5000) through --check (release build)
fuzz: all
	$(PYTHON) -m tools.fuzz_namelists --bin bin/tubempm --count $(or $(N),5000) --seed $(or $(SEED),1) --out build/fuzz

## fuzz-scenes: run N (default 200) valid but extreme scenes to their end (tools/fuzz_scenes.py)
##              on the debug build (BUILD=asan: the sanitizer build); failures kept in build/
fuzz-scenes: deps
	@$(MAKE) --no-print-directory BUILD=$(TEST_BUILD) build/$(TEST_BUILD)/tubempm
	$(PYTHON) -m tools.fuzz_scenes --bin build/$(TEST_BUILD)/tubempm --count $(or $(N),200) \
	  --seed $(or $(SEED),1) --out build/fuzz_scenes

## clean: remove build/ and bin/
clean:
	rm -rf build bin

## help: list the targets
help:
	@echo "tubempm make targets:"
	@grep -E '^## ' Makefile | sed 's/^## /  /'
	@echo "variables: BUILD=release|debug|asan|native  CASE=file.nml  FC=compiler  PYTHON=python3  JOBS=n (builds; default: up to 2 cores)"
	@echo "           LEVEL=quick|full|all  BACKEND=local|slurm  BATCH_FLAGS=... (study, stability)"
