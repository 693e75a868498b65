# Fuzz targets of the native firmware (docs/hardening.md).  Included by Makefile.
#
#   make fuzz [FUZZ_SECONDS=60] [FUZZ_TARGETS="queue serial cmd"] [FUZZ_CARDS="inc ssi stp"]
#        [FUZZ_EMU_TARGETS="script image card68k"] [FUZZ_HOST_TARGETS="batch telegram"]
#        libFuzzer (clang), each target and card FUZZ_SECONDS seconds, starting from
#        tests/fuzz/corpus/TARGET; new inputs go to build/fuzz/work/TARGET-CARD,
#        crashes to build/fuzz/crash-TARGET-CARD-*, a summary to build/fuzz/summary.txt
#   make fuzz-replay   every input of tests/fuzz/corpus through every target, built with
#        the host compiler and ASan+UBSan (part of make test; no clang needed)
#   make fuzz-merge    add the work inputs that reach new coverage to tests/fuzz/corpus
#   make fuzz-cov      line coverage of firmware/ by the corpus (clang, llvm-cov)

FUZZ_TARGETS ?= queue serial cmd
FUZZ_CARDS   ?= inc ssi stp
FUZZ_SECONDS ?= 60
FUZZ_JOBS    ?= 1
FUZZ_CLANG   ?= clang
LLVM_PROFDATA ?= llvm-profdata
LLVM_COV     ?= llvm-cov

FZ_ALL_TARGETS := queue serial cmd
FZ_INC   := -Ihal -Ifirmware -Iharness -Ihal/target -DHAL_NATIVE
# UBSan recovers so that fuzz_hal.c's __ubsan_on_report() can tell known bugs
# from new ones (new ones abort there); ASan errors abort at once
FZ_SAN   := -fsanitize=address,undefined -fno-sanitize-recover=all -fsanitize-recover=undefined \
            -fno-omit-frame-pointer
FZ_GCC_CFLAGS   := -std=gnu11 -g -O1 -Wall -Wextra -Werror $(FZ_INC) $(FZ_SAN)
FZ_CLANG_CFLAGS := -std=gnu11 -g -O1 -Wall -Wextra $(FZ_INC) $(FZ_SAN) -DFZ_FAST_BOOT
FZ_COV_CFLAGS   := -std=gnu11 -g -O0 $(FZ_INC) -fprofile-instr-generate -fcoverage-mapping -DFZ_NO_SAN -DFZ_FAST_BOOT
FZ_DEPS  := tests/fuzz/fuzz_card.h tests/fuzz/fuzz_input.h tests/fuzz/fuzz.mk $(FW_HDRS) $(HARNESS_HDRS)

# objects: firmware and targets get libFuzzer's coverage, the harness only the sanitizers
FZ_FW_OBJS = $(patsubst firmware/%.c,$(B)/fuzz/$(1)-$(2)/fw_%.o,$(fw_srcs_$(2))) \
             $(patsubst harness/%.c,$(B)/fuzz/$(1)-$(2)/h_%.o,$(HARNESS_CORE)) \
             $(B)/fuzz/$(1)-$(2)/rt_runtime.o $(B)/fuzz/$(1)-$(2)/fuzz_hal.o

define FZ_OBJ_RULES
$(B)/fuzz/$(1)-$(2)/fw_%.o: firmware/%.c $(FZ_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) $$(FZ_COVER_$(1)) -DMAC4_CARD=$(card_$(2)) -c $$< -o $$@
$(B)/fuzz/$(1)-$(2)/fuzz_%.o: tests/fuzz/fuzz_%.c $(FZ_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) $$(FZ_COVER_$(1)) -DMAC4_CARD=$(card_$(2)) -c $$< -o $$@
$(B)/fuzz/$(1)-$(2)/h_%.o: harness/%.c $(FZ_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) -DMAC4_CARD=$(card_$(2)) -c $$< -o $$@
$(B)/fuzz/$(1)-$(2)/rt_%.o: hal/target/%.c $(FZ_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) -DMAC4_CARD=$(card_$(2)) -c $$< -o $$@
$(B)/fuzz/$(1)-$(2)/replay.o: tests/fuzz/replay.c
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) -c $$< -o $$@
$(B)/fuzz/$(1)-$(2)/fuzz_hal.o: tests/fuzz/fuzz_hal.c harness/hal_native.c $(FZ_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_CFLAGS_$(1)) -DMAC4_CARD=$(card_$(2)) -c $$< -o $$@
endef

