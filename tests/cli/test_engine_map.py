"""tanksim engine-map (issue 5): the full-load dynamometer sweep writes one row
per 100 rpm from 800 to 2100 rpm with units in the header; the engine-map
presets run as engine_dyno scenarios with crank-angle cylinder channels."""
import csv
import json
import os
import signal
import subprocess
import time

from conftest import TANKSIM


def run(*args):
    return subprocess.run([TANKSIM, *args], capture_output=True, text=True, timeout=300)


def mean_value_dyno(tmp_path):
    """A full-rack engine_dyno config at the mean-value fidelity (fast)."""
    cfg = tmp_path / "cfg.json"
    cfg.write_text(json.dumps({"run": {"kind": "engine_dyno"},
                               "engine": {"fidelity": "mean_value"}, "control": {"rack": 1.0}}))
    return cfg


def test_engine_map_mean_value_sweep(tmp_path):
    cfg = mean_value_dyno(tmp_path)
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "map.csv"))
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(open(tmp_path / "map.csv")))
    head = rows[0]
    for col in ("speed_rpm [rpm]", "torque [N*m]", "power [W]", "bsfc [g/kWh]", "boost [Pa]",
                "exhaust_temp [K]", "peak_pressure [Pa]"):
        assert col in head
    speeds = [int(r[0]) for r in rows[1:]]
    assert speeds == list(range(800, 2101, 100))
    rated = rows[-1]
    power = float(rated[head.index("power [W]")])
    assert 0.9e6 < power < 1.3e6  # the virtual engine's ~1.1 MW class
    # torque x speed = power on every row
    for r in rows[1:]:
        assert abs(float(r[2]) * float(r[1]) - float(r[3])) < 1e-3 * abs(float(r[3])) + 1
    # the columns' identities (a survivor of the session-26 mutation pass swapped fuel and
    # air): fuel = bsfc x power, and air / fuel a diesel's 20-60 at full load
    fuel, air, bsfc = (head.index(c) for c in ("fuel_flow [kg/s]", "air_flow [kg/s]",
                                               "bsfc [g/kWh]"))
    for r in rows[1:]:
        p = float(r[3])
        assert abs(float(r[fuel]) - float(r[bsfc]) * p / 3.6e9) < 2e-3 * float(r[fuel]) + 2e-6, r
        assert 20 < float(r[air]) / float(r[fuel]) < 60, r


def test_engine_map_map_fidelity_leaves_manifold_cells_empty(tmp_path):
    # the map engine has no manifolds or turbochargers: its exhaust and intake
    # temperatures and turbo speed are empty cells, as its peak pressure is
    # (they read 0.0 K, the intercooler wall's 325.0 K and 0 until session 22);
    # the mean-value engine, which models them, fills them
    for fidelity, empty in (("map", True), ("mean_value", False)):
        cfg = tmp_path / f"{fidelity}.json"
        cfg.write_text(json.dumps({"run": {"kind": "engine_dyno"},
                                   "engine": {"fidelity": fidelity}, "control": {"rack": 1.0}}))
        out = run("engine-map", str(cfg), "--out", str(tmp_path / f"{fidelity}.csv"))
        assert out.returncode == 0, out.stderr
        rows = list(csv.reader(open(tmp_path / f"{fidelity}.csv")))
        head = rows[0]
        for col in ("exhaust_temp [K]", "intake_temp [K]", "turbo_speed [rad/s]"):
            cells = [r[head.index(col)] for r in rows[1:]]
            if empty:
                assert cells == [""] * len(cells), (col, cells)
            else:
                assert all(float(c) > 0 for c in cells), (col, cells)
        assert all(float(r[head.index("torque [N*m]")]) > 0 for r in rows[1:])


