# Native unit tests (cmocka), built with ASan and UBSan.  Included by Makefile.
UNIT_TESTS := test_crc16 test_queue test_boot test_runtime test_serial test_plant test_servo test_profile test_stepper test_ext test_motion
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
NATIVE_CFLAGS := -std=gnu11 -g -O1 -Wall -Wextra -Werror -Ihal -Ifirmware -Iharness -Ihal/target \
                 -DHAL_NATIVE $(SAN)
# The card a test's firmware is built for, with that card's sources
# (fw_srcs_CARD): inc unless named here.  test_stepper tests the STP's own
# rate stage (stepper.h, stp_rate.c).
UNIT_CARD_test_stepper := stp
unit_card = $(or $(UNIT_CARD_$(1)),inc)
UNIT_SUPPORT_SRCS := harness/hal_native.c hal/target/runtime.c $(HARNESS_CORE)

$(B)/unit/%: tests/unit/%.c tests/unit/unit_support.h $(FW_ALL_SRCS) $(UNIT_SUPPORT_SRCS) $(FW_HDRS) $(HARNESS_HDRS)
	@mkdir -p $(@D)
	@echo "  CC-ASAN $@"; $(HOSTCC) $(NATIVE_CFLAGS) -DMAC4_CARD=$(card_$(call unit_card,$*)) $< \
		$(fw_srcs_$(call unit_card,$*)) $(UNIT_SUPPORT_SRCS) -lcmocka -lm -o $@

unit: $(addprefix $(B)/unit/,$(UNIT_TESTS))
	@set -e; for t in $(UNIT_TESTS); do echo "== $$t"; $(B)/unit/$$t; done
