#!/usr/bin/python3
"""config_fuzz.py — adversarial run-config generator and runner for `tanksim run`.

Why: every field of a run config has a row in the parameter table (sim/cfg_*.c:
JSON pointer, type, unit, min, max); the project rule is that any config the
table accepts either runs (finite series and summary) or is refused with a
clear error naming the field, and that nothing crashes, hangs or silently
produces NaN. This script reads the schema (`tanksim schema`, generated from
the table), derives for every shipped preset configs that push each field to
its limits (min, max, just inside, 0, tiny/huge within range; arrays with
0/1/max/max+1 entries and non-monotone values; every enum value; empty/long
strings; wrong JSON types) plus combinations known to stress the physics
(track fidelity x n_long/n_trans maxima, rtol limits, zero inertias, zero and
negative torque, grade limits, tiny durations, sample-rate limits), runs each
with a capped run.duration under `timeout`, and classifies the result:

  OK      exit 0, series.csv and summary.json finite
  ERROR   non-zero exit, stderr names a JSON pointer of the config (/section/field)
  NOPTR   non-zero exit, no pointer in the message (unclear error)
  CRASH   killed by a signal, or an ASan/UBSan report on stderr
  HANG    killed by the timeout
  NAN     exit 0 but NaN/Inf in series.csv or summary.json

Not part of `make test` (thousands of runs). Usage:
  tests/fuzz/config_fuzz.py --bin build-asan/tanksim --out /tmp/fuzz [--tier 1|2|3]
      [--jobs 2] [--timeout 60] [--preset NAME ...] [--field /sec/name ...] [--list]
Writes OUT/results.jsonl (one line per case) and keeps OUT/cases/<id>/ (config,
stderr, outputs) only for cases that are not OK/ERROR. Prints counts per class.
"""
import argparse
import concurrent.futures as cf
import json
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PRESET_DIR = os.path.join(ROOT, "sim", "data", "presets")

# Duration cap per run (s): the long presets are cut to this; engine_dyno presets are
# already short (0.1 s) and cost ~1 s under ASan.
DURATION_CAP = 0.6


def load_schema(binary):
    out = subprocess.run([binary, "schema"], capture_output=True, text=True, check=True).stdout
    schema = json.loads(out)
    fields = []
    for sec, sv in schema["properties"].items():
        if "properties" not in sv:
            continue
        for name, f in sv["properties"].items():
            fields.append((sec, name, f))
    return fields


def resolve_chain(name):
    """Preset document merged over its parent chain (sections shallow-merged)."""
    doc = json.load(open(os.path.join(PRESET_DIR, name + ".json")))
    parent = doc.get("preset")
    merged = resolve_chain(parent) if parent else {}
    for k, v in doc.items():
        if isinstance(v, dict):
            merged.setdefault(k, {}).update(v)
        elif k != "preset":
            merged[k] = v
    return merged


def inside(lo, hi, frac):
    return lo + (hi - lo) * frac


def number_values(f, is_int):
    off = "anyOf" in f  # 0 (off) or a number in [minimum, maximum]
    rng = f["anyOf"][1] if off else f
    lo, hi = rng["minimum"], rng["maximum"]
    vals = [("min", lo), ("max", hi)] + ([("off", 0.0), ("tiny", 1e-300)] if off else [])
    if is_int:
        if hi - lo >= 2:
            vals += [("min+1", lo + 1), ("max-1", hi - 1)]
        vals += [("below_min", lo - 1), ("above_max", hi + 1)]
        if lo < 0 < hi:
            vals.append(("zero", 0))
        return [(k, int(v)) for k, v in vals]
    span = hi - lo
    vals += [("just_above_min", lo + span * 1e-9 if lo == 0 else lo * (1 + 1e-9) if lo > 0 else lo + span * 1e-9),
             ("just_below_max", hi - span * 1e-9)]
    if lo < 0 < hi or lo == 0:
        if lo < 0 < hi:
            vals.append(("zero", 0.0))
        vals.append(("tiny", 1e-300 if hi > 1e-300 else hi))
    if lo > 0:
        vals.append(("tiny_in_range", lo * 1.0000001))
    below = 0.5 * lo if off else lo - max(abs(lo), 1) * 1e-6  # (0 itself is valid when off)
    vals += [("below_min", below), ("above_max", hi + max(abs(hi), 1) * 1e-6)]
    return vals


