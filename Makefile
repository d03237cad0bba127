# RSE build. Targets (README.md has the story):
#   make deps        install the Debian packages the project needs (idempotent; root or sudo)
#   make / all       build rse-fsw for this machine, or for CROSS_COMPILE=aarch64-linux-gnu-
#   make test        every unit-test suite on the host, and for aarch64, armhf and s390x under
#                    qemu-user; powerpc built and rse-fsw run once; then the Slurm campaign
#                    test (make test-slurm); all built and run in parallel (every core);
#                    ends with the per-target table and one line "N passed, N failed" (total)
#   make host-test   host suites only (quick edit-test loop)
#   make cross-test  the cross targets only (suites under qemu-user, powerpc built and run once)
#   make all CROSS_COMPILE=arm-linux-gnueabihf-   rse-fsw for one target (also aarch64-linux-gnu-,
#                    s390x-linux-gnu-, powerpc-linux-gnu-); docs/cross_targets.md
#   make demo        the autonomous mission demo (rse-demo: rse-fsw and rse-sim in lockstep, GOTO
#                    from the ground, console streamed, mission summary);
#                    make demo DEMO_SECONDS=300 DEMO_ARGS="--no-faults"
#   make montecarlo  the demo mission over MC_SEEDS seeds (default 200) on every core: the campaign
#                    table (rse-montecarlo, docs/montecarlo.md); make montecarlo MC_SEEDS=1000 MC_FIRST=1
#   make test-slurm  only the Slurm campaign test (a one-node cluster on localhost; make test runs it too)
#   make plan-picture  the demo map planned at Delta = 1e-2 and 1e-6, drawn to build/plan_picture.svg
#   make mission-control       the mission control display (Open MCT) on the paced demo: http://127.0.0.1:8090/
#   make mission-control-deps  Node.js, Chromium and the display's npm packages (ground/mission_control/web)
#   make mission-control-web-test  the display's JavaScript library under node --test
#   make mission-control-display-test MC_URL=...  the browser test against a running rse-ground serve
#   make bench       benchmarks; they print their figures (see docs/performance.md)
#   make bench-check the same, but a missed target (MISSED / NOT MET / FAIL) fails it
#   make clean
# Every target that builds depends on deps, so a fresh clone needs no manual step.

SHELL := /bin/bash
.DEFAULT_GOAL := all
.DELETE_ON_ERROR:

CROSS_COMPILE ?=
# The flight computers (docs/cross_targets.md). make test builds every one and
# runs the suites of CROSS_TEST_TARGETS under qemu-user. CROSS_BUILD_ONLY
# targets have no Debian port, so no CppUTest to link the suites with: their
# flight code is compiled, rse-fsw linked (mbedTLS built from Debian's source
# package) and run once in lockstep under qemu-user.
CROSS_AARCH64 := aarch64-linux-gnu-
CROSS_ARMHF := arm-linux-gnueabihf-
CROSS_S390X := s390x-linux-gnu-
CROSS_POWERPC := powerpc-linux-gnu-
# In make test's build order: the slowest suites under emulation first.
CROSS_TEST_TARGETS := $(CROSS_S390X) $(CROSS_ARMHF) $(CROSS_AARCH64)
CROSS_BUILD_ONLY := $(CROSS_POWERPC)
CXX := $(CROSS_COMPILE)g++
AR := $(CROSS_COMPILE)ar
# The build folder's name: the Debian port's for 32-bit ARM (the triple says
# only "arm"), the triple's first word otherwise.
arch_of = $(if $(filter arm-linux-gnueabihf-,$(1)),armhf,$(patsubst %-linux-gnu-,%,$(1)))
ARCH := $(if $(CROSS_COMPILE),$(call arch_of,$(CROSS_COMPILE)),$(shell uname -m))
BUILD := build/$(ARCH)
HOST_ARCH := $(shell uname -m)
TRIPLE := $(patsubst %-,%,$(CROSS_COMPILE))
BUILD_ONLY := $(filter $(CROSS_COMPILE),$(CROSS_BUILD_ONLY))

# How test binaries run: natively, or under qemu-user with the target's libraries.
# s390x: qemu-s390x 7.2 aborts every dynamically linked program it loads itself
# with -L ("stack smashing detected", even int main() { return 3; }); started
# through the target's own dynamic loader they run, so the loader is the program.
QEMU_armhf := qemu-arm
QEMU_powerpc := qemu-ppc
RUNNER_s390x := qemu-s390x /usr/$(TRIPLE)/lib/ld64.so.1 --library-path /usr/$(TRIPLE)/lib
RUNNER := $(if $(CROSS_COMPILE),$(or $(RUNNER_$(ARCH)),$(or $(QEMU_$(ARCH)),qemu-$(ARCH)) -L /usr/$(TRIPLE)),)

# Parallel builds: every core, unless the caller gave its own -j (its jobserver
# is then shared). Read where recipes expand it: only there does MAKEFLAGS hold -j.
NPROC := $(shell nproc)
PARALLEL = $(if $(filter -j%,$(MAKEFLAGS)),,-j$(NPROC))

# ---------------------------------------------------------------------------
# Debian packages: exactly what the build, tests, cross-tests and the vcan VM
# test need (the VM test also downloads Debian's kernel package into build/).
# COIN-OR CBC: the exact MILP reference of the chance-constrained planner
# (unit_test/bench/cc_reference_milp.*), linked into the host build of the
# system_cc_reference suite and into bench_cc_reference only; never into flight code,
# rse-fsw or any aarch64 binary (the suite's CBC tests are host only).
CBC_PACKAGES := coinor-libcbc-dev
# Slurm (and munge, its authentication) for the Monte Carlo campaign test: a
# one-node cluster on localhost that the test starts and stops itself
# (unit_test/integration/slurm/; docs/montecarlo.md). Installing them starts no
# daemon. Installed by test-slurm (make test), not by make demo.
SLURM_PACKAGES := slurm-wlm munge
# Cross targets: the compiler, and the suites' libraries in the Debian port
# (multiarch: dpkg --add-architecture, done by deps). powerpc is no Debian
# release architecture: only its compiler and C/C++ runtime are packaged.
CROSS_PACKAGES := g++-aarch64-linux-gnu libcpputest-dev:arm64 libmbedtls-dev:arm64 \
                  g++-arm-linux-gnueabihf libcpputest-dev:armhf libmbedtls-dev:armhf \
                  g++-s390x-linux-gnu libcpputest-dev:s390x libmbedtls-dev:s390x \
                  g++-powerpc-linux-gnu
