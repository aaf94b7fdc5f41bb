#!/bin/bash
# suite_http_fuzz.sh — a short deterministic subset of the HTTP fuzzer
# (tests/fuzz/http_fuzz.py --subset, seed 1) in `make test` / `make asan`,
# against the daemon under test (TANKSIM_BUILD/tanksimd): wrong methods,
# odd paths, every fifth bad query value per parameter, bad bodies and
# framing, idle and trickled connections, abandoned requests and streams,
# races on one session, requests during SIGTERM, then a restart on the same
# store. Every check must pass the oracle described in tests/fuzz/README.md;
# the summary counts one test per request class (~1,140 checks in 14 classes).
# About 15 s under ASan; the full pass stays outside make test.
set -u
cd "$(dirname "$0")/../.."
BIN=${TANKSIM_BUILD:-build}/tanksimd
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
timeout 120 /usr/bin/python3 tests/fuzz/http_fuzz.py --bin "$BIN" --seed 1 --subset --per-class --out "$OUT" \
  >"$OUT/log" 2>&1
rc=$?
grep -v '^  ' "$OUT/log" | grep -v '^[0-9]* passed' | tail -n 40
last=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$OUT/log" | tail -n 1)
if [ -z "$last" ]; then
  echo "FAIL http_fuzz.py ended without a summary (exit status $rc)"; tail -n 20 "$OUT/log"
  echo "0 passed, 1 failed"
  exit 1
fi
if [ "$rc" -ne 0 ] && [[ "$last" == *" 0 failed" ]]; then
  echo "FAIL http_fuzz.py exit status $rc"; echo "${last%%,*}, 1 failed"; exit 1
fi
echo "$last"
[ "$rc" -eq 0 ]
