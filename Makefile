# tis - vertex-model tissue mechanics.  See README.md.
#
#   make              libmesh/libmesh.a and the programs in bin/
#   make check        every test through prove (SAN=1: with ASan and UBSan);
#                     make check-slow: every shipped sample remade, ...
#   make bench        benchmarks in bench/, results in bench/RESULTS.md
#   make figures      figures/*.png (gnuplot): a1, a3 against p0, f(l) curves
#   make demo         installs what is missing, builds, runs the default job
#   make install      PREFIX=/usr/local DESTDIR=: programs, man pages, the
#                     library (libtis.a, include/tis/, tis.pc), documentation
#
# Everything is found by wildcard: a new libmesh/LAYER/*.c or *.cc joins
# the library, a new tools/tis-*.c is a program, tests/*.c a unit test,
# tests/*.sh a program test, bench/*.sh a benchmark.  The layers of
# libmesh, bottom up, each using only those before it (tests/layers.sh
# checks it; doc/DESIGN.md has the map):
LAYERS = core tissue solve dynamics analysis draw

VERSION = 0.1
PREFIX ?= /usr/local
DESTDIR ?=

CC ?= cc
CXX ?= c++
OPT ?= -O2 -march=x86-64-v2
CFLAGS ?= $(OPT) -g
CXXFLAGS ?= $(OPT) -g
WARN = -Wall -Wextra
# OpenMP for the threads of the kernel, the Hessian and the preconditioner
# (the numbers do not depend on their count: energy.h)
OMP = -fopenmp
LIB_INC = $(LAYERS:%=-Ilibmesh/%)
ALL_CFLAGS = -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) $(OMP) $(LIB_INC) -DTIS_VERSION='"$(VERSION)"' $(CFLAGS)
ALL_CXXFLAGS = -std=c++17 $(WARN) $(OMP) $(LIB_INC) $(CXXFLAGS)
LIBS = -lcholmod -lsundials_cvode -lsundials_nvecserial -lnlopt -llapacke -lopenblas -lgsl -lgslcblas -lgmp -lmpfr -lstdc++ -lm -lpthread -lgomp

# SAN=1 builds everything with sanitizers into build-san/, apart from the
# normal objects, so the two never mix.
ifeq ($(SAN),1)
O = build-san/
SANFLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
ALL_CFLAGS += $(SANFLAGS)
ALL_CXXFLAGS += $(SANFLAGS)
LDFLAGS += $(SANFLAGS)
export ASAN_OPTIONS = detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS = print_stacktrace=1:halt_on_error=1
else ifeq ($(CHECK),1)
# CHECK=1: the whole tissue is validated after every T1 (invariants.h),
# into build-check/
O = build-check/
ALL_CFLAGS += -DTIS_CHECK_INVARIANTS
else
O =
endif

