# cfrd: the two commands a new user types are `make run` and `make test`.
# Both install what is missing (Debian packages and PyPI packages), then build.

SHELL := /bin/bash
.DEFAULT_GOAL := run

DECK ?= inputs/embankment.dat
APT_PACKAGES := gfortran libsuitesparse-dev libhdf5-dev liblapack-dev libblas-dev \
                pkg-config calculix-ccx
PIP_PACKAGES := fpm numpy matplotlib h5py

# HDF5's Fortran modules and libraries live in Debian's serial folders: ask pkg-config.
HDF5_CFLAGS = $(shell pkg-config --cflags hdf5 2>/dev/null)
HDF5_LDIRS = $(shell pkg-config --libs-only-L hdf5 2>/dev/null)
RELEASE_FLAGS = -O3 -march=native -funroll-loops $(HDF5_CFLAGS)
DEBUG_FLAGS = -O0 -g -Wall -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace \
              $(HDF5_CFLAGS)
FPM_RELEASE = FPM_LDFLAGS="$(HDF5_LDIRS)" fpm --profile release --flag "$(RELEASE_FLAGS)"
FPM_DEBUG = FPM_LDFLAGS="$(HDF5_LDIRS)" fpm --profile debug --flag "$(DEBUG_FLAGS)"

.PHONY: run test bench deps build build-debug clean

## deps: install whatever is missing; a second call only checks (well under a second).
deps:
	@tools/ensure_deps.sh "$(APT_PACKAGES)" "$(PIP_PACKAGES)"

## build: release build, program at bin/cfrd
build: deps
	@$(FPM_RELEASE) install --prefix "$(CURDIR)" --bindir bin --no-rebuild >/dev/null 2>&1 || \
	  $(FPM_RELEASE) install --prefix "$(CURDIR)" --bindir bin

## build-debug: debug build with every runtime check, program at build/debug-bin/cfrd
build-debug: deps
	@$(FPM_DEBUG) install --prefix "$(CURDIR)/build" --bindir debug-bin >/dev/null

## run: build, run the default deck, print its result table
run: build
	@bin/cfrd $(DECK)

## test: debug build, every test; the last line is `N passed, N failed`
test: build-debug
	@tools/run_tests.sh "$(FPM_DEBUG)"

## bench: timing figures (see docs/performance.md)
bench: build
	@python3 tools/bench.py

clean:
	rm -rf build bin
