# cfrd: the two commands a new user types are `make run` and `make test`.
# Both install what is missing (Debian packages and PyPI packages), then build.

SHELL := /bin/bash
.DEFAULT_GOAL := run

# The default deck: Tianshengqiao-I at the knee of accuracy against time (docs/accuracy-cost.md:
# mesh x2, 2 increments per layer, 5 m water steps; about 4 s). The x1 decks are the paper's
# resolution and the fast regression decks (0.5 s, below the knee).
DECK ?= inputs/tianshengqiao.dat
APT_PACKAGES := gfortran gcc libsuitesparse-dev libhdf5-dev libdeflate-dev liblapack-dev \
                libblas-dev pkg-config calculix-ccx libopenblas0-pthread libopenblas-pthread-dev \
                libmetis-dev
PIP_PACKAGES := fpm numpy scipy matplotlib h5py tomli meshio
# Only for make slurm-check (CI): a private one-node Slurm cluster.
SLURM_APT_PACKAGES := slurmctld slurmd slurm-client munge

# HDF5's Fortran modules and libraries live in Debian's serial folders: ask pkg-config.
HDF5_CFLAGS = $(shell pkg-config --cflags hdf5 2>/dev/null)
HDF5_LDIRS = $(shell pkg-config --libs-only-L hdf5 2>/dev/null)
# OpenMP for the element loops (cfrd --threads; src/core/cfrd_omp_threads.f90): compiled and
# linked with every profile, tests included. Without it the program runs one thread.
OPENMP_FLAGS = -fopenmp
RELEASE_FLAGS = -O3 -march=native -funroll-loops $(OPENMP_FLAGS) $(HDF5_CFLAGS)
DEBUG_FLAGS = -O0 -g -Wall -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace \
              $(OPENMP_FLAGS) $(HDF5_CFLAGS)
# fpm takes the subcommand first: $(call fpm,SUBCOMMAND,PROFILE,FLAGS[,LINK DIRS FIRST])
fpm = FPM_LDFLAGS="$(4) $(HDF5_LDIRS) $(OPENMP_FLAGS)" fpm $(1) --profile $(2) --flag "$(3)"
# The release program takes HDF5 from its static archives (libhdf5-dev's libhdf5.a and
# libhdf5_fortran.a, linked under the names fpm.toml asks for, through this folder of
# links searched first): Debian's shared libhdf5_serial brings libcurl and some 30 more
# libraries (its read-only S3 driver, which cfrd never uses), and resolving their symbols
# took half of the process start (docs/performance.md (r)). Without the archives the
# folder stays empty and the shared libraries are linked as before.
HDF5_LIBDIR = $(patsubst -L%,%,$(firstword $(HDF5_LDIRS)))
STATIC_LIBS = build/static-libs
# libdeflate (HDF5's deflate filter computed by libdeflate, src/io/cfrd_h5_deflate.c) is
# linked from its archive into the release program the same way (one shared object fewer
# to load); the debug build and the tests link libdeflate.so.
DEFLATE_ARCHIVE = $(shell gcc -print-file-name=libdeflate.a 2>/dev/null)
# So are SuiteSparse (libsuitesparse-dev's archives) and OpenBLAS (libopenblas-pthread-dev's
# libopenblas.a, BLAS and LAPACK in one archive, linked under the names lapack and blas):
# the shared OpenBLAS alone made the loader resolve some 20,000 symbol relocations at
# every start, about a tenth of a small deck's run (docs/performance.md (r), (y)). The
# same library versions as the shared objects: the same kernels, the same bits. METIS
# stays shared (Debian ships no archive of it). cfrd_blas_threads finds OpenBLAS's thread
# controls by dlsym: linked statically, they are pulled in and exported by name.
SUITESPARSE_ARCHIVES = umfpack cholmod amd camd colamd ccolamd suitesparseconfig
OPENBLAS_ARCHIVE = $(shell gcc -print-file-name=libopenblas.a 2>/dev/null)
comma := ,
OPENBLAS_CONTROLS = openblas_set_num_threads blas_thread_shutdown_
STATIC_BLAS_LDFLAGS = $(if $(wildcard $(OPENBLAS_ARCHIVE)),$(foreach f,$(OPENBLAS_CONTROLS),\
                      -Wl$(comma)-u$(comma)$(f) -Wl$(comma)--export-dynamic-symbol=$(f)))

