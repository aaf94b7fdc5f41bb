#!/usr/bin/env python3
"""Regenerate the engine map tables (/engine/map_*_<variant>) and the part-boost
tables (/engine/pb_*_<variant>, spool_speed, spool_ratio, spool_lag) in
sim/data/defaults/engine.json from the crank-angle model's own runs.

Usage (from the repository root, after `make`):
    tools/engine_maps.py            # runs the sweeps and spool-ups, rewrites the CSVs and the JSON
    tools/engine_maps.py --no-run   # only re-reads sim/data/engine_maps/*.csv

Full-load sweep: `build/tanksim engine-map --preset engine-map-<variant>`
(sim/data/engine_maps/<variant>.csv). Spool-ups: the same command with
--spool (sim/data/engine_maps/<variant>_spool.csv): from the launch's idle
state, crank held at 800..2200 rpm, rack stepped to 1, one row per cycle.

Part-boost factors: at each spool speed the cycles are binned by
ratio = boost / map_boost(speed) (bins of width SPOOL_DR centred on
spool_ratio); each bin's mean of eta_v, eta_i, q_wall and indicated torque is
divided by the full-load sweep's value at that speed (indicated torque =
brake + friction). Empty bins take the nearest filled bin at that speed (the
1000-rpm spool-up stays on the low-boost branch and never fills the high bins).
The bins near ratio 1 average the spool-up's later cycles, when the walls are
still warming: the factors carry the launch's cold-wall heat loss.
spool_lag (map fidelity's boost time constant vs spool_speed): per speed, the
time the boost takes to cover 63.2 % of its way from the idle value to
map_boost; where it never gets there within the run (1000 rpm: the launch stays
on the low-boost branch), the first-order equivalent t_end / -ln(1 - fraction
covered at t_end); median over the three variants.
"""
import csv
import json
import math
import statistics
import subprocess
import sys

VARIANTS = ("conventional", "lhr05", "lhr10")
COLUMNS = {"torque": ("torque", 1), "boost": ("boost", 0), "fuel": ("fuel_flow", 6),
           "eta_v": ("eta_v", 4), "eta_i": ("eta_i", 4), "q_wall": ("q_wall", 4)}
SPOOL_RATIO = [0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0]
SPOOL_DR = 0.125


def read_csv(path):
    rows = list(csv.reader(open(path)))
    head = [h.split(" ")[0] for h in rows[0]]
    return [dict(zip(head, map(float, r))) for r in rows[1:]]


def interp(xs, ys, x):
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            f = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + f * (ys[i] - ys[i - 1])
    return ys[-1]


def part_boost(sweep, spool):
    """pb tables (row-major speed x ratio), spool speeds [rad/s], t63 list."""
    ws = [r["speed"] for r in sweep]
    full = {k: [r[k] for r in sweep] for k in ("boost", "eta_v", "eta_i", "q_wall")}
    full["t_ind"] = [r["torque"] + 0.0 for r in sweep]  # friction added below
    speeds = sorted({r["speed"] for r in spool})
    tables = {"eta_v": [], "eta_i": [], "q_wall": [], "torque": []}
    t63 = []
    for w in speeds:
        cyc = [r for r in spool if r["speed"] == w]
        p_fl = interp(ws, full["boost"], w)
        fric = cyc[0]["friction_torque"]  # friction depends on speed only
        ref = {"eta_v": interp(ws, full["eta_v"], w), "eta_i": interp(ws, full["eta_i"], w),
               "q_wall": interp(ws, full["q_wall"], w),
               "torque": interp(ws, full["t_ind"], w) + fric}
        col = {"eta_v": "eta_v", "eta_i": "eta_i", "q_wall": "q_wall", "torque": "indicated_torque"}
        bins = []
        for rj in SPOOL_RATIO:
            sel = [r for r in cyc if abs(r["boost"] / p_fl - rj) <= SPOOL_DR / 2 or
                   (rj == SPOOL_RATIO[-1] and r["boost"] / p_fl > rj)]
            bins.append({k: statistics.mean(r[c] for r in sel) / ref[k] for k, c in col.items()}
                        if sel else None)
        filled = [j for j, b in enumerate(bins) if b]
        if not filled:
            sys.exit("spool-up at %.1f rad/s fills no ratio bin" % w)
        for j in range(len(bins)):
            if not bins[j]:
                bins[j] = bins[min(filled, key=lambda i: abs(i - j))]
        for k in tables:
            tables[k] += [round(b[k], 4) for b in bins]
        p0 = cyc[0]["boost"]
        goal = p0 + 0.632 * (p_fl - p0)
        hit = [r["time"] for r in cyc if r["boost"] >= goal]
        if hit:
            t63.append(hit[0])
        else:
            frac = (cyc[-1]["boost"] - p0) / (p_fl - p0)
            t63.append(cyc[-1]["time"] / -math.log(1 - frac))
    return tables, [round(w, 3) for w in speeds], t63


def main():
    if "--no-run" not in sys.argv:
        procs = []
        for v in VARIANTS:
            procs.append(subprocess.Popen(["build/tanksim", "engine-map", "--preset", "engine-map-" + v,
                                           "--out", "sim/data/engine_maps/%s.csv" % v]))
            procs.append(subprocess.Popen(["build/tanksim", "engine-map", "--preset", "engine-map-" + v,
                                           "--spool", "sim/data/engine_maps/%s_spool.csv" % v]))
        if any(p.wait() for p in procs):
            sys.exit("engine-map failed")
    path = "sim/data/defaults/engine.json"
    doc = json.load(open(path))  # _sources are kept as they are
    t63 = {}
    for v in VARIANTS:
        rows = list(csv.reader(open("sim/data/engine_maps/%s.csv" % v)))
        head = [h.split(" ")[0] for h in rows[0]]
        speeds = [round(float(r[head.index("speed")]), 3) for r in rows[1:]]
        if speeds != doc["map_speed"]:
            sys.exit("%s: speeds differ from /engine/map_speed" % v)
        for key, (col, nd) in COLUMNS.items():
            vals = [round(float(r[head.index(col)]), nd) for r in rows[1:]]
            doc["map_%s_%s" % (key, v)] = [int(x) if nd == 0 else x for x in vals]
        sweep = read_csv("sim/data/engine_maps/%s.csv" % v)
        spool = read_csv("sim/data/engine_maps/%s_spool.csv" % v)
        tables, sp, t = part_boost(sweep, spool)
        doc["spool_speed"] = sp
        doc["spool_ratio"] = SPOOL_RATIO
        for k, vals in tables.items():
            doc["pb_%s_%s" % (k, v)] = vals
        t63[v] = t
        print("%s: boost 63 %% times %s s" % (v, ", ".join("%.2f" % x for x in t)))
    doc.pop("boost_lag", None)
    doc["spool_lag"] = [round(statistics.median(t63[v][i] for v in VARIANTS), 3)
                        for i in range(len(doc["spool_speed"]))]
    print("spool_lag %s s" % doc["spool_lag"])
    json.dump(doc, open(path, "w"), indent=1)
    open(path, "a").write("\n")


if __name__ == "__main__":
    main()