def test_engine_map_writes_a_sidecar(tmp_path):
    """The CSV said nothing of what made it (variant, fidelity, rack, ambient air).
    Beside it now goes FILE.csv.json, as run's summary.json: those, every column's
    unit and the resolved config, which re-runs to the same CSV. The CSV itself is
    unchanged (tools/engine_maps.py reads it). Not FILE.json: a config of the same
    stem (map.json here, tools/wastegate_sweep.py's VARIANT.json) is left alone."""
    cfg = tmp_path / "map.json"
    cfg.write_text(json.dumps({"run": {"kind": "engine_dyno"},
                               "engine": {"variant": "lhr05", "fidelity": "mean_value"},
                               "control": {"rack": 0.8},
                               "driveline": {"ambient_temperature": 310.0}}))
    before = cfg.read_text()
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "map.csv"))
    assert out.returncode == 0, out.stderr
    assert cfg.read_text() == before
    side = json.load(open(tmp_path / "map.csv.json"))
    assert side["kind"] == "engine_map" and side["csv"] == "map.csv"
    assert (side["variant"], side["fidelity"], side["rack"]) == ("lhr05", "mean_value", 0.8)
    assert side["ambient_temperature"] == 310.0 and side["ambient_pressure"] > 9e4
    assert side["units"] == {"rack": "1", "ambient_pressure": "Pa", "ambient_temperature": "K"}
    head = next(csv.reader(open(tmp_path / "map.csv")))
    assert [f"{c['name']} [{c['unit']}]" for c in side["columns"]] == head
    assert side["config"]["engine"]["variant"] == "lhr05"
    echo = tmp_path / "echo.json"
    echo.write_text(json.dumps(side["config"]))
    out = run("engine-map", str(echo), "--out", str(tmp_path / "again.csv"))
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "again.csv").read_bytes() == (tmp_path / "map.csv").read_bytes()


def test_engine_map_sidecar_fails_with_its_csv(tmp_path):
    # the pair is put in place together: a sidecar that cannot be written takes the
    # CSV with it (exit 1), so no CSV stands without its record
    cfg = mean_value_dyno(tmp_path)
    os.symlink("/dev/full", tmp_path / "m.csv.json")
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "m.csv"))
    assert out.returncode == 1 and "m.csv.json" in out.stderr and "not written" in out.stderr
    assert not (tmp_path / "m.csv").exists()
    # a CSV written to a pipe or device has no name to put a sidecar beside
    out = run("engine-map", str(cfg), "--out", "/dev/stdout")
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("speed_rpm [rpm],") and not os.path.exists("/dev/stdout.json")


def test_engine_map_writes_through_a_symlink(tmp_path):
    # a symlink is written through, in place: renaming the tmp file onto it
    # replaced the link itself (as root even /dev/stdout's), session 21
    cfg = mean_value_dyno(tmp_path)
    (tmp_path / "real.csv").write_text("old\n")
    os.symlink(tmp_path / "real.csv", tmp_path / "link.csv")
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "link.csv"))
    assert out.returncode == 0, out.stderr
    assert os.path.islink(tmp_path / "link.csv")
    assert open(tmp_path / "real.csv").read().startswith("speed_rpm [rpm],")
    assert not (tmp_path / "link.csv.json").exists()  # written in place: no sidecar


def test_engine_map_temporary_is_its_own(tmp_path):
    # the CSV and its sidecar were written as the fixed FILE.tmp and renamed: a
    # FILE.tmp of the user's was overwritten and moved onto the output, and a
    # link of that name was written through (and then itself renamed into place).
    # Each output now gets a new temporary beside it (FILE.XXXXXX, O_EXCL)
    cfg = mean_value_dyno(tmp_path)
    (tmp_path / "m.csv.tmp").write_text("mine\n")
    (tmp_path / "victim").write_text("victim\n")
    os.symlink(tmp_path / "victim", tmp_path / "m.csv.json.tmp")
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "m.csv"))
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "m.csv.tmp").read_text() == "mine\n"
    assert (tmp_path / "victim").read_text() == "victim\n"
    assert os.path.islink(tmp_path / "m.csv.json.tmp")
    assert not os.path.islink(tmp_path / "m.csv.json")
    assert open(tmp_path / "m.csv").read().startswith("speed_rpm [rpm],")
    assert json.load(open(tmp_path / "m.csv.json"))["kind"] == "engine_map"
    assert sorted(os.listdir(tmp_path)) == ["cfg.json", "m.csv", "m.csv.json", "m.csv.json.tmp",
                                            "m.csv.tmp", "victim"]  # no temporary left


