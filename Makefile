# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# Thin wrapper over CMake/CTest. `make run`: build and run selfcol-cli check
# on the bundled mesh; `make test`: build and pass the tests. Both install
# missing Debian packages first (make deps).
BUILD ?= build
CMAKE_FLAGS ?=
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
DEB_PACKAGES := cmake make gcc g++ pkg-config libccd-dev libbullet-dev libbullet-extras-dev \
                libeigen3-dev libcmocka-dev libpng-dev python3 python3-dev python3-venv
VERSION := $(shell sed -n 's/^\#define SELFCOL_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)/\2/p' include/selfcol/version.h | paste -sd.)

.PHONY: all build deps test run clean version abi-dump abi-check bench bench-full bench-smoke bench-sweep bench-python plot fuzz wheel docs blender-addon blender-test
all: build

deps:
	@sh tools/deps.sh $(DEB_PACKAGES)

build: deps
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

run: build
	@# selfcol-cli exits 1 when it finds interferences, and the bundled mesh has them on
	@# purpose: only a status above 1 (usage or input error) fails this target.
	$(BUILD)/tools/cli/selfcol-cli check tests/data/folded_ribbon.obj --png $(BUILD)/folded_ribbon.png; \
	  status=$$?; [ $$status -le 1 ] || exit $$status
	@echo "picture: $(BUILD)/folded_ribbon.png"

# Benchmarks (tools/bench): a representative subset in a few minutes, everything,
# and the tiny smoke run CI uses (never a timing assertion). `make plot` draws docs/.
bench: build
	sh tools/bench/run.sh --subset default --build $(BUILD)

bench-full: build
	sh tools/bench/run.sh --subset full --build $(BUILD)

bench-smoke: build
	sh tools/bench/run.sh --subset smoke --build $(BUILD)
	sh tools/bench/run_sweep.sh --smoke --build $(BUILD)

bench-sweep: build
	sh tools/bench/run_sweep.sh --build $(BUILD)

# Python packages side by side on cloth-ball 92 (tools/bench/side_by_side.sh):
# install time into a fresh venv and one-thread queries of selfcol's wheel,
# ipctk, pymeshlab, libigl and trimesh -> tools/bench/results/side_by_side.md.
bench-python: wheel
	sh tools/bench/side_by_side.sh --build $(BUILD)

plot:
	sh tools/plot/plot.sh

# The core's fuzz targets (tests/fuzz; clang's libFuzzer): FUZZ_SECONDS each.
FUZZ_SECONDS ?= 60
fuzz:
	sh tests/fuzz/run.sh $(FUZZ_SECONDS) build-fuzz

# The Python wheel that installs with no compiler (libccd inside, manylinux
# tag), proven in a fresh venv with no compiler on PATH (tools/wheel.sh):
# $(BUILD)/wheel/dist/selfcol-*.whl.
wheel: deps
	sh tools/wheel.sh $(BUILD)

# The Blender add-on's zip, the module inside (tools/blender_addon.sh):
# $(BUILD)/blender/selfcol_blender-$(VERSION).zip. blender-test also installs
# it into Debian's blender, headless, and checks its marks against selfcol-cli.
blender-addon: deps
	sh tools/blender_addon.sh $(BUILD)

blender-test: build
	sh tools/blender_addon.sh $(BUILD) --test

# The Python API reference from the docstrings (pdoc): $(BUILD)/docs/python/.
docs: deps
	sh tools/docs.sh $(BUILD)

# ABI baselines of this version (at a release), and the check against the newest
# ones: libselfcol, and libselfcol_bullet when the build has it (Bullet found).
# `make abi-dump` refreshes both baselines of $(VERSION). While a version is
# unreleased (libselfcol_bullet-0.2.0.abi: the adapter is new in 0.2.0), its
# baselines are re-dumped whenever its API changes before the release. The
# dumps hold the public types only and no path (tools/abi_dump.sh), so an
# internal move or struct change leaves them alone.
BULLET_LIB := $(BUILD)/adapters/bullet/libselfcol_bullet.so
abi-dump: build
	@sh tools/deps.sh abigail-tools
	sh tools/abi_dump.sh $(BUILD)/lib/libselfcol.so include/selfcol \
	  tests/abi/libselfcol-$(VERSION).abi
	@if [ -e $(BULLET_LIB) ]; then \
	  echo "sh tools/abi_dump.sh $(BULLET_LIB) adapters/bullet/include/selfcol tests/abi/libselfcol_bullet-$(VERSION).abi"; \
	  sh tools/abi_dump.sh $(BULLET_LIB) adapters/bullet/include/selfcol \
	    tests/abi/libselfcol_bullet-$(VERSION).abi; \
	else \
	  echo "abi-dump: no $(BULLET_LIB) (libselfcol_bullet not built): its baseline is left alone"; \
	fi

abi-check: build
	@sh tools/deps.sh abigail-tools
	sh tools/abi_check.sh $(BUILD)/lib/libselfcol.so
	@if [ -e $(BULLET_LIB) ]; then \
	  echo "sh tools/abi_check.sh $(BULLET_LIB) libselfcol_bullet adapters/bullet/include/selfcol"; \
	  sh tools/abi_check.sh $(BULLET_LIB) libselfcol_bullet adapters/bullet/include/selfcol; \
	else \
	  echo "abi-check: no $(BULLET_LIB) (libselfcol_bullet not built): skipped"; \
	fi

version:
	@echo $(VERSION)

clean:
	rm -rf $(BUILD)
