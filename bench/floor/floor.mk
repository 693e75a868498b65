# bench/floor: the floor routines and their runner (bench/floor/README.md).
# Never linked into the firmware: `make bench` runs them (tools/bench.py),
# tests/timing/test_floor.py holds them to the firmware's C.
FLOOR_DIR  := $(B)/floor
FLOOR_ASM  := $(wildcard bench/floor/*.S)
FLOOR_BINS := $(patsubst bench/floor/%.S,$(FLOOR_DIR)/%.bin,$(FLOOR_ASM))
FLOOR_INC  := $(wildcard bench/floor/*.inc) bench/floor/floor.h hal/mac4_map.h
FLOOR_CARDS := $(CARDS)
FLOOR_RUNS := $(foreach c,$(FLOOR_CARDS),$(FLOOR_DIR)/floorrun-$(c))

.PHONY: floor
floor: $(FLOOR_BINS) $(FLOOR_RUNS)

# A routine is position independent (its branches PC-relative, its data and
# registers at absolute addresses): the runner loads its .text at FLOOR_CODE.
$(FLOOR_DIR)/%.o: bench/floor/%.S $(FLOOR_INC) | $(MUS)/.stamp
	@mkdir -p $(@D)
	$(CC68) -m68000 -Ihal -Ibench/floor -c $< -o $@
$(FLOOR_DIR)/%.bin: $(FLOOR_DIR)/%.o
	@if [ -n "$$($(CROSS)objdump -r $< | sed -n '/^[0-9a-f]\{8\} /p')" ]; then \
		echo "$<: relocations: a floor routine must be position independent"; exit 1; fi
	$(OBJCOPY68) -O binary -j .text $< $@

# the runner per card: the emulator's 68000 and bus model, and the
# firmware's C for the host that the routines are checked against
# (measure.c with the card's encoder interface, FW_INC/FW_SSI, counter_meas.c)
FLOOR_REF_servo := bench/floor/ref_servo.c firmware/servo.c firmware/measure.c firmware/servo_meas.c firmware/params.c
FLOOR_REF_inc := $(FLOOR_REF_servo) $(FW_INC)
FLOOR_REF_ssi := $(FLOOR_REF_servo) $(FW_SSI)
FLOOR_REF_stp := bench/floor/ref_stp.c firmware/tick_stp.c firmware/stepper.c firmware/stp_rate.c firmware/stp_meas.c \
                 firmware/stp_motion.c firmware/axis.c firmware/motion.c firmware/servo.c firmware/stp_profile.c firmware/profile.c firmware/measure.c firmware/params.c \
                 firmware/counter_meas.c
FLOOR_CFLAGS := $(HOSTCFLAGS) -DHAL_NATIVE -Ibench/floor -Ihal -Ifirmware -Iharness -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"'
define FLOOR_RUN_RULE
$(FLOOR_DIR)/floorrun-$(1): bench/floor/floorrun.c bench/floor/floorrun.h $$(FLOOR_REF_$(1)) harness/buswait.c \
                            $(FW_HDRS) $(FLOOR_INC) $(MUSOBJ)
	@mkdir -p $$(@D)
	$$(HOSTCC) $$(FLOOR_CFLAGS) -DMAC4_CARD=$(card_$(1)) bench/floor/floorrun.c $$(FLOOR_REF_$(1)) \
		harness/buswait.c $(MUSOBJ) -lm -o $$@
endef
$(foreach c,$(FLOOR_CARDS),$(eval $(call FLOOR_RUN_RULE,$(c))))
