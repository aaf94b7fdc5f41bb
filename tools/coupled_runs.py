#!/usr/bin/env python3
"""coupled_runs.py -- the paper's Section IV runs (Figs. 28-35) with the coupled
scenario: runs the presets through build/tanksim and prints the figures the
issue-10 report quotes. Once-run script (minutes of CPU), not a test.

Usage: tools/coupled_runs.py [OUTDIR]   (default /tmp/tanksim-coupled-runs)
Runs: flat-coupled-rack90, bump-coupled-rack90, bump-coupled-ivs5mph,
bump-prescribed-coupled-nopowertrain, and sensitivity runs given as
config overrides (IVS with the gains `tanksim tune` computes now; 90 % rack with a 1950-rpm
upshift speed on flat and bumps).
"""
import csv
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TANKSIM = os.path.join(ROOT, "build", "tanksim")
MPH = 0.44704
LBF = 4.44822
COURSE = 152.4  # m: the bump course is 500 ft long [P II.D]


def run(name, preset=None, config=None, out=None):
    d = os.path.join(out, name)
    if config is not None:
        path = os.path.join(out, name + ".json")
        with open(path, "w") as f:
            json.dump(config, f)
        args = [TANKSIM, "run", path, "--out", d]
    else:
        args = [TANKSIM, "run", "--preset", preset, "--out", d]
    p = subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
    print(f"# {name}: {p.stderr.strip() or p.stdout.strip()}", flush=True)
    with open(os.path.join(d, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    summary = json.load(open(os.path.join(d, "summary.json")))
    cols = {k: [float(r[k]) for r in rows] for k in rows[0]}
    return cols, {k: v["value"] for k, v in summary.get("metrics", {}).items()}


def window(c, key, t0, t1):
    return [v for t, v in zip(c["t"], c[key]) if t0 <= t < t1]


def course_end(c):
    """(t, speed in mph) where vehicle.x first reaches the course's end, or None."""
    for t, x, v in zip(c["t"], c["vehicle.x"], c["vehicle.speed"]):
        if x >= COURSE:
            return t, v / MPH
    return None


def peak_split(c):
    """Peak rear-roller tension and the quasi-static (massless-track) tension in
    the same sample, both lbf, and the vehicle's x there."""
    tn = c["track.tension.rear_roller"]
    i = max(range(len(tn)), key=tn.__getitem__)
    return tn[i] / LBF, c["track.tension.quasi_static"][i] / LBF, c["vehicle.x"][i]


def shift_ends(c):
    g = c["transmission.gear"]
    return [c["t"][i] for i in range(1, len(g)) if g[i - 1] < round(g[i]) and g[i] == round(g[i])
            and g[i] > 1]


def shifts_report(c, label):
    span = "span.rear_roller_front_roller.deflection"
    for te in shift_ends(c):
        before = window(c, "track.tension.rear_roller", te - 0.2, te - 0.02)
        base = sum(before) / len(before)
        after = window(c, "track.tension.rear_roller", te, te + 0.3)
        d0, d1 = window(c, span, te - 0.42, te - 0.02), window(c, span, te, te + 0.4)
        print(f"  {label}: shift ends {te:6.2f} s: tension before {base/1e3:6.1f} kN, after "
              f"max {max(after)/1e3:6.1f} min {min(after)/1e3:6.1f} kN; span deflection p-p "
              f"{1e3*(max(d0)-min(d0)):5.2f} -> {1e3*(max(d1)-min(d1)):5.2f} mm")


def main():
    args = sys.argv[1:]
    if "-h" in args or "--help" in args:
        print(__doc__)
        return
    if len(args) > 1 or (args and args[0].startswith("-")):
        sys.exit("coupled_runs.py: one OUTDIR expected, got %s (--help)" % " ".join(args))
    out = args[0] if args else "/tmp/tanksim-coupled-runs"
    os.makedirs(out, exist_ok=True)
    flat, mf = run("flat-coupled-rack90", preset="flat-coupled-rack90", out=out)
    bump, mb = run("bump-coupled-rack90", preset="bump-coupled-rack90", out=out)
    ivs, mi = run("bump-coupled-ivs5mph", preset="bump-coupled-ivs5mph", out=out)
    pres, mp = run("bump-prescribed-coupled-nopowertrain",
                   preset="bump-prescribed-coupled-nopowertrain", out=out)
    print("\nFigs. 28-30 (flat, 90 % rack):")
    print("  shifts (half done) at", [round(mf[f"shift_{g}_{g+1}_half_s"], 2) for g in (1, 2, 3)],
          "s; peak sprocket torque", round(mf["peak_sprocket_torque"]), "N m; final speed",
          round(mf["final_speed_mph"], 1), "mph; peak tension", round(mf["peak_tension"] / 1e3, 1),
          "kN")
    shifts_report(flat, "flat")
    print("\nFig. 31 (bump vs flat, 90 % rack):")
    print("  shifts flat", [round(mf[f"shift_{g}_{g+1}_half_s"], 2) for g in (1, 2, 3)],
          "bump", [round(mb[f"shift_{g}_{g+1}_half_s"], 2) for g in (1, 2, 3)])
    tq_f, tq_b = flat["sprocket.torque"], bump["sprocket.torque"]
    diff = max(abs(a - b) for a, b in zip(tq_f, tq_b))
    print(f"  largest |sprocket torque bump - flat| {diff:.0f} N m; mean torque 5-30 s flat "
          f"{sum(window(flat, 'sprocket.torque', 5, 30))/len(window(flat, 'sprocket.torque', 5, 30)):.0f}"
          f" bump {sum(window(bump, 'sprocket.torque', 5, 30))/len(window(bump, 'sprocket.torque', 5, 30)):.0f} N m")
    shifts_report(bump, "bump")
    print("\nFig. 32 (bump-course speed):")
    print(f"  prescribed torque (no powertrain): top {mp['top_speed_mph']:.1f} mph (paper 27)")
    print(f"  powertrain, 90 % rack: top {mb['top_speed_mph']:.1f} mph, at 30 s "
          f"{mb['final_speed_mph']:.1f} mph")
    end = course_end(bump)
    print("  powertrain, 90 % rack, at the course's end (x = 152.4 m): " +
          (f"{end[1]:.2f} mph at {end[0]:.2f} s" if end else "not reached"))
    print(f"  powertrain + IVS 5 mph: top {mi['top_speed_mph']:.1f} mph")
    print("\nFigs. 33-35 (IVS at 5 mph over the bumps):")
    for k in ["time_to_target", "rack_at_launch", "mean_speed_error_mph",
              "mean_abs_speed_error_mph", "rack_min", "rack_max", "engine_speed_min",
              "engine_speed_max"]:
        print(f"  {k} = {mi[k]:.3f}")
    th = mi["time_to_target"]
    r = window(ivs, "rack.demand", th, 1e9)
    print(f"  rack after the target: share of samples below 0.1 {sum(x < 0.1 for x in r)/len(r):.2f},"
          f" above 0.9 {sum(x > 0.9 for x in r)/len(r):.2f}")
    slip = [p - t for p, t in zip(ivs["tc.pump.speed"], ivs["tc.turbine.speed"])]
    print(f"  converter slip range {min(slip):.1f} .. {max(slip):.1f} rad/s")
    late = window(ivs, "rack.demand", 10, 1e9)
    print(f"  rack after 10 s: mean {sum(late)/len(late):.3f}, share above 0.5 "
          f"{sum(x > 0.5 for x in late)/len(late):.2f}")
    for label, c in (("IVS 5 mph", ivs), ("prescribed", pres)):
        pk, qs, x = peak_split(c)
        print(f"  {label}: peak tension {pk:.0f} lbf at x = {x:.2f} m, quasi-static part there "
              f"{qs:.0f} lbf")
    print(f"  peak tension: IVS 5 mph {mi['peak_tension']/LBF:.0f} lb, prescribed "
          f"{mp['peak_tension']/LBF:.0f} lb (paper: axis to 35,000 lb, high-speed much higher)")
    # sensitivity runs
    tune = json.loads(subprocess.run([TANKSIM, "tune", "--preset", "bump-coupled-ivs5mph"],
                                     capture_output=True, text=True, cwd=ROOT,
                                     check=True).stdout)
    kp, ti = tune["kp"], tune["ti"]
    zn, mz = run("bump-coupled-ivs5mph-zn", config={
        "preset": "bump-coupled-ivs5mph", "control": {"kp": kp, "ti": ti}}, out=out)
    print(f"\nIVS with the `tanksim tune` gains (X {tune['x']:.2f} s, kp {kp:.4f}, ti {ti:.2f} s):")
    for k in ["time_to_target", "rack_at_launch", "mean_abs_speed_error_mph", "rack_min",
              "rack_max", "peak_tension"]:
        print(f"  {k} = " + ("not reached" if mz[k] is None else f"{mz[k]:.3f}"))
    for ter in ("flat", "bumps"):
        c, m = run(f"{ter}-rack90-1950rpm", config={
            "preset": "flat-coupled-rack90", "terrain": {"kind": ter},
            "driveline": {"shift_speed": 204.2}}, out=out)
        print(f"1950-rpm upshift, {ter}: shifts",
              [round(m[f"shift_{g}_{g+1}_half_s"], 2) for g in (1, 2, 3)])


if __name__ == "__main__":
    main()