def test_engine_map_concurrent_writers_of_one_csv(tmp_path):
    # two runs writing one --out shared FILE.tmp: the second truncated the first's
    # file, and whichever renamed second found no FILE.tmp (exit 1). Both succeed
    # now, and the CSV is one run's whole
    cfg = mean_value_dyno(tmp_path)
    procs = [subprocess.Popen([TANKSIM, "engine-map", str(cfg), "--out", str(tmp_path / "m.csv")],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
             for _ in range(2)]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "one.csv"))
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "m.csv").read_bytes() == (tmp_path / "one.csv").read_bytes()
    assert sorted(os.listdir(tmp_path)) == ["cfg.json", "m.csv", "m.csv.json", "one.csv",
                                            "one.csv.json"]


def test_engine_map_name_near_the_limit(tmp_path):
    # PATH.XXXXXX is 3 bytes longer than the former PATH.tmp: a CSV named with
    # 250 bytes (its sidecar 255, the limit) got "File name too long". Such
    # names take a short hidden temporary in the same directory
    cfg = mean_value_dyno(tmp_path)
    name = "m" * 246 + ".csv"
    out = run("engine-map", str(cfg), "--out", str(tmp_path / name))
    assert out.returncode == 0, out.stderr
    assert open(tmp_path / name).read().startswith("speed_rpm [rpm],")
    assert json.load(open(tmp_path / (name + ".json")))["kind"] == "engine_map"
    assert sorted(os.listdir(tmp_path)) == sorted(["cfg.json", name, name + ".json"])


def test_engine_map_killed_leaves_no_temporary(tmp_path):
    # each temporary has a name of its own, so one a killed run left would never
    # be reused and replaced: SIGTERM (or SIGINT, SIGHUP) removes them, and the
    # process still ends by that signal
    cfg = mean_value_dyno(tmp_path)
    p = subprocess.Popen([TANKSIM, "engine-map", str(cfg), "--out", str(tmp_path / "m.csv")],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while not [n for n in os.listdir(tmp_path) if n.startswith("m.csv.")]:
        assert p.poll() is None and time.monotonic() < deadline, "no temporary appeared"
        time.sleep(0.005)
    p.send_signal(signal.SIGTERM)
    assert p.wait(timeout=60) == -signal.SIGTERM
    assert os.listdir(tmp_path) == ["cfg.json"]


def test_engine_map_output_mode_follows_the_umask(tmp_path):
    # what a plain create gives (0666 less the umask), as before the temporaries:
    # mkstemp's 0600 would make every output private
    cfg = mean_value_dyno(tmp_path)
    for umask, mode in ((0o022, 0o644), (0o077, 0o600), (0o002, 0o664)):
        path = tmp_path / f"m{umask:o}.csv"
        out = subprocess.run([TANKSIM, "engine-map", str(cfg), "--out", str(path)],
                             capture_output=True, text=True, timeout=300,
                             preexec_fn=lambda u=umask: os.umask(u))
        assert out.returncode == 0, out.stderr
        for f in (path, tmp_path / (path.name + ".json")):
            assert os.stat(f).st_mode & 0o777 == mode, (f, oct(os.stat(f).st_mode), oct(umask))


def test_engine_map_needs_out(tmp_path):
    out = run("engine-map", "--preset", "engine-map-conventional")
    assert out.returncode == 2 and "--out" in out.stderr


def test_dyno_preset_runs_crank_angle_traces(tmp_path):
    out = run("run", "--preset", "engine-map-conventional", "--out", str(tmp_path / "o"),
              "--until", "0.0060317460317")  # 76 rows of 1/12600 s (an end off the rows is refused)
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(open(tmp_path / "o" / "series.csv")))
    head = rows[0]
    p = [float(r[head.index("cylinder.pressure")]) for r in rows[1:]]
    speed = [float(r[head.index("engine.speed")]) for r in rows[1:]]
    assert len(rows) == 1 + 1 + 76  # header, row 0, rows up to 76 / 12600 s
    assert all(abs(s - 219.91) < 1e-6 for s in speed)
    assert max(p) > 3e5 and min(p) > 0
    summary = json.load(open(tmp_path / "o" / "summary.json"))
    assert "brake_torque_mean" in summary["metrics"]
    assert summary["integrators"] == []  # fixed crank-angle steps: no counters kept
    assert "integrator steps" not in out.stdout  # was "0 integrator steps"


