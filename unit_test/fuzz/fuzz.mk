# make fuzz: libFuzzer targets (see unit_test/fuzz/README.md). Included by the top Makefile.
#
#   make fuzz [FUZZ_SECONDS=60]   build with clang (libFuzzer, ASan, UBSan) into
#                                 build/fuzz/ and run each target FUZZ_SECONDS
#                                 seconds from a copy of its seed corpus; fails on
#                                 any crash or sanitizer report
#   make fuzz-build               build the fuzz targets only
#   make fuzz-seeds               regenerate unit_test/fuzz/corpus/ (make_seeds.cpp)
#
# Host only (clang for this machine): with CROSS_COMPILE set these targets refuse.

FUZZ_SECONDS ?= 60
FUZZ_CXX := clang++
FUZZ_DIR := build/fuzz
FUZZ_SRC_DIR := unit_test/fuzz
# fuzz_table: the image checks and codecs alone (thousands of inputs a second);
# fuzz_table_service: those and the table service's whole load sequence (a few
# hundred a second). A target's seeds and reproducers are those of the name
# before its first '_' (table_service: corpus/table, regressions/table).
FUZZ_TARGETS := command table table_service plan
FUZZ_CORPUS := $(FUZZ_SRC_DIR)/corpus
FUZZ_REGRESSIONS := $(FUZZ_SRC_DIR)/regressions

# Flight code keeps its rules (no exceptions, no RTTI); UBSan's vptr check needs
# RTTI, so it is off. Every sanitizer finding is fatal (no recovery), so libFuzzer
# records it as a crash. -fsanitize=fuzzer-no-link instruments the flight code
# for coverage; only the harnesses link libFuzzer's main.
FUZZ_SANITIZE := -fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=all
FUZZ_CXXFLAGS := $(CXXSTD) -O1 -g -fno-omit-frame-pointer -fno-exceptions -fno-rtti \
                 $(FUZZ_SANITIZE) -fsanitize=fuzzer-no-link
FUZZ_HARNESS_WARNINGS := -Wall -Wextra -Wshadow -Werror

FUZZ_FLIGHT_OBJS := $(FLIGHT_SRCS:%.cpp=$(FUZZ_DIR)/obj/%.o)
FUZZ_FLIGHT_LIB := $(FUZZ_DIR)/lib/librse_flight_fuzz.a
FUZZ_TABLES_OBJ := $(FUZZ_DIR)/obj/gen/default_tables.o
FUZZ_BINS := $(FUZZ_TARGETS:%=$(FUZZ_DIR)/bin/fuzz_%)

$(FUZZ_DIR)/obj/fsw/%.o: fsw/%.cpp | deps
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(CPPFLAGS) $(FUZZ_CXXFLAGS) -c $< -o $@

$(FUZZ_DIR)/obj/hal/%.o: hal/%.cpp | deps
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(CPPFLAGS) $(FUZZ_CXXFLAGS) -c $< -o $@

$(FUZZ_TABLES_OBJ): $(DEFAULT_TABLES_SRC) | deps
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(CPPFLAGS) $(FUZZ_CXXFLAGS) -c $< -o $@

$(FUZZ_DIR)/obj/$(FUZZ_SRC_DIR)/%.o: $(FUZZ_SRC_DIR)/%.cpp | deps
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(CPPFLAGS) $(FUZZ_CXXFLAGS) $(FUZZ_HARNESS_WARNINGS) -c $< -o $@

$(FUZZ_FLIGHT_LIB): $(FUZZ_FLIGHT_OBJS)
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^

$(FUZZ_DIR)/bin/fuzz_%: $(FUZZ_DIR)/obj/$(FUZZ_SRC_DIR)/fuzz_%.o $(FUZZ_TABLES_OBJ) $(FUZZ_FLIGHT_LIB)
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(FUZZ_SANITIZE) -fsanitize=fuzzer -o $@ $^ $(LDLIBS_CRYPTO)

.PHONY: fuzz fuzz-build fuzz-seeds fuzz-host-only
fuzz-host-only:
	@if [ -n "$(CROSS_COMPILE)" ]; then echo "fuzz: host only; run without CROSS_COMPILE" >&2; exit 1; fi

fuzz-build: fuzz-host-only deps $(FUZZ_BINS)

# Each target runs even when an earlier one failed; the summary lines come
# together at the end and the exit status is non-zero if any target failed.
fuzz: fuzz-build
	@status=0; \
	for t in $(FUZZ_TARGETS); do \
	  seeds=$${t%%_*}; \
	  $(FUZZ_SRC_DIR)/run_fuzz.sh $$t $(FUZZ_DIR)/bin/fuzz_$$t $(FUZZ_CORPUS)/$$seeds $(FUZZ_DIR)/work/$$t \
	    $(FUZZ_SECONDS) $(FUZZ_REGRESSIONS)/$$seeds || status=1; \
	done; \
	echo "==== make fuzz summary ($(FUZZ_SECONDS) s per target)"; \
	for t in $(FUZZ_TARGETS); do cat $(FUZZ_DIR)/work/$$t/summary.txt 2>/dev/null || echo "fuzz $$t: no result"; done; \
	exit $$status

# Seeds: make_seeds (host g++, linked with the host flight library and the
# default table images) rewrites both corpora from the dictionary and tables/*.toml.
FUZZ_SEEDS_BIN := $(BUILD)/bin/make_fuzz_seeds
$(FUZZ_SEEDS_BIN): $(BUILD)/obj/$(FUZZ_SRC_DIR)/make_seeds.o $(DEFAULT_TABLES_OBJ) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

fuzz-seeds: fuzz-host-only deps $(FUZZ_SEEDS_BIN)
	@mkdir -p $(FUZZ_CORPUS)/command $(FUZZ_CORPUS)/table
	rm -f $(FUZZ_CORPUS)/command/* $(FUZZ_CORPUS)/table/*
	$(FUZZ_SEEDS_BIN) $(FUZZ_CORPUS)

# The fuzz objects' header dependencies (the top Makefile includes only $(BUILD)'s).
-include $(shell find $(FUZZ_DIR)/obj -name '*.d' 2>/dev/null)

# The harness objects are intermediates of a pattern chain: keep them.
.SECONDARY: $(FUZZ_TARGETS:%=$(FUZZ_DIR)/obj/$(FUZZ_SRC_DIR)/fuzz_%.o)
