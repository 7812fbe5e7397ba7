# Motion-control firmware for the Arduino Mega 2560 and its host simulator `motionsim`.
# The Makefile is the one entry point; the long parts live in tools/ and can be run alone.
#
#   make setup      install everything (Debian packages, .venv, arduino-cli)   -> tools/setup.sh
#   make test       build everything and run every test; ends with "N passed, N failed"
#   make profiles   standard scenarios -> build/profiles/*.csv, *.png, profiles.xlsx
#   make firmware   build every sketch for the Mega and print the flash/SRAM table
#   make sim        build build/motionsim
#   make upload SKETCH=<name> PORT=<device>    flash a real Mega over USB
#   make monitor PORT=<device> [BAUD=115200]   serial monitor (default 9600 baud), CR+LF line ends
#   make emulate SKETCH=<name> [INPUT=<file>]  run a sketch's ELF in the ATmega2560 emulator
#   make emulate SKETCH=<name> LIVE=1          ... in real time on a pseudo-terminal: talk to it with make monitor PORT=<its path>
#   make bench      step-engine benchmark in the emulator -> docs/bench.md (committed; about 8 min on 2 cores)
#   make fuzz [FUZZ_LINES=10000] [FUZZ_SEED=1] [FUZZ_SIM_RUNS=<lines/20>]   fuzz every sketch's serial
#                   console in the emulator and motionsim under ASan+UBSan (tools/fuzz) -> docs/fuzz-summary.md;
#                   make test runs a short one
#   make clean

SHELL := /bin/bash
.DEFAULT_GOAL := help

BUILD   := build
PY      := .venv/bin/python
CC      ?= cc
CXX     ?= c++

# Host builds: the same lib/src sources as the sketches, C11, warnings are errors.
# -ffp-contract=off keeps float arithmetic in the order written (no fused multiply-add), as on AVR.
WARN      := -Wall -Wextra -Werror
HOST_CFLAGS   := -std=c11 -O2 -g $(WARN) -ffp-contract=off -D_POSIX_C_SOURCE=200809L -Ilib/src -Isim
HOST_CXXFLAGS := -std=c++11 -O2 -g $(WARN) -ffp-contract=off -Ilib/src -Isim
SAN_FLAGS     := -O1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all

LIB_C    := $(sort $(wildcard lib/src/*.c))
LIB_CXX  := $(sort $(wildcard lib/src/*.cpp))
# sim/: plant_*.c are the physical models (e.g. the DC motor + encoder) that the unit tests and
# the emulator harness link too; every other sim/*.c is the motionsim program itself.
SIM_MODELS := $(sort $(wildcard sim/plant_*.c))
SIM_MAIN   := $(filter-out $(SIM_MODELS),$(sort $(wildcard sim/*.c)))
HDRS       := $(wildcard lib/src/*.h sim/*.h)

UNIT_HDRS  := $(wildcard test/unit/*.h)
UNIT_SRCS  := $(sort $(wildcard test/unit/test_*.c test/unit/test_*.cpp))
UNIT_NAMES := $(basename $(notdir $(UNIT_SRCS)))
UNIT_BINS  := $(addprefix $(BUILD)/test/unit/,$(UNIT_NAMES))
SAN_BINS   := $(addprefix $(BUILD)/test/unit-san/,$(UNIT_NAMES))

# every folder of firmware/ but libraries/; tools/build_firmware.sh refuses one whose .ino lacks the
# marker line "// motion-sketch: <family>" (what the sketch is, for the build, the emulator and the tests)
SKETCHES := $(sort $(patsubst firmware/%/,%,$(filter-out firmware/libraries/,$(wildcard firmware/*/))))

.PHONY: help setup sim firmware profiles test unit upload monitor emulate fuzz clean check-setup bench

help:
	@sed -n '1,/^$$/p' Makefile | sed -n 's/^# \{0,1\}//p'

setup:
	@bash tools/setup.sh

# $(error) stops make with one line (no second "Error 1" line from a failed recipe).
check-setup:
	$(if $(and $(wildcard .venv/bin/python),$(wildcard .tools/arduino-cli)),,$(error the toolchain is not installed: run 'make setup' first))
	@:

# ---------------------------------------------------------------------------------------
# Host objects: one set normal, one set with AddressSanitizer + UBSan.
$(BUILD)/host/%.o: %.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -c $< -o $@
$(BUILD)/host/%.o: %.cpp $(HDRS)
	@mkdir -p $(dir $@)
	$(CXX) $(HOST_CXXFLAGS) -c $< -o $@
$(BUILD)/host-san/%.o: %.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(SAN_FLAGS) -c $< -o $@
$(BUILD)/host-san/%.o: %.cpp $(HDRS)
	@mkdir -p $(dir $@)
	$(CXX) $(HOST_CXXFLAGS) $(SAN_FLAGS) -c $< -o $@

