# Native unit tests (cmocka), built with ASan and UBSan.  Included by Makefile.
UNIT_TESTS := test_crc16 test_queue test_boot test_runtime test_serial test_plant test_servo test_profile test_stepper test_ext test_motion
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
NATIVE_CFLAGS := -std=gnu11 -g -O1 -Wall -Wextra -Werror -Ihal -Ifirmware -Iharness -Ihal/target \
                 -DHAL_NATIVE -DMAC4_CARD=0 $(SAN)
NATIVE_SRCS := $(fw_srcs_inc) harness/hal_native.c hal/target/runtime.c \
               $(HARNESS_CORE)

$(B)/unit/%: tests/unit/%.c tests/unit/unit_support.h $(NATIVE_SRCS) $(FW_HDRS) $(HARNESS_HDRS)
	@mkdir -p $(@D)
	@echo "  CC-ASAN $@"; $(HOSTCC) $(NATIVE_CFLAGS) $< $(NATIVE_SRCS) -lcmocka -lm -o $@

unit: $(addprefix $(B)/unit/,$(UNIT_TESTS))
	@set -e; for t in $(UNIT_TESTS); do echo "== $$t"; $(B)/unit/$$t; done
