# Sluice build.  `make` builds the static libraries of libsrc/ and every
# application into bin/; `make debug` the same with sanitizers into
# build/debug and bin-debug/; `make test` runs the unit and case tests;
# `make demo` installs what is missing, builds and runs tutorials/damBreak.

# `make` alone builds everything (`all`), whatever rule comes first below.
.DEFAULT_GOAL := all

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
# WERROR=1 (CI) turns every warning into an error.
CFLAGS   += $(if $(WERROR),-Werror)
CFLAGS   += -std=c11 -D_GNU_SOURCE -fopenmp $(OPT) $(WARN) -Ilibsrc -MMD -MP
LDLIBS   := -lgsl -lgslcblas -lz -lm
LDFLAGS  += -fopenmp $(LDOPT)

MODULES  := $(notdir $(wildcard libsrc/*))
# The libraries in layer order, highest first: each may use only those to
# its right.  They are linked in this order without --start-group, so that
# a call upwards (a lower layer using a higher one) fails to link.
LAYERS   := functionObjects case solver domain effects boundary motion surface neighbours geometry \
            caseFolder dictedit timestep app dictionary io particles kernel parallel core
ifneq ($(sort $(MODULES)),$(sort $(LAYERS)))
  $(error libsrc modules and LAYERS in the Makefile differ: $(sort $(MODULES)) vs $(sort $(LAYERS)))
endif
LIBS     := $(foreach m,$(LAYERS),$(BUILD)/lib/libsl_$(m).a)

# MPI (issue 17): with mpicc on the PATH (Debian: libopenmpi-dev) the
# parallel layer is built against MPI and every program links it; MPI=no
# builds without it (libsrc/parallel is then one rank, its exchanges no-ops,
# and the parallel tests report themselves skipped).  Only libsrc/parallel
# includes mpi.h.
MPI      ?= $(if $(shell command -v mpicc 2>/dev/null),yes,no)
ifeq ($(MPI),yes)
  MPI_CFLAGS := -DSL_HAVE_MPI $(patsubst -I%,-isystem %,$(shell mpicc --showme:compile 2>/dev/null))
  LDLIBS     += $(shell mpicc --showme:link 2>/dev/null)
endif
$(BUILD)/libsrc/parallel/%.o: CFLAGS += $(MPI_CFLAGS)
# A change of MPI=yes/no rebuilds the parallel layer (and so relinks every
# program): the stamp is made when the makefile is read, since .SECONDARY
# would not remake a missing prerequisite.
MPI_STAMP := $(BUILD)/.mpi-$(MPI)
$(shell mkdir -p $(BUILD) && [ -f $(MPI_STAMP) ] || { rm -f $(BUILD)/.mpi-*; touch $(MPI_STAMP); })
$(BUILD)/libsrc/parallel/par.o: $(MPI_STAMP)
APPDIRS  := $(wildcard applications/solvers/*) $(wildcard applications/utilities/*)
APPS     := $(foreach d,$(APPDIRS),$(BIN)/$(notdir $(d)))
TESTSRC  := $(wildcard tests/unit/test_*.c)
TESTS    := $(patsubst tests/unit/%.c,$(BUILD)/tests/%,$(TESTSRC))

# test objects are intermediate files: keep them, so `make test` after `make` relinks nothing
.SECONDARY:

.PHONY: all debug test test-unit test-cases test-debug demo bench bench-timestep bench-paper clean format format-check
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
	    $(LIBS) $$(LDLIBS)
endef
$(foreach d,$(APPDIRS),$(eval $(call app_rules,$(d))))

$(BUILD)/tests/%: $(BUILD)/tests/unit/%.o $(LIBS)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) -o $@ $< $(LIBS) $(LDLIBS) -lcmocka

$(BUILD)/%.o: %.c
	@mkdir -p $(@D)
	$(CC) $(CFLAGS) -c -o $@ $<

debug:
	$(MAKE) MODE=debug all

# Unit tests (cmocka) and case tests; tests/run_tests names each program as
# it starts, closes with the summary line "N passed, N failed, N skipped",
# and after a full passing run writes doc/hostile-inputs.md.
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

bench: $(BIN)/benchPcisph $(BIN)/pcisph
	@tests/bench/run_bench $(BIN)

bench-timestep: $(BIN)/pcisph
	@tests/bench/run_bench_timestep $(BIN)

# Issue 16: accuracy per second on SPlisHSPlasH's DamBreak (controller cost
# at eta 0.05 % against the paper's at 0.1 %, paired runs; baseline binaries
# from SLUICE_PAPER_BASE_BIN) and CBD small at the paper's scale.
bench-paper: $(BIN)/pcisph $(BIN)/editDictionary
	@tests/bench/run_bench_paper $(BIN)

# The house style is .clang-format (clang-format 14, Debian 12's).  `make format`
# applies it; `make format-check` lists the files that differ and fails (CI runs
# it); another clang-format version formats differently, so the check then says
# it is skipped instead of failing on the version.
CLANG_FORMAT ?= clang-format
format:
	$(CLANG_FORMAT) -i $$(git ls-files '*.c' '*.h')

format-check:
	@if ! $(CLANG_FORMAT) --version 2>/dev/null | grep -q 'version 14\.'; then \
	    echo "format-check: SKIPPED (needs clang-format 14, found: $$($(CLANG_FORMAT) --version 2>/dev/null || echo none))"; \
	    exit 0; fi; \
	bad=$$(for f in $$(git ls-files '*.c' '*.h'); do \
	    $(CLANG_FORMAT) --style=file "$$f" | cmp -s - "$$f" || echo "$$f"; done); \
	if [ -n "$$bad" ]; then \
	    echo "format-check: these files differ from .clang-format (run 'make format'):"; \
	    echo "$$bad" | sed 's/^/  /'; exit 1; fi; \
	echo "format-check: $$(git ls-files '*.c' '*.h' | wc -l) files follow .clang-format"

clean:
	rm -rf build bin

-include $(shell find build -name '*.d' 2>/dev/null)

# Fuzzing (libFuzzer; Debian: clang libclang-rt-14-dev).  `make fuzz` builds
# the targets of tests/fuzz/ with ASan+UBSan into build/fuzz and runs each
# for FUZZ_SECONDS (FUZZ_TARGETS: dict obj stl); see tests/fuzz/run_fuzz.
FUZZ_CC      ?= clang
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= dict obj stl
FUZZ_FLAGS   := -std=c11 -D_GNU_SOURCE -g -O1 -fno-omit-frame-pointer -Ilibsrc \
                -Wno-unknown-pragmas -fsanitize=fuzzer,address,undefined \
                -fno-sanitize-recover=undefined
FUZZ_CORE    := libsrc/core/sl_log.c libsrc/core/sl_mem.c
FUZZ_MESH    := $(addprefix libsrc/geometry/,mesh.c mesh_io.c mesh_distance.c mesh_grid.c) \
                libsrc/io/atomic_file.c $(FUZZ_CORE)
.PHONY: fuzz fuzz-build fuzz-check
fuzz-check:
	@command -v $(FUZZ_CC) > /dev/null || { echo "make fuzz needs $(FUZZ_CC) and libFuzzer" \
	    "(Debian: apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }
fuzz-build: build/fuzz/fuzz_dict build/fuzz/fuzz_obj build/fuzz/fuzz_stl
build/fuzz/fuzz_dict: tests/fuzz/fuzz_dict.c $(wildcard libsrc/dictionary/*.c) $(FUZZ_CORE) \
                      $(wildcard libsrc/dictionary/*.h libsrc/core/*.h)
build/fuzz/fuzz_obj: FUZZ_DEF := -DFUZZ_OBJ
build/fuzz/fuzz_stl: FUZZ_DEF := -DFUZZ_STL
build/fuzz/fuzz_obj build/fuzz/fuzz_stl: tests/fuzz/fuzz_mesh.c $(FUZZ_MESH) \
                                         $(wildcard libsrc/geometry/*.h libsrc/io/*.h libsrc/core/*.h)
build/fuzz/fuzz_%: | fuzz-check
	@rm -rf $(@D)/obj_$* && mkdir -p $(@D)/obj_$*
	$(FUZZ_CC) $(FUZZ_FLAGS) $(WARN) $(FUZZ_DEF) -c -o $(@D)/obj_$*/harness.o $<
	cd $(@D)/obj_$* && $(FUZZ_CC) $(FUZZ_FLAGS) -I$(CURDIR)/libsrc -c \
	    $(addprefix $(CURDIR)/,$(filter-out $<,$(filter %.c,$^)))
	$(FUZZ_CC) $(FUZZ_FLAGS) -o $@ $(@D)/obj_$*/*.o -lm
fuzz: fuzz-build
	@tests/fuzz/run_fuzz build/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# The dictionary parser tests under valgrind, leaks included.  Valgrind
# 3.19 cannot run AVX-512 code, so this build targets generic x86-64-v2.
VALGRIND ?= valgrind --leak-check=full --error-exitcode=1 -q
.PHONY: test-valgrind
test-valgrind:
	@$(MAKE) --no-print-directory BUILD=build/valgrind BIN=build/valgrind/bin \
	    ARCH=-march=x86-64-v2 build/valgrind/tests/test_dictionary
	$(VALGRIND) build/valgrind/tests/test_dictionary
