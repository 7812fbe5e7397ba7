# tools/emu/emu.mk - the ATmega2560 emulator harness (included by the Makefile before `test`).
#
#   build/motionemu                 the harness: our C program on libsimavr (tools/emu/*.c)
#   build/emu/emu_selftest.elf      a tiny avr-libc program with known timing (harness self-test)
#   build/emu/pid_v1_avr.elf        lib's PID module + the PID_v1 float32 vectors, for the ATmega2560
#   build/emu/text_parse_avr.elf    lib's text_parse_real + decimal words and their nearest floats
#   make emulate SKETCH=<name> [INPUT=<file>] [EMULATE_OUT=<dir>]   run a sketch in the emulator -> build/emulate/
#                                                                   (or a library example: SKETCH=MoveAndBack)
#   make emulate SKETCH=<name> LIVE=1                               ... as a board on a pseudo-terminal
#
# EMU_DEPS is what `make test` builds first; EMU_SUITES is the emulator suite for tools/run_tests.py
# (one TAP line per check, "# summary:" lines carry the figures).

EMU_SRCS   := $(sort $(wildcard tools/emu/*.c))
EMU_HDRS   := $(wildcard tools/emu/*.h) $(wildcard sim/plant_*.h)
# The DC-motor plant is the same object file motionsim links (from build/libmotion.a).
EMU_CFLAGS := -std=gnu11 -O2 -g -Wall -Wextra -Werror -ffp-contract=off -I/usr/include/simavr -Itools/emu -Isim -Ilib/src
EMU_LIBS   := $(BUILD)/libmotion.a -lsimavr -lelf -lm

$(BUILD)/motionemu: $(EMU_SRCS) $(EMU_HDRS) $(BUILD)/libmotion.a
	$(CC) $(EMU_CFLAGS) $(EMU_SRCS) $(EMU_LIBS) -o $@

$(BUILD)/emu/emu_selftest.elf: test/emu/selftest/emu_selftest.c
	@mkdir -p $(dir $@)
	avr-gcc -mmcu=atmega2560 -Os -DF_CPU=16000000UL -Wall -Wextra -Werror $< -o $@
# an ELF for another AVR (ATmega328P): the harness must refuse it
$(BUILD)/emu/wrong_mcu.elf: test/emu/selftest/wrong_mcu.c
	@mkdir -p $(dir $@)
	avr-gcc -mmcu=atmega328p -Os -Wall -Wextra -Werror $< -o $@

# Small AVR test programs built with the Arduino core's C flags (double = float on the AVR), so lib's
# code runs on avr-libc's float arithmetic as in the sketches; test/emu/avr_uart.h prints their lines.
AVR_TEST_CC := avr-gcc -mmcu=atmega2560 -DF_CPU=16000000UL -Os -g -std=gnu11 -ffunction-sections -fdata-sections \
               -flto -fuse-linker-plugin -Wl,--gc-sections -Wall -Wextra -Werror -Ilib/src -Itest/emu -I$(BUILD)/emu

# lib's PID module on the real target: test/emu/pid_avr/pid_v1_avr.c replays the PID_v1 float32
# reference vectors (test/data/pid_v1) through it.
EMU_PID_DATA := test/data/pid_v1
EMU_PID_ELF  := $(BUILD)/emu/pid_v1_avr.elf
$(BUILD)/emu/pid_vectors.h: test/emu/pid_avr/gen_pid_vectors.py $(wildcard $(EMU_PID_DATA)/*.json $(EMU_PID_DATA)/float32/*.csv)
	@mkdir -p $(dir $@)
	$(PY) $< $(EMU_PID_DATA) > $@.tmp && mv $@.tmp $@
$(EMU_PID_ELF): test/emu/pid_avr/pid_v1_avr.c test/emu/avr_uart.h $(BUILD)/emu/pid_vectors.h lib/src/pidv1_ctrl.c $(wildcard lib/src/*.h)
	$(AVR_TEST_CC) $< lib/src/pidv1_ctrl.c -o $@ -lm

# lib's number parser on the real target: test/emu/text_parse_avr/text_parse_avr.c feeds it the
# decimal words of gen_real_words.py (with the nearest float of each, computed exactly in Python),
# so text_parse_real runs on avr-libc's float arithmetic and strtod as in the sketches.
EMU_TEXT_ELF := $(BUILD)/emu/text_parse_avr.elf
$(BUILD)/emu/real_words.h: test/emu/text_parse_avr/gen_real_words.py
	@mkdir -p $(dir $@)
	$(PY) $< > $@.tmp && mv $@.tmp $@
$(EMU_TEXT_ELF): test/emu/text_parse_avr/text_parse_avr.c test/emu/avr_uart.h $(BUILD)/emu/real_words.h \
                 lib/src/text_parse.c lib/src/text_parse.h lib/src/motion_status.h
	$(AVR_TEST_CC) $< lib/src/text_parse.c -o $@ -lm

# lib's step planner on the real target: test/emu/step_avr/step_planner_avr.c plans the benchmark's
# reference moves and prints the planner's cycles per command and per step (make bench reads them).
EMU_STEP_ELF := $(BUILD)/emu/step_planner_avr.elf
EMU_STEP_SRCS := lib/src/step_planner.c lib/src/step_exact.c lib/src/step_queue.c lib/src/ramp.c lib/src/ramp_common.c \
                 lib/src/ramp_exact.c lib/src/ramp_leib.c lib/src/ramp_simplistic.c lib/src/ramp_sigmoid.c \
                 lib/src/motion_status.c
$(EMU_STEP_ELF): test/emu/step_avr/step_planner_avr.c test/emu/avr_uart.h $(EMU_STEP_SRCS) $(wildcard lib/src/*.h)
	@mkdir -p $(dir $@)
	$(AVR_TEST_CC) $< $(EMU_STEP_SRCS) -o $@ -lm

# The sketches the emulator checks are built by the same script as `make firmware`; its stamp
# makes `make test` rebuild them when firmware/ or lib/ changed.
EMU_FW_SRCS := $(shell find firmware lib -type f 2>/dev/null | LC_ALL=C sort)
# A renamed or copied file keeps its old time (mv, cp -p): the list of names is a prerequisite too,
# rewritten only when it changes.
EMU_FW_LIST := $(BUILD)/emu/firmware.files
$(shell mkdir -p $(BUILD)/emu && printf '%s\n' $(EMU_FW_SRCS) | cmp -s - $(EMU_FW_LIST) || printf '%s\n' $(EMU_FW_SRCS) > $(EMU_FW_LIST))
$(BUILD)/emu/firmware.stamp: $(EMU_FW_SRCS) $(EMU_FW_LIST) tools/build_firmware.sh
	@mkdir -p $(dir $@)
	@if ls firmware/*/*.ino >/dev/null 2>&1; then bash tools/build_firmware.sh >$(BUILD)/emu/firmware.log 2>&1 || { cat $(BUILD)/emu/firmware.log; exit 1; }; fi
	@touch $@

# LeibRampStepper in the lab's timed-loop mode (STEPPER_TIMED_LOOP=1), for its own emulator check
EMU_TIMED_ELF := $(BUILD)/emu/timed/LeibRampStepper/LeibRampStepper.ino.elf
$(EMU_TIMED_ELF): $(EMU_FW_SRCS) tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/timed
	@if [ -f firmware/LeibRampStepper/LeibRampStepper.ino ]; then FIRMWARE_OUT=$(BUILD)/emu/timed \
	  FIRMWARE_DEFINES="-DSTEPPER_TIMED_LOOP=1" bash tools/build_firmware.sh LeibRampStepper \
	  >$(BUILD)/emu/timed.log 2>&1 || { cat $(BUILD)/emu/timed.log; exit 1; }; fi

# ExactRampStepper with the console's cut made as late as it can be (1.5 ms ahead, no margin): its
# check (checks_reliability.py, check_cut_race) retargets hundreds of times, so that some cuts are
# laid out just as the step interrupt reaches them
EMU_CUTRACE_ELF := $(BUILD)/emu/cutrace/ExactRampStepper/ExactRampStepper.ino.elf
$(EMU_CUTRACE_ELF): $(EMU_FW_SRCS) tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/cutrace
	@if [ -f firmware/ExactRampStepper/ExactRampStepper.ino ]; then FIRMWARE_OUT=$(BUILD)/emu/cutrace \
	  FIRMWARE_DEFINES="-DSTEP_CONSOLE_CUT_MARGIN_US=0 -DSTEP_CONSOLE_CUT_AHEAD_US=1500 -DMOTION_STEPPER_CUT_MARGIN_US=0 -DMOTION_STEPPER_LOOP_CUT_US=1500 -DMOTION_STEPPER_LOOP_CUT_SLOW_US=2500" bash tools/build_firmware.sh \
	  ExactRampStepper >$(BUILD)/emu/cutrace.log 2>&1 || { cat $(BUILD)/emu/cutrace.log; exit 1; }; fi

# test/emu/SmoothStart: the smooth ramp at a high acceleration and jerk, for its own check
# (checks_library.py, check_smooth_start)
EMU_SMOOTHSTART_ELF := $(BUILD)/emu/smoothstart/SmoothStart/SmoothStart.ino.elf
$(EMU_SMOOTHSTART_ELF): $(EMU_FW_SRCS) test/emu/SmoothStart/SmoothStart.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/smoothstart
	@FIRMWARE_OUT=$(BUILD)/emu/smoothstart bash tools/build_firmware.sh test/emu/SmoothStart \
	  >$(BUILD)/emu/smoothstart.log 2>&1 || { cat $(BUILD)/emu/smoothstart.log; exit 1; }
# the same sketch far beyond the smooth planner's throughput (check_smooth_stall)
EMU_SMOOTHSTALL_ELF := $(BUILD)/emu/smoothstall/SmoothStart/SmoothStart.ino.elf
$(EMU_SMOOTHSTALL_ELF): $(EMU_FW_SRCS) test/emu/SmoothStart/SmoothStart.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/smoothstall
	@FIRMWARE_OUT=$(BUILD)/emu/smoothstall FIRMWARE_DEFINES="-DSTEPPER_MAX_SPS_SMOOTH=80000 -DMULTI_MAX_SPS=80000 -DSMOOTHSTART_VMAX=80000 \
	  -DSMOOTHSTART_ACCEL=640000 -DSMOOTHSTART_JERK=10240000" bash tools/build_firmware.sh test/emu/SmoothStart \
	  >$(BUILD)/emu/smoothstall.log 2>&1 || { cat $(BUILD)/emu/smoothstall.log; exit 1; }

# test/emu/OneStepper: one Stepper with its limit lifted, for the check that the planner tick never holds a
# step edge back (checks_library.py, check_one_stepper; make bench's ladder builds it the same way)
EMU_ONESTEPPER_ELF := $(BUILD)/emu/onestepper/OneStepper/OneStepper.ino.elf
$(EMU_ONESTEPPER_ELF): $(EMU_FW_SRCS) test/emu/OneStepper/OneStepper.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/onestepper
	@FIRMWARE_OUT=$(BUILD)/emu/onestepper FIRMWARE_DEFINES="-DMULTI_MAX_SPS=200000" bash tools/build_firmware.sh \
	  test/emu/OneStepper >$(BUILD)/emu/onestepper.log 2>&1 || { cat $(BUILD)/emu/onestepper.log; exit 1; }

# StopOnSwitch built with -DMOTION_STEPPER_CUT_US=0 (the cuts off, as docs/stop-latency.md offers): it must
# build warning-free, and its stop acts after the queued lead, on the law (checks_library.py, check_no_cut)
EMU_NOCUT_ELF := $(BUILD)/emu/nocut/StopOnSwitch/StopOnSwitch.ino.elf
$(EMU_NOCUT_ELF): $(EMU_FW_SRCS) firmware/libraries/MotionStepper/examples/StopOnSwitch/StopOnSwitch.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/nocut
	@FIRMWARE_OUT=$(BUILD)/emu/nocut FIRMWARE_DEFINES="-DMOTION_STEPPER_CUT_US=0" bash tools/build_firmware.sh \
	  firmware/libraries/MotionStepper/examples/StopOnSwitch >$(BUILD)/emu/nocut.log 2>&1 || { cat $(BUILD)/emu/nocut.log; exit 1; }

# test/emu/SameTarget: loop() calls moveTo() with the target in force on every pass (checks_library.py,
# check_same_target)
EMU_SAMETARGET_ELF := $(BUILD)/emu/sametarget/SameTarget/SameTarget.ino.elf
$(EMU_SAMETARGET_ELF): $(EMU_FW_SRCS) test/emu/SameTarget/SameTarget.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/sametarget
	@FIRMWARE_OUT=$(BUILD)/emu/sametarget bash tools/build_firmware.sh \
	  test/emu/SameTarget >$(BUILD)/emu/sametarget.log 2>&1 || { cat $(BUILD)/emu/sametarget.log; exit 1; }

# test/emu/CruiseBeside: three Steppers at 25,000 steps/s, two of them stopped steeply at once while the third
# cruises (checks_library.py, check_cruise_beside)
EMU_CRUISEBESIDE_ELF := $(BUILD)/emu/cruisebeside/CruiseBeside/CruiseBeside.ino.elf
$(EMU_CRUISEBESIDE_ELF): $(EMU_FW_SRCS) test/emu/CruiseBeside/CruiseBeside.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/cruisebeside
	@FIRMWARE_OUT=$(BUILD)/emu/cruisebeside bash tools/build_firmware.sh \
	  test/emu/CruiseBeside >$(BUILD)/emu/cruisebeside.log 2>&1 || { cat $(BUILD)/emu/cruisebeside.log; exit 1; }

# test/emu/HeapShare: a sketch that uses malloc beside a Stepper (the heap shared with board_take:
# checks_library.py, check_heap_share)
EMU_HEAPSHARE_ELF := $(BUILD)/emu/heapshare/HeapShare/HeapShare.ino.elf
$(EMU_HEAPSHARE_ELF): $(EMU_FW_SRCS) test/emu/HeapShare/HeapShare.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/heapshare
	@FIRMWARE_OUT=$(BUILD)/emu/heapshare bash tools/build_firmware.sh \
	  test/emu/HeapShare >$(BUILD)/emu/heapshare.log 2>&1 || { cat $(BUILD)/emu/heapshare.log; exit 1; }

# test/emu/TightSram: a Stepper in a sketch that has used up most of its SRAM (begin() keeps
# BOARD_STACK_RESERVE for the stack or refuses: checks_library.py, check_tight_sram)
EMU_TIGHTSRAM_ELF := $(BUILD)/emu/tightsram/TightSram/TightSram.ino.elf
$(EMU_TIGHTSRAM_ELF): $(EMU_FW_SRCS) test/emu/TightSram/TightSram.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/tightsram
	@FIRMWARE_OUT=$(BUILD)/emu/tightsram bash tools/build_firmware.sh \
	  test/emu/TightSram >$(BUILD)/emu/tightsram.log 2>&1 || { cat $(BUILD)/emu/tightsram.log; exit 1; }
# and MultiAxisStepper with a reserve no Mega holds: its console says each begin()'s refusal before READY
EMU_NOROOM_ELF := $(BUILD)/emu/noroom/MultiAxisStepper/MultiAxisStepper.ino.elf
$(EMU_NOROOM_ELF): $(EMU_FW_SRCS) firmware/MultiAxisStepper/MultiAxisStepper.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/noroom
	@FIRMWARE_OUT=$(BUILD)/emu/noroom FIRMWARE_DEFINES="-DBOARD_STACK_RESERVE=6000" bash tools/build_firmware.sh \
	  MultiAxisStepper >$(BUILD)/emu/noroom.log 2>&1 || { cat $(BUILD)/emu/noroom.log; exit 1; }

# test/emu/ThreeSteppers: two and three Steppers moving at once (checks_library.py, check_three_steppers):
# three at 10,000 and at 25,000 steps/s (50,000 steps/s^2, and 200,000 for the legs alone), two at 25,000 and 20,000;
# two-20k-late: two at 20,000 with cuts too close for their plans (a 1 ms margin, the stop's first cut 250 us
# ahead, the planned cut 400 us): the stop must come off at a cut tried farther ahead (StepCut.h's retries);
# two-20k-race: two at 20,000 whose cut search waits 2.5 ms between choosing the slot after the current one
# and timing it (MULTI_TEST_CUT_FIND_WAIT_US): the step interrupt takes that slot meanwhile, and the search
# must start again from the slot after it (MultiStepEngine::cut_find), not give the cut up
EMU_THREE_BUILDS := three-10k:-DTS_N=3 three-25k:-DTS_N=3+-DTS_V=25000 three-25k-steep:-DTS_N=3+-DTS_V=25000+-DTS_A=200000 \
  two-25k:-DTS_N=2+-DTS_V=25000 two-20k:-DTS_N=2+-DTS_V=20000 \
  two-20k-late:-DTS_N=2+-DTS_V=20000+-DMOTION_STEPPER_CUT_CRUISE_US=250+-DMOTION_STEPPER_CUT_US=400+-DMOTION_STEPPER_CUT_SLOW_US=400+-DMOTION_STEPPER_CUT_MARGIN_US=1000 \
  two-20k-race:-DTS_N=2+-DTS_V=20000+-DMULTI_TEST_CUT_FIND_WAIT_US=2500
EMU_THREE_ELFS := $(foreach b,$(EMU_THREE_BUILDS),$(BUILD)/emu/$(word 1,$(subst :, ,$(b)))/ThreeSteppers/ThreeSteppers.ino.elf)
define emu_three_rule
$(BUILD)/emu/$(1)/ThreeSteppers/ThreeSteppers.ino.elf: $(EMU_FW_SRCS) test/emu/ThreeSteppers/ThreeSteppers.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/$(1)
	@FIRMWARE_OUT=$(BUILD)/emu/$(1) FIRMWARE_DEFINES="$(subst +, ,$(2))" bash tools/build_firmware.sh test/emu/ThreeSteppers \
	  >$(BUILD)/emu/$(1).log 2>&1 || { cat $(BUILD)/emu/$(1).log; exit 1; }
endef
$(foreach b,$(EMU_THREE_BUILDS),$(eval $(call emu_three_rule,$(word 1,$(subst :, ,$(b))),$(word 2,$(subst :, ,$(b))))))

# test/emu/GroupStop: a StepperGroup's stop() at a cut of its queues (checks_library.py, check_group_stop)
EMU_GROUP_BUILDS := group-two-20k:-DGS_N=2+-DGS_V=20000 group-three-10k:-DGS_N=3+-DGS_V=10000 \
  group-three-10k-steep:-DGS_N=3+-DGS_V=10000+-DGS_A=100000 group-three-15k:-DGS_N=3+-DGS_V=15000 \
  group-two-20k-set:-DGS_N=2+-DGS_V=20000+-DGS_SET_MS=500
EMU_GROUP_ELFS := $(foreach b,$(EMU_GROUP_BUILDS),$(BUILD)/emu/$(word 1,$(subst :, ,$(b)))/GroupStop/GroupStop.ino.elf)
define emu_group_rule
$(BUILD)/emu/$(1)/GroupStop/GroupStop.ino.elf: $(EMU_FW_SRCS) test/emu/GroupStop/GroupStop.ino tools/build_firmware.sh
	@mkdir -p $(BUILD)/emu/$(1)
	@FIRMWARE_OUT=$(BUILD)/emu/$(1) FIRMWARE_DEFINES="$(subst +, ,$(2))" bash tools/build_firmware.sh test/emu/GroupStop \
	  >$(BUILD)/emu/$(1).log 2>&1 || { cat $(BUILD)/emu/$(1).log; exit 1; }
endef
$(foreach b,$(EMU_GROUP_BUILDS),$(eval $(call emu_group_rule,$(word 1,$(subst :, ,$(b))),$(word 2,$(subst :, ,$(b))))))

# The lab sketches with moveOneStep()'s two direction lines (those writing dirPin) replaced by
# `(void)direction;`: the lab exercise undone. Their emulator check (checks_sketches.py,
# check_direction_hook) sees DIR never change while the moves go both ways: the sketch's hook, not
# the engine, drives DIR. The check itself verifies that exactly two lines differ.
EMU_NODIR_SKETCHES := $(foreach s,LeibRampStepper SimplisticRampStepper,$(if $(wildcard firmware/$(s)/$(s).ino),$(s)))
EMU_NODIR_STAMP := $(BUILD)/emu/nodir.stamp
$(EMU_NODIR_STAMP): $(EMU_FW_SRCS) tools/build_firmware.sh
	@rm -rf $(BUILD)/emu/nodir-src && mkdir -p $(BUILD)/emu/nodir-src
	@for s in $(EMU_NODIR_SKETCHES); do mkdir -p $(BUILD)/emu/nodir-src/$$s && \
	  sed -E 's/^([[:space:]]*).*digitalWrite\(dirPin.*$$/\1(void)direction;/' firmware/$$s/$$s.ino \
	  > $(BUILD)/emu/nodir-src/$$s/$$s.ino; done
	@if [ -n "$(EMU_NODIR_SKETCHES)" ]; then FIRMWARE_SRC=$(BUILD)/emu/nodir-src FIRMWARE_OUT=$(BUILD)/emu/nodir \
	  bash tools/build_firmware.sh $(EMU_NODIR_SKETCHES) >$(BUILD)/emu/nodir.log 2>&1 || { cat $(BUILD)/emu/nodir.log; exit 1; }; fi
	@touch $@

EMU_DEPS := $(BUILD)/motionemu $(BUILD)/motionsim $(BUILD)/emu/emu_selftest.elf $(BUILD)/emu/wrong_mcu.elf \
            $(BUILD)/emu/firmware.stamp $(EMU_TIMED_ELF) $(EMU_CUTRACE_ELF) $(EMU_SMOOTHSTART_ELF) $(EMU_SMOOTHSTALL_ELF) $(EMU_ONESTEPPER_ELF) $(EMU_NOCUT_ELF) $(EMU_SAMETARGET_ELF) $(EMU_CRUISEBESIDE_ELF) $(EMU_HEAPSHARE_ELF) $(EMU_TIGHTSRAM_ELF) $(EMU_NOROOM_ELF) $(EMU_THREE_ELFS) $(EMU_GROUP_ELFS) $(EMU_NODIR_STAMP) $(EMU_PID_ELF) $(EMU_TEXT_ELF)

EMU_SUITES := "emulator (simavr)|tap|$(PY) test/emu/run_emu_tests.py --tap"

# make emulate SKETCH=X builds only X: its ELF is remade when X's own files, the libraries every
# sketch is built with (lib/src, firmware/libraries but their examples) or the build script changed, or a file of
# those was added, removed or renamed (EMULATE_LIST, rewritten only when the list of names changes).
# Not the other sketches, not the test-only builds. An unknown SKETCH is left to emulate.py, which
# says so in one line. LIVE=1: an interactive board on a pseudo-terminal (tools/emu/emulate.py --live).
# EMULATE_OUT: where the outputs go (default build/emulate)
# SKETCH may also name a library example (lib/examples/X, firmware/libraries/<Lib>/examples/X, as
# tools/build_firmware.sh builds them; a sketch of that name comes first): EMULATE_DIR is its folder,
# EMULATE_ARG what build_firmware.sh is given (a sketch's name, an example's folder). A name with
# glob characters matches nothing (the folder found must be named SKETCH).
EMULATE_OUT ?= $(BUILD)/emulate
EMULATE_INO := $(and $(SKETCH),$(filter 1,$(words $(SKETCH))),$(firstword $(wildcard firmware/$(SKETCH)/$(SKETCH).ino \
                 lib/examples/$(SKETCH)/$(SKETCH).ino firmware/libraries/*/examples/$(SKETCH)/$(SKETCH).ino)))
EMULATE_DIR := $(patsubst %/,%,$(dir $(EMULATE_INO)))
EMULATE_OK  := $(if $(filter $(SKETCH),$(notdir $(EMULATE_DIR))),$(EMULATE_INO))
ifneq ($(EMULATE_OK),)
EMULATE_ARG  := $(if $(filter firmware/$(SKETCH),$(EMULATE_DIR)),$(SKETCH),$(EMULATE_DIR))
EMULATE_ELF  := $(BUILD)/firmware/$(SKETCH)/$(SKETCH).ino.elf
# the libraries' own examples are no source of another sketch or example
EMULATE_SRCS := $(shell { find $(EMULATE_DIR) lib/src lib/library.properties -type f; \
                  find firmware/libraries -path 'firmware/libraries/*/examples' -prune -o -type f -print; } 2>/dev/null | LC_ALL=C sort -u)
EMULATE_LIST := $(BUILD)/emu/files-$(SKETCH).list
$(shell mkdir -p $(BUILD)/emu && printf '%s\n' $(EMULATE_SRCS) | cmp -s - $(EMULATE_LIST) || printf '%s\n' $(EMULATE_SRCS) > $(EMULATE_LIST))
$(EMULATE_ELF): $(EMULATE_SRCS) $(EMULATE_LIST) tools/build_firmware.sh
	@echo "make emulate: building $(SKETCH) (arduino-cli; log: $(BUILD)/firmware/$(SKETCH).log) ..."
	@start=$$(date +%s); bash tools/build_firmware.sh $(EMULATE_ARG) >$(BUILD)/emu/build-$(SKETCH).log 2>&1 \
	  || { cat $(BUILD)/emu/build-$(SKETCH).log; exit 1; }; \
	  echo "make emulate: built $(SKETCH) in $$(( $$(date +%s) - start )) s"
endif
emulate: check-setup $(BUILD)/motionemu $(BUILD)/motionsim $(EMULATE_ELF)
	@$(PY) tools/emu/emulate.py $(if $(SKETCH),--sketch "$(SKETCH)") $(if $(INPUT),--input "$(INPUT)") \
	  $(if $(filter-out 0,$(LIVE)),--live) --out "$(EMULATE_OUT)"