LIB_OBJS       := $(patsubst %,$(BUILD)/host/%.o,$(basename $(LIB_C) $(LIB_CXX)))
LIB_OBJS_SAN   := $(patsubst %,$(BUILD)/host-san/%.o,$(basename $(LIB_C) $(LIB_CXX)))
MODEL_OBJS     := $(patsubst %,$(BUILD)/host/%.o,$(basename $(SIM_MODELS)))
MODEL_OBJS_SAN := $(patsubst %,$(BUILD)/host-san/%.o,$(basename $(SIM_MODELS)))
SIM_OBJS       := $(patsubst %,$(BUILD)/host/%.o,$(basename $(SIM_MAIN)))
SIM_OBJS_SAN   := $(patsubst %,$(BUILD)/host-san/%.o,$(basename $(SIM_MAIN)))

$(BUILD)/libmotion.a: $(LIB_OBJS) $(MODEL_OBJS)
	@rm -f $@
	ar rcs $@ $^
$(BUILD)/libmotion-san.a: $(LIB_OBJS_SAN) $(MODEL_OBJS_SAN)
	@rm -f $@
	ar rcs $@ $^

sim: $(BUILD)/motionsim
$(BUILD)/motionsim: $(SIM_OBJS) $(BUILD)/libmotion.a
	$(CXX) $(SIM_OBJS) $(BUILD)/libmotion.a -lcjson -lm -o $@
# motionsim with AddressSanitizer + UBSan, for the fuzzer (tools/fuzz)
$(BUILD)/motionsim-san: $(SIM_OBJS_SAN) $(BUILD)/libmotion-san.a
	$(CXX) $(SAN_FLAGS) $(SIM_OBJS_SAN) $(BUILD)/libmotion-san.a -lcjson -lm -o $@

