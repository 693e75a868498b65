# The conformance lane (docs/cpu-timing.md).  Included by Makefile.
#   make conformance [SST=DIR]   every vector file of DIR through the core as
#                                mac4sim builds it; default ../shared/m68000-tests
#                                when it exists, else the subset in tests/conformance/vectors
SST_SHARED := $(wildcard ../shared/m68000-tests)
SST ?= $(if $(SST_SHARED),$(SST_SHARED),tests/conformance/vectors)
.PHONY: conformance
$(B)/sst: tests/conformance/sst.c $(MUSOBJ) harness/musashi_cnf.h
	$(HOSTCC) $(HOSTCFLAGS) -Iharness -Ihal -I$(MUS) -DMUSASHI_CNF='"musashi_cnf.h"' $< $(MUSOBJ) -lm -o $@
conformance: $(B)/sst
	$(B)/sst $(SST)
