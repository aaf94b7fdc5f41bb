# tanksim — build, run and test. The two commands a user needs are `make run`
# and `make test`; both install missing Debian packages first (`make deps`).
#
# Layers (enforced by tests/check_layers.sh):
#   sim/     libtanksim.a — the simulation library (libc, libm, SUNDIALS, LAPACKE, FFTW)
#   render/  offscreen OpenGL (OSMesa) + PNG; reads sim geometry, no HTTP/JSON
#   api/     JSON <-> model (jansson), problem documents, the embedded default store
#   cli/     build/tanksim, the command-line runner
#   server/  build/tanksimd, the HTTP daemon (libmicrohttpd)

SHELL := /bin/bash
BUILD ?= build
CC ?= cc
OPT ?= -O2
SAN ?=
CFLAGS := -std=c11 -Wall -Wextra -Werror $(OPT) -g -D_POSIX_C_SOURCE=200809L -MMD -MP $(SAN)
LDFLAGS := $(SAN)

# Debian packages the build, the tests and `make run` need.
DEB_PACKAGES := build-essential pkg-config libmicrohttpd-dev libjansson-dev libosmesa6-dev \
  libsundials-dev libpng-dev zlib1g-dev liblapacke-dev liblapack-dev libblas-dev libfftw3-dev \
  libsqlite3-dev libcmocka-dev cppcheck python3 python3-pytest python3-requests python3-yaml \
  curl nodejs chromium

LIBS_SIM := -lsundials_cvode -lsundials_kinsol -lsundials_nvecserial \
  -lsundials_sunlinsoldense -lsundials_sunmatrixdense -llapacke -llapack -lblas -lfftw3 -lm
LIBS_API := -ljansson
LIBS_RENDER := -lOSMesa -lpng -lz
LIBS_SERVER := -lmicrohttpd -lsqlite3 -lpthread
LIBS_ALL := $(LIBS_SERVER) $(LIBS_API) $(LIBS_RENDER) $(LIBS_SIM)

SIM_SRC := $(sort $(wildcard sim/*.c))
RENDER_SRC := $(sort $(wildcard render/*.c))
API_SRC := $(sort $(wildcard api/*.c))
CLI_SRC := $(sort $(wildcard cli/*.c))
SERVER_SRC := $(sort $(wildcard server/*.c))
TEST_SRC := $(sort $(wildcard tests/*/test_*.c))
BENCH_SRC := $(sort $(wildcard tests/bench/bench_*.c))
STORE_FILES := $(sort $(shell find sim/data -type f 2>/dev/null)) $(wildcard api/openapi.yaml)

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))
SIM_OBJ := $(call obj,$(SIM_SRC))
RENDER_OBJ := $(call obj,$(RENDER_SRC))
API_OBJ := $(call obj,$(API_SRC)) $(BUILD)/obj/gen/embedded_store.o
CLI_OBJ := $(call obj,$(CLI_SRC))
SERVER_OBJ := $(call obj,$(SERVER_SRC))
TEST_BIN := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRC))
BENCH_BIN := $(patsubst tests/bench/%.c,$(BUILD)/bench/%,$(BENCH_SRC))

LIB_SIM := $(BUILD)/libtanksim.a
LIB_RENDER := $(BUILD)/libtanksim_render.a
LIB_API := $(BUILD)/libtanksim_api.a
LIBS_OWN := $(LIB_API) $(LIB_RENDER) $(LIB_SIM)

.PHONY: all deps web run install test asan tsan bench format lint check-layers clean
.DEFAULT_GOAL := all

all: $(BUILD)/tanksimd $(BUILD)/tanksim $(LIB_SIM) web | deps

# Debian's nodejs 18 ships npm as a separate package; NodeSource's nodejs
# includes it. Install Debian's npm only when no npm is on PATH.
deps:
	@./deploy/install-deps.sh $(DEB_PACKAGES)
	@command -v npm >/dev/null 2>&1 || ./deploy/install-deps.sh npm

