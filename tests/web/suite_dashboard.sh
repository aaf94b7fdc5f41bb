#!/bin/bash
# suite_dashboard.sh — the browser test of the dashboard (tests/web/dashboard.test.mjs):
# headless Debian chromium driven by playwright-core from web/node_modules
# (installed by `make web`), against real tanksimd daemons from $TANKSIM_BUILD.
# Screenshots: tests/out/web/*.png. Last line: "N passed, N failed".
set -u
cd "$(dirname "$0")/../.."
if [ ! -d web/node_modules/playwright-core ] || [ ! -f web_static/app.js ]; then
  echo "dashboard not built (web/node_modules or web_static/app.js missing): run make web"
  echo "0 passed, 1 failed"
  exit 1
fi
if [ ! -x /usr/bin/chromium ] && [ -z "${CHROMIUM:-}" ]; then
  echo "no /usr/bin/chromium (Debian package chromium, installed by make deps)"
  echo "0 passed, 1 failed"
  exit 1
fi
exec timeout 300 node tests/web/dashboard.test.mjs
