#!/usr/bin/env python3
"""Wastegate and turbine-geometry sweep for issue 5 (paper Section III.B.3,
Fig. 18): can the wastegate's actuator law, or a turbine geometry scheduled in
engine speed (/engine/turb_sched_*), let the LHR engines' extra exhaust energy raise boost
enough for the paper's rated-power gains (+15.7 % / +19.8 % over 1350 hp for
0.5 / 1.0 mm zirconia, within 2 points) while the conventional engine stays
calibrated at 1108 kW?

Per case (a set of /engine overrides): /engine/wg_area (or --cal KEY) is re-calibrated on the
CONVENTIONAL rated point only (1108 kW at 2100 rpm, secant in log area on the
first point of the crank-angle lug-down), then the full-load lug-down
(`tanksim engine-map`, 2100 -> 800 rpm) of the three variants is run with that
value and the LHR gains are PREDICTED (unless the case itself was chosen
for them: see the docstring's tables). Prints one row per case: rated power and
gain over 1350 hp, torque and boost at 800 / 1000 / 1400 / 2100 rpm, and at rated
BSFC, peak cylinder pressure and exhaust manifold temperature. Nothing is
written to the repository.

Usage (repository root, after `make`):
    tools/wastegate_sweep.py                 # the built-in case list (below)
    tools/wastegate_sweep.py wg_crack=2e5 wg_full=8e5 [...]   # one case
    tools/wastegate_sweep.py --cal turb_area_ref wg_area=0       # calibrate another
                                                  # /engine key on the rated point
    tools/wastegate_sweep.py --cal turb_sched_bypass --table2 \
        turb_sched_speed=188.5,219.91 turb_sched_nozzle=1,1.25 \
        turb_sched_gate=1,0 turb_sched_bypass=0,0.00027
                                  # array values: comma lists; --cal on an
                                  # array key calibrates its LAST node
--table2 also runs the point-mass Table 2 accelerations (crank-angle engine,
accel-pointmass-<variant> presets with the case's /engine overrides) and
prints speed at 20 s, 0-60 and 20-60 km/h times against the paper's.
Runs at most two tanksim processes at a time (~20 s per case).

Result of the built-in list on engine.json as of commit 0720e02 (default gate
wg_crack 2.8 bar, wg_full 8 bar): NO case reaches the 1.0 mm target (>= +17.8 %).
- Spring law (crack 1.2-3.2 bar x full 5-10 bar, each re-calibrated): LHR10
  +14.6 ... +15.9 %, LHR05 +14.0 ... +14.9 %; the full-open boost hardly
  matters (same area per bar of spring range), the crack does: the
  gate's elasticity d ln(open area) / d ln(boost) = p/(p - crack) is 1.4 at
  crack 1.2 bar and 3.2 at 2.8 bar, and even 1.4 holds the LHR boost rise to
  +4 % (4.07 -> 4.23 bar). Cracks below 2.4 bar open the gate at low speed
  and the lug-down falls to its low-boost branch at 1000 rpm (1.5-1.6 bar,
  ~3 kN*m instead of 2.9 bar, 6 kN*m).
- A fixed bypass (crack 1.0, full 1.01 bar: elasticity 0, the limit of any
  gate whose opening does not grow with the LHR's exhaust energy, e.g. an
  engine-speed-scheduled gate at rated): +16.0 / +17.5 %, still short, and
  the low-speed hold is lost (1.12 bar, 2175 N*m at 800 rpm).
- Compressor / turbine map levers (tip-Mach loss, u/c_s optimum, nozzle area,
  peak efficiencies, flow-coefficient optimum): +14.4 ... +15.7 %.
- Fixed bypass with a larger turbine nozzle (same calibration): turb_area_ref
  0.0008 -> +16.1 / +17.8 %, 0.0011 -> +16.9 / +19.0 % (both gains within 2
  points), and no bypass, turb_area_ref calibrated instead (--cal
  turb_area_ref wg_area=0: 0.00152) -> +18.5 / +21.2 % (0.5 mm now 0.8 point
  OVER the band); but each of these has lost the full-load high-boost branch
  by 1000 rpm (1.1-1.2 bar, ~2.0-2.1 kN*m). The default gate law with
  turb_area_ref 0.0008 already folds at 1000 rpm (1.42 bar), so the nozzle
  that holds the lug-down (<= 0.00075) caps the 1.0 mm gain at +17.5 % for
  any bypass whose opening does not shrink as exhaust energy rises (an
  engine-speed-scheduled gate included: at rated it is a fixed bypass).
The boost at 800 rpm is 1.09-1.33 bar (low-boost branch) in every case.

Engine-speed (open-loop) turbine geometry, /engine/turb_sched_speed,
_nozzle, _gate, _bypass (branch vgt, engine.json of commit 92ea86e; rated kW
and gain over 1350 hp conv/0.5/1.0 mm; boost bar and torque N*m at
1000/1400/2100 rpm conventional; peak bar at rated; Table 2 = the point-mass
runs, crank-angle engine, speed at 20 s, 0-60 and 20-60 km/h times, paper
65.67/66.29/66.43 km/h, 17.2/16.95/16.9 s, 13.2/12.9/12.8 s). Main (gate
acting at every speed): +10.0/+14.2/+15.0 %, boost 2.89/3.58/4.07 bar,
torque 6032/6038/5038 N*m, peak 213 bar; Table 2 66.24/68.05/68.25 km/h,
16.69/15.94/15.88 s, 12.59/11.88/11.77 s.
1. No gate (wg_area=0), fixed nozzle: the fold boundary of any open-loop
   geometry. The high-boost branch holds down to 900 / 1000 / 1200 / 1400 /
   1700 / 2000 rpm for turb_area_ref 0.00065 / 0.00075 / 0.0009 / 0.0011 /
   0.0013 / 0.00152, and where it holds the boost is >= 4.1 bar: the
   turbine/compressor power ratio RISES with boost at low speed, so without
   boost feedback there is no equilibrium between ~1.2 bar and ~4 bar.
   0.00075: 4.25 bar, 8770 N*m, 265 bar peak at 1000 rpm.
2. No gate, nozzle scheduled along that boundary (factor on 0.00152 of
   0.49/0.59/0.72/0.855/1.0 at 1000/1200/1400/1700/2000 rpm; rated = the
   gate-free fixed turbine, +10.0/+18.5/+21.1 %, 0.5 mm OVER its band):
   1000 rpm 4.32/4.83/5.00 bar, 8898/9931/10151 N*m, 269/301/311 bar peak
   (conv/0.5/1.0 mm), the LHR torque ABOVE the all-metal one (Fig. 18a:
   below). Rejected: peak pressures and the Fig. 18a trend.
3. Gate acting (main's law), nozzle factor 1 at 1600 rpm -> calibrated 1.69
   at 2100: +10.1/+14.8/+15.9 % (the gate, ~13 % open at rated, still
   absorbs the LHR energy).
4. Fixed bypass at every speed (wg_crack=1e5 wg_full=1.01e5, wg_area
   calibrated), nozzle 0.00075 / 0.0009 / 0.0011 / 0.0013: +15.9/+17.4,
   +16.3/+18.0, +16.9/+19.0, +17.9/+20.2 %; rated BSFC 225/216/210/206
   g/kWh; exhaust/intake manifold pressure at rated (quasi-steady orifice
   estimate from the sweep's flows) 1.37/1.21/1.06/0.96; but the larger
   nozzles fold to the low-boost branch below 1400-1700 rpm.
5. Gate saturated at rated (wg_full=3.3e5, a fixed bypass there), nozzle
   factor 1 -> 1.6 from 1300 rpm (1.6: pressure ratio ~1 at rated):
   +10.0/+17.5/+19.6 %, but the LHRs' boost is free wherever the gate is
   saturated: 1400 rpm torque 5665/6084/6274 N*m, Table 2 20-60 km/h
   13.27/11.82/11.43 s (1.0 mm 10.7 % below the paper's: fails issue 6).
   From 1800 rpm: 4.4-4.7 bar and 237-256 bar peak at 1800 rpm.
6. Gate overridden at rated, open-loop bypass calibrated there (schedule
   nodes 1800 and 2100 rpm: nozzle 1 -> F, gate authority 1 -> 0, bypass
   0 -> calibrated; identical to main below 1800 rpm):
     F     bypass m^2  gains %      rated boost  BSFC  peak  T2 20-60 s
     1.0   0.000282    +16.0/+17.5  4.07/4.24/4.33  225  213/225/230  12.68/11.91/11.78
     1.1   0.000284    +16.2/+17.9  3.91/4.09/4.18  220  207/217/223  12.65/11.88/11.74
     1.15  0.000282    +16.2/+17.9  3.84/4.02/4.11  218  203/214/221  12.63/11.86/11.72
     1.25  0.000270    +16.4/+18.3  3.74/3.92/4.02  215  199/210/215  12.59/11.81/11.67
     1.4   0.000239    +16.8/+18.8  3.62/3.81/3.91  211  193/205/211  12.52/11.73/11.58
     1.6   0.000180    +17.5/+19.6  3.51/3.72/3.82  208  188/201/207  12.41/11.61/11.46
   (first node 1900 rpm instead: same rated point, Table 2 within 0.1
   km/h and 0.03 s). With F = 1.25 all Table 2 rows pass, the mean-value
   and map engines are within 1.6 % of the crank-angle speed at 20 s, but
   the MEAN-VALUE engine's own turbo falls 3.1 % short of the crank-angle
   rated torque (4882 vs 5038 N*m, boost 3.56 vs 3.74 bar; main: -0.9 %):
   its mean-flow turbine lacks the pulse energy, which matters more as the
   nozzle opens (mean-value rated torque -6.7 % at F = 1.6, -0.6 % at 1.1,
   +1.7 % at 1.0, those three with the F = 1.25 sweep's eta tables). The window where the 1.0 mm gain is in its band
   (F >= ~1.08) and the mean-value engine within 3 % (F <= ~1.23) gives
   the 1.0 mm engine +17.9...+18.2 % against a floor of 17.8: a calibrated
   knife edge, so no schedule is adopted (engine.json: tables empty).
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HP1350 = 1350 * 745.7  # [W] the KTTA38's rating (paper III.B.3)
TARGET = 1108.0  # [kW] the conventional rated point wg_area is calibrated to
VARIANTS = ("conventional", "lhr05", "lhr10")
CASES = (
    # the gate's spring law: crack (preload) and full-open boost [Pa]
    [{"wg_crack": cr, "wg_full": fu}
     for cr in (1.2e5, 1.6e5, 2.0e5, 2.4e5, 2.8e5, 3.2e5) for fu in (5e5, 8e5, 10e5)] +
    # the limit of a soft gate: a fixed bypass orifice (open at all boosts)
    [{"wg_crack": 1.0e5, "wg_full": 1.01e5}] +
    # other turbocharger levers with the default gate law
    [{"comp_mach_width": 2.5}, {"comp_mach_opt": 1.3}, {"turb_bsr_opt": 0.6},
     {"turb_bsr_opt": 0.8}, {"turb_area_ref": 0.00065}, {"turb_area_ref": 0.00085},
     {"turb_eta_max": 0.75}, {"comp_eta_max": 0.75}, {"comp_phi_opt": 0.10}])


def start(variant, ov, tmp, out=None):
    cfg = os.path.join(tmp, variant + ".json")
    json.dump({"preset": "engine-map-" + variant, "engine": ov}, open(cfg, "w"))
    out = out or os.path.join(tmp, variant + ".csv")
    return subprocess.Popen(["build/tanksim", "engine-map", cfg, "--out", out],
                            stderr=subprocess.PIPE, text=True)


CAL = "wg_area"  # the /engine key calibrated on the conventional rated point


def rated_kw(ov, tmp):
    """Conventional rated power [kW]: the lug-down's first point, then stop.
    None when tanksim printed something else first (a config error: the
    message goes to stderr)."""
    p = start("conventional", ov, tmp)
    line = p.stderr.readline()
    p.kill()
    p.wait()
    f = line.split()
    if len(f) < 2 or f[-1] != "kW":
        sys.stderr.write("tanksim engine-map: " + line)
        return None
    return float(f[-2])


def with_cal(ov, a):
    """ov with the calibrated value a: /engine/CAL, or for an array key
    (turb_sched_*) its last node."""
    if isinstance(ov.get(CAL), list):
        return dict(ov, **{CAL: ov[CAL][:-1] + [a]})
    return dict(ov, **{CAL: a})


def calibrate(ov, tmp):
    xs, ys = [], []
    if isinstance(ov.get(CAL), list):
        a = ov[CAL][-1]
    else:
        a = 0.00116 if CAL == "wg_area" else 0.0015
    for _ in range(14):
        kw = rated_kw(with_cal(ov, a), tmp)
        if kw is None:
            return None
        xs.append(math.log(a))
        ys.append(kw - TARGET)
        if abs(ys[-1]) < 0.5:
            return a
        if len(xs) == 1:
            a *= 1.3 if ys[-1] > 0 else 1 / 1.3
        else:
            s = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
            a = math.exp(xs[-1] - max(min(ys[-1] / s, 1.5), -1.5))
        if a > 0.05:
            break
    return None


def lugdowns(ov, tmp):
    rows = {}
    for pair in (VARIANTS[:2], VARIANTS[2:]):
        procs = {v: start(v, ov, tmp) for v in pair}
        for v, p in procs.items():
            p.communicate()
            if p.returncode != 0:
                return None
            r = list(csv.reader(open(os.path.join(tmp, v + ".csv"))))
            head = [h.split(" ")[0] for h in r[0]]
            rows[v] = {int(float(x[0])): dict(zip(head, map(float, x))) for x in r[1:]}
    return rows


TABLE2 = {"conventional": (65.67, 17.2, 13.2), "lhr05": (66.29, 16.95, 12.9),
          "lhr10": (66.43, 16.9, 12.8)}  # paper Table 2: km/h at 20 s, 0-60 s, 20-60 s
METRICS = ("speed_at_20s_kmh", "t_0_60_kmh_s", "t_20_60_kmh_s")


def table2(ov, tmp):
    """Point-mass Table 2 runs (crank-angle engine) with the case's overrides."""
    res = {}
    for pair in (VARIANTS[:2], VARIANTS[2:]):
        procs = {}
        for v in pair:
            cfg = os.path.join(tmp, "pm_" + v + ".json")
            json.dump({"preset": "accel-pointmass-" + v, "engine": ov}, open(cfg, "w"))
            procs[v] = subprocess.Popen(["build/tanksim", "run", cfg, "--out",
                                         os.path.join(tmp, "pm_" + v)],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        for v, p in procs.items():
            p.communicate()
            m = json.load(open(os.path.join(tmp, "pm_" + v, "summary.json")))["metrics"]
            res[v] = [m[k]["value"] for k in METRICS]
    return "  Table 2 " + "; ".join(
        "%s %s" % (v, " ".join("%.2f (%+.1f %%)" % (x, 100 * (x / p - 1))
                               for x, p in zip(res[v], TABLE2[v]))) for v in VARIANTS)


def value(text):
    """A command-line value: a number, or a comma list (array keys)."""
    if "," in text or text == "":
        return [float(x) for x in text.split(",") if x]
    return float(text)


def main():
    global CAL
    args = sys.argv[1:]
    if "-h" in args or "--help" in args:
        print(__doc__)
        return
    bad = [a for i, a in enumerate(args) if "=" not in a and a != "--table2" and a != "--cal"
           and (i == 0 or args[i - 1] != "--cal")]
    if bad or args[-1:] == ["--cal"]:
        sys.exit("wastegate_sweep.py: KEY=VALUE, --cal KEY or --table2 expected, got %s "
                 "(--help)" % (" ".join(bad) or "--cal without a KEY"))
    if "--cal" in args:
        i = args.index("--cal")
        CAL = args[i + 1]
        del args[i:i + 2]
    with_t2 = "--table2" in args
    if with_t2:
        args.remove("--table2")
    cases = CASES
    if args:
        cases = [{k: value(v) for k, v in (a.split("=", 1) for a in args)}]
    print("case | calibrated " + CAL + " | rated kW conv/lhr05/lhr10 | gain % over 1350 hp "
          "(paper +9.9/+15.7/+19.8) | torque N*m 800, 1000, 1400, 2100 rpm (conv/05/10) | "
          "boost bar 800, 1000, 1400, 2100 | rated BSFC g/kWh, peak bar, exhaust K")
    with tempfile.TemporaryDirectory() as tmp:
        for ov in cases:
            name = " ".join("%s=%s" % (k, ",".join("%g" % x for x in v) if isinstance(v, list)
                                       else "%g" % v) for k, v in ov.items())
            a = calibrate(ov, tmp)
            rows = lugdowns(with_cal(ov, a), tmp) if a else None
            if not rows:
                print("%s | no calibration or a failed lug-down" % name, flush=True)
                continue

            def trio(rpm, col, scale=1.0, fmt="%.0f"):
                return "/".join(fmt % (rows[v][rpm][col] * scale) for v in VARIANTS)
            print("%s | %.6g | %s | %s | %s, %s, %s, %s | %s, %s, %s, %s | %s, %s, %s" % (
                name, a, trio(2100, "power", 1e-3, "%.1f"),
                "/".join("%+.1f" % (100 * (rows[v][2100]["power"] / HP1350 - 1))
                         for v in VARIANTS),
                trio(800, "torque"), trio(1000, "torque"), trio(1400, "torque"),
                trio(2100, "torque"), trio(800, "boost", 1e-5, "%.2f"),
                trio(1000, "boost", 1e-5, "%.2f"), trio(1400, "boost", 1e-5, "%.2f"),
                trio(2100, "boost", 1e-5, "%.2f"), trio(2100, "bsfc", 1, "%.1f"),
                trio(2100, "peak_pressure", 1e-5, "%.0f"), trio(2100, "exhaust_temp")),
                flush=True)
            if with_t2:
                print(table2(with_cal(ov, a), tmp), flush=True)


if __name__ == "__main__":
    main()