# universal-ctags: the house rules test measures every C++ function's length with it
# (unit_test/system/layering/house_rules_test.sh).
# Mission control (rse-ground serve, ground/mission_control/; host only): the
# SQLite archive (C API), HTTP and WebSocket with Boost.Beast/Asio
# (header-only), JSON with nlohmann/json (header-only).
MC_PACKAGES := libsqlite3-dev libboost-dev nlohmann-json3-dev
DEB_PACKAGES := g++ make file libcpputest-dev libeigen3-dev libtomlplusplus-dev universal-ctags \
                qemu-user $(CROSS_PACKAGES) \
                qemu-system-x86 busybox-static can-utils \
                libmbedtls-dev tshark clang libclang-rt-14-dev \
                $(CBC_PACKAGES) $(MC_PACKAGES)
SUDO := $(if $(filter 0,$(shell id -u)),,$(shell command -v sudo))

.PHONY: deps
deps:
	@native=$$(dpkg --print-architecture); missing=""; \
	for p in $(DEB_PACKAGES); do \
	  case "$$p" in *:*) want="installed $${p#*:}";; *) want="installed ($$native|all)";; esac; \
	  dpkg-query -W -f='$${db:Status-Status} $${Architecture}\n' "$$p" 2>/dev/null | grep -qxE "$$want" \
	    || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "deps: installing$$missing"; \
	  if [ "$$(id -u)" != 0 ] && [ -z "$(SUDO)" ]; then \
	    echo "deps: missing packages and not root (no sudo): run 'make deps' as root" >&2; exit 1; \
	  fi; \
	  for a in $$(printf '%s\n' $$missing | sed -n 's/.*://p' | sort -u); do \
	    dpkg --print-foreign-architectures | grep -qx "$$a" || $(SUDO) dpkg --add-architecture "$$a"; \
	  done; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi

# ---------------------------------------------------------------------------
# Flags. Flight code (fsw/, hal/): no exceptions, no RTTI, strict warnings.
# EIGEN_RUNTIME_NO_MALLOC everywhere so the allocation tests can forbid Eigen
# heap use at run time (it costs nothing unless asked).
# 64-bit file offsets and time_t on 32-bit targets too (no-op on 64-bit ones):
# without them readdir() fails on a filesystem with 64-bit directory offsets
# (seen: armhf under qemu-user on ext4) and time_t overflows in January 2038.
CPPFLAGS := -I. -isystem /usr/include/eigen3 -DEIGEN_RUNTIME_NO_MALLOC -D_FILE_OFFSET_BITS=64 -D_TIME_BITS=64 -MMD -MP
CXXSTD := -std=c++17
# Cross targets keep line tables only (-g1: backtraces with functions and lines
# under gdb-multiarch, no variables): full -g costs 17 % more compile time per
# file (measured over 40 files with arm-linux-gnueabihf-g++), and the cross
# builds are most of make test's CPU since issue 30 split the code into ~490
# files. The host keeps full debug information.
OPT := $(if $(CROSS_COMPILE),-O2 -g1,-O2 -g)
WARNINGS := -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wold-style-cast \
            -Wnon-virtual-dtor -Wcast-align -Wdouble-promotion -Wformat=2 -Wundef -Werror
FLIGHT_CXXFLAGS := $(CXXSTD) $(OPT) $(WARNINGS) -fno-exceptions -fno-rtti
# Test and host-tool code: CppUTest's macros expand to casts that -Wold-style-cast
# and -Wconversion reject, so those two are off there.
# CPPUTEST_MEM_LEAK_DETECTION_DISABLED: CppUTest's headers otherwise define
# `new` as new(__FILE__, __LINE__), whose operator ignores alignment, and a test
# group holding an over-aligned member (FswApp: Eigen's fixed-size types want 16
# bytes) is then misaligned where malloc aligns to 8 (armhf: Eigen's assertion).
# Leaks are still found (the library's operator new), without file and line.
TEST_CXXFLAGS := $(CXXSTD) $(OPT) -Wall -Wextra -Wpedantic -Wshadow -Werror -DCPPUTEST_MEM_LEAK_DETECTION_DISABLED
SIM_CXXFLAGS := $(CXXSTD) $(OPT) $(WARNINGS)
# HMAC-SHA-256 for authenticated commands: Debian's mbedTLS (libmbedcrypto);
# for a build-only target, built from Debian's source package (a prerequisite
# of rse-fsw, so it links as one of its objects).
SOURCE_MBEDCRYPTO := $(if $(BUILD_ONLY),$(BUILD)/mbedtls/libmbedcrypto.a)
LDLIBS_CRYPTO := $(if $(BUILD_ONLY),,-lmbedcrypto)
LDLIBS_TEST := -lCppUTest -lpthread $(LDLIBS_CRYPTO)
# Bind every symbol at load time: no lazy-binding stall in the first frames.
LDFLAGS := -Wl,-z,now