# Unit tests (cmocka), each linked against the same library archive.
$(BUILD)/test/unit/%: test/unit/%.c $(BUILD)/libmotion.a $(HDRS) $(UNIT_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -Itest/unit $< $(BUILD)/libmotion.a -lcmocka -lcjson -lm -o $@
$(BUILD)/test/unit/%: test/unit/%.cpp $(BUILD)/libmotion.a $(HDRS) $(UNIT_HDRS)
	@mkdir -p $(dir $@)
	$(CXX) $(HOST_CXXFLAGS) -Itest/unit $< $(BUILD)/libmotion.a -lcmocka -lcjson -lm -o $@
$(BUILD)/test/unit-san/%: test/unit/%.c $(BUILD)/libmotion-san.a $(HDRS) $(UNIT_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) $(SAN_FLAGS) -Itest/unit $< $(BUILD)/libmotion-san.a -lcmocka -lcjson -lm -o $@
$(BUILD)/test/unit-san/%: test/unit/%.cpp $(BUILD)/libmotion-san.a $(HDRS) $(UNIT_HDRS)
	@mkdir -p $(dir $@)
	$(CXX) $(HOST_CXXFLAGS) $(SAN_FLAGS) -Itest/unit $< $(BUILD)/libmotion-san.a -lcmocka -lcjson -lm -o $@

# A test program whose source is gone (renamed or deleted) must not keep running from build/.
STALE_UNIT_BINS = $(filter-out $(UNIT_BINS) $(SAN_BINS),$(wildcard $(BUILD)/test/unit/* $(BUILD)/test/unit-san/*))
unit: $(UNIT_BINS) $(SAN_BINS)
	@$(if $(STALE_UNIT_BINS),echo "removing stale test programs: $(STALE_UNIT_BINS)"; rm -f $(STALE_UNIT_BINS),:)

# ---------------------------------------------------------------------------------------
firmware: check-setup
	@bash tools/build_firmware.sh

profiles: check-setup $(BUILD)/motionsim
	@$(PY) tools/profiles.py --motionsim $(BUILD)/motionsim --out $(BUILD)/profiles

# The emulator harness (tools/emu) contributes EMU_SUITES, EMU_DEPS and `make emulate`.
-include tools/emu/emu.mk

# The step engine measured in the emulator (tools/bench/bench.py): one table, docs/bench.md (working files in build/bench).
bench: check-setup $(BUILD)/motionsim $(BUILD)/motionemu $(EMU_STEP_ELF)
	@$(PY) tools/bench/bench.py --motionsim $(BUILD)/motionsim --out $(BUILD)/bench --doc docs/bench.md --planner-elf $(EMU_STEP_ELF)

# Everything is built first; then every suite runs and one summary line closes the output.
# A suite is "name|kind|command": kind tap (cmocka and the harness print TAP) or pytest.
TEST_SUITES = \
	"unit (cmocka)|tap-dir|$(BUILD)/test/unit" \
	"unit (cmocka, ASan+UBSan)|tap-dir|$(BUILD)/test/unit-san" \
	"motionsim CLI|pytest|test/cli" \
	"firmware build|firmware|tools/build_firmware.sh" \
	$(EMU_SUITES) \
	"fuzz (emulator, motionsim ASan+UBSan)|tap|$(PY) tools/fuzz/run_fuzz.py --tap"

test: check-setup $(BUILD)/motionsim $(BUILD)/motionsim-san unit $(EMU_DEPS)
	@MOTIONSIM=$(abspath $(BUILD)/motionsim) $(PY) tools/run_tests.py $(TEST_SUITES)

# The long fuzz campaign (tools/fuzz/run_fuzz.py): FUZZ_LINES lines over all sketches, FUZZ_SIM_RUNS motionsim
# invocations (default FUZZ_LINES / 20), seed FUZZ_SEED; failing inputs are kept in build/fuzz/failures;
# the summary is written to docs/fuzz-summary.md (generated, committed).
FUZZ_LINES ?= 10000
FUZZ_SEED  ?= 1
fuzz: check-setup $(BUILD)/motionsim-san $(EMU_DEPS)
	@$(PY) tools/fuzz/run_fuzz.py --lines "$(FUZZ_LINES)" --seed "$(FUZZ_SEED)" $(if $(FUZZ_SIM_RUNS),--sim-runs "$(FUZZ_SIM_RUNS)") --summary docs/fuzz-summary.md

# ---------------------------------------------------------------------------------------
# A real board over USB (cannot run without one). Every refusal is one line and exit 2: the checks
# are $(error) calls, which make expands before it runs the recipe's first command.
board-error = $(error make $@: $(1))
one-word    = $(and $(1),$(filter 1,$(words $(1))))
# a sketch (firmware/<Name>) or an example of our libraries (its folder: what build_firmware.sh builds)
UPLOAD_DIR = $(if $(filter $(SKETCHES),$(SKETCH)),$(SKETCH),$(firstword $(wildcard firmware/libraries/*/examples/$(SKETCH) lib/examples/$(SKETCH))))
VALID_SKETCH = $(and $(call one-word,$(SKETCH)),$(UPLOAD_DIR))
PORT_CHECK = $(if $(PORT),,$(call board-error,PORT=<device> is missing (e.g. PORT=/dev/ttyACM0); sketches: $(SKETCHES)))
PORT_EXISTS = $(if $(and $(call one-word,$(PORT)),$(wildcard $(PORT))),,$(call board-error,PORT '$(PORT)' does not exist (is the Mega plugged in? try ls /dev/ttyACM* /dev/ttyUSB*)))
MONITOR_BAUDS := 9600 19200 38400 57600 115200
UPLOAD_HINT = make upload: avrdude could not flash $(SKETCH) through $(PORT): is it the Mega's port (ls /dev/ttyACM* /dev/ttyUSB*)? is a Serial Monitor (make monitor, the IDE) holding it? is the board an Arduino Mega 2560 (this needs -p m2560)?

upload:
	$(if $(VALID_SKETCH),,$(call board-error,SKETCH=<name> is $(if $(SKETCH),unknown ('$(SKETCH)'),missing); sketches: $(SKETCHES); or a library example (docs/library.md)))
	$(PORT_CHECK)
	$(if $(and $(wildcard $(PY)),$(wildcard .tools/arduino-cli)),,$(call board-error,the toolchain is not installed: run 'make setup' first))
	$(PORT_EXISTS)
	@bash tools/build_firmware.sh $(UPLOAD_DIR)
	@echo "avrdude -c wiring -p m2560 -P $(PORT) -b 115200 -D -U flash:w:$(BUILD)/firmware/$(SKETCH)/$(SKETCH).ino.hex:i"
	@avrdude -c wiring -p m2560 -P $(PORT) -b 115200 -D -U flash:w:$(BUILD)/firmware/$(SKETCH)/$(SKETCH).ino.hex:i \
	  || { echo "$(UPLOAD_HINT)" >&2; exit 1; }

monitor:
	$(if $(PORT),,$(call board-error,PORT=<device> is missing (e.g. PORT=/dev/ttyACM0)))
	$(if $(filter-out $(MONITOR_BAUDS),$(BAUD)),$(call board-error,BAUD '$(BAUD)' is not one of $(MONITOR_BAUDS)))
	$(if $(wildcard $(PY)),,$(call board-error,the Python environment ($(PY)) is not installed: run 'make setup' first))
	$(PORT_EXISTS)
	$(PY) -m serial.tools.miniterm --eol CRLF --raw $(PORT) $(or $(BAUD),9600)

clean:
	rm -rf $(BUILD)

