# MAC4 firmware, EPROM images and card emulator.  See README.md.
# `make help` prints the lines below that start with "#   make".
#   make               EPROM images for INC, SSI, STP, build/mac4sim, build/commands.json
#   make demo          boot the emulated MAC4-INC and show what a host sees
#   make test          every lane below, in this order (TEST_LANES); about 7 min on 2 cores
#   make unit          cmocka unit tests of the firmware, native, ASan+UBSan
#   make system        pytest: the EPROM images in the emulator (tests/system)
#   make sanitize-short  the script reader's and scenarios' tests on the ASan+UBSan emulator
#   make hardening     fuzz corpus replay, 68000-only check, cppcheck, qemu witness
#   make board-check   the generated map files are what board/mac4.toml gives
#   make docs-check    docs/commands.md is its table's; the files and names docs mention exist
#   make arch-check    no call cycle between firmware files but the declared interfaces;
#                      each axis_t part, status bit and parameter only by its writers
#   make conformance   the 68000 core against the reference vectors (docs/cpu-timing.md)
#   make debug-identical  the EPROM bytes do not depend on -g
#   make differential  native build against the EPROM image, tick for tick
#   make timing        the hard deadlines (tests/timing)
#   make bench         emulator speed, the cycle figures beside their aims and floors, build/perf.json
#   make floor         the floor routines and build/floor/floorrun-CARD (bench/floor/README.md)
#   make native        build/mac4sim-native-CARD: the firmware compiled for the host
#   make board         regenerate hal/mac4_map.h, harness/bus_map.h, host/mac4card/board.py
#   make docs          regenerate docs/commands.md from firmware/commands.def
#   make fuzz          every fuzz target, native firmware and emulator (FUZZ_SECONDS=N; tests/fuzz/fuzz.mk)
#   make sanitize      every system test on the ASan+UBSan emulator (build/san/mac4sim)
#   make deps          install/fetch what the build needs (the others do it too)
#   make clean         remove build/

CROSS   ?= m68k-linux-gnu-
CC68    := $(CROSS)gcc
OBJCOPY68 := $(CROSS)objcopy
SIZE68  := $(CROSS)size
HOSTCC  ?= cc
PYTHON  ?= python3
B       := build

CARDS   := inc ssi stp
card_inc := 0
card_ssi := 1
card_stp := 2