FZ_CC_gcc      = $(HOSTCC)
FZ_CFLAGS_gcc  = $(FZ_GCC_CFLAGS)
FZ_CC_clang    = $(FUZZ_CLANG)
FZ_CFLAGS_clang = $(FZ_CLANG_CFLAGS)
FZ_COVER_clang = -fsanitize=fuzzer-no-link
FZ_CC_cov      = $(FUZZ_CLANG)
FZ_CFLAGS_cov  = $(FZ_COV_CFLAGS)
$(foreach c,$(CARDS),$(foreach tc,gcc clang cov,$(eval $(call FZ_OBJ_RULES,$(tc),$(c)))))

define FZ_BIN_RULES
$(B)/fuzz/replay-$(1)-$(2): $(call FZ_FW_OBJS,gcc,$(2)) $(B)/fuzz/gcc-$(2)/fuzz_$(1).o $(B)/fuzz/gcc-$(2)/replay.o
	@echo "  LD-ASAN $$@"; $$(HOSTCC) $$(FZ_SAN) $$^ -o $$@
$(B)/fuzz/fuzz-$(1)-$(2): $(call FZ_FW_OBJS,clang,$(2)) $(B)/fuzz/clang-$(2)/fuzz_$(1).o
	@echo "  LD-FUZZ $$@"; $$(FUZZ_CLANG) -fsanitize=fuzzer,address,undefined $$^ -o $$@
$(B)/fuzz/cov-$(1)-$(2): $(call FZ_FW_OBJS,cov,$(2)) $(B)/fuzz/cov-$(2)/fuzz_$(1).o $(B)/fuzz/cov-$(2)/replay.o
	@echo "  LD-COV  $$@"; $$(FUZZ_CLANG) -fprofile-instr-generate $$^ -o $$@
endef
$(foreach t,$(FZ_ALL_TARGETS),$(foreach c,$(CARDS),$(eval $(call FZ_BIN_RULES,$(t),$(c)))))

FZ_REPLAY_BINS := $(foreach t,$(FZ_ALL_TARGETS),$(foreach c,$(CARDS),$(B)/fuzz/replay-$(t)-$(c)))

# ---- the targets on the emulator: the host-script reader (fuzz_script.c),
# the EPROM image loader (fuzz_image.c), the firmware as the 68000 image under
# a misbehaving host (fuzz_card68k.c).  The harness as mac4sim links it, every
# file it opens through fuzz_fopen.c; one binary per target, the card picked
# by the input's first byte.
FUZZ_EMU_TARGETS ?= script image card68k
# mac4host's batch parser and telegram decoder (fuzz_host.py, Python)
FUZZ_HOST_TARGETS ?= batch telegram
FZ_EMU_ALL := script image card68k
FZ_EMU_HSRCS := $(filter-out harness/mac4sim.c,$(HARNESS_SRCS))
FZ_EMU_FLAGS := -Iharness -Ihal -Ifirmware -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"' \
                -DFZ_EPROM_DIR='"$(abspath $(B)/eprom)"'
FZ_EMU_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FZ_EMU_CFLAGS_gcc   := -std=gnu11 -g -O2 -Wall -Wextra -Werror $(FZ_EMU_SAN) $(FZ_EMU_FLAGS)
FZ_EMU_CFLAGS_clang := -std=gnu11 -g -O2 -Wall -Wextra $(FZ_EMU_SAN) $(FZ_EMU_FLAGS) -fsanitize=fuzzer-no-link
FZ_EMU_DEPS := tests/fuzz/fuzz_emu.h tests/fuzz/fuzz_input.h tests/fuzz/fuzz_fopen.h tests/fuzz/fuzz.mk $(HARNESS_HDRS) $(MUS)/.stamp
FZ_EMU_OBJS = $(patsubst harness/%.c,$(B)/fuzz/emu-$(1)/h_%.o,$(FZ_EMU_HSRCS)) $(B)/fuzz/emu-$(1)/fopen.o