DECKS ?= $(wildcard inputs/*.dat)
OUT ?= batch-results
STUDY ?= inputs/studies/tianshengqiao-joint.dat

.PHONY: run test bench fuzz figures batch study references slurm-check deps build build-debug clean \
        floor

## deps: install whatever is missing; a second call only checks (well under a second).
deps:
	@tools/ensure_deps.sh "$(APT_PACKAGES)" "$(PIP_PACKAGES)"

## build: release build, program at bin/cfrd
build: deps
	@mkdir -p build $(STATIC_LIBS)
	@if [ -f "$(HDF5_LIBDIR)/libhdf5.a" ] && [ -f "$(HDF5_LIBDIR)/libhdf5_fortran.a" ]; then \
	  ln -sf "$(HDF5_LIBDIR)/libhdf5.a" $(STATIC_LIBS)/libhdf5_serial.a; \
	  ln -sf "$(HDF5_LIBDIR)/libhdf5_fortran.a" $(STATIC_LIBS)/libhdf5_serial_fortran.a; fi
	@if [ -f "$(DEFLATE_ARCHIVE)" ]; then ln -sf "$(DEFLATE_ARCHIVE)" $(STATIC_LIBS)/libdeflate.a; fi
	@for l in $(SUITESPARSE_ARCHIVES); do a=$$(gcc -print-file-name=lib$$l.a); \
	  if [ -f "$$a" ]; then ln -sf "$$a" $(STATIC_LIBS)/lib$$l.a; fi; done
	@if [ -f "$(OPENBLAS_ARCHIVE)" ]; then ln -sf "$(OPENBLAS_ARCHIVE)" $(STATIC_LIBS)/liblapack.a; \
	  ln -sf "$(OPENBLAS_ARCHIVE)" $(STATIC_LIBS)/libblas.a; fi
	@# fpm relinks only when an object changes: a changed link (flags, archives) removes
	@# the linked program so that it is linked again
	@{ echo "$(STATIC_BLAS_LDFLAGS)"; ls -l $(STATIC_LIBS) | grep -o 'lib[^ ]*\.a ->.*'; } \
	  >build/release-link.new; cmp -s build/release-link.new build/release-link || \
	  { rm -f build/gfortran_*/app/cfrd; mv build/release-link.new build/release-link; }
	@$(call fpm,install,release,$(RELEASE_FLAGS),-L$(CURDIR)/$(STATIC_LIBS) $(STATIC_BLAS_LDFLAGS)) \
	  --prefix "$(CURDIR)" --bindir bin \
	  >build/release.log 2>&1 || { cat build/release.log; exit 1; }

## build-debug: debug build with every runtime check, program at build/debug-bin/cfrd.
## It starts from scratch: fpm 0.12 can miss a changed derived type in a module that others
## use and link stale objects; a clean debug build takes seconds.
build-debug: deps
	@mkdir -p build
	@rm -rf build/gfortran_* build/cache.toml
	@$(call fpm,install,debug,$(DEBUG_FLAGS)) --prefix "$(CURDIR)/build" --bindir debug-bin \
	  >build/debug.log 2>&1 || { cat build/debug.log; exit 1; }

## run: build, run the default deck, print its result table
run: build
	@bin/cfrd $(DECK)

## test: debug build, every test; the last line is `N passed, N failed`
test: build-debug
	@OMP_WAIT_POLICY=passive $(call fpm,test,debug,$(DEBUG_FLAGS)) >build/fortran-tests.log 2>&1; \
	  tools/run_tests.sh build/fortran-tests.log

## figures: run DECK, then draw the paper's figures from its results into FIGURES
## (tools/figures.py: contours, gauge histories, interface opening and stresses, Table 5)
FIGURES ?= build/figures
figures: build
	@bin/cfrd --quiet $(DECK)
	@python3 tools/figures.py $(basename $(DECK)).h5 --out $(FIGURES)

## batch: run many decks at once, one process per deck on every core, then a summary table
## (make batch DECKS="inputs/a.dat inputs/b.dat" [OUT=DIR] [JOBS=N]; docs/results.md)
batch: build
	@python3 tools/batch.py --cfrd bin/cfrd --out "$(OUT)" $(if $(JOBS),--jobs $(JOBS)) $(DECKS)

## study: expand a template deck over its parameter table, run the cases, table and figure
## (make study [STUDY=TEMPLATE.dat] [JOBS=N]; results in study-TEMPLATE/)
study: build
	@python3 tools/study.py --cfrd bin/cfrd $(if $(JOBS),--jobs $(JOBS)) $(STUDY)