LIB_C = $(sort $(wildcard $(LAYERS:%=libmesh/%/*.c)))
LIB_CC = $(sort $(wildcard $(LAYERS:%=libmesh/%/*.cc)))
LIB_H = $(sort $(wildcard $(LAYERS:%=libmesh/%/*.h)))
LIB_OBJ = $(LIB_C:%.c=$(O)%.o) $(LIB_CC:%.cc=$(O)%.o)
LIB = $(O)libmesh/libmesh.a

PROGS_SRC = $(sort $(wildcard tools/tis-*.c))
PROGS = $(PROGS_SRC:tools/%.c=$(O)bin/%)
CLI_SRC = $(sort $(wildcard tools/cli*.c))
CLI_H = $(sort $(wildcard tools/cli*.h))
CLI_OBJ = $(CLI_SRC:%.c=$(O)%.o)
CLI = $(O)tools/libcli.a

UNIT_SRC = $(sort $(wildcard tests/*.c))
UNITS = $(UNIT_SRC:tests/%.c=$(O)tests/%.test)
SHELL_TESTS = $(filter-out tests/lib.sh,$(sort $(wildcard tests/*.sh)))

MAN1 = $(wildcard man/*.1)
MAN5 = $(wildcard man/*.5)
MAN7 = $(wildcard man/*.7)

.PHONY: all check check-slow mutate bench demo deps install uninstall clean samples figures fuzz fuzz-build studies

all: $(LIB) $(PROGS)

$(O)libmesh/%.o: libmesh/%.c $(LIB_H)
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

# active_rk.c's static inline vector helpers take AVX vectors by value;
# gcc 12 notes that ABI change however the file's pragma asks (-Wpsabi
# is not honoured there), and a static inline function has no ABI.
$(O)libmesh/dynamics/active_rk.o: ALL_CFLAGS += -Wno-psabi

$(O)libmesh/%.o: libmesh/%.cc $(LIB_H)
	@mkdir -p $(@D)
	$(CXX) $(ALL_CXXFLAGS) -c -o $@ $<

$(LIB): $(LIB_OBJ)
	@mkdir -p $(@D)
	rm -f $@
	ar rcs $@ $(LIB_OBJ)

# The programs' shared plumbing (tools/cli*.c, one concern a file; cli.h
# includes their headers) as an archive: a program links what it uses.
$(O)tools/%.o: tools/%.c $(CLI_H) $(LIB_H)
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(CLI): $(CLI_OBJ)
	rm -f $@
	ar rcs $@ $(CLI_OBJ)

$(O)bin/%: tools/%.c $(CLI) $(CLI_H) $(LIB) $(LIB_H)
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -Itools $(LDFLAGS) -o $@ $< $(CLI) $(LIB) $(LIBS)

$(O)tests/%.test: tests/%.c tests/tap.h tests/sample.h $(LIB) $(LIB_H)
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) $(LDFLAGS) -o $@ $< $(LIB) $(LIBS)

# Program tests find the programs through TIS_BIN (and PATH).
check: $(LIB) $(PROGS) $(UNITS)
	TIS_BIN=$(CURDIR)/$(O)bin PATH="$(CURDIR)/$(O)bin:$$PATH" \
	  TIS_SAN="$(SAN)" TIS_SANFLAGS="$(SANFLAGS)" TIS_LIBOBJ=$(CURDIR)/$(O)libmesh \
	  prove -j2 $(UNITS) $(SHELL_TESTS)

# The slow checks make check samples once: every shipped sample remade
# from its own history lines and compared with the file, cell by cell
# (tests/samples.sh), and every document number tests/docs.sh knows: about
# 12 CPU minutes.
check-slow: $(LIB) $(PROGS)
	TIS_BIN=$(CURDIR)/$(O)bin PATH="$(CURDIR)/$(O)bin:$$PATH" TIS_SLOW=1 \
	  prove -v tests/samples.sh tests/docs.sh

# Single-line mutations of the code (tests/mutate/list), each in a scratch
# copy of the tree, rebuilt and tested there: every one must be caught.
# Slow (tens of minutes): before a release and after a change to the tests,
# not in every CI run.  MUTATE="NAME ..." runs only those.
mutate: all
	./tests/mutate/run $(MUTATE)

# figures.sh and the study it draws on (disorder-a1.sh, about half an hour)
# are measurements of physics, not of speed: they run under `make figures`.
STUDIES = bench/figures.sh bench/disorder-a1.sh bench/anneal-protocol.sh
bench: all
	@for b in $(filter-out $(STUDIES),$(wildcard bench/*.sh)); do \
	  [ -x "$$b" ] || continue; \
	  echo "== $$b"; PATH="$(CURDIR)/bin:$$PATH" "$$b" || exit 1; done

DEBS = libgsl-dev libnlopt-dev libcgal-dev libsuitesparse-dev libsundials-dev liblapacke-dev libopenblas-dev g++ make perl
# the table and VTK tests use these when present (CI installs them)
TESTDEBS = python3-pandas python3-numpy python3-matplotlib python3-pytest ffmpeg gnuplot-nox python3-vtk9 pkgconf groff-base
# the sweeps (studies/): GNU parallel; the SLURM test: slurm-wlm
SWEEPDEBS = parallel procps slurm-wlm
FIGDEBS = gnuplot-nox
# what make demo uses beyond the build: ffmpeg for its movie (optional:
# without it the demo says so and makes no movie)
DEMODEBS = ffmpeg
deps:
	@./.ci/deps $(DEBS) $(DEMODEBS)

demo:
	@./.ci/deps --quiet $(DEBS)
	@./.ci/deps --quiet $(DEMODEBS) || echo "demo: ffmpeg is optional: without it no movie"
	@$(MAKE) --no-print-directory all
	@PATH="$(CURDIR)/bin:$$PATH" ./samples/demo.sh

samples: all
	PATH="$(CURDIR)/bin:$$PATH" $(MAKE) -C samples

figures: all
	@./.ci/deps --quiet $(FIGDEBS)
	PATH="$(CURDIR)/bin:$$PATH" ./bench/figures.sh
	$(MAKE) -C studies figures

# The paper's active-junction studies (studies/README.md): every study on
# its small grid, minutes each on 2 cores; make -C studies NAME for one.
studies: all
	@./.ci/deps --quiet $(FIGDEBS) $(SWEEPDEBS)
	$(MAKE) -C studies all

# The library installs as libtis.a with its headers in include/tis/ and
# tis.pc (libMesh, the finite-element library, owns the names libmesh and
# libmesh.pc); the documentation the man pages refer to goes to DOCDIR.
LIBDIR = $(PREFIX)/lib
INCDIR = $(PREFIX)/include/tis
PCDIR = $(LIBDIR)/pkgconfig
DOCDIR = $(PREFIX)/share/doc/tis
DOCS = README.md LICENSE CITATION.cff doc/DESIGN.md doc/relax-energy.c bench/RESULTS.md
# The shipped samples (not make -C samples large's), which the programs
# find by the name samples/NAME.mesh (tis(7), FILES)
SAMPLEDIR = $(PREFIX)/share/tis/samples
SAMPLES = $(sort $(wildcard samples/disordered-[0-9].mesh samples/ordered-[0-9][0-9].mesh))
# The Python module (python/tis) goes where Debian's python3 looks for a
# prefix's modules: PREFIX/lib/python3.N/dist-packages for /usr/local and
# /usr, the user's site-packages for PREFIX=$$HOME/.local, else
# PREFIX/lib/python3.N/site-packages (on PYTHONPATH); the example beside
# the documentation.
PYTHON ?= /usr/bin/python3
PYVER := $(shell $(PYTHON) -c 'import sys; print("python%d.%d" % sys.version_info[:2])' 2>/dev/null || echo python3)
ifndef PYDIR
PYDIR := $(shell $(PYTHON) -c 'import os, site, sys; p = os.path.abspath(sys.argv[1]); \
  print(site.USER_SITE if p == os.path.abspath(site.USER_BASE) else os.path.join(p, "lib", sys.argv[2], \
  "dist-packages" if p in ("/usr", "/usr/local") else "site-packages"))' '$(PREFIX)' '$(PYVER)' 2>/dev/null || \
  echo '$(PREFIX)/lib/$(PYVER)/dist-packages')
endif
PY_SRC = $(sort $(wildcard python/tis/*.py))
PY_EXAMPLES = $(sort $(wildcard python/examples/*.py))

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/man/man1 \
	  $(DESTDIR)$(PREFIX)/share/man/man5 $(DESTDIR)$(PREFIX)/share/man/man7 \
	  $(DESTDIR)$(INCDIR) $(DESTDIR)$(PCDIR) $(DESTDIR)$(DOCDIR)
	install -m 755 $(PROGS) $(DESTDIR)$(PREFIX)/bin
	install -m 644 $(MAN1) $(DESTDIR)$(PREFIX)/share/man/man1
	install -m 644 $(MAN5) $(DESTDIR)$(PREFIX)/share/man/man5
	install -m 644 $(MAN7) $(DESTDIR)$(PREFIX)/share/man/man7
	install -m 644 $(LIB_H) $(DESTDIR)$(INCDIR)
	install -m 644 $(LIB) $(DESTDIR)$(LIBDIR)/libtis.a
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}/lib' 'includedir=$${prefix}/include' '' \
	  'Name: tis' 'Description: 2D vertex-model tissue mechanics (libmesh of the tis suite)' \
	  'Version: $(VERSION)' 'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -ltis' \
	  'Libs.private: $(LIBS)' >$(DESTDIR)$(PCDIR)/tis.pc
	install -m 644 $(DOCS) $(DESTDIR)$(DOCDIR)
	install -m 644 samples/README.md $(DESTDIR)$(DOCDIR)/samples.md
	install -d $(DESTDIR)$(SAMPLEDIR)
	install -m 644 $(SAMPLES) $(DESTDIR)$(SAMPLEDIR)
	install -d $(DESTDIR)$(PYDIR)/tis $(DESTDIR)$(DOCDIR)/python
	install -m 644 $(PY_SRC) $(DESTDIR)$(PYDIR)/tis
	install -m 644 $(PY_EXAMPLES) $(DESTDIR)$(DOCDIR)/python

uninstall:
	rm -f $(PROGS:$(O)bin/%=$(DESTDIR)$(PREFIX)/bin/%) \
	  $(MAN1:man/%=$(DESTDIR)$(PREFIX)/share/man/man1/%) \
	  $(MAN5:man/%=$(DESTDIR)$(PREFIX)/share/man/man5/%) \
	  $(MAN7:man/%=$(DESTDIR)$(PREFIX)/share/man/man7/%) \
	  $(addprefix $(DESTDIR)$(INCDIR)/,$(notdir $(LIB_H))) $(DESTDIR)$(LIBDIR)/libtis.a \
	  $(DESTDIR)$(PCDIR)/tis.pc $(addprefix $(DESTDIR)$(DOCDIR)/,$(notdir $(DOCS)) samples.md) \
	  $(PY_SRC:python/tis/%=$(DESTDIR)$(PYDIR)/tis/%) $(PY_EXAMPLES:python/examples/%=$(DESTDIR)$(DOCDIR)/python/%) \
	  $(SAMPLES:samples/%=$(DESTDIR)$(SAMPLEDIR)/%)
	rm -rf $(DESTDIR)$(PYDIR)/tis/__pycache__
	-rmdir $(DESTDIR)$(PYDIR)/tis $(DESTDIR)$(DOCDIR)/python $(DESTDIR)$(SAMPLEDIR) $(DESTDIR)$(PREFIX)/share/tis 2>/dev/null
	-rmdir $(DESTDIR)$(INCDIR) $(DESTDIR)$(DOCDIR) 2>/dev/null

# make fuzz: every fuzz/*.c is a libFuzzer harness (clang, ASan + UBSan,
# the library instrumented for coverage, in build-fuzz/), run FUZZ_S
# seconds from its seed corpus fuzz/corpus/NAME; any finding fails it
# (fuzz/run says where the input is).  Needs clang and libclang-rt-14-dev.
FUZZ_S ?= 60
FUZZ_CC ?= clang
FUZZ_CXX ?= clang++
FUZZ_FLAGS = -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
FUZZ_SRC = $(sort $(wildcard fuzz/*.c))
FUZZ_BIN = $(FUZZ_SRC:fuzz/%.c=build-fuzz/%)
FUZZ_LIB = build-fuzz/libmesh.a
FUZZ_LIB_OBJ = $(LIB_C:%.c=build-fuzz/%.o) $(LIB_CC:%.cc=build-fuzz/%.o)
FUZZDEBS = clang libclang-rt-14-dev

build-fuzz/libmesh/%.o: libmesh/%.c $(LIB_H)
	@mkdir -p $(@D)
	$(FUZZ_CC) -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) $(LIB_INC) $(FUZZ_FLAGS) -fsanitize=fuzzer-no-link -c -o $@ $<

build-fuzz/libmesh/%.o: libmesh/%.cc $(LIB_H)
	@mkdir -p $(@D)
	$(FUZZ_CXX) -std=c++17 $(WARN) $(LIB_INC) $(FUZZ_FLAGS) -fsanitize=fuzzer-no-link -c -o $@ $<

$(FUZZ_LIB): $(FUZZ_LIB_OBJ)
	rm -f $@
	ar rcs $@ $(FUZZ_LIB_OBJ)

build-fuzz/%: fuzz/%.c $(FUZZ_LIB) $(LIB_H) $(CLI_SRC) $(CLI_H) $(PROGS_SRC)
	@mkdir -p $(@D)
	$(FUZZ_CC) -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) $(LIB_INC) -Itools \
	  -DTIS_VERSION='"$(VERSION)"' $(FUZZ_FLAGS) -fsanitize=fuzzer -c -o $@.o $<
	$(FUZZ_CXX) $(FUZZ_FLAGS) -fsanitize=fuzzer -o $@ $@.o $(FUZZ_LIB) $(LIBS)

fuzz-build:
	@./.ci/deps --quiet $(FUZZDEBS)
	@$(MAKE) --no-print-directory $(FUZZ_BIN)

fuzz: fuzz-build
	./fuzz/run $(FUZZ_S) $(FUZZ_BIN)

clean:
	rm -rf libmesh/*/*.o tools/*.o tools/*.a $(LIB) bin tests/*.test build-san build-check build-fuzz demo-out
