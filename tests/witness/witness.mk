# The qemu-m68k witness (docs/hardening.md).  Included by Makefile.
#   make witness    build both sides and compare them (tests/witness/test_witness.py)
# Kernels: tests/witness/kernels.txt; a kernel whose source is missing is not built.
WB := $(B)/witness
QEMU_M68K ?= qemu-m68k
WITNESS_ALL := $(shell awk '!/^\#/ && NF {print $$1}' tests/witness/kernels.txt)
witness_src = $(shell awk '$$1 == "$(1)" {print $$2}' tests/witness/kernels.txt)
WITNESS_KERNELS := $(foreach k,$(WITNESS_ALL),$(if $(wildcard $(call witness_src,$(k))),$(k)))
WITNESS_COMMON := tests/witness/witness.c
WITNESS_DEPS := tests/witness/witness.h tests/witness/witness.mk tests/witness/kernels.txt $(WB)/kernels.h \
                $(FW_HDRS) $(foreach k,$(WITNESS_KERNELS),$(call witness_src,$(k)))
WITNESS_CFLAGS68 := $(filter-out -fstack-usage,$(CFLAGS68)) -DMAC4_CARD=0 -I$(WB) -Itests/witness
WITNESS_CFLAGS := -std=gnu11 -g -O1 -Wall -Wextra -Werror -fsanitize=address,undefined -fno-sanitize-recover=all \
                  -fno-omit-frame-pointer -ffunction-sections -fdata-sections -Wl,--gc-sections -DHAL_NATIVE -DMAC4_CARD=0 -Ihal -Ihal/target -Ifirmware -I$(WB) -Itests/witness

.PHONY: witness witness-bins FORCE
$(WB)/kernels.h: FORCE
	@mkdir -p $(@D)
	@echo '#define KERNELS $(foreach k,$(WITNESS_KERNELS),KERNEL($(k)))' > $@.new
	@cmp -s $@.new $@ && rm $@.new || mv $@.new $@

WITNESS_M68K_OBJS := $(foreach k,$(WITNESS_KERNELS),$(WB)/m68k/k_$(k).o) \
                     $(WB)/m68k/witness.o $(WB)/m68k/witness_m68k.o $(WB)/m68k/start_m68k.o $(WB)/m68k/runtime.o
$(WB)/m68k/%.o: tests/witness/%.c $(WITNESS_DEPS) | $(MUS)/.stamp
	@mkdir -p $(@D)
	@echo "  CC68    $@"; $(CC68) $(WITNESS_CFLAGS68) -c $< -o $@
$(WB)/m68k/runtime.o: hal/target/runtime.c $(WITNESS_DEPS) | $(MUS)/.stamp
	@mkdir -p $(@D)
	@echo "  CC68    $@"; $(CC68) $(WITNESS_CFLAGS68) -c $< -o $@
$(WB)/m68k/start_m68k.o: tests/witness/start_m68k.S | $(MUS)/.stamp
	@mkdir -p $(@D)
	$(CC68) -m68000 -Wa,--noexecstack -c $< -o $@
$(WB)/witness-m68k: $(WITNESS_M68K_OBJS)
	$(CC68) -m68000 -nostdlib -static -Wl,--gc-sections -Wl,-e,_start -Wl,--build-id=none $^ -o $@
$(WB)/witness-native: $(foreach k,$(WITNESS_KERNELS),tests/witness/k_$(k).c) $(WITNESS_COMMON) \
                      tests/witness/witness_native.c hal/target/runtime.c $(WITNESS_DEPS)
	@mkdir -p $(@D)
	@echo "  CC-ASAN $@"; $(HOSTCC) $(WITNESS_CFLAGS) $(foreach k,$(WITNESS_KERNELS),tests/witness/k_$(k).c) \
		$(WITNESS_COMMON) tests/witness/witness_native.c hal/target/runtime.c -o $@

witness-bins: $(WB)/witness-m68k $(WB)/witness-native
witness: witness-bins
	$(PYTHON) -m pytest -q tests/witness
