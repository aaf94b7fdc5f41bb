#!/usr/bin/env python3
"""Regenerate the engine map tables (/engine/map_*_<variant>) in
sim/data/defaults/engine.json from the crank-angle model's own full-load sweep.

Usage (from the repository root, after `make`):
    tools/engine_maps.py            # runs the three sweeps, rewrites the CSVs and the JSON
    tools/engine_maps.py --no-run   # only re-reads sim/data/engine_maps/*.csv

Each sweep is `build/tanksim engine-map --preset engine-map-<variant>`; the
full CSV output stays in sim/data/engine_maps/<variant>.csv as provenance.
"""
import csv
import json
import subprocess
import sys

VARIANTS = ("conventional", "lhr05", "lhr10")
COLUMNS = {"torque": ("torque", 1), "boost": ("boost", 0), "fuel": ("fuel_flow", 6),
           "eta_v": ("eta_v", 4), "eta_i": ("eta_i", 4), "q_wall": ("q_wall", 4)}


def main():
    if "--no-run" not in sys.argv:
        procs = [subprocess.Popen(["build/tanksim", "engine-map", "--preset", "engine-map-" + v,
                                   "--out", "sim/data/engine_maps/%s.csv" % v]) for v in VARIANTS]
        if any(p.wait() for p in procs):
            sys.exit("engine-map failed")
    path = "sim/data/defaults/engine.json"
    doc = json.load(open(path))  # _sources are kept as they are
    for v in VARIANTS:
        rows = list(csv.reader(open("sim/data/engine_maps/%s.csv" % v)))
        head = [h.split(" ")[0] for h in rows[0]]
        speeds = [round(float(r[head.index("speed")]), 3) for r in rows[1:]]
        if speeds != doc["map_speed"]:
            sys.exit("%s: speeds differ from /engine/map_speed" % v)
        for key, (col, nd) in COLUMNS.items():
            vals = [round(float(r[head.index(col)]), nd) for r in rows[1:]]
            doc["map_%s_%s" % (key, v)] = [int(x) if nd == 0 else x for x in vals]
    json.dump(doc, open(path, "w"), indent=1)
    open(path, "a").write("\n")


if __name__ == "__main__":
    main()