# `make web`: the browser dashboard. Sources and the npm lock file live in
# web/; `npm ci` fetches uPlot, fetch-event-source, esbuild and playwright-core
# (for tests/web) into web/node_modules; esbuild bundles into web_static/
# (app.js, app.css, index.html — gitignored), which tanksimd serves at /.
# Both steps are file targets, so an up-to-date tree costs nothing.
WEB_SRC := $(sort $(wildcard web/src/*)) web/build.mjs
WEB_STAMP := web/node_modules/.package-lock.json
web: web_static/app.js

$(WEB_STAMP): web/package.json web/package-lock.json | deps
	@echo "  NPM     web/ (npm ci)"
	@cd web && npm ci --no-audit --no-fund --loglevel=error
	@touch $@

web_static/app.js: $(WEB_SRC) $(WEB_STAMP)
	@cd web && node build.mjs

$(BUILD)/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	@echo "  CC      $<"
	@$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/gen/embedded_store.c: $(STORE_FILES) api/embed.sh
	@mkdir -p $(dir $@)
	@echo "  EMBED   $@"
	@./api/embed.sh $@ $(STORE_FILES)

$(BUILD)/obj/gen/embedded_store.o: $(BUILD)/gen/embedded_store.c
	@mkdir -p $(dir $@)
	@$(CC) $(CFLAGS) -Iapi -c $< -o $@

$(LIB_SIM): $(SIM_OBJ)
	@rm -f $@
	@echo "  AR      $@"
	@ar rcs $@ $^
$(LIB_RENDER): $(RENDER_OBJ)
	@rm -f $@
	@echo "  AR      $@"
	@ar rcs $@ $^
$(LIB_API): $(API_OBJ)
	@rm -f $@
	@echo "  AR      $@"
	@ar rcs $@ $^

$(BUILD)/tanksimd: $(SERVER_OBJ) $(LIBS_OWN)
	@echo "  LD      $@"
	@$(CC) $(LDFLAGS) -o $@ $(SERVER_OBJ) $(LIBS_OWN) $(LIBS_ALL)
$(BUILD)/tanksim: $(CLI_OBJ) $(LIBS_OWN)
	@echo "  LD      $@"
	@$(CC) $(LDFLAGS) -o $@ $(CLI_OBJ) $(LIBS_OWN) $(LIBS_ALL)

# Each tests/MODULE/test_NAME.c is one cmocka program linked with every layer.
$(BUILD)/tests/%: tests/%.c $(LIBS_OWN) tests/test_util.h | deps
	@mkdir -p $(dir $@)
	@echo "  TEST    $@"
	@$(CC) $(CFLAGS) -I. -Itests -o $@ $< $(LIBS_OWN) $(LIBS_ALL) -lcmocka

$(BUILD)/bench/%: tests/bench/%.c $(LIBS_OWN) | deps
	@mkdir -p $(dir $@)
	@echo "  BENCH   $@"
	@$(CC) $(CFLAGS) -I. -Itests -o $@ $< $(LIBS_OWN) $(LIBS_ALL)

# `make run [RUN_PORT=8080]`: the daemon in the foreground on 127.0.0.1, data under ./var.
RUN_PORT ?= 8080
run: all
	./$(BUILD)/tanksimd --bind 127.0.0.1 --port $(RUN_PORT) --data-dir ./var

# `make install [PREFIX=/usr/local] [DESTDIR=] [UNITDIR=/etc/systemd/system]`: the two
# programs, the dashboard (with its source maps) and the systemd unit
# (deploy/tanksimd.service, its paths rewritten for PREFIX; skipped with a message
# when UNITDIR cannot be written, e.g. a user's own PREFIX). The unit runs as a
# transient user (DynamicUser) with its store in /var/lib/tanksim (StateDirectory):
# no account to create. Then: systemctl daemon-reload && systemctl enable --now tanksimd.
PREFIX ?= /usr/local
UNITDIR ?= /etc/systemd/system
install: all
	install -D -m 755 $(BUILD)/tanksimd $(DESTDIR)$(PREFIX)/bin/tanksimd
	install -D -m 755 $(BUILD)/tanksim $(DESTDIR)$(PREFIX)/bin/tanksim
	install -d $(DESTDIR)$(PREFIX)/share/tanksim/web_static
	install -m 644 web_static/index.html web_static/app.js web_static/app.css \
	  web_static/app.js.map web_static/app.css.map $(DESTDIR)$(PREFIX)/share/tanksim/web_static/
	@d='$(DESTDIR)$(UNITDIR)'; \
	if mkdir -p "$$d" 2>/dev/null && [ -w "$$d" ]; then \
	  sed 's|/usr/local/|$(PREFIX)/|g' deploy/tanksimd.service > "$$d/tanksimd.service" && \
	  echo "installed $$d/tanksimd.service"; \
	else \
	  echo "make install: $$d is not writable: systemd unit not installed (set UNITDIR=DIR)"; \
	fi

# `make test [T=module]`: every suite (C unit tests per module, layer check,
# end-to-end tests against a real daemon); ends with "N passed, N failed".
test: all $(TEST_BIN)
	@./tests/run_all.sh $(BUILD) "$(T)"

asan:
	$(MAKE) BUILD=build-asan OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" test

# `make tsan`: every suite under ThreadSanitizer (`make tsan T=server/` for
# some). The concurrency ones are tests/sim/test_threads (runs of every kind
# on threads over shared models), tests/server/* (worker pool, streams,
# cancel, persistence; test_stress.py mixes them) and tests/fuzz/suite_http_fuzz
# (races on one session, requests during SIGTERM); the rest are single-threaded
# but cheap enough (~6 min for all on 2 cores). halt_on_error stops a racing
# process at its first report; reports also go to build-tsan/tsan-report.PID
# (daemons and CLI runs started by the tests included), and any such file fails
# the target. tests/tsan.supp: third-party false positives only.
TSAN_OPTS := halt_on_error=1 second_deadlock_stack=1 suppressions=$(CURDIR)/tests/tsan.supp \
  log_path=$(CURDIR)/build-tsan/tsan-report
tsan:
	@rm -f build-tsan/tsan-report.*
	@TSAN_OPTIONS="$(TSAN_OPTS)" $(MAKE) BUILD=build-tsan OPT=-O1 \
	  SAN="-fsanitize=thread -fno-omit-frame-pointer" test; rc=$$?; \
	  for r in build-tsan/tsan-report.*; do [ -e "$$r" ] || continue; rc=1; \
	    echo "== ThreadSanitizer report $$r"; cat "$$r"; done; \
	  exit $$rc

bench: all $(BENCH_BIN)
	@set -e; for b in $(BENCH_BIN); do echo "== $$b"; $$b; done; \
	  [ -n "$(BENCH_BIN)" ] || echo "no benchmarks yet"

check-layers:
	@./tests/check_layers.sh

C_FILES = $(shell git ls-files '*.c' '*.h' 2>/dev/null || find sim api cli server render tests -name '*.[ch]')
format: | deps
	@./deploy/install-deps.sh clang-format
	clang-format -i $(C_FILES)
lint: | deps
	cppcheck --quiet --error-exitcode=1 --std=c11 --enable=warning,portability,performance \
	  --suppress=missingIncludeSystem --inline-suppr -D__GNUC__ \
	  --library=tests/lint/jansson.cfg sim api cli server render

clean:
	rm -rf build build-asan build-tsan web_static/app.* web_static/index.html

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