# The card variant by file: the sources every card links, plus the servo
# cards' (INC, SSI) or the stepper's own, plus each card's encoder interface
# (FW_INC, FW_SSI; the STP's counter is the INC's, in FW_STP);
# fw_srcs_CARD is what a card links.
FW_ALL_SRCS := $(wildcard firmware/*.c)
FW_SERVO := firmware/tick_servo.c firmware/servo_meas.c firmware/servo_motion.c
FW_INC   := firmware/counter_meas.c
FW_SSI   := firmware/ssi_meas.c
FW_STP   := firmware/tick_stp.c firmware/stepper.c firmware/stp_rate.c firmware/stp_meas.c firmware/stp_motion.c \
            $(FW_INC)
FW_SRCS  := $(filter-out $(FW_SERVO) $(FW_INC) $(FW_SSI) $(FW_STP),$(FW_ALL_SRCS))
fw_srcs_inc := $(FW_SRCS) $(FW_SERVO) $(FW_INC)
fw_srcs_ssi := $(FW_SRCS) $(FW_SERVO) $(FW_SSI)
fw_srcs_stp := $(FW_SRCS) $(FW_STP)
TGT_SRCS := hal/target/hal_target.c hal/target/runtime.c
TGT_ASM  := hal/target/crt0.S hal/target/vectors.S
FW_HDRS  := $(wildcard firmware/*.h firmware/*.def hal/*.h hal/target/*.h) Makefile
# Objects list the headers they include in a dependency file beside them
# (DEPFLAGS; read at the end of this file), so that a header change rebuilds
# what includes it and nothing else; every object also depends on Makefile.
DEPFLAGS := -MMD -MP

WARN     := -Wall -Wextra -Werror -Wconversion -Wshadow -Wstrict-prototypes -Wmissing-prototypes
OPT68 ?= -Os
# debug information for gdb (docs/debugging.md); the EPROM bytes do not
# depend on it (make debug-identical)
DEBUG68 ?= -g
CFLAGS68 := $(DEBUG68) -m68000 -ffreestanding -nostdlib -fno-pic -fno-builtin -std=c11 $(OPT68) \
            -fstack-usage -ffunction-sections -mstrict-align -fno-store-merging -fno-expensive-optimizations $(WARN) -Ihal -Ihal/target -Ifirmware -DHAL_TARGET
LDFLAGS68 := -m68000 -nostdlib -static -T linker/mac4.ld -Wl,--gc-sections -Wl,--build-id=none -Wl,--fatal-warnings

HOSTWARN := -Wall -Wextra -Werror
HOSTCFLAGS := -std=gnu11 -O2 -g $(HOSTWARN)

MUS      := $(B)/deps/musashi
MUSOBJ   := $(B)/musashi/m68kcpu.o $(B)/musashi/m68kops.o $(B)/musashi/m68kdasm.o $(B)/musashi/softfloat.o
MUSCFLAGS := -std=gnu99 -O2 -g -w -I$(MUS) -Iharness -Ihal -DMUSASHI_CNF='"musashi_cnf.h"' -DMAC4_IDLE_HOOK

# the workbench (docs/debugging.md): gdb stub, waveforms, front panel
BENCH_SRCS := harness/gdbstub.c harness/bench_script.c harness/panel.c
HARNESS_CORE := harness/sim.c harness/bus.c harness/periph.c harness/axisboard.c harness/host.c harness/run.c \
                harness/plant.c harness/plant_servo.c harness/plant_stepper.c harness/plant_config.c harness/plant_trace.c harness/plant_vme.c harness/buswait.c harness/vcd.c
# the devices of periph.c's table, a file each
HARNESS_CORE += harness/sysctl.c harness/timer.c harness/uart.c harness/virq.c
HARNESS_SRCS := $(HARNESS_CORE) \
                harness/script.c harness/script_serial.c harness/serial_host.c harness/script_plant.c harness/cpu_m68k.c harness/idle.c harness/profile.c harness/cmdnames.c harness/mac4sim.c \
                harness/perf.c $(BENCH_SRCS)
HARNESS_HDRS := $(wildcard harness/*.h) hal/mac4_map.h firmware/commands.def

IMAGES := $(foreach c,$(CARDS),$(B)/eprom/mac4-$(c).bin)

.PHONY: all deps demo test unit system clean images docs native timing differential bench help
all: images $(B)/mac4sim $(B)/commands.json

# $(MUS) is the fetched Musashi with our patch series applied (tools/musashi-patch.sh,
# harness/musashi-patches/README.md): its stamp depends on every patch file and on
# the folder (a patch added or removed), so a changed series rebuilds the core.
MUS_PATCHES := $(sort $(wildcard harness/musashi-patches/*.patch))
deps: $(MUS)/.stamp
$(MUS)/.stamp: tools/bootstrap.sh tools/deps/pypi.txt tools/deps/apt.txt tools/deps/python.txt \
               tools/musashi-patch.sh harness/musashi-patches $(MUS_PATCHES)
	@BUILD=$(B) CROSS=$(CROSS) tools/bootstrap.sh

images: $(IMAGES)

# ---- firmware for the 68000, one build directory per card -------------
define CARD_RULES
$(B)/fw-$(1)/%.o: firmware/%.c Makefile | $(MUS)/.stamp
	@mkdir -p $$(@D)
	@echo "  CC68    $$@"; $$(CC68) $$(CFLAGS68) $$(DEPFLAGS) -DMAC4_CARD=$(card_$(1)) -c $$< -o $$@
$(B)/fw-$(1)/hal_%.o: hal/target/%.c Makefile | $(MUS)/.stamp
	@mkdir -p $$(@D)
	@echo "  CC68    $$@"; $$(CC68) $$(CFLAGS68) $$(DEPFLAGS) -DMAC4_CARD=$(card_$(1)) -c $$< -o $$@
$(B)/fw-$(1)/asm_%.o: hal/target/%.S Makefile | $(MUS)/.stamp
	@mkdir -p $$(@D)
	$$(CC68) $$(DEBUG68) $$(DEPFLAGS) -m68000 -Ihal -c $$< -o $$@
FW_OBJS_$(1) := $(patsubst firmware/%.c,$(B)/fw-$(1)/%.o,$(fw_srcs_$(1))) \
                $(patsubst hal/target/%.c,$(B)/fw-$(1)/hal_%.o,$(TGT_SRCS)) \
                $(patsubst hal/target/%.S,$(B)/fw-$(1)/asm_%.o,$(TGT_ASM))
$(B)/eprom/mac4-$(1).elf: $$(FW_OBJS_$(1)) linker/mac4.ld
	@mkdir -p $$(@D)
	$$(CC68) $$(LDFLAGS68) -Wl,-Map,$(B)/eprom/mac4-$(1).map $$(FW_OBJS_$(1)) -o $$@
$(B)/eprom/mac4-$(1).bin: $(B)/eprom/mac4-$(1).elf tools/mkeprom.py
	$$(OBJCOPY68) -O binary -j .vectors -j .text -j .data $$< $(B)/eprom/mac4-$(1).raw
	$$(SIZE68) -A $$< > $(B)/eprom/mac4-$(1).sections
	$$(CROSS)nm -n $$< > $(B)/eprom/mac4-$(1).sym
	$$(PYTHON) tools/mkeprom.py $(B)/eprom/mac4-$(1).raw $(B)/eprom/mac4-$(1) \
		--sections $(B)/eprom/mac4-$(1).sections
endef
$(foreach c,$(CARDS),$(eval $(call CARD_RULES,$(c))))

# ---- Musashi, generated and compiled with our configuration -------------
$(MUS)/m68kops.c: $(MUS)/.stamp
	$(HOSTCC) -O2 -w -o $(MUS)/m68kmake $(MUS)/m68kmake.c
	cd $(MUS) && ./m68kmake
$(B)/musashi/m68kcpu.o: $(MUS)/m68kops.c harness/musashi_cnf.h
	@mkdir -p $(@D)
	$(HOSTCC) $(MUSCFLAGS) -c $(MUS)/m68kcpu.c -o $@
$(B)/musashi/m68kops.o: $(MUS)/m68kops.c harness/musashi_cnf.h
	@mkdir -p $(@D)
	$(HOSTCC) $(MUSCFLAGS) -c $(MUS)/m68kops.c -o $@
$(B)/musashi/m68kdasm.o: $(MUS)/m68kops.c harness/musashi_cnf.h
	@mkdir -p $(@D)
	$(HOSTCC) $(MUSCFLAGS) -c $(MUS)/m68kdasm.c -o $@
$(B)/musashi/softfloat.o: $(MUS)/m68kops.c
	@mkdir -p $(@D)
	$(HOSTCC) $(MUSCFLAGS) -c $(MUS)/softfloat/softfloat.c -o $@

# ---- the emulator: one object per harness source (build/harness/) ----------
HARNESS_INC := -Iharness -Ihal -Ifirmware -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"'
$(B)/harness/%.o: harness/%.c Makefile | $(MUS)/m68kops.c
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(HOSTCC) $(HOSTCFLAGS) $(DEPFLAGS) $(HARNESS_INC) -c $< -o $@
$(B)/mac4sim: $(patsubst harness/%.c,$(B)/harness/%.o,$(HARNESS_SRCS)) $(MUSOBJ)
	$(HOSTCC) $(HOSTCFLAGS) $^ -lm -o $@

# ---- mac4sim with ASan and UBSan (docs/hardening.md, "Sanitizers"): `make
# sanitize` runs every system test on it (MAC4SIM= tells conftest.py), the
# script reader's tests are the short lane in make test -------------------------
SAN_CFLAGS := -std=gnu11 -O2 -g $(HOSTWARN) -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
$(B)/san/mac4sim: $(HARNESS_SRCS) $(HARNESS_HDRS) $(MUSOBJ)
	@mkdir -p $(@D); ln -sfn ../eprom $(@D)/eprom; ln -sf ../commands.json $(@D)/commands.json
	$(HOSTCC) $(SAN_CFLAGS) -Iharness -Ihal -Ifirmware -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"' \
		$(HARNESS_SRCS) $(MUSOBJ) -lm -o $@
.PHONY: sanitize sanitize-short
sanitize: all $(B)/san/mac4sim
	MAC4SIM=$(B)/san/mac4sim $(PYTHON) -m pytest -q tests/system
sanitize-short: all $(B)/san/mac4sim
	MAC4SIM=$(B)/san/mac4sim $(PYTHON) -m pytest -q tests/system/test_script_reader.py tests/system/test_scenarios.py

# ---- the native builds: the firmware compiled for the host as the CPU -------
# (harness/cpu_native.h).  Per card: the firmware, hal/native and the integer
# runtime in one relocatable object with only the entry points global and its
# static data in sections of its own (reset at every card reset), linked with
# the emulator into build/mac4sim-native-CARD.  ASan and UBSan (as for the
# unit tests) abort on undefined behaviour, so the differential test sees it.
NATIVE_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
NATIVE_FW_CFLAGS := -std=gnu11 -O1 -g $(HOSTWARN) $(NATIVE_SAN) -Ihal -Ifirmware -Iharness -Ihal/target -DHAL_NATIVE
NATIVE_ENTRIES := fw_boot_stage1 fw_init fw_main_step fw_isr_tick fw_isr_axis fw_isr_uart fw_isr_estop \
                  hal_native_stop_jmp hal_native_irq_mask hal_irq_save hal_irq_restore
NATIVES := $(foreach c,$(CARDS),$(B)/mac4sim-native-$(c))
define NATIVE_RULES
$(B)/native-$(1)/fw_%.o: firmware/%.c Makefile
	@mkdir -p $$(@D)
	@echo "  CC-NAT  $$@"; $$(HOSTCC) $$(NATIVE_FW_CFLAGS) $$(DEPFLAGS) -DMAC4_CARD=$(card_$(1)) -c $$< -o $$@
$(B)/native-$(1)/hal_%.o: harness/hal_%.c Makefile
	@mkdir -p $$(@D)
	@echo "  CC-NAT  $$@"; $$(HOSTCC) $$(NATIVE_FW_CFLAGS) $$(DEPFLAGS) -DMAC4_CARD=$(card_$(1)) -c $$< -o $$@
$(B)/native-$(1)/rt_%.o: hal/target/%.c Makefile
	@mkdir -p $$(@D)
	@echo "  CC-NAT  $$@"; $$(HOSTCC) $$(NATIVE_FW_CFLAGS) $$(DEPFLAGS) -DMAC4_CARD=$(card_$(1)) -c $$< -o $$@
$(B)/native-$(1)/harness/%.o: harness/%.c Makefile | $(MUS)/m68kops.c
	@mkdir -p $$(@D)
	@echo "  CC-NAT  $$@"; $$(HOSTCC) $$(HOSTCFLAGS) $$(DEPFLAGS) $$(HARNESS_INC) -DHAL_NATIVE -DMAC4_CARD=$(card_$(1)) \
		$$(NATIVE_SAN) -c $$< -o $$@
NATIVE_OBJS_$(1) := $(patsubst firmware/%.c,$(B)/native-$(1)/fw_%.o,$(fw_srcs_$(1))) \
                    $(B)/native-$(1)/hal_native.o $(B)/native-$(1)/rt_runtime.o
$(B)/native-$(1)/fw.o: $$(NATIVE_OBJS_$(1))
	$$(HOSTCC) -r -nostdlib $$^ -o $$@.r
	objcopy $(foreach e,$(NATIVE_ENTRIES),--keep-global-symbol=$(e)) \
		--rename-section .data=mac4fw_data --rename-section .data.rel.local=mac4fw_datarel \
		--rename-section .data.rel=mac4fw_datarel --rename-section .bss=mac4fw_bss $$@.r $$@
	@rm -f $$@.r
$(B)/mac4sim-native-$(1): $(patsubst harness/%.c,$(B)/native-$(1)/harness/%.o,$(HARNESS_SRCS) harness/cpu_native.c) \
                        $(B)/native-$(1)/fw.o $(MUSOBJ)
	$$(HOSTCC) $$(HOSTCFLAGS) $$^ $(NATIVE_SAN) -lm -o $$@
endef
$(foreach c,$(CARDS),$(eval $(call NATIVE_RULES,$(c))))
native: $(NATIVES)

# ---- make bench: the bare Musashi core beside the full emulator --------------
$(B)/mac4bare: harness/m68k_bare.c hal/mac4_map.h $(MUSOBJ)
	$(HOSTCC) $(HOSTCFLAGS) -Iharness -Ihal -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"' $< $(MUSOBJ) -lm -o $@

# The stock bare core: the same bare-core program on the fetched Musashi
# WITHOUT any patch of ours (musashi-orig copied, its tables generated), the
# reference `make bench` sets the emulator's speed against (tools/bench.py).
MUS_STOCK := $(B)/deps/musashi-stock
$(MUS_STOCK)/m68kops.c: $(MUS)/.stamp
	rm -rf $(MUS_STOCK) && cp -r $(B)/deps/musashi-orig $(MUS_STOCK) && rm -f $(MUS_STOCK)/.stamp
	$(HOSTCC) -O2 -w -o $(MUS_STOCK)/m68kmake $(MUS_STOCK)/m68kmake.c
	cd $(MUS_STOCK) && ./m68kmake
$(B)/mac4bare-stock: harness/m68k_bare.c hal/mac4_map.h harness/musashi_cnf.h $(MUS_STOCK)/m68kops.c
	$(HOSTCC) $(HOSTCFLAGS) -Iharness -Ihal -I$(MUS_STOCK) -DMUSASHI_CNF='"musashi_cnf.h"' $< \
		$(MUS_STOCK)/m68kcpu.c $(MUS_STOCK)/m68kops.c $(MUS_STOCK)/m68kdasm.c $(MUS_STOCK)/softfloat/softfloat.c \
		-O2 -w -lm -o $@

# ---- the command dictionary, from firmware/commands.def ---------------------
$(B)/gen_commands: tools/gen_commands.c firmware/commands.def firmware/status.def firmware/status.h
	@mkdir -p $(@D)
	$(HOSTCC) $(HOSTCFLAGS) -Ifirmware -Ihal $< -o $@
$(B)/commands.json: $(B)/gen_commands
	$(B)/gen_commands > $@.tmp
	$(PYTHON) -c 'import json,sys; json.load(open(sys.argv[1]))' $@.tmp && mv $@.tmp $@
docs: $(B)/commands.json tools/commands_md.py
	$(PYTHON) tools/commands_md.py $(B)/commands.json docs/commands.md

# ---- tests -----------------------------------------------------------------
include tests/unit/unit.mk

# `make test`, defined here once: the lanes in order; the native/68000
# agreement and the cycle deadlines last, so that a deadline the firmware
# misses does not keep the other lanes from running
TEST_LANES := unit system sanitize-short hardening board-check docs-check arch-check conformance debug-identical differential timing
test: all $(TEST_LANES)
system: all
	$(PYTHON) -m pytest -q tests/system

# ---- native/68000 agreement, cycle deadlines, benchmark (docs/performance.md) ----
differential: all native
	$(PYTHON) -m pytest -q tests/differential
timing: all $(B)/busvectors floor
	$(PYTHON) -m pytest -q tests/timing
bench: all $(B)/mac4bare $(B)/mac4bare-stock floor
	$(PYTHON) tools/bench.py

# ---- bus timing: the wait-state model against the 68000 reference vectors ----
# (docs/memory-map.md, "Bus timing"; tests/timing/test_bus_timing.py)
$(B)/busvectors: tests/timing/busvectors.c tests/conformance/sstfile.c tests/conformance/sstfile.h harness/buswait.c harness/buswait.h hal/mac4_map.h $(MUSOBJ)
	$(HOSTCC) $(HOSTCFLAGS) -Iharness -Ihal -I$(MUS) -Itests/conformance -DMUSASHI_CNF='"musashi_cnf.h"' \
		tests/timing/busvectors.c tests/conformance/sstfile.c harness/buswait.c $(MUSOBJ) -lm -o $@

demo: all
	@tools/demo.sh

clean:
	rm -rf $(B)

# ---- hardening: fuzz corpus replay, 68000 check, cppcheck, qemu witness -----
# (docs/hardening.md)
include tests/fuzz/fuzz.mk
include tests/witness/witness.mk

CPPCHECK ?= cppcheck
CPPCHECK_FLAGS := -q --enable=warning,style,performance,portability --std=c11 --error-exitcode=1 \
                  --inline-suppr --suppressions-list=tools/cppcheck.supp -Ihal -Ifirmware
.PHONY: hardening check68000 cppcheck
hardening: fuzz-replay check68000 cppcheck witness
check68000: images
	$(PYTHON) tools/check68000.py $(foreach c,$(CARDS),$(B)/eprom/mac4-$(c).elf)
cppcheck: deps
	@set -e; for c in $(foreach c,$(CARDS),$(card_$(c))); do \
		echo "cppcheck firmware/ hal/target/ (MAC4_CARD=$$c)"; \
		$(CPPCHECK) $(CPPCHECK_FLAGS) -DHAL_TARGET -DMAC4_CARD=$$c -Ihal/target firmware hal/target; done
	@echo "cppcheck firmware/ harness/hal_native.c (HAL_NATIVE)"
	@$(CPPCHECK) $(CPPCHECK_FLAGS) -DHAL_NATIVE -DMAC4_CARD=0 -Iharness firmware harness/hal_native.c

# ---- the board description (docs/board.md): board/mac4.toml generates
# hal/mac4_map.h, harness/bus_map.h and host/mac4card/board.py; `make board`
# after changing it, `board-check` fails when they differ from it ----------
.PHONY: board board-check docs-check
board:
	$(PYTHON) tools/genboard.py board/mac4.toml
board-check:
	$(PYTHON) tools/genboard.py --check board/mac4.toml

# ---- the generated pages are what their tables give, and every file and
# name the documentation and the comments mention exists (tools/doccheck.py)
docs-check: $(B)/commands.json
	$(PYTHON) tools/commands_md.py --check $(B)/commands.json docs/commands.md
	$(PYTHON) tools/doccheck.py

# ---- the firmware's shape (docs/firmware.md): no call cycle between its files
# but the declared interfaces of tools/callgraph.allow, read from the objects;
# each part of axis_t written by its declared writers (card.h, status.def,
# tools/onewriter.allow), the parameters by params.c alone (docs/hardening.md)
.PHONY: arch-check
arch-check: images
	$(PYTHON) tools/callgraph.py
	$(PYTHON) tools/onewriter.py

# ---- the 68000 core against the reference vectors (docs/cpu-timing.md) -----
include tests/conformance/conformance.mk

# ---- the floor routines of make bench, never in the firmware (bench/floor/README.md)
include bench/floor/floor.mk

# ---- the workbench (docs/debugging.md) -------------------------------------
# The images carry -g debug information in their ELF for gdb; the EPROM bytes
# must not depend on it: build them once more without -g and compare.
.PHONY: debug-identical
debug-identical: images
	@$(MAKE) --no-print-directory B=$(B)/nodebug MUS=$(MUS) DEBUG68= \
		$(foreach c,$(CARDS),$(B)/nodebug/eprom/mac4-$(c).bin) > $(B)/nodebug.log 2>&1 \
		|| { cat $(B)/nodebug.log; exit 1; }
	@for c in $(CARDS); do cmp $(B)/eprom/mac4-$$c.bin $(B)/nodebug/eprom/mac4-$$c.bin || exit 1; \
		echo "debug-identical: mac4-$$c.bin the same with and without -g"; done

.PHONY: help
help:
	@sed -n 's/^#   make/make/p' Makefile

# the dependency files of every object built so far (DEPFLAGS)
-include $(shell find $(B) -name '*.d' 2>/dev/null)
