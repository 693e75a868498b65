# The conformance lane (docs/cpu-timing.md).  Included by Makefile.
#   make conformance [SST=DIR]   every vector file of DIR through the core as
#                                mac4sim builds it, one instruction per test
# SST defaults to ../shared/m68000-tests beside the clone (../../shared for a
# git worktree one folder deeper) when it exists, else to the subset committed
# in tests/conformance/vectors (tools/sst_subset.py).  `make test` runs it (TEST_LANES).
SST_SHARED := $(firstword $(wildcard ../shared/m68000-tests ../../shared/m68000-tests))
SST ?= $(if $(SST_SHARED),$(SST_SHARED),tests/conformance/vectors)
.PHONY: conformance
$(B)/sst: tests/conformance/sst.c tests/conformance/sstfile.c tests/conformance/sstfile.h $(MUSOBJ) harness/musashi_cnf.h
	$(HOSTCC) $(HOSTCFLAGS) -Iharness -Ihal -I$(MUS) -Itests/conformance -DMUSASHI_CNF='"musashi_cnf.h"' \
		tests/conformance/sst.c tests/conformance/sstfile.c $(MUSOBJ) -lm -o $@
conformance: $(B)/sst
	$(B)/sst $(SST)
	$(PYTHON) -m pytest -q tests/conformance