def array_values(f, default):
    lo, hi = f["items"]["minimum"], f["items"]["maximum"]
    cap = f["maxItems"]
    base = default if isinstance(default, list) and default else [inside(lo, hi, 0.5)]
    mid = base[len(base) // 2]
    vals = [("empty", []), ("one", [base[0]]), ("cap_lo", [lo] * cap),
            ("cap_ramp", [inside(lo, hi, i / max(cap - 1, 1)) for i in range(cap)]),
            ("over_cap", [mid] * (cap + 1)), ("reversed", list(reversed(base))),
            ("all_min", [lo] * len(base)), ("all_max", [hi] * len(base)),
            ("dup", [base[0]] * len(base)),
            ("zigzag", [lo if i % 2 else hi for i in range(len(base))] if len(base) > 1 else [hi]),
            ("elem_out_of_range", [hi + max(abs(hi), 1)] + base[1:])]
    return vals


def field_cases(sec, name, f, default):
    t = f.get("type")
    if t == "number":
        return number_values(f, False) + [("type_string", "1"), ("type_null", None),
                                          ("type_bool", True), ("huge_literal", 1e308)]
    if t == "integer":
        return number_values(f, True) + [("type_float", 1.5), ("type_string", "1")]
    if t == "boolean":
        return [("true", True), ("false", False), ("type_int", 2)]
    if t == "string" and "enum" in f:
        return [("enum_" + e, e) for e in f["enum"]] + [("enum_bad", "no_such_value"), ("enum_empty", "")]
    if t == "string":
        n = f.get("maxLength", 255)
        return [("empty", ""), ("long_max", "a" * n), ("too_long", "a" * (n + 1)),
                ("dotdot", "../../../../etc/passwd"), ("nul_like", "a\u0000b"), ("type_int", 3)]
    if t == "array":
        return array_values(f, default) + [("type_scalar", 1.0), ("elem_string", ["x"])]
    return []


def stress_cases(preset, resolved):
    """Combinations known to stress the physics."""
    kind = resolved.get("run", {}).get("kind", "pointmass")
    out = []
    if kind in ("vehicle", "coupled") or "track" in resolved:
        for fid in ("static", "lumped", "quasi_static", "longitudinal", "transverse", "coupled"):
            for nl, nt in ((16, 16), (0, 0), (16, 0), (0, 16), (1, 1)):
                out.append((f"track_{fid}_{nl}x{nt}", {"track": {"fidelity": fid, "n_long": nl, "n_trans": nt}}))
    for r in (1e-10, 1e-2):
        out.append((f"rtol_{r}", {"run": {"rtol": r}}))
        out.append((f"rtol_{r}_atol_max", {"run": {"rtol": r, "atol": 1e-2}}))
    out.append(("atol_min_rtol_min", {"run": {"rtol": 1e-10, "atol": 1e-14}}))
    out.append(("zero_inertias_track", {"track": {"idler_inertia": 0, "roller_inertia": 0, "sprocket_inertia": 0}}))
    out.append(("zero_inertias_driveline", {"driveline": {"pump_inertia": 0, "output_inertia": 0}}))
    out.append(("zero_inertias_coupling", {"coupling": {"interface_inertia": 0}}))
    for tq in (0.0, -6000.0, -200000.0, 200000.0):
        out.append((f"torque_{tq}", {"drive": {"kind": "constant", "torque": tq}}))
        out.append((f"torque_ramp_{tq}", {"drive": {"kind": "ramp", "torque": tq, "ramp_time": 0.0}}))
    for g in (-0.6, 0.6):
        out.append((f"grade_{g}", {"vehicle": {"grade": g}}))
        out.append((f"grade_{g}_torque0", {"vehicle": {"grade": g}, "drive": {"kind": "constant", "torque": 0}}))
    for d in (0.001, 0.0011, 0.002):
        out.append((f"duration_{d}", {"run": {"duration": d}}))
    for sr in (1.0, 20000.0):
        out.append((f"sample_rate_{sr}", {"run": {"sample_rate": sr}}))
        out.append((f"sample_rate_{sr}_dur_min", {"run": {"sample_rate": sr, "duration": 0.001}}))
    out.append(("max_step_min", {"run": {"max_step": 1e-300}}))
    out.append(("max_step_max", {"run": {"max_step": 1.0}}))
    out.append(("table_one_point", {"drive": {"kind": "table", "table_t": [0.0], "table_torque": [1000.0]}}))
    out.append(("table_empty", {"drive": {"kind": "table", "table_t": [], "table_torque": []}}))
    out.append(("table_mismatch", {"drive": {"kind": "table", "table_t": [0, 1, 2], "table_torque": [1, 2]}}))
    out.append(("table_nonmono", {"drive": {"kind": "table", "table_t": [0, 2, 1], "table_torque": [1, 2, 3]}}))
    out.append(("table_dup_t", {"drive": {"kind": "table", "table_t": [0, 0, 0], "table_torque": [1, 2, 3]}}))
    out.append(("bumps_mismatch", {"terrain": {"kind": "bumps", "bump_start": [1, 2], "bump_height": [0.1], "bump_length": [1, 1, 1]}}))
    out.append(("bumps_overlap", {"terrain": {"kind": "bumps", "bump_start": [0, 0], "bump_height": [2, -2], "bump_length": [0.01, 0.01]}}))
    out.append(("bumps_under_vehicle", {"terrain": {"kind": "bumps", "bump_start": [0.0], "bump_height": [2.0], "bump_length": [0.01]}}))
    out.append(("terrain_profile_missing", {"terrain": {"kind": "profile", "profile_csv": "no_such.csv"}}))
    out.append(("terrain_course_missing", {"terrain": {"kind": "profile", "course": "no_such_course"}}))
    out.append(("terrain_course_dir_etc", {"terrain": {"kind": "profile", "course_dir": "/etc", "course": "passwd"}}))
    out.append(("terrain_profile_dev_zero", {"terrain": {"kind": "profile", "profile_csv": "/dev/zero"}}))
    out.append(("terrain_profile_dir", {"terrain": {"kind": "profile", "profile_csv": "/tmp"}}))
    out.append(("mass_min_inertia_min", {"vehicle": {"mass": 1000, "hull_pitch_inertia": 1000}}))
    out.append(("road_wheel_one", {"vehicle": {"road_wheel_x": [2.0]}}))
    out.append(("road_wheel_same_x", {"vehicle": {"road_wheel_x": [2.0] * 7}}))
    out.append(("road_wheel_outside", {"vehicle": {"road_wheel_x": [12.0, -2.0]}}))
    out.append(("layout_collapsed", {"vehicle": {"sprocket_x": 0, "rear_roller_x": 0, "front_roller_x": 0, "idler_x": 0}}))
    out.append(("layout_reversed", {"vehicle": {"sprocket_x": 6, "idler_x": 0}}))
    out.append(("stations_out", {"vehicle": {"damper_station": [10], "bump_stop_station": [10], "anchor_station": 10}}))
    out.append(("gear_one", {"driveline": {"gear_ratio": [3.0], "gear_efficiency": [0.9]}}))
    out.append(("gear_mismatch", {"driveline": {"gear_ratio": [3.0, 2.0], "gear_efficiency": [0.9]}}))
    out.append(("tc_one", {"driveline": {"tc_speed_ratio": [0.0], "tc_torque_ratio": [2.0], "tc_k_factor": [2.0]}}))
    out.append(("tc_nonmono", {"driveline": {"tc_speed_ratio": [0.9, 0.0, 0.5], "tc_torque_ratio": [1, 2, 3], "tc_k_factor": [2, 2, 2]}}))
    out.append(("shift_inverted", {"driveline": {"shift_speed": 50, "downshift_speed": 250}}))
    out.append(("governor_inverted", {"control": {"governor_low_idle": 500, "governor_high_idle": 0}}))
    out.append(("ivs_mode", {"control": {"mode": "ivs", "target_speed": 40}}))
    out.append(("ivs_zero_target", {"control": {"mode": "ivs", "target_speed": 0}}))
    out.append(("schedule_mismatch", {"control": {"schedule_x": [1, 2], "schedule_kp": [1], "schedule_ti": [1, 2, 3]}}))
    out.append(("schedule_nonmono", {"control": {"schedule_x": [2, 1, 0], "schedule_kp": [1, 2, 3], "schedule_ti": [1, 2, 3]}}))
    out.append(("valve_timing_equal", {"engine": {"ivo": 1.0, "ivc": 1.0, "evo": 1.0, "evc": 1.0}}))
    out.append(("bore_min_stroke_max", {"engine": {"bore": 0.05, "stroke": 0.3, "rod_length": 0.1}}))
    out.append(("rod_shorter_than_crank", {"engine": {"stroke": 0.3, "rod_length": 0.1}}))
    out.append(("wg_crack_above_full", {"engine": {"wg_crack": 1e6, "wg_full": 1e5}}))
    out.append(("wg_crack_eq_full", {"engine": {"wg_crack": 3e5, "wg_full": 3e5}}))
    for fid in ("crank_angle", "mean_value", "map"):
        for v in ("conventional", "lhr05", "lhr10"):
            out.append((f"engine_{fid}_{v}", {"engine": {"fidelity": fid, "variant": v}}))
    out.append(("spool_mismatch", {"engine": {"spool_speed": [100, 200], "spool_ratio": [0.5], "spool_lag": [1, 1, 1]}}))
    out.append(("map_one_point", {"engine": {"map_speed": [100.0], "map_torque_conventional": [1000.0]}}))
    out.append(("coupling_monolithic", {"coupling": {"method": "monolithic"}}))
    out.append(("coupling_steps_max", {"coupling": {"lead": 0.1, "leader_step": 0.1, "follower_step": 0.1}}))
    out.append(("coupling_steps_min", {"coupling": {"lead": 1e-5, "leader_step": 1e-6, "follower_step": 1e-6}}))
    out.append(("coupling_lead_lt_step", {"coupling": {"lead": 1e-5, "leader_step": 0.1, "follower_step": 0.1}}))
    out.append(("macro_step_max", {"driveline": {"engine_macro_step": 0.01}}))
    out.append(("macro_step_zero", {"driveline": {"engine_macro_step": 0.0}}))
    out.append(("ca_step_max", {"engine": {"ca_step": 0.1}}))
    out.append(("doc_not_object", []))
    out.append(("unknown_section", {"nosuch": {"a": 1}}))
    out.append(("unknown_field", {"run": {"nosuch": 1}}))
    out.append(("section_not_object", {"run": 3}))
    out.append(("preset_missing", {"preset": "no-such-preset"}))
    out.append(("preset_traversal", {"preset": "../defaults/run"}))
    return out


# Tier 2: which sections' fields are swept on which preset, over which base overrides (a
# section a scenario does not read would only repeat its baseline). The crank-angle engine's
# fields are swept on engine-map-conventional (the dynamometer), the map fidelity's tables on
# the point-mass acceleration run with engine.fidelity = map, the mean-value engine and the
# co-simulation on bump-coupled-rack90. TYPE_PRESET gets the out-of-range and wrong-type values
# of every field (refused by the table reader before any model code runs).
TYPE_PRESET = "m1"
TIER2 = [
    ("pointmass-prescribed", {}, {"run", "vehicle", "drive"}),
    ("accel-pointmass-conventional", {"engine": {"fidelity": "map"}},
     {"engine", "driveline", "control", "vehicle", "drive"}),
    ("bump-prescribed-coupled", {}, {"run", "track", "vehicle", "terrain", "drive"}),
    ("bump-prescribed-static", {}, {"track", "vehicle", "terrain"}),
    ("engine-map-conventional", {}, {"run", "engine"}),
    ("bump-coupled-rack90", {}, {"run", "engine", "driveline", "control", "coupling"}),
]


def make_cases(fields, presets, tier, only_fields):
    cases = []
    for p in presets:
        resolved = resolve_chain(p)
        dur = resolved.get("run", {}).get("duration", 20.0)
        cap = {"run": {"duration": min(dur, DURATION_CAP)}}

        def add(label, over):
            if isinstance(over, dict):
                doc = {"preset": p}
                if "preset" in over:
                    doc["preset"] = over["preset"]
                for s, v in cap.items():
                    doc[s] = dict(v)
                for s, v in over.items():
                    if s == "preset":
                        continue
                    if isinstance(v, dict) and isinstance(doc.get(s), dict):
                        doc[s].update(v)
                    else:
                        doc[s] = v
            else:
                doc = over
            cases.append({"id": f"{p}__{label}", "preset": p, "label": label, "doc": doc})

        add("baseline", {})
        if tier >= 1:
            for label, over in stress_cases(p, resolved):
                add(label, over)
        plans = [(b, secs) for (q, b, secs) in TIER2 if q == p] if tier == 2 else [({}, None)]
        if p == TYPE_PRESET and tier == 2:
            plans.append(({}, "invalid"))
        for base, sections in (plans if tier >= 2 else []):
            for sec, name, f in fields:
                ptr = f"/{sec}/{name}"
                if only_fields and ptr not in only_fields:
                    continue
                if isinstance(sections, set) and sec not in sections:
                    continue
                default = resolved.get(sec, {}).get(name, f.get("default"))
                for label, val in field_cases(sec, name, f, default):
                    # out-of-range and wrong-type values are refused by the generic
                    # reader before any model code runs: one preset checks them
                    # (tier 2); in-range values go to every preset that uses the section
                    invalid = label.startswith(("type_", "below_", "above_", "over_cap", "elem_",
                                                "enum_bad", "enum_empty", "too_long", "huge_"))
                    if tier == 2 and invalid != (sections == "invalid"):
                        continue
                    over = json.loads(json.dumps(base))
                    over.setdefault(sec, {})[name] = val
                    tag = "".join(f"{k}.{kk}={vv}," for k, v in base.items() for kk, vv in v.items())
                    add(f"{tag}{sec}.{name}={label}", over)
    return cases


NUM_RE = re.compile(r"(?i)(?<![a-z_])(nan|-?inf(inity)?)(?![a-z_])")
# a config pointer, the root-document error, or a JSON parse error (file:line:col)
PTR_RE = re.compile(r"/(run|track|vehicle|terrain|drive|engine|driveline|control|coupling|preset)\b|"
                    r"config error( at)?: |\.json:\d+:\d+: ")


def classify(rc, stderr, outdir):
    if "AddressSanitizer" in stderr or "runtime error:" in stderr or "LeakSanitizer" in stderr \
            or "UndefinedBehaviorSanitizer" in stderr:
        return "CRASH"
    if rc == 124 or rc == -9:
        return "HANG"
    if rc < 0 or rc > 128:
        return "CRASH"
    if rc != 0:
        return "ERROR" if PTR_RE.search(stderr) else "NOPTR"
    for fn in ("series.csv", "summary.json"):
        path = os.path.join(outdir, fn)
        if not os.path.exists(path):
            return "NOPTR"
        with open(path) as fh:
            text = fh.read()
        if fn == "series.csv":
            body = text.split("\n", 1)[1] if "\n" in text else ""
            if NUM_RE.search(body):
                return "NAN"
        else:
            if NUM_RE.search(re.sub(r'"[^"]*"', '""', text)):
                return "NAN"
    return "OK"


def run_case(binary, case, out, timeout):
    d = os.path.join(out, "cases", re.sub(r"[^A-Za-z0-9_.=+-]", "_", case["id"])[:200])
    os.makedirs(d, exist_ok=True)
    cfg = os.path.join(d, "config.json")
    with open(cfg, "w") as fh:
        json.dump(case["doc"], fh)
    env = dict(os.environ)
    env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
    env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1")
    env["LSAN_OPTIONS"] = "suppressions=" + os.path.join(ROOT, "tests", "lsan.supp") + ":print_suppressions=0"
    t0 = time.time()
    try:
        p = subprocess.run(["timeout", "-s", "KILL", str(timeout), binary, "run", cfg, "--out", os.path.join(d, "out")],
                           capture_output=True, text=True, errors="replace", env=env, cwd=ROOT)
        rc, stderr = p.returncode, p.stderr
        if rc == 137:
            rc = 124
    except Exception as e:  # noqa: BLE001 — report, never stop the sweep
        rc, stderr = -1, repr(e)
    if rc in (126, 127):  # the binary could not be run (being relinked?): not a result
        raise SystemExit(f"cannot run {binary}: {stderr.strip()}")
    cls = classify(rc, stderr, os.path.join(d, "out"))
    res = {"id": case["id"], "preset": case["preset"], "label": case["label"], "class": cls, "rc": rc,
           "wall": round(time.time() - t0, 2), "stderr": stderr[-2000:]}
    if cls in ("OK", "ERROR"):
        shutil.rmtree(d, ignore_errors=True)
    else:
        with open(os.path.join(d, "stderr.txt"), "w") as fh:
            fh.write(stderr)
    return res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build-asan", "tanksim"))
    ap.add_argument("--out", default="/tmp/tanksim-fuzz")
    ap.add_argument("--tier", type=int, default=2)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=60)
    ap.add_argument("--preset", nargs="*")
    ap.add_argument("--field", nargs="*")
    ap.add_argument("--match", help="regex on case id")
    ap.add_argument("--skip-done", action="store_true", help="skip ids already in results.jsonl")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    fields = load_schema(a.bin)
    presets = a.preset or sorted(f[:-5] for f in os.listdir(PRESET_DIR) if f.endswith(".json"))
    cases = make_cases(fields, presets, a.tier, set(a.field or []))
    # the physics combinations of every preset first, then the field sweeps
    # (and the crank-angle engine presets, ~1 s a run under ASan, last)
    cases.sort(key=lambda c: ("=" in c["label"], c["preset"].startswith("engine-map")))
    if a.match:
        cases = [c for c in cases if re.search(a.match, c["id"])]
    os.makedirs(a.out, exist_ok=True)
    resf = os.path.join(a.out, "results.jsonl")
    if a.skip_done and os.path.exists(resf):
        done = {json.loads(l)["id"] for l in open(resf)}
        cases = [c for c in cases if c["id"] not in done]
    if a.list:
        for c in cases:
            print(c["id"], json.dumps(c["doc"]))
        print(len(cases), "cases", file=sys.stderr)
        return 0
    counts = {}
    with open(resf, "a") as rf, cf.ThreadPoolExecutor(max_workers=min(a.jobs, 2)) as ex:
        futs = [ex.submit(run_case, a.bin, c, a.out, a.timeout) for c in cases]
        for fu in cf.as_completed(futs):
            r = fu.result()
            counts[r["class"]] = counts.get(r["class"], 0) + 1
            rf.write(json.dumps(r) + "\n")
            rf.flush()
            if r["class"] not in ("OK", "ERROR"):
                print(f"{r['class']:6s} {r['id']}  rc={r['rc']}  {r['stderr'].strip().splitlines()[-1][:160] if r['stderr'].strip() else ''}",
                      flush=True)
    print(" ".join(f"{k}={v}" for k, v in sorted(counts.items())), f"total={len(cases)}")
    return 1 if any(k in counts for k in ("CRASH", "HANG", "NAN")) else 0


if __name__ == "__main__":
    sys.exit(main())
