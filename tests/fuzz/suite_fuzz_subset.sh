#!/bin/bash
# suite_fuzz_subset.sh — a reduced, deterministic subset of the config fuzzer
# (tests/fuzz/config_fuzz.py) in `make test` / `make asan`: the configs behind
# the sweep's findings plus baselines, run through the real `tanksim run`
# (the build under test: TANKSIM_BUILD). Each must end OK or with an error
# naming a config field (class ERROR): never CRASH, HANG, NAN or an error
# without a pointer (NOPTR). A few seconds; the full sweep stays outside
# make test (thousands of runs).
set -u
cd "$(dirname "$0")/../.."
BIN=${TANKSIM_BUILD:-build}/tanksim
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
MATCH='__(baseline|layout_collapsed|road_wheel_same_x|max_step_min|terrain_profile_dev_zero|terrain_profile_dir|section_not_object|track_transverse_16x0|torque_0\.0|grade_0\.6_torque0|duration_0\.001|sample_rate_20000\.0_dur_min)$'
/usr/bin/python3 tests/fuzz/config_fuzz.py --bin "$BIN" --out "$OUT" --tier 1 --jobs 2 --timeout 60 \
  --preset pointmass-prescribed bump-prescribed-static --match "$MATCH" >"$OUT/log" 2>&1
/usr/bin/python3 - "$OUT/results.jsonl" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
p = f = 0
for r in sorted(rows, key=lambda r: r["id"]):
    good = r["class"] in ("OK", "ERROR")
    p += good
    f += not good
    tail = r["stderr"].strip().splitlines()[-1][:160] if r["stderr"].strip() else ""
    print(("ok   " if good else "FAIL ") + f"{r['id']}: {r['class']} {tail}")
if len(rows) < 20:
    print(f"FAIL expected >= 20 cases, ran {len(rows)}")
    f += 1
print(f"{p} passed, {f} failed")
sys.exit(1 if f else 0)
PY