def test_engine_map_spool_rows(tmp_path):
    """--spool (issue 6): launch spool-ups at held speed, one row per engine
    cycle, 800-2200 rpm in 200-rpm steps, 6 s each; boost rises from about
    ambient. The mean-value fidelity keeps this fast (the tables in engine.json
    come from crank-angle spool-ups, tools/engine_maps.py)."""
    cfg = mean_value_dyno(tmp_path)
    out = run("engine-map", str(cfg), "--spool", str(tmp_path / "spool.csv"))
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(open(tmp_path / "spool.csv")))
    head = [h.split(" ")[0] for h in rows[0]]
    for col in ("speed_rpm", "time", "boost", "eta_v", "eta_i", "q_wall", "indicated_torque"):
        assert col in head
    side = json.load(open(tmp_path / "spool.csv.json"))  # what made it, as for the map
    assert side["kind"] == "engine_spool" and side["fidelity"] == "mean_value"
    assert side["rack"] == 1.0 and side["spool_time"] == 6.0 and side["units"]["spool_time"] == "s"
    assert [f"{c['name']} [{c['unit']}]" for c in side["columns"]] == rows[0]
    data = [dict(zip(head, map(float, r))) for r in rows[1:]]
    assert sorted({int(r["speed_rpm"]) for r in data}) == list(range(800, 2201, 200))
    for rpm in (1400, 2200):
        cyc = [r for r in data if r["speed_rpm"] == rpm]
        t = [r["time"] for r in cyc]
        assert all(b > a for a, b in zip(t, t[1:])) and 5.9 < t[-1] < 6.2
        assert abs(t[0] - 4 * 3.14159265 / cyc[0]["speed"]) < 1e-3  # one cycle per row
        assert cyc[0]["boost"] < 1.3e5 < 3e5 < cyc[-1]["boost"]


def test_engine_map_spool_progress_is_the_shared_helpers(tmp_path):
    # the spool-ups printed "  spool 1600 rpm done" themselves; they report through
    # cli.h's tsc_progress now, as run and tune do: "tanksim engine-map: ..." lines
    # after the first 2 s, the last always once any was shown. The crank-angle
    # spool-ups (tools/engine_maps.py's) take ~1 s each here, 8 to 12 s in all
    out = run("engine-map", "--preset", "engine-map-conventional",
              "--spool", str(tmp_path / "spool.csv"))
    assert out.returncode == 0, out.stderr
    lines = out.stderr.splitlines()
    assert lines and all(l.startswith("tanksim engine-map: spool-up at ") for l in lines), lines
    done = [int(l.split("(")[1].split(" of ")[0]) for l in lines]
    assert done == sorted(set(done)) and done[-1] == 8, lines
    assert lines[-1].startswith("tanksim engine-map: spool-up at 2200 rpm done (8 of 8), 100 %, ")
    assert lines[-1].endswith(" s wall"), lines


def test_engine_map_spool_leaves_unmodelled_cells_empty(tmp_path):
    # the map fidelity has no eta_v / eta_i / q_wall: empty cells, as in the map's
    # CSV (the spool rows printed "nan" until session 21)
    cfg = tmp_path / "map.json"
    cfg.write_text(json.dumps({"run": {"kind": "engine_dyno"}, "engine": {"fidelity": "map"},
                               "control": {"rack": 1.0}}))
    out = run("engine-map", str(cfg), "--spool", str(tmp_path / "spool.csv"))
    assert out.returncode == 0, out.stderr
    text = open(tmp_path / "spool.csv").read()
    assert "nan" not in text
    rows = list(csv.reader(text.splitlines()))
    col = rows[0].index("eta_v [1]")
    assert all(r[col] == "" for r in rows[1:]) and all(r[0] for r in rows[1:])


def test_engine_maps_tool_reproduces_defaults(tmp_path):
    """engine.json's map and part-boost tables are exactly what
    tools/engine_maps.py derives from the stored CSVs (no hand edits)."""
    import os
    import shutil
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    shutil.copytree(os.path.join(root, "sim", "data", "engine_maps"),
                    tmp_path / "sim" / "data" / "engine_maps")
    os.makedirs(tmp_path / "sim" / "data" / "defaults")
    src = os.path.join(root, "sim", "data", "defaults", "engine.json")
    shutil.copy(src, tmp_path / "sim" / "data" / "defaults" / "engine.json")
    out = subprocess.run(["/usr/bin/python3", os.path.join(root, "tools", "engine_maps.py"),
                          "--no-run"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert json.load(open(tmp_path / "sim" / "data" / "defaults" / "engine.json")) == \
        json.load(open(src))