# ---------------------------------------------------------------------------
# Default table images: rse-ground (always a host build, also when cross
# compiling) compiles tables/*.toml into images and those into a C++ source
# that rse-fsw and the test binaries link, so the flight software boots with
# the same bytes ground would upload. Not part of the flight library: the
# ground tool links that library and must not need its own output.
HOST_GROUND_BIN := build/$(shell uname -m)/bin/rse-ground
TABLE_SOURCES := $(sort $(wildcard tables/*.toml))
TABLE_DEFS := fsw/tables/table_defs.def
DEFAULT_TABLES_SRC := $(BUILD)/gen/default_tables.cpp
DEFAULT_TABLES_OBJ := $(BUILD)/obj/gen/default_tables.o

# ---------------------------------------------------------------------------
# Flight library and executable.
FLIGHT_SRCS := $(filter-out fsw/app/main.cpp,$(sort $(wildcard fsw/*/*.cpp hal/*/*.cpp)))
FLIGHT_OBJS := $(FLIGHT_SRCS:%.cpp=$(BUILD)/obj/%.o)
FLIGHT_LIB := $(BUILD)/lib/librse_flight.a
FSW_BIN := $(BUILD)/bin/rse-fsw

$(BUILD)/obj/fsw/%.o: fsw/%.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(FLIGHT_CXXFLAGS) -c $< -o $@

$(BUILD)/obj/hal/%.o: hal/%.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(FLIGHT_CXXFLAGS) -c $< -o $@

# rse-sim (host side: full language allowed, but it runs in-process with the
# flight code in lockstep tests, so it too allocates only while setting up).
$(BUILD)/obj/sim_stub/%.o: sim_stub/%.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(SIM_CXXFLAGS) -c $< -o $@

$(BUILD)/obj/unit_test/%.o: unit_test/%.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(TEST_CXXFLAGS) -c $< -o $@

$(FLIGHT_LIB): $(FLIGHT_OBJS)
	@mkdir -p $(@D)
	rm -f $@ && $(AR) rcs $@ $^

# The simulator library: the world, the device and drive emulators, the
# scenarios and the lockstep rig (sim_stub/lockstep/: FswApp + RoverSim on one
# virtual clock, the in-memory ground, the mission runner). The rig needs the
# flight and ground libraries: link them after it. rse-fsw never links it.
SIM_MAINS := sim_stub/main.cpp sim_stub/mission_demo.cpp sim_stub/montecarlo_main.cpp
SIM_SRCS := $(filter-out $(SIM_MAINS),$(sort $(wildcard sim_stub/*.cpp sim_stub/*/*.cpp)))
SIM_OBJS := $(SIM_SRCS:%.cpp=$(BUILD)/obj/%.o)
SIM_LIB := $(BUILD)/lib/librse_sim.a

$(SIM_LIB): $(SIM_OBJS)
	@mkdir -p $(@D)
	rm -f $@ && $(AR) rcs $@ $^

$(FSW_BIN): $(BUILD)/obj/fsw/app/main.o $(DEFAULT_TABLES_OBJ) $(FLIGHT_LIB) $(SOURCE_MBEDCRYPTO)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)
ifneq ($(SOURCE_MBEDCRYPTO),)
$(SOURCE_MBEDCRYPTO): unit_test/cross/build_mbedcrypto.sh | deps
	unit_test/cross/build_mbedcrypto.sh $(CROSS_COMPILE) $@
endif

# The ground library for its number text (a site file's numbers: sim_stub/scenario/site_file.cpp).
SIM_BIN := $(BUILD)/bin/rse-sim
$(SIM_BIN): $(BUILD)/obj/sim_stub/main.o $(SIM_LIB) $(BUILD)/lib/librse_ground.a $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# Ground tools (host side: full language allowed). ground/*.cpp other than the
# mains form the ground library, which the unit tests link too.
$(BUILD)/obj/ground/%.o: ground/%.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(SIM_CXXFLAGS) -c $< -o $@