define FZ_EMU_OBJ_RULES
$(B)/fuzz/emu-$(1)/h_%.o: harness/%.c $(FZ_EMU_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_EMU_CFLAGS_$(1)) -include tests/fuzz/fuzz_fopen.h -c $$< -o $$@
$(B)/fuzz/emu-$(1)/fopen.o: tests/fuzz/fuzz_fopen.c $(FZ_EMU_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_EMU_CFLAGS_$(1)) -c $$< -o $$@
$(B)/fuzz/emu-$(1)/fuzz_%.o: tests/fuzz/fuzz_%.c $(FZ_EMU_DEPS)
	@mkdir -p $$(@D)
	@echo "  $(1)-FZ  $$@"; $$(FZ_CC_$(1)) $$(FZ_EMU_CFLAGS_$(1)) -c $$< -o $$@
endef
$(foreach tc,gcc clang,$(eval $(call FZ_EMU_OBJ_RULES,$(tc))))

define FZ_EMU_BIN_RULES
$(B)/fuzz/replay-$(1): $(call FZ_EMU_OBJS,gcc) $(B)/fuzz/emu-gcc/fuzz_$(1).o $(B)/fuzz/gcc-inc/replay.o $(MUSOBJ)
	@echo "  LD-ASAN $$@"; $$(HOSTCC) $(FZ_EMU_SAN) $$^ -lm -o $$@
$(B)/fuzz/fuzz-$(1): $(call FZ_EMU_OBJS,clang) $(B)/fuzz/emu-clang/fuzz_$(1).o $(MUSOBJ)
	@echo "  LD-FUZZ $$@"; $$(FUZZ_CLANG) -fsanitize=fuzzer,address,undefined $$^ -lm -o $$@
endef
$(foreach t,$(FZ_EMU_ALL),$(eval $(call FZ_EMU_BIN_RULES,$(t))))
FZ_EMU_REPLAY_BINS := $(foreach t,$(FZ_EMU_ALL),$(B)/fuzz/replay-$(t))

.PHONY: fuzz fuzz-replay fuzz-merge fuzz-cov fuzz-tools fuzz-known
fuzz-replay: $(FZ_REPLAY_BINS) $(FZ_EMU_REPLAY_BINS) images
	@set -e; for t in $(FZ_ALL_TARGETS); do for c in $(CARDS); do \
		dirs="tests/fuzz/corpus/$$t"; [ -d tests/fuzz/regress/$$t ] && dirs="$$dirs tests/fuzz/regress/$$t"; \
		$(B)/fuzz/replay-$$t-$$c $$dirs; done; done
	@set -e; for t in $(FZ_EMU_ALL); do $(B)/fuzz/replay-$$t tests/fuzz/corpus/$$t 2>/dev/null || \
		{ FUZZ_REPLAY_VERBOSE=1 $(B)/fuzz/replay-$$t tests/fuzz/corpus/$$t; exit 1; }; done
	@$(PYTHON) tests/fuzz/fuzz_host.py --replay