## references: rerun inputs/*.dat and rewrite the references in outputs/reference/ whose
## results changed beyond the regression tolerances (explain why in the commit)
references: build
	@python3 tools/regression.py --refresh --cfrd bin/cfrd

## slurm-check: a study's job array through a real one-node Slurm cluster started for the
## purpose (private munge key, ports and state under build/slurm-check; about 15 s; CI)
slurm-check: build
	@tools/ensure_deps.sh "$(SLURM_APT_PACKAGES)" ""
	@tools/slurm_cluster_check.sh bin/cfrd build/slurm-check

## fuzz: 10,000 mutated decks of inputs/ through bin/cfrd: no crash, hang, vague message or
## NaN (make fuzz [FUZZ_COUNT=N] [FUZZ_SEED=S]; about 6 min; docs/robustness.md)
FUZZ_COUNT ?= 10000
FUZZ_SEED ?= 1
fuzz: build
	@python3 tools/fuzz.py --cfrd bin/cfrd --count $(FUZZ_COUNT) --seed $(FUZZ_SEED) \
	  --workdir build/fuzz/run

## bench: timing figures (see docs/performance.md)
## and then the accuracy-cost study (make accuracy, below).
## make bench BASELINE=OLD/cfrd: instead, before and after in one run: OLD and bin/cfrd on the
## x4 bonded, joint, thin and contact decks (midpoint, Newton), alternately, 3 rounds, the
## ratios of user, analysis and factorisation time and the results' agreement to 1e-8
## (tools/bench_baseline.py; BENCH_FLAGS="--rounds 1 --solvers midpoint" and so on)
bench: build
	@if [ -n "$(BASELINE)" ]; then \
	  python3 tools/bench_baseline.py --baseline "$(BASELINE)" --cfrd bin/cfrd $(BENCH_FLAGS); \
	else python3 tools/bench.py && $(MAKE) --no-print-directory accuracy; fi

## floor: numeric factorisation of UMFPACK against CHOLMOD supernodal (AMD, METIS, NESDIS) on
## the matrix cfrd factorises first in the last stage of the x4 bonded, joint and thin decks,
## best of 5, one BLAS thread (make floor [MTX=FILE.mtx] for one matrix; docs/performance.md
## (k); about 2 min). The libraries run as in cfrd: CHOLMOD's OpenMP loops on the calling
## thread (its compiled-in team of 4 otherwise spins on 2 cores: 3 times the time) and no
## mmap for the large blocks (cfrd_memory), so that each factorisation reuses warm pages
## (docs/performance.md (aj))
FLOOR_STAGE ?= 45
FLOOR_ENV = OPENBLAS_NUM_THREADS=1 OMP_MAX_ACTIVE_LEVELS=0 \
  GLIBC_TUNABLES=glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1073741824
build/floor/factor_floor: tools/factor_floor.c
	@mkdir -p build/floor
	@gcc -O2 -Wall -o $@ $< -lcholmod -lumfpack -lsuitesparseconfig -lm
floor: build build/floor/factor_floor
	@if [ -n "$(MTX)" ]; then $(FLOOR_ENV) build/floor/factor_floor $(MTX); else \
	  for i in bonded joint thin; do \
	    python3 tools/tianshengqiao.py --refine 4 --interface $$i --deck build/floor/x4-$$i.dat \
	      >/dev/null && \
	    CFRD_WRITE_MATRIX=build/floor/x4-$$i.mtx CFRD_WRITE_MATRIX_STAGE=$(FLOOR_STAGE) \
	      bin/cfrd --quiet --compress 0 --out build/floor build/floor/x4-$$i.dat && \
	    $(FLOOR_ENV) build/floor/factor_floor build/floor/x4-$$i.mtx || exit 1; \
	  done; fi

## accuracy: error against wall time of the Tianshengqiao-I decks, one knob at a time;
## tables and plots in build/accuracy/ (docs/accuracy-cost.md; runs cached there, about
## 15 min from scratch on a shared 2-core machine; ACCURACY_FLAGS="--max-refine 4" leaves
## out the x8 meshes, ACCURACY_FLAGS="--doc docs/accuracy-cost.md --plot-prefix
## docs/accuracy-cost" refreshes the document's tables and plots)
.PHONY: accuracy
accuracy: build
	@python3 tools/accuracy_cost.py $(ACCURACY_FLAGS)

clean:
	rm -rf build bin
