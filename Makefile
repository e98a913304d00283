# Sluice build.  `make` builds the static libraries of libsrc/ and every
# application into bin/; `make debug` the same with sanitizers into
# build/debug and bin-debug/; `make test` runs the unit and case tests;
# `make demo` installs what is missing, builds and runs tutorials/damBreak.

CC       ?= gcc
MODE     ?= release
# The release build is tuned for the build machine; ARCH=-march=x86-64-v3
# (or -march=x86-64) gives a binary for other machines.
ARCH     ?= -march=native
ifeq ($(MODE),debug)
  BUILD  := build/debug
  BIN    := build/debug/bin
  OPT    := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -DSL_DEBUG
  LDOPT  := -fsanitize=address,undefined
else
  BUILD  := build/release
  BIN    := bin
  # -fno-math-errno/-fno-trapping-math let the compiler vectorise sqrt and
  # the kernels; -fassociative-math/-fno-signed-zeros let it vectorise the
  # neighbour sums.  Results stay deterministic for any thread count because
  # every per-particle sum is evaluated in the same order by one thread.
  OPT    := -O3 $(ARCH) -g -fno-math-errno -fno-trapping-math \
            -fassociative-math -fno-signed-zeros
  LDOPT  :=
endif

WARN     := -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion \
            -Wdouble-promotion -Wmissing-prototypes -Wstrict-prototypes \
            -Wformat=2 -Wundef
CFLAGS   += -std=c11 -D_GNU_SOURCE -fopenmp $(OPT) $(WARN) -Ilibsrc -MMD -MP
LDLIBS   := -lgsl -lgslcblas -lz -lm
LDFLAGS  += -fopenmp $(LDOPT)

MODULES  := $(notdir $(wildcard libsrc/*))
LIBS     := $(foreach m,$(MODULES),$(BUILD)/lib/libsl_$(m).a)
APPDIRS  := $(wildcard applications/solvers/*) $(wildcard applications/utilities/*)
APPS     := $(foreach d,$(APPDIRS),$(BIN)/$(notdir $(d)))
TESTSRC  := $(wildcard tests/unit/test_*.c)
TESTS    := $(patsubst tests/unit/%.c,$(BUILD)/tests/%,$(TESTSRC))

.PHONY: all debug test test-unit test-cases test-debug demo bench bench-timestep clean format
all: $(APPS) $(TESTS)

# One static library per libsrc/<module>.
define module_rules
$(BUILD)/lib/libsl_$(1).a: $(patsubst %.c,$(BUILD)/%.o,$(wildcard libsrc/$(1)/*.c))
	@mkdir -p $$(@D)
	$$(AR) rcs $$@ $$^
endef
$(foreach m,$(MODULES),$(eval $(call module_rules,$(m))))

# One program per application folder.
define app_rules
$(BIN)/$(notdir $(1)): $(patsubst %.c,$(BUILD)/%.o,$(wildcard $(1)/*.c)) $(LIBS)
	@mkdir -p $$(@D)
	$$(CC) $$(LDFLAGS) -o $$@ $(patsubst %.c,$(BUILD)/%.o,$(wildcard $(1)/*.c)) \
	    -Wl,--start-group $(LIBS) -Wl,--end-group $$(LDLIBS)
endef
$(foreach d,$(APPDIRS),$(eval $(call app_rules,$(d))))

$(BUILD)/tests/%: $(BUILD)/tests/unit/%.o $(LIBS)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) -o $@ $< -Wl,--start-group $(LIBS) -Wl,--end-group $(LDLIBS) -lcmocka

$(BUILD)/%.o: %.c
	@mkdir -p $(@D)
	$(CC) $(CFLAGS) -c -o $@ $<

debug:
	$(MAKE) MODE=debug all

# Unit tests (cmocka) and case tests; tests/run_tests closes with the
# summary line "N passed, N failed".
test: all
	@etc/installDependencies --check
	@tests/run_tests $(BUILD) $(BIN)

test-debug:
	$(MAKE) MODE=debug all
	@tests/run_tests build/debug build/debug/bin --quick

demo:
	@etc/installDependencies
	$(MAKE) all
	@etc/runDemo

bench: $(BIN)/benchPcisph
	@tests/bench/run_bench $(BIN)

bench-timestep: $(BIN)/pcisph
	@tests/bench/run_bench_timestep $(BIN)

format:
	clang-format -i $$(git ls-files '*.c' '*.h')

clean:
	rm -rf build bin

-include $(shell find build -name '*.d' 2>/dev/null)
