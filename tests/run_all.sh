#!/bin/bash
# run_all.sh BUILD [FILTER] — run every test suite and print one summary line.
#
# Suites: the layer check; cppcheck (make lint); every cmocka program BUILD/tests/MODULE/test_*;
# every pytest file tests/MODULE/test_*.py (run by Debian's /usr/bin/python3);
# every script tests/MODULE/suite_*.sh, whose last line is "N passed, N failed".
# FILTER (make test T=...) keeps suites whose path contains it.
# Output: one line per suite (the whole log of a failing suite), then
# "N passed, N failed" summed over all suites. Exit status 1 on any failure.
set -u
BUILD=${1:-build}
FILTER=${2:-}
export TANKSIM_BUILD=$(cd "$BUILD" && pwd)
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
OUT=tests/out
mkdir -p "$OUT"
total_pass=0
total_fail=0

report() { # name pass fail logfile
  local name=$1 p=$2 f=$3 log=$4
  total_pass=$((total_pass + p)); total_fail=$((total_fail + f))
  if [ "$f" -gt 0 ]; then
    echo "FAIL $name: $p passed, $f failed"; sed 's/^/    /' "$log" | tail -n 80
  else
    echo "ok   $name: $p passed"
  fi
}

want() { [ -z "$FILTER" ] || [[ "$1" == *"$FILTER"* ]]; }

# 1. layer boundaries
if want check_layers; then
  log=$OUT/check_layers.log
  if ./tests/check_layers.sh >"$log" 2>&1; then report check_layers 1 0 "$log"
  else report check_layers 0 1 "$log"; fi
fi

# 1b. static analysis (cppcheck, `make lint`)
if want lint; then
  log=$OUT/lint.log
  if make --no-print-directory lint >"$log" 2>&1; then report lint 1 0 "$log"
  else report lint 0 1 "$log"; fi
fi

# 2. C unit tests (cmocka)
for t in $(find "$BUILD/tests" -type f -name 'test_*' -perm -u+x 2>/dev/null | sort); do
  name=${t#"$BUILD"/tests/}
  want "$name" || continue
  log=$OUT/$(echo "$name" | tr / _).log
  CMOCKA_MESSAGE_OUTPUT=stdout timeout 600 "$t" >"$log" 2>&1
  rc=$?
  p=$(grep -E '^\[  PASSED  \] [0-9]+ test' "$log" | awk '{s+=$4} END {print s+0}')
  f=$(grep -E '^\[  FAILED  \] [0-9]+ test' "$log" | awk '{s+=$4} END {print s+0}')
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "(exit status $rc)" >>"$log"; fi
  report "$name" "$p" "$f" "$log"
done

# 3. end-to-end tests (pytest)
for py in $(find tests -name 'test_*.py' 2>/dev/null | sort); do
  want "$py" || continue
  log=$OUT/$(echo "${py#tests/}" | tr / _).log
  timeout 900 /usr/bin/python3 -m pytest -q -p no:cacheprovider -c tests/pytest.ini --rootdir=tests "$py" >"$log" 2>&1
  rc=$?
  line=$(grep -E '[0-9]+ (passed|failed|error)' "$log" | tail -n 1)
  p=$(echo "$line" | grep -oE '[0-9]+ passed' | grep -oE '[0-9]+' || echo 0)
  f=$(echo "$line" | grep -oE '[0-9]+ failed' | grep -oE '[0-9]+' || echo 0)
  e=$(echo "$line" | grep -oE '[0-9]+ errors?' | grep -oE '[0-9]+' || echo 0)
  p=${p:-0}; f=$(( ${f:-0} + ${e:-0} ))
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  report "${py#tests/}" "$p" "$f" "$log"
done

# 4. script suites (browser tests and others)
for s in $(find tests -name 'suite_*.sh' 2>/dev/null | sort); do
  want "$s" || continue
  log=$OUT/$(echo "${s#tests/}" | tr / _).log
  timeout 900 bash "$s" >"$log" 2>&1
  rc=$?
  line=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$log" | tail -n 1)
  p=$(echo "$line" | awk '{print $1+0}'); f=$(echo "$line" | awk '{print $3+0}')
  p=${p:-0}; f=${f:-0}
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  report "${s#tests/}" "$p" "$f" "$log"
done

echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ] && [ "$total_pass" -gt 0 ]
