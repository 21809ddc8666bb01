# PERI-NOSPD: the two commands a fresh machine needs.
#   make run    provision (Debian packages, LAMMPS from Debian's source
#               package), build the plugin alone and run the flagship example
#   make test   provision, build the plugin and the test programs, and run
#               the whole test suite through ctest
# Other targets: make lammps | plugin (the plugin and the test programs) |
#   plugin-only (the plugin alone) | bench | chart | doc | clean
SHELL := /bin/bash
JOBS ?= $(shell nproc)
BUILD ?= build
LAMMPS_SRC = $(shell bash cmake/lammps.sh print-src)
LAMMPS_BLD = $(shell bash cmake/lammps.sh print-dir)

.PHONY: all lammps configure plugin plugin-only run test bench chart doc clean

all: plugin

lammps:
	bash cmake/lammps.sh all

# configured every time (a second when nothing changed), so that a build
# folder made against an older LAMMPS build follows the current one
configure: lammps
	cmake -S . -B $(BUILD) -DLAMMPS_SOURCE_DIR=$(LAMMPS_SRC)/src -DLAMMPS_BINARY_DIR=$(LAMMPS_BLD) > /dev/null

# every target: the plugin and the test programs
plugin: configure
	cmake --build $(BUILD) -j $(JOBS)

# the plugin alone (CMake target nospdplugin, src/PERI-NOSPD/CMakeLists.txt):
# what the flagship needs
plugin-only: configure
	cmake --build $(BUILD) -j $(JOBS) --target nospdplugin

run: plugin-only
	bash examples/run-flagship.sh $(LAMMPS_BLD)/lmp $(BUILD)/plugin

test: plugin
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: plugin
	bash bench/run.sh $(LAMMPS_BLD)/lmp $(BUILD)/plugin

# speed against accuracy and the stability study (bench/chart, ~10-20 min)
chart: plugin
	LMP=$(LAMMPS_BLD)/lmp PLUGIN_DIR=$(BUILD)/plugin bash bench/chart/run_all.sh

doc:
	bash cmake/lammps.sh deps
	/usr/bin/python3 -m sphinx -W -b html doc $(BUILD)/doc-html

clean:
	rm -rf $(BUILD)