# The reproducers of known, reported bugs (tests/fuzz/known/NAME.TARGET.CARD),
# strict: each fails while its bug is open.  Informational, not part of make test.
fuzz-known: $(FZ_REPLAY_BINS)
	@for f in tests/fuzz/known/K*; do b=$${f##*/}; t=$$(echo $$b | cut -d. -f2); c=$$(echo $$b | cut -d. -f3); \
		if FUZZ_STRICT=1 $(B)/fuzz/replay-$$t-$$c $$f >/dev/null 2>$(B)/fuzz/known.err; then \
			echo "FIXED      $$b: move it to tests/fuzz/corpus/$$t and drop its rule in fuzz_card.h"; \
		else echo "still open $$b: $$(grep -m1 -h 'PROPERTY VIOLATED\|UNDEFINED' $(B)/fuzz/known.err | cut -c1-110)"; fi; \
	done

fuzz-tools: deps
	@command -v $(FUZZ_CLANG) >/dev/null || { echo "make fuzz needs clang: tools/bootstrap.sh installs it" >&2; exit 1; }

fuzz: fuzz-tools $(foreach t,$(FUZZ_TARGETS),$(foreach c,$(FUZZ_CARDS),$(B)/fuzz/fuzz-$(t)-$(c))) \
      $(foreach t,$(FUZZ_EMU_TARGETS),$(B)/fuzz/fuzz-$(t)) images $(B)/commands.json
	@mkdir -p $(B)/fuzz; : > $(B)/fuzz/summary.txt
	@set -e; for t in $(FUZZ_TARGETS); do for c in $(FUZZ_CARDS); do \
		tests/fuzz/run.sh $(B) $$t $$c $(FUZZ_SECONDS) $(FUZZ_JOBS) | tee -a $(B)/fuzz/summary.txt; \
	done; done
	@set -e; for t in $(FUZZ_EMU_TARGETS); do \
		tests/fuzz/run.sh $(B) $$t all $(FUZZ_SECONDS) $(FUZZ_JOBS) | tee -a $(B)/fuzz/summary.txt; done
	@set -e; for t in $(FUZZ_HOST_TARGETS); do \
		$(PYTHON) tests/fuzz/fuzz_host.py --target $$t --seconds $(FUZZ_SECONDS) | tee -a $(B)/fuzz/summary.txt; done
	@echo "summary in $(B)/fuzz/summary.txt"
	@! grep -E "crashes [1-9]" $(B)/fuzz/summary.txt || { echo "make fuzz: findings above (build/fuzz/crash-*)"; exit 1; }

# Only inputs that reach new edges are kept (-use_counters=0: not new hit
# counts), so the corpus in the repository stays small and its replay fast.
fuzz-merge: fuzz-tools $(foreach t,$(FUZZ_TARGETS),$(foreach c,$(FUZZ_CARDS),$(B)/fuzz/fuzz-$(t)-$(c)))
	@set -e; for t in $(FUZZ_TARGETS); do for c in $(FUZZ_CARDS); do \
		[ -d $(B)/fuzz/work/$$t-$$c ] || continue; \
		$(B)/fuzz/fuzz-$$t-$$c -merge=1 -use_counters=0 -max_len=4096 tests/fuzz/corpus/$$t \
			$(B)/fuzz/work/$$t-$$c 2>&1 | grep -E "MERGE-OUTER: [0-9]+ new files" || true; \
	done; done
	@$(MAKE) --no-print-directory $(FZ_REPLAY_BINS)
	@# inputs that hit a known bug belong in tests/fuzz/known, not in the corpus
	@for t in $(FUZZ_TARGETS); do for f in tests/fuzz/corpus/$$t/*; do for c in $(CARDS); do \
		FUZZ_STRICT=1 $(B)/fuzz/replay-$$t-$$c $$f >/dev/null 2>&1 || { echo "known bug: $$f ($$c) left out"; rm $$f; break; }; \
	done; done; done

fuzz-cov: fuzz-tools $(foreach t,$(FUZZ_TARGETS),$(foreach c,$(FUZZ_CARDS),$(B)/fuzz/cov-$(t)-$(c)))
	@rm -rf $(B)/fuzz/prof; mkdir -p $(B)/fuzz/prof
	@set -e; for c in $(FUZZ_CARDS); do objs=""; for t in $(FUZZ_TARGETS); do \
		dirs="tests/fuzz/corpus/$$t"; [ -d $(B)/fuzz/work/$$t-$$c ] && dirs="$$dirs $(B)/fuzz/work/$$t-$$c"; \
		LLVM_PROFILE_FILE=$(B)/fuzz/prof/$$t-$$c.profraw $(B)/fuzz/cov-$$t-$$c $$dirs >/dev/null 2>&1; \
		objs="$$objs -object $(B)/fuzz/cov-$$t-$$c"; done; \
		$(LLVM_PROFDATA) merge -o $(B)/fuzz/prof/$$c.profdata $(B)/fuzz/prof/*-$$c.profraw; \
		echo "== firmware/ covered by the corpus of $(FUZZ_TARGETS) on $$c (work corpora included)"; \
		$(LLVM_COV) report $${objs# -object} -instr-profile=$(B)/fuzz/prof/$$c.profdata \
			$(filter firmware/%,$(FW_ALL_SRCS)) | grep -v "^---" | \
			awk 'NR == 1 {print "file           functions  lines    branches"; next} \
			     {printf "%-14s %-10s %-8s %s\n", $$1, $$7, $$10, $$13}'; \
	done
