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
brake + friction). Empty bins below the highest one filled take the nearest
filled bin at that speed; empty bins above it (the 1000-rpm spool-up stays on
the low-boost branch and never fills the high bins) go straight from the
highest filled bin to factor 1 at ratio 1, the full-load sweep's point (until
session 20 they held the low branch's value, so the map engine at 1000 rpm
and full boost reported 2.89 bar with 2755 N*m where the sweep had 6032; 6029 today).
The bins near ratio 1 average the spool-up's later cycles, when the walls are
still warming: the factors carry the launch's cold-wall heat loss.
spool_lag (map fidelity's boost time constant vs spool_speed): per speed, the
time the boost takes to cover 63.2 % of its way from the idle value to
map_boost; where it never gets there within the run (1000 rpm: the launch stays
on the low-boost branch), the first-order equivalent t_end / -ln(1 - fraction
covered at t_end); median over the three variants.
Turbo-match diagnosis (no runs, nothing written):
    tools/engine_maps.py --match [VARIANT] [key=value ...]
prints, per bank, turbine power (x mech. efficiency) against compressor power
as functions of boost at 1000, 1300, 1600 and 2100 rpm with the turbo held at
the speed the compressor needs: a quasi-steady mean-flow mirror of
sim/engine_turbo.c (synthetic maps, orifice turbine, wastegate actuator
without its end rounding) and sim/engine_manifold.c (intercooler orifice and
effectiveness), the engine taken from the crank-angle sweep of the variant
(eta_v = map_eta_v, exhaust minus intake manifold temperature from
sim/data/engine_maps/VARIANT.csv, phi from Eq. 13). key=value overrides
/engine/<key> (e.g. wg_area=0 turb_area_ref=0.00152). The equilibrium boosts it
finds match the crank-angle lug-down within 0.1 bar from 1000 to 2100 rpm
with the default maps (0.3 bar high at 2100 rpm with wg_area=0
turb_area_ref=0.00152); pulse energy and the cycle's flow variations are left out.
"""
import csv
import json
import math
import os
import statistics
import subprocess
import sys

VARIANTS = ("conventional", "lhr05", "lhr10")
COLUMNS = {"torque": ("torque", 1), "boost": ("boost", 0), "fuel": ("fuel_flow", 6),
           "eta_v": ("eta_v", 4), "eta_i": ("eta_i", 4), "q_wall": ("q_wall", 4)}
SPOOL_RATIO = [0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0]
SPOOL_DR = 0.125
# part-boost table key -> spool CSV column
SPOOL_COLUMNS = {"eta_v": "eta_v", "eta_i": "eta_i", "q_wall": "q_wall",
                 "torque": "indicated_torque"}


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
    speeds = sorted({r["speed"] for r in spool})
    tables = {"eta_v": [], "eta_i": [], "q_wall": [], "torque": []}
    t63 = []
    for w in speeds:
        cyc = [r for r in spool if r["speed"] == w]
        p_fl = interp(ws, full["boost"], w)
        fric = cyc[0]["friction_torque"]  # friction depends on speed only
        ref = {"eta_v": interp(ws, full["eta_v"], w), "eta_i": interp(ws, full["eta_i"], w),
               "q_wall": interp(ws, full["q_wall"], w),
               "torque": interp(ws, [r["torque"] for r in sweep], w) + fric}  # indicated
        bins = []
        for rj in SPOOL_RATIO:
            sel = [r for r in cyc if abs(r["boost"] / p_fl - rj) <= SPOOL_DR / 2 or
                   (rj == SPOOL_RATIO[-1] and r["boost"] / p_fl > rj)]
            bins.append({k: statistics.mean(r[c] for r in sel) / ref[k]
                         for k, c in SPOOL_COLUMNS.items()} if sel else None)
        filled = [j for j, b in enumerate(bins) if b]
        if not filled:
            sys.exit("spool-up at %.1f rad/s fills no ratio bin" % w)
        top = max(filled)
        for j in range(len(bins)):
            if bins[j]:
                continue
            if j > top:
                # above the highest ratio the spool-up reached (1000 rpm stays on
                # the low-boost branch): straight on to the full-load point, factor
                # 1 at ratio 1, as the torque follows the air (constant phi, Eq. 14)
                f = (SPOOL_RATIO[j] - SPOOL_RATIO[top]) / (1.0 - SPOOL_RATIO[top])
                bins[j] = {k: bins[top][k] + f * (1.0 - bins[top][k]) for k in bins[top]}
            else:
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


def match_table(argv):
    """--match: turbine vs compressor power of one bank against boost (see the header)."""
    args = [a for a in argv if a != "--match"]
    variant = next((a for a in args if "=" not in a), "conventional")
    c = json.load(open("sim/data/defaults/engine.json"))
    for a in args:
        if "=" in a:
            k, v = a.split("=", 1)
            c[k] = float(v)
    dl = json.load(open("sim/data/defaults/driveline.json"))
    pa, ta = dl["ambient_pressure"], dl["ambient_temperature"]
    sweep = read_csv("sim/data/engine_maps/%s.csv" % variant)
    g, r_air, cp = 1.4, c["r_air"], 1005.0  # the compressor map's constants (constants.h)
    s = c["turbo_flow_scale"]
    d_c, d_t = c["comp_diameter_ref"] * math.sqrt(s), c["turb_diameter_ref"] * math.sqrt(s)
    a_t = c["turb_area_ref"] * s
    vd_bank = 6 * math.pi / 4 * c["bore"] ** 2 * c["stroke"]

    def psi(pr, gg):  # engine_manifold.c flow function, choked below the critical ratio
        pr = max(pr, (2 / (gg + 1)) ** (gg / (gg - 1)))
        return math.sqrt(max(2 * gg / (gg - 1) * (pr ** (2 / gg) - pr ** ((gg + 1) / gg)), 0))

    def orifice(cda, pu, tu, pd, gg, rr):
        if cda <= 0:
            return 0.0
        base = cda * pu / math.sqrt(rr * tu)
        pr = pd / pu
        return base * psi(0.99, gg) * (1 - pr) / 0.01 if pr > 0.99 else base * psi(pr, gg)

    def upstream(cda, m, t, pd, gg, rr):  # pressure that passes m through cda into pd
        lo, hi = pd, 50 * pd
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if orifice(cda, mid, t, pd, gg, rr) < m else (lo, mid)
        return 0.5 * (lo + hi)

    def compressor(m, pr):  # engine_turbo.c en_compressor, inverted for the tip speed
        dh = cp * ta * (pr ** ((g - 1) / g) - 1)
        rho = pa / (r_air * ta)
        u = math.sqrt((m / (rho * d_c ** 2 * c["comp_phi_choke"])) ** 2 + dh / c["comp_psi0"])
        x = (m / (rho * u * d_c ** 2) - c["comp_phi_opt"]) / c["comp_phi_width"]
        eta = c["comp_eta_max"] * (1 - x * x)
        mach = u / math.sqrt(g * r_air * ta)
        if mach > c["comp_mach_opt"]:
            y = (mach - c["comp_mach_opt"]) / c["comp_mach_width"]
            eta *= 1 - y * y
        eta = max(eta, c["comp_eta_min"])
        return u, m * dh / eta, eta, air_after(ta, dh / eta)

    def cp_gas(t, f):
        tt = t / 1000.0
        return sum(((1 - f) * a + f * b) * tt ** j
                   for j, (a, b) in enumerate(zip(c["cp_air"], c["cp_burned"])))

    def h_air(t):  # sensible enthalpy of air from 0 K (differences only), the cp polynomial's integral
        tt = t / 1000.0
        return 1000.0 * sum(a * tt ** (j + 1) / (j + 1) for j, a in enumerate(c["cp_air"]))

    def air_after(t1, dh):  # engine_turbo.c outlet_air: h(T2) = h(T1) + dh
        t = t1 + dh / cp_gas(t1, 0)
        for _ in range(3):
            t -= (h_air(t) - h_air(t1) - dh) / cp_gas(t, 0)
        return t

    print("%s, per bank: boost [bar]: turbine power x eta_m / compressor power [kW], "
          "q = their ratio" % variant)
    for rpm in (1000, 1300, 1600, 2100):
        w = rpm * math.pi / 30
        row = next(r for r in sweep if abs(r["speed_rpm"] - rpm) < 1)
        d_exh = row["exhaust_temp"] - row["intake_temp"]
        eta_v = interp(c["map_speed"], c["map_eta_v_" + variant], w)
        phi = min(c["phi_rated"] + c["phi_curvature"] * (w - c["phi_speed"]) ** 2,
                  c["phi_max"])
        cells = []
        for pb in (1.2, 1.6, 2.0, 2.4, 2.8, 3.2, 3.6, 4.0):
            p_im, t_im = pb * 1e5, 330.0
            for _ in range(40):  # intake temperature through compressor + intercooler
                m = eta_v * p_im / (r_air * t_im) * vd_bank * w / (4 * math.pi)
                p_ic = upstream(c["ic_cda"], m, t_im, p_im, g, r_air)
                u, p_c, eta_c, t_c = compressor(m, p_ic / pa)
                cp_c = cp_gas(t_c, 0)  # engine_manifold.c: the outlet air's cp
                t_im = t_c - (1 - math.exp(-c["ic_ua"] / (m * cp_c))) * (t_c - c["ic_wall_temp"])
            t3 = t_im + d_exh
            r_ex = c["r_burned"]
            cp_ex = cp_gas(t3, min(phi, 1))
            g_ex = cp_ex / (cp_ex - r_ex)
            m_ex = m * (1 + phi / c["afr_stoich"])
            opening = min(max((p_im - c["wg_crack"]) / max(c["wg_full"] - c["wg_crack"], 1), 0), 1)
            p3 = upstream(a_t + opening * c["wg_area"], m_ex, t3, pa, g_ex, r_ex)
            m_t = orifice(a_t, p3, t3, pa, g_ex, r_ex)
            dh_t = cp_ex * t3 * (1 - (pa / p3) ** ((g_ex - 1) / g_ex))
            bsr = u * d_t / d_c / math.sqrt(2 * dh_t) / c["turb_bsr_opt"]
            p_t = c["turbo_mech_eff"] * m_t * max(c["turb_eta_max"] * (2 * bsr - bsr * bsr), 0) * dh_t
            cells.append("%.1f: %3.0f/%3.0f q %.2f" % (pb, p_t / 1e3, p_c / 1e3, p_t / p_c))
        print("%4d rpm  %s" % (rpm, "  ".join(cells)))


PARALLEL = 2


def main():
    args = sys.argv[1:]
    if "-h" in args or "--help" in args:
        print(__doc__)
        return
    bad = [a for a in args if a not in ("--match", "--no-run")]
    if bad and "--match" not in args:
        sys.exit("engine_maps.py: --no-run or --match expected, got %s (--help)" % " ".join(bad))
    if "--match" in sys.argv:
        match_table(sys.argv[1:])
        return
    if "--no-run" not in sys.argv:
        jobs = []
        for v in VARIANTS:
            jobs.append(["build/tanksim", "engine-map", "--preset", "engine-map-" + v,
                         "--out", "sim/data/engine_maps/%s.csv" % v])
            jobs.append(["build/tanksim", "engine-map", "--preset", "engine-map-" + v,
                         "--spool", "sim/data/engine_maps/%s_spool.csv" % v])
        # at most PARALLEL processes at once (the 2-core machines this runs on)
        for i in range(0, len(jobs), PARALLEL):
            procs = [subprocess.Popen(j) for j in jobs[i:i + PARALLEL]]
            if any(p.wait() for p in procs):
                sys.exit("engine-map failed")
        # engine-map writes a provenance sidecar (FILE.csv.json: the resolved
        # config, tables included) beside each CSV; here the provenance is this
        # script and the presets, and every file under sim/data is embedded in
        # the binaries (Makefile STORE_FILES), so they are not kept
        for j in jobs:
            side = j[-1] + ".json"
            if os.path.exists(side):
                os.remove(side)
    path = "sim/data/defaults/engine.json"
    doc = json.load(open(path))  # _sources are kept as they are
    t63 = {}
    for v in VARIANTS:
        sweep = read_csv("sim/data/engine_maps/%s.csv" % v)
        if [round(r["speed"], 3) for r in sweep] != doc["map_speed"]:
            sys.exit("%s: speeds differ from /engine/map_speed" % v)
        for key, (col, nd) in COLUMNS.items():
            vals = [round(r[col], nd) for r in sweep]
            doc["map_%s_%s" % (key, v)] = [int(x) if nd == 0 else x for x in vals]
        spool = read_csv("sim/data/engine_maps/%s_spool.csv" % v)
        tables, sp, t = part_boost(sweep, spool)
        doc["spool_speed"] = sp
        doc["spool_ratio"] = SPOOL_RATIO
        for k, vals in tables.items():
            doc["pb_%s_%s" % (k, v)] = vals
        t63[v] = t
        print("%s: boost 63 %% times %s s" % (v, ", ".join("%.2f" % x for x in t)))
    doc["spool_lag"] = [round(statistics.median(t63[v][i] for v in VARIANTS), 3)
                        for i in range(len(doc["spool_speed"]))]
    print("spool_lag %s s" % doc["spool_lag"])
    json.dump(doc, open(path, "w"), indent=1)
    open(path, "a").write("\n")


if __name__ == "__main__":
    main()