GROUND_MAINS := ground/rse_isotp.cpp ground/rse_ground.cpp ground/plan_picture.cpp
GROUND_SRCS := $(filter-out $(GROUND_MAINS),$(sort $(wildcard ground/*.cpp)))
GROUND_LIB := $(BUILD)/lib/librse_ground.a
$(GROUND_LIB): $(GROUND_SRCS:%.cpp=$(BUILD)/obj/%.o)
	@mkdir -p $(@D)
	rm -f $@ && $(AR) rcs $@ $^

ISOTP_BIN := $(BUILD)/bin/rse-isotp
$(ISOTP_BIN): $(BUILD)/obj/ground/rse_isotp.o $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^

# The mission control server (rse-ground serve): its own library, host only
# (SQLite, Boost.Beast), linked into rse-ground and its suite
# (unit_test/ground/mission_control/), never into the cross-built ground library.
MC_SRCS := $(sort $(wildcard ground/mission_control/*.cpp))
MC_LIB := $(BUILD)/lib/librse_mission_control.a
LDLIBS_MC := -lsqlite3 -lpthread
$(MC_LIB): $(MC_SRCS:%.cpp=$(BUILD)/obj/%.o)
	@mkdir -p $(@D)
	rm -f $@ && $(AR) rcs $@ $^

GROUND_BIN := $(BUILD)/bin/rse-ground
$(GROUND_BIN): $(BUILD)/obj/ground/rse_ground.o $(MC_LIB) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO) $(LDLIBS_MC)

# rse-plan-picture: the default tables' map planned at two risk bounds, one SVG.
PLAN_PICTURE_BIN := $(BUILD)/bin/rse-plan-picture
$(PLAN_PICTURE_BIN): $(BUILD)/obj/ground/plan_picture.o $(DEFAULT_TABLES_OBJ) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# rse-demo: the mission in lockstep (host only, like rse-sim): the
# simulator library with the ground library (the GOTO encoder) and the flight library.
DEMO_BIN := $(BUILD)/bin/rse-demo
$(DEMO_BIN): $(BUILD)/obj/sim_stub/mission_demo.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# rse-montecarlo: the mission over many seeds (sim_stub/montecarlo/, host only
# like rse-demo): local worker processes, Slurm array blocks, merged tables.
MC_BIN := $(BUILD)/bin/rse-montecarlo
$(MC_BIN): $(BUILD)/obj/sim_stub/montecarlo_main.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# The default table images (DEFAULT_TABLES_SRC above). A cross build first
# makes the host rse-ground in a make run of its own.
ifeq ($(CROSS_COMPILE),)
$(DEFAULT_TABLES_SRC): $(TABLE_SOURCES) $(TABLE_DEFS) $(HOST_GROUND_BIN)
else
.PHONY: host-ground
host-ground:
	@$(MAKE) --no-print-directory CROSS_COMPILE= $(HOST_GROUND_BIN)
$(DEFAULT_TABLES_SRC): $(TABLE_SOURCES) $(TABLE_DEFS) | host-ground
endif
	@mkdir -p $(@D)
	$(HOST_GROUND_BIN) table build --cpp $@ $(TABLE_SOURCES)
$(DEFAULT_TABLES_OBJ): $(DEFAULT_TABLES_SRC)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(FLIGHT_CXXFLAGS) -c $< -o $@

# A cross build makes what runs on the rover; a host build adds the simulator
# and the ground tools.
HOST_TOOLS := $(SIM_BIN) $(DEMO_BIN) $(ISOTP_BIN) $(GROUND_BIN) $(PLAN_PICTURE_BIN) $(MC_BIN)
.PHONY: all
all: $(FSW_BIN) $(if $(CROSS_COMPILE),,$(HOST_TOOLS))

# ---------------------------------------------------------------------------
# Unit-test suites. unit_test/ mirrors the code (docs/architecture.md, "Where
# the tests live"): a suite is a folder under unit_test/, at any depth, that
# holds .cpp files itself, and its binary is test_<that folder under unit_test/,
# '/' as '_'>: unit_test/fsw/estimator/ is test_fsw_estimator, unit_test/ground/
# test_ground, unit_test/ground/mission_control/ (a folder of its own, so a suite
# of its own) test_ground_mission_control. Each is linked with the shared support
# code (allocation guard, CppUTest main). These folders, and those under them,
# hold helpers, not suites:
TEST_HELPER_DIRS := support integration bench fuzz cross
# HOST_ONLY_SUITES are not built for a cross target (their libraries are the host's).
# system_layering reads the sources (includes, ownership): the same on every
# target, so host only, like the house rules script.
HOST_ONLY_SUITES := ground_mission_control system_layering
suite_name = $(subst /,_,$(patsubst unit_test/%,%,$(1)))
ALL_SUITE_DIRS := $(sort $(patsubst %/,%,$(dir $(filter-out $(TEST_HELPER_DIRS:%=unit_test/%/%),\
                    $(shell find unit_test -name '*.cpp' -type f)))))
SUITE_DIRS := $(strip $(foreach d,$(ALL_SUITE_DIRS),\
                $(if $(and $(CROSS_COMPILE),$(filter $(call suite_name,$(d)),$(HOST_ONLY_SUITES))),,$(d))))
SUITES := $(foreach d,$(SUITE_DIRS),$(call suite_name,$(d)))
# Two folders must not map to one name (unit_test/a/b and unit_test/a_b).
$(if $(filter-out $(words $(SUITES)),$(words $(sort $(SUITES)))),\
  $(error two unit_test folders give one suite name: $(SUITES)))
SUPPORT_OBJS := $(patsubst %.cpp,$(BUILD)/obj/%.o,$(wildcard unit_test/support/*.cpp))

# suite_rule NAME FOLDER. A suite may add objects (SUITE_OBJS_<name>) and
# libraries (SUITE_LIBS_<name>), and leave test files out of a cross build
# (SUITE_HOST_ONLY_<name>).
define suite_rule
$(BUILD)/bin/test_$(1): $(patsubst %.cpp,$(BUILD)/obj/%.o,$(filter-out $(if $(CROSS_COMPILE),$(SUITE_HOST_ONLY_$(1))),$(wildcard $(2)/*.cpp))) $(SUITE_OBJS_$(1)) $(SUPPORT_OBJS) $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $$(@D)
	$(CXX) $(LDFLAGS) -o $$@ $$^ $(LDLIBS_TEST) $(SUITE_LIBS_$(1))
endef
# Chance-constrained planning reference (host-only benchmark code in
# unit_test/bench/): instance generator, Monte Carlo checker and shared checks
# build for both architectures; the CBC MILP reference for the host only.
CC_BENCH_OBJS := $(patsubst %.cpp,$(BUILD)/obj/%.o,unit_test/bench/cc_common.cpp \
                   unit_test/bench/cc_instances.cpp unit_test/bench/cc_monte_carlo.cpp)
CC_MILP_OBJ := $(BUILD)/obj/unit_test/bench/cc_reference_milp.o
CBC_CPPFLAGS := -isystem /usr/include/coin
CBC_LDLIBS := -lCbcSolver -lCbc -lOsiClp -lClp -lOsi -lCoinUtils
$(CC_MILP_OBJ): unit_test/bench/cc_reference_milp.cpp | deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CBC_CPPFLAGS) $(TEST_CXXFLAGS) -c $< -o $@
SUITE_HOST_ONLY_system_cc_reference := $(wildcard unit_test/system/cc_reference/*_milp.cpp unit_test/system/cc_reference/*_host.cpp)
# The 700 m Snowdrift traverse: 12 s on the host, minutes under emulation (the 100 m field flies on every target).
SUITE_HOST_ONLY_system_lockstep := $(wildcard unit_test/system/lockstep/*_host.cpp)
# qemu-user 7.2 on the development VM hangs in pthread_create: the writer
# thread's tests run on the host only (rse-fsw under qemu: --auth-store-sync).
SUITE_HOST_ONLY_hal_nvm := unit_test/hal/nvm/test_threaded_record_writer.cpp
# fork() under qemu-user is not what the worker-pool tests are about, nor a whole site-mission run the row's bookkeeping (*_host.cpp): host only.
SUITE_HOST_ONLY_sim_stub_montecarlo := unit_test/sim_stub/montecarlo/test_worker_pool.cpp $(wildcard unit_test/sim_stub/montecarlo/*_host.cpp)
# The mission control server's suite: its library, SQLite and threads (host only).
SUITE_OBJS_ground_mission_control := $(MC_LIB)
SUITE_LIBS_ground_mission_control := $(LDLIBS_MC)
SUITE_OBJS_system_cc_reference := $(CC_BENCH_OBJS) $(if $(CROSS_COMPILE),,$(CC_MILP_OBJ))
SUITE_LIBS_system_cc_reference := $(if $(CROSS_COMPILE),,$(CBC_LDLIBS))
$(foreach d,$(SUITE_DIRS),$(eval $(call suite_rule,$(call suite_name,$(d)),$(d))))
TEST_BINS := $(SUITES:%=$(BUILD)/bin/test_%)
# Script suites drive the built executables (RSE_BIN_DIR, under RSE_RUNNER).
# The vcan test boots an x86_64 VM with real SocketCAN: host build only.
# The tshark check captures the UDP ground link on lo: host build only too.
VCAN_TEST := unit_test/integration/vcan_test/vcan_integration_test.sh
# The mission over vcan commanded only from the ground (three processes, time
# scale 5 in the VM), compared with the lockstep run: about 5 minutes.
VCAN_MISSION_TEST := unit_test/integration/vcan_test/vcan_mission_test.sh
TSHARK_TEST := unit_test/integration/tshark/tshark_ccsds_test.sh
WATCHDOG_TEST := unit_test/integration/watchdog_test/watchdog_vm_test.sh
# The simulator programs' command lines (rse-sim, rse-demo, rse-montecarlo:
# --help and bad options, docs/operations.md): host tools, so host only.
SIM_CLI_TEST := unit_test/integration/rse_sim_cli_test.sh
# rse-ground's command line (--help, bad command lines, the offline commands):
# rse-ground is a host tool, so host only.
GROUND_CLI_TEST := unit_test/integration/rse_ground_cli_test.sh
# The size of the rooms (issue 30): no source file in fsw/ hal/ ground/ sim_stub/
# over 800 lines, no C++ function there over 100 (universal-ctags reads them);
# it prints each folder's largest file and longest function. Reads sources: host only.
HOUSE_RULES_TEST := unit_test/system/layering/house_rules_test.sh
# The harness's own counts (run_suites.sh, summarize.sh, run_benches.sh with fake
# suites and benches): shell only, so host only.
HARNESS_TEST := unit_test/integration/harness_counts_test.sh
# The mission control display (issue 19): its JavaScript library under node,
# and end to end: rse-ground serve, the paced demo over UDP, headless Chromium
# (host only; needs mission-control-deps, which make test runs first).
MC_WEB_TEST := unit_test/ground/mission_control/web/web_lib_test.sh
MC_DISPLAY_TEST := unit_test/ground/mission_control/web/mission_control_test.sh
# The suites that boot the qemu VM (real-time, mostly waiting): make test runs
# them as a set of their own (test-run-vm), one after the other, as soon as
# VCAN_BINS are built. The mission control display's end-to-end test closes the
# set: it is real-time too (the paced demo, Chromium), and beside the VM's
# mission its Chromium took the CPU the emulated rover needed (CI: frames 33 ms
# late, task-stalled faults 25-30 raised, the vcan mission's check failed).
VM_SUITES := $(VCAN_TEST) $(VCAN_MISSION_TEST) $(WATCHDOG_TEST) $(MC_DISPLAY_TEST)
SCRIPT_SUITES := unit_test/integration/rse_fsw_cli_test.sh $(if $(CROSS_COMPILE),,$(HOUSE_RULES_TEST) $(SIM_CLI_TEST) $(GROUND_CLI_TEST) $(HARNESS_TEST) $(MC_WEB_TEST) $(MC_DISPLAY_TEST) $(VCAN_TEST) $(VCAN_MISSION_TEST) $(TSHARK_TEST) $(WATCHDOG_TEST))

RESULTS := build/test-results.txt

# rse-fsw and rse-sim as separate processes on a real vcan0 (in a qemu VM with
# Debian's kernel where this kernel has no CAN), checked with can-utils; then
# the mission over vcan commanded only from the ground (test-vcan-mission alone).
# Both suites' counts go to one results file and one summary line.
VCAN_BINS := $(FSW_BIN) $(SIM_BIN) $(GROUND_BIN) $(ISOTP_BIN) $(DEMO_BIN)
.PHONY: test-vcan test-vcan-mission
test-vcan: deps
	@mkdir -p build && rm -f $(RESULTS)
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(VCAN_BINS)
	@RSE_BIN_DIR=build/$(shell uname -m)/bin unit_test/run_suites.sh $(RESULTS) "$(shell uname -m)" "" \
	  $(VCAN_TEST) $(VCAN_MISSION_TEST)
	@unit_test/summarize.sh $(RESULTS)
test-vcan-mission: deps
	@mkdir -p build && rm -f $(RESULTS)
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(VCAN_BINS)
	@RSE_BIN_DIR=build/$(shell uname -m)/bin unit_test/run_suites.sh $(RESULTS) "$(shell uname -m)" "" \
	  $(VCAN_MISSION_TEST)
	@unit_test/summarize.sh $(RESULTS)

.PHONY: test-binaries run-suites host-test cross-test test
test-binaries: $(TEST_BINS) $(FSW_BIN) $(if $(CROSS_COMPILE),,$(HOST_TOOLS))

# Runs this arch's suites, appending one line per suite to $(RESULTS); builds
# them first (in parallel) unless the caller already did (SUITES_BUILT=1).
# RUN_SET=vm: only the VM suites; RUN_SET=no-vm: all the others (make test).
SUITES_BUILT ?=
RUN_SET ?=
RUN_SUITES = $(if $(filter vm,$(RUN_SET)),$(VM_SUITES),\
               $(TEST_BINS) $(if $(filter no-vm,$(RUN_SET)),$(filter-out $(VM_SUITES),$(SCRIPT_SUITES)),$(SCRIPT_SUITES)))
run-suites:
	@$(if $(SUITES_BUILT),,$(MAKE) --no-print-directory $(PARALLEL) test-binaries || echo "$(ARCH)/build 0 1" >> $(RESULTS))
	@RSE_BIN_DIR=$(BUILD)/bin unit_test/run_suites.sh $(RESULTS) "$(ARCH)" "$(RUNNER)" $(RUN_SUITES)

host-test: deps
	@mkdir -p build && rm -f $(RESULTS)
	@$(MAKE) --no-print-directory run-suites CROSS_COMPILE=
	@unit_test/summarize.sh $(RESULTS)

# ---------------------------------------------------------------------------
# make test: one parallel make over every target (the host, CROSS_TEST_TARGETS,
# CROSS_BUILD_ONLY), then the cross-target wire check, the Slurm test and the
# summary. Per target its build (test-build/T) comes before its run
# (test-run/T). The order of the builds follows the longest chain: first the
# programs the VM suites need (test-build-vm), whose run (test-run-vm: the vcan
# tests and the watchdog test, ten minutes of an emulated machine that mostly
# idles, about a quarter of a core) then starts at once; then the host's suites;
# then the cross targets (they need the host rse-ground for their default
# tables), which build and run beside the host's runs, side by side. The VM run
# holds a job slot while hardly using a core, so make test gets one slot beyond
# one per core (TEST_JOBS). -k: a target that fails to build is counted
# ("T/build 0 1") and the others go on; -Otarget: each run's output is printed
# whole when it ends (its console is in build/logs/ as it happens). Timings:
# docs/performance.md, "Build and test times".
# The host's real-time tests (the VM's mission at time scale 5, rse-fsw on its
# real clock) must not lose their CPU to the work beside them: the cross
# targets build and run at nice 19, so they take only what the host leaves idle.
# (A cross suite at normal priority beside the vcan mission made the rover's
# frames start 4 ms late and changed the mission: measured, docs/performance.md.)
beside_host = $(if $(call test_prefix,$(1)),nice -n 19)
TEST_JOBS = $(if $(filter -j%,$(MAKEFLAGS)),,-j$$(( $(NPROC) + 1 )))
test_label = $(if $(filter host,$(1)),$(HOST_ARCH),$(call arch_of,$(1)))
test_prefix = $(if $(filter host,$(1)),,$(1))
TEST_SETS := host $(CROSS_TEST_TARGETS)

test: deps mission-control-deps
	@mkdir -p build && rm -f $(RESULTS) && rm -rf $(WIRE_DIR)
	@echo "make test: building and running $(foreach t,$(TEST_SETS),$(call test_label,$(t))) and building $(foreach t,$(CROSS_BUILD_ONLY),$(call test_label,$(t))) (rse-fsw under qemu, no suites) in parallel; each prints when it ends"
	@$(MAKE) --no-print-directory $(TEST_JOBS) -k -Otarget test-run-vm $(TEST_SETS:%=test-run/%) \
	  $(CROSS_BUILD_ONLY:%=test-build-only/%) || echo "make test: some target failed (counted in the results below)"
	@$(MAKE) --no-print-directory -k $(TEST_SETS:%=test-wire/%) || true
	@$(MAKE) --no-print-directory test-slurm SLURM_RESULTS=$(RESULTS)
	@unit_test/summarize.sh $(RESULTS)

# The cross targets only (their builds and suites, the build-only targets):
# make cross-test, or one of them: make cross-test CROSS_TEST_TARGETS=s390x-linux-gnu- CROSS_BUILD_ONLY=
cross-test: deps
	@mkdir -p build && rm -f $(RESULTS)
	@$(MAKE) --no-print-directory $(TEST_JOBS) -k -Otarget $(CROSS_TEST_TARGETS:%=test-run/%) $(CROSS_BUILD_ONLY:%=test-build-only/%) \
	  || echo "make cross-test: some target failed (counted in the results below)"
	@unit_test/summarize.sh $(RESULTS)

.PHONY: test-host-ground FORCE
FORCE:
test-host-ground:
	@$(MAKE) --no-print-directory CROSS_COMPILE= $(HOST_GROUND_BIN)
# First the programs the VM suites run (their ten minutes are the longest
# chain), then the host's suites with every slot, then the cross targets beside
# the runs. The VM set counts as the host's (x86_64) in the results.
.PHONY: test-build-vm test-run-vm
test-build-vm: test-host-ground
	@$(MAKE) --no-print-directory CROSS_COMPILE= $(VCAN_BINS) || { echo "$(HOST_ARCH)/vm-build 0 1" >> $(RESULTS); exit 1; }
# The VM suites get 30 minutes each, not 900 s: the vcan mission (about 450 s
# of wall time a run) runs a second time when its first run took another route
# (vcan_mission_test.sh; issue 33 is to take that retry out), and under 900 s the
# second run was killed half-way and the first run's failures counted.
test-run-vm: test-build-vm
	@SUITE_TIMEOUT=1800 $(MAKE) --no-print-directory CROSS_COMPILE= SUITES_BUILT=1 RUN_SET=vm run-suites
test-build/host: test-build-vm
# The cross targets build one after the other, each with every free slot, in
# CROSS_TEST_TARGETS order: s390x's suites take longest under emulation, so
# they start first; the build-only targets last.
build_chain = $(if $(word 2,$(1)),$(eval test-build/$(word 2,$(1)): test-build/$(firstword $(1)))$(call build_chain,$(wordlist 2,$(words $(1)),$(1))))
$(call build_chain,host $(CROSS_TEST_TARGETS))
$(CROSS_BUILD_ONLY:%=test-build-only/%): test-build/$(lastword host $(CROSS_TEST_TARGETS))
test-build/%: test-host-ground FORCE
	@$(call beside_host,$*) $(MAKE) --no-print-directory CROSS_COMPILE=$(call test_prefix,$*) test-binaries \
	  || { echo "$(call test_label,$*)/build 0 1" >> $(RESULTS); exit 1; }
test-run/%: test-build/% FORCE
	@$(call beside_host,$*) $(MAKE) --no-print-directory CROSS_COMPILE=$(call test_prefix,$*) SUITES_BUILT=1 \
	  $(if $(call test_prefix,$*),,RUN_SET=no-vm) run-suites
# The cross-target wire check (unit_test/system/wire_exchange/): once every target's
# run has written its samples to WIRE_DIR, each target reads all the others'
# (results "<target>-peers/test_system_wire_exchange").
WIRE_DIR := build/wire
TEST_LABELS = $(foreach t,$(TEST_SETS),$(call test_label,$(t)))
test-wire/%: FORCE
	@$(MAKE) --no-print-directory CROSS_COMPILE=$(call test_prefix,$*) wire-peers
.PHONY: wire-peers
wire-peers:
	@RSE_WIRE_DIR=$(WIRE_DIR) RSE_WIRE_PEERS="$(filter-out $(ARCH),$(TEST_LABELS))" \
	  unit_test/run_suites.sh $(RESULTS) "$(ARCH)-peers" "$(RUNNER)" $(BUILD)/bin/test_system_wire_exchange
# A build-only target (docs/cross_targets.md), two checks: the flight code
# (fsw/, hal/) compiled with the flight warnings as errors and rse-fsw linked;
# then rse-fsw run for 1 s of lockstep under qemu-user (100 frames, exit 0).
test-build-only/%: test-host-ground FORCE
	@$(call beside_host,$*) $(MAKE) --no-print-directory CROSS_COMPILE=$* rse-fsw-lockstep-check
.PHONY: rse-fsw-lockstep-check
rse-fsw-lockstep-check:
	@if $(MAKE) --no-print-directory all; then echo "$(ARCH)/flight-build 1 0 0" >> $(RESULTS); \
	else echo "$(ARCH)/flight-build 0 1 0" >> $(RESULTS); exit 1; fi
	@rm -f $(BUILD)/lockstep-auth.dat; \
	if $(RUNNER) $(FSW_BIN) --lockstep --duration 1 --lab-key --auth-store-sync \
	     --auth-store $(BUILD)/lockstep-auth.dat --auth-store-create > $(BUILD)/lockstep-check.log 2>&1 \
	   && grep -q "rse-fsw summary: 100 frames run, 0 overruns" $(BUILD)/lockstep-check.log; then \
	  echo "$(ARCH)/rse-fsw-lockstep 1 0 0" >> $(RESULTS); echo "[$(ARCH)] rse-fsw: 1 s of lockstep under qemu-user, 100 frames"; \
	else echo "$(ARCH)/rse-fsw-lockstep 0 1 0" >> $(RESULTS); cat $(BUILD)/lockstep-check.log; exit 1; fi

# The Monte Carlo campaign on Slurm (docs/montecarlo.md): a one-node cluster on
# localhost (munged, slurmctld, slurmd with a config written into
# build/slurm_test/), a 20-seed campaign in 4 array tasks, merged and checked
# against the local run of the same seeds; every daemon stopped. Its counts go
# to SLURM_RESULTS: alone, its own results file and summary line; from make
# test, the one results file of every suite (make test's summary counts it).
# Where Slurm cannot run, it fails: nothing is skipped.
SLURM_TEST := unit_test/integration/slurm/slurm_campaign_test.sh
SLURM_RESULTS ?=
.PHONY: test-slurm slurm-deps
slurm-deps: deps
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(SLURM_PACKAGES)"
test-slurm: slurm-deps
	@mkdir -p build
	@$(if $(SLURM_RESULTS),,rm -f $(RESULTS))
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(HOST_MC_BIN) \
	  || echo "$(HOST_ARCH)/slurm-build 0 1" >> $(or $(SLURM_RESULTS),$(RESULTS))
	@RSE_BIN_DIR=build/$(HOST_ARCH)/bin unit_test/run_suites.sh $(or $(SLURM_RESULTS),$(RESULTS)) "$(HOST_ARCH)" "" \
	  $(SLURM_TEST)
	@$(if $(SLURM_RESULTS),,unit_test/summarize.sh $(RESULTS))

# ---------------------------------------------------------------------------
# Mission control display, browser side (docs/mission_control.md):
# ground/mission_control/web holds index.html, the RSE plugin for Open MCT and
# package.json + package-lock.json (openmct; puppeteer-core for the browser
# test, which drives Debian's Chromium: nothing downloads a browser).
# mission-control-deps: Node.js and npm from Debian only when the machine has
# none (a newer Node already installed is kept: Debian's npm would conflict
# with it), Chromium like every Debian package here, and npm ci whenever
# node_modules is missing or older than the lock file.
MC_WEB := ground/mission_control/web
MC_DEB_PACKAGES := chromium
.PHONY: mission-control-deps mission-control-web-test mission-control-display-test
mission-control-deps: deps
	@command -v node >/dev/null && command -v npm >/dev/null \
	  || $(MAKE) --no-print-directory deps DEB_PACKAGES="nodejs npm"
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(MC_DEB_PACKAGES)"
	@if [ ! -d $(MC_WEB)/node_modules ] || [ $(MC_WEB)/package-lock.json -nt $(MC_WEB)/node_modules ]; then \
	  echo "mission-control-deps: npm ci in $(MC_WEB)"; \
	  (cd $(MC_WEB) && npm ci --no-audit --no-fund) && touch $(MC_WEB)/node_modules; \
	fi

# The display's JavaScript library (dictionary, limits, history paging, risk
# ellipses, ...) under Node's test runner: no browser, no server.
mission-control-web-test: mission-control-deps
	bash $(MC_WEB_TEST)

# make mission-control: the display on the demo. rse-ground serve on
# http://$(MC_HTTP)/ (telemetry on UDP 127.0.0.1:$(MC_TLM_PORT), archive
# build/mission_control/archive.sqlite, kept across runs), and the demo mission
# paced at MC_PACE x real time sending its telemetry there; the display stays
# up after the mission (its archive answers history) until Ctrl-C. On a live
# rover: rse-ground --tlm-port PORT serve (docs/mission_control.md).
MC_HTTP ?= 127.0.0.1:8090
MC_TLM_PORT ?= 1235
MC_PACE ?= 1
.PHONY: mission-control
mission-control: mission-control-deps
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= build/$(HOST_ARCH)/bin/rse-ground $(HOST_DEMO_BIN)
	@build/$(HOST_ARCH)/bin/rse-ground --tlm-port 127.0.0.1:$(MC_TLM_PORT) serve --http $(MC_HTTP) & serve=$$!; \
	  trap 'kill $$serve 2>/dev/null; wait $$serve' EXIT INT TERM; sleep 1; \
	  kill -0 $$serve 2>/dev/null || exit 1; \
	  echo "mission-control: open http://$(MC_HTTP)/ in a browser; the demo starts now at $(MC_PACE)x real time"; \
	  $(HOST_DEMO_BIN) --pace $(MC_PACE) --udp-telemetry 127.0.0.1:$(MC_TLM_PORT) --duration $(DEMO_SECONDS) \
	    --any-outcome $(DEMO_ARGS); \
	  echo "mission-control: the mission is over; the display stays up on http://$(MC_HTTP)/ (Ctrl-C stops it)"; \
	  wait $$serve

# The browser test against a running rse-ground serve at MC_URL:
# make mission-control-display-test MC_URL=http://127.0.0.1:8090/ [MC_TEST_ARGS="--history --interval S:E"]
MC_URL ?= http://127.0.0.1:8090/
MC_TEST_ARGS ?=
mission-control-display-test: mission-control-deps
	node unit_test/ground/mission_control/web/display_test.mjs --url $(MC_URL) \
	  --screenshot build/mission_control/display_test.png $(MC_TEST_ARGS)

# ---------------------------------------------------------------------------
# Demo, plan picture and benchmarks (host).
# make demo: rse-demo with the demo scenario (sim_stub/scenarios/demo_mission.toml):
# DEMO_SECONDS simulated seconds at most, DEMO_ARGS more options (rse-demo --help),
# e.g. DEMO_ARGS="--no-faults" or DEMO_ARGS="--goto 12,3,1e-2".
DEMO_SECONDS ?= 180
DEMO_ARGS ?=
HOST_DEMO_BIN := build/$(shell uname -m)/bin/rse-demo
.PHONY: demo bench bench-check plan-picture montecarlo
demo: deps
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(HOST_DEMO_BIN)
	$(HOST_DEMO_BIN) --duration $(DEMO_SECONDS) $(DEMO_ARGS)

# make montecarlo: the demo mission over MC_SEEDS seeds from MC_FIRST on MC_JOBS
# worker processes (default: every core), its table and the wall time
# (docs/montecarlo.md); the result file is build/montecarlo/results.txt.
# MC_ARGS: more options (rse-montecarlo run's MISSION options, e.g. --no-faults).
# Exits 3 when a check of the table failed (a collision within the risk bound).
MC_SEEDS ?= 200
MC_FIRST ?= 1
MC_JOBS ?= $(shell nproc)
MC_ARGS ?=
HOST_MC_BIN := build/$(shell uname -m)/bin/rse-montecarlo
montecarlo: deps
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(HOST_MC_BIN)
	$(HOST_MC_BIN) run --seeds $(MC_FIRST):$(MC_SEEDS) --jobs $(MC_JOBS) --out build/montecarlo/results.txt \
	  --table build/montecarlo/table.txt $(MC_ARGS)

# The demo map planned at Delta = 1e-2 and 1e-6 (docs/deliberative.md, "Picture").
HOST_PLAN_PICTURE_BIN := build/$(shell uname -m)/bin/rse-plan-picture
PLAN_PICTURE_SVG := build/plan_picture.svg
plan-picture: deps
	@$(MAKE) --no-print-directory $(PARALLEL) CROSS_COMPILE= $(HOST_PLAN_PICTURE_BIN)
	$(HOST_PLAN_PICTURE_BIN) -o $(PLAN_PICTURE_SVG)

# Each program unit_test/bench/bench_*.cpp is one benchmark; make bench runs them
# all (the other .cpp files there are code the benchmarks share).
BENCH_BINS := $(patsubst unit_test/bench/%.cpp,$(BUILD)/bin/%,$(wildcard unit_test/bench/bench_*.cpp))
$(BUILD)/bin/bench_%: $(BUILD)/obj/unit_test/bench/bench_%.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# The RRT* benchmark runs OMPL's RRT* beside ours as the reference. OMPL (and
# Boost under it) is a host-only benchmark dependency: never linked into flight
# code or the unit tests, so `make test` does not install it.
BENCH_PACKAGES := libompl-dev $(CBC_PACKAGES)
OMPL_CPPFLAGS := -isystem /usr/include/ompl-1.5
.PHONY: bench-deps
bench-deps: deps
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(BENCH_PACKAGES)"
$(BUILD)/obj/unit_test/bench/bench_rrt_star.o: unit_test/bench/bench_rrt_star.cpp | bench-deps
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(OMPL_CPPFLAGS) $(TEST_CXXFLAGS) -c $< -o $@
$(BUILD)/bin/bench_rrt_star: $(BUILD)/obj/unit_test/bench/bench_rrt_star.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO) -lompl

# The fault-recovery, lockstep-mission and plan-executive benchmarks run whole missions through the ground link (the ground library).
$(BUILD)/bin/bench_fault_recovery $(BUILD)/bin/bench_lockstep_mission $(BUILD)/bin/bench_plan_executive $(BUILD)/bin/bench_global_route $(BUILD)/bin/bench_site_fields: $(BUILD)/bin/bench_%: $(BUILD)/obj/unit_test/bench/bench_%.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(GROUND_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)
# The site-field campaign samples its flown horizons against the whole site map.
$(BUILD)/bin/bench_site_fields: $(BUILD)/obj/unit_test/bench/whole_map_mc.o $(CC_BENCH_OBJS)

# The ground-link flood benchmark runs rse-fsw and signs its commands with the ground library.
$(BUILD)/bin/bench_ground_flood: $(BUILD)/obj/unit_test/bench/bench_ground_flood.o $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(GROUND_LIB) $(FLIGHT_LIB) | $(FSW_BIN)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO) -lpthread

# The chance-constrained reference benchmark: CBC's exact MILP (host only).
$(BUILD)/bin/bench_cc_reference: $(BUILD)/obj/unit_test/bench/bench_cc_reference.o $(CC_BENCH_OBJS) $(CC_MILP_OBJ) $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO) $(CBC_LDLIBS)

# How tight each risk bound is against Monte Carlo (issue 15 item 3): no CBC.
$(BUILD)/bin/bench_cc_risk_bounds: $(BUILD)/obj/unit_test/bench/bench_cc_risk_bounds.o $(CC_BENCH_OBJS) $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO)

# The completeness and hard-budget benchmark of the same planner (issue 15): CBC decides instances without a witness.
$(BUILD)/bin/bench_cc_complete: $(BUILD)/obj/unit_test/bench/bench_cc_complete.o $(CC_BENCH_OBJS) $(CC_MILP_OBJ) $(DEFAULT_TABLES_OBJ) $(SIM_LIB) $(FLIGHT_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $^ $(LDLIBS_CRYPTO) $(CBC_LDLIBS)

# unit_test/bench/run_benches.sh runs them all, each whatever the others did, and
# ends with a summary line. A bench exits 3 when it missed a target
# (bench_targets.hpp). make bench reports a missed target and exits 0 (it fails
# only when a bench could not run); make bench-check fails on a missed target too.
# RSE_BENCH_FORCE_MISS=1 makes every target a miss (to see bench-check fail).
BENCH_RUN := $(filter-out %/bench_socketcan,$(BENCH_BINS)) unit_test/bench/bench_ground_flood_keyed.sh unit_test/bench/vm_bench.sh
bench: bench-deps $(BENCH_BINS)
	@RSE_BIN_DIR=$(BUILD)/bin unit_test/bench/run_benches.sh $(BENCH_RUN)

bench-check: bench-deps $(BENCH_BINS)
	@RSE_BIN_DIR=$(BUILD)/bin unit_test/bench/run_benches.sh --check $(BENCH_RUN)

# libFuzzer targets with sanitizers (Debian clang): make fuzz [FUZZ_SECONDS=60]
include unit_test/fuzz/fuzz.mk

.PHONY: clean
clean:
	rm -rf build

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
