"""tanksim runner basics (issue 2): help, version, unknown commands, config
errors naming the field, and a run writing series.csv + summary.json."""
import csv
import json
import os
import subprocess

from conftest import TANKSIM


def run(*args, cwd=None):
    return subprocess.run([TANKSIM, *args], capture_output=True, text=True, cwd=cwd, timeout=300)


def test_help_lists_commands_and_version():
    out = run("--help")
    assert out.returncode == 0 and "run" in out.stdout
    out = run("--version")
    assert out.returncode == 0 and out.stdout.startswith("tanksim ")


def test_each_command_has_help():
    # `tanksim COMMAND --help` prints that command's usage line and exits 0 (it
    # was read as a missing CONFIG.json / --out and exited 2).
    for cmd in ("run", "modes", "render", "engine-map", "tune", "schema"):
        for flag in ("--help", "-h"):
            out = run(cmd, flag)
            assert out.returncode == 0, (cmd, flag, out.stderr)
            assert out.stdout.startswith("usage: tanksim " + cmd), (cmd, out.stdout)
    assert "--schedule-mass" in run("tune", "--help").stdout
    # each option's unit is in its help (session-29 review: tune, run and engine-map
    # printed only the usage line, without kg / rad / s)
    tune = run("tune", "--help").stdout
    assert "[kg]" in tune and "[rad]" in tune
    assert "--until T" in run("run", "--help").stdout and "[s]" in run("run", "--help").stdout
    em = run("engine-map", "--help").stdout
    assert "--spool" in em and "[g/kWh]" in em
    assert "--preset NAME" in run("run", "--preset", "m1", "--help").stdout


def test_unknown_command():
    out = run("frobnicate")
    assert out.returncode == 2 and "unknown command 'frobnicate'" in out.stderr


def test_run_preset_writes_series_and_summary(tmp_path):
    out = run("run", "--preset", "pointmass-prescribed", "--out", str(tmp_path / "o"),
              "--until", "5")
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "o" / "series.csv") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[0] == "t" and "vehicle.speed" in header
    assert len(rows) == 1 + 5 * 500 + 1  # header + rows 0..2500 at 500 Hz
    summary = json.load(open(tmp_path / "o" / "summary.json"))
    units = {c["name"]: c["unit"] for c in summary["channels"]}
    assert units["vehicle.speed"] == "m/s" and units["t"] == "s"
    assert summary["dof"] == 1 and summary["config"]["run"]["kind"] == "pointmass"
    (work,) = summary["integrators"]  # one CVODE integrator, its counters
    assert work["integrator"] == "pointmass" and work["steps"] > 0
    assert work["rhs_evals"] >= work["steps"] and work["newton_iters"] >= work["steps"]
    assert f"{work['steps']} integrator steps" in out.stdout
    v = [float(r[header.index("vehicle.speed")]) for r in rows[1:]]
    assert v[0] == 0 and all(b >= a - 1e-9 for a, b in zip(v, v[1:]))  # accelerates


def test_config_file_errors_name_the_field(tmp_path):
    cfg = tmp_path / "bad.json"
    cfg.write_text(json.dumps({"preset": "pointmass-prescribed",
                               "track": {"n_trans": 99}, "vehicle": {"mass": "heavy"}}))
    out = run("run", str(cfg), "--out", str(tmp_path / "o"))
    assert out.returncode != 0
    assert "/track/n_trans" in out.stderr and "/vehicle/mass" in out.stderr
    out = run("run", str(tmp_path / "missing.json"))
    assert out.returncode != 0 and "missing.json" in out.stderr
    out = run("run", "--preset", "nope")
    assert out.returncode != 0 and "no preset named 'nope'" in out.stderr


def test_run_arguments_are_checked(tmp_path):
    # --until was read with an unchecked strtod ('abc' ran to 0 s, -3 ran
    # nothing, 50 was cut to the 30-s duration without a word) and unknown
    # arguments were ignored: each is now a usage error naming the argument
    o = str(tmp_path / "o")
    for bad, said in [(["--until", "-3"], "--until: number in [0, 30]"),
                      (["--until", "abc"], "got 'abc'"),
                      (["--until", "0x10"], "got '0x10'"),  # plain decimal, as the daemon's
                      (["--until", " 5"], "got ' 5'"),
                      (["--until", "50"], "--until: number in [0, 30], got '50'"),
                      (["--until=5"], "unknown argument '--until=5'"),
                      (["--bogus", "1"], "unknown argument '--bogus'"),
                      (["--out"], "unknown argument '--out'"),
                      (["second.json"], "give either CONFIG.json or --preset NAME")]:
        out = run("run", "--preset", "pointmass-prescribed", "--out", o, *bad) if bad != ["--out"] \
            else run("run", "--preset", "pointmass-prescribed", "--out")
        assert out.returncode == 2, (bad, out.stderr)
        assert said in out.stderr, (bad, out.stderr)
    assert not os.path.exists(o)  # nothing was run
    # a missing or unreadable config names its path once
    out = run("run", str(tmp_path / "missing.json"))
    assert out.returncode == 1 and out.stderr.count("missing.json") == 1, out.stderr
    (tmp_path / "bad.json").write_text("{bad")
    out = run("run", str(tmp_path / "bad.json"))
    assert out.returncode == 1 and out.stderr.count("bad.json") == 1, out.stderr
    assert "bad.json:1:" in out.stderr


def test_what_cannot_be_done_exactly_is_refused(tmp_path):
    # Found by an audit (session 16): each of these ran and exited 0, doing
    # something other than what was asked.
    o = str(tmp_path / "o")
    # an end between two sample rows was floored without a word (0.0031 s ran 0.002)
    out = run("run", "--preset", "pointmass-prescribed", "--until", "0.0031", "--out", o)
    assert out.returncode == 2 and "--until: a whole number of sample periods" in out.stderr, out.stderr
    assert "nearest 0.002 or 0.004 s" in out.stderr
    cfg = tmp_path / "grid.json"  # the daemon's session never reached such a duration's end
    cfg.write_text(json.dumps({"preset": "pointmass-prescribed", "run": {"duration": 1.5, "sample_rate": 1}}))
    out = run("run", str(cfg), "--out", o)
    assert out.returncode == 1 and "/run/duration: a whole number of sample periods" in out.stderr, out.stderr
    # a key given twice: the second "run" replaced the first (a 30-s run for a 0.2-s one)
    cfg.write_text('{"preset": "pointmass-prescribed", "run": {"duration": 0.2}, "run": {"sample_rate": 100}}')
    out = run("run", str(cfg), "--out", o)
    assert out.returncode == 1 and "duplicate" in out.stderr, out.stderr
    out = run("run", "--preset", "pointmass-prescribed", "--out", "")
    assert out.returncode == 2 and "--out" in out.stderr, out.stderr
    assert not os.path.exists(o)
    # a run that fails leaves no summary of an earlier run beside its series
    cfg.write_text(json.dumps({"preset": "pointmass-prescribed", "run": {"duration": 0.1}}))
    assert run("run", str(cfg), "--out", o).returncode == 0
    assert os.path.exists(os.path.join(o, "summary.json"))
    os.remove(os.path.join(o, "series.csv"))
    os.mkdir(os.path.join(o, "series.csv"))  # this run cannot write its series
    out = run("run", str(cfg), "--out", o)
    assert out.returncode == 1 and "series.csv" in out.stderr, out.stderr
    assert not os.path.exists(os.path.join(o, "summary.json"))
    # engine-map's --out and --spool are alternatives: --out was ignored
    out = run("engine-map", "--preset", "engine-map-conventional", "--out", str(tmp_path / "m.csv"),
              "--spool", str(tmp_path / "s.csv"))
    assert out.returncode == 2 and "not both" in out.stderr, out.stderr
    # neither: the message names both (it named --out alone, session-32 review)
    out = run("engine-map", "--preset", "engine-map-conventional")
    assert out.returncode == 2 and "--out" in out.stderr and "--spool" in out.stderr, out.stderr
    # output that cannot be written is a failure (modes and tune exited 0)
    with open("/dev/full", "w") as full:
        r = subprocess.run([TANKSIM, "modes", "--preset", "m1"], stdout=full, stderr=subprocess.PIPE,
                           text=True, timeout=60)
    assert r.returncode == 1 and "cannot write the output" in r.stderr, r.stderr


def test_modes_only_presets_are_not_run(tmp_path):
    # m1 and table1-span are the eigenanalyses of Fig. 5 and Table 1: they set no
    # /run, and `run` used to go on with the default point-mass scenario
    for preset in ("m1", "table1-span"):
        out = run("run", "--preset", preset, "--out", str(tmp_path / preset))
        assert out.returncode == 1 and "/preset" in out.stderr and "modes" in out.stderr, out.stderr
        assert not (tmp_path / preset).exists()
        assert run("modes", "--preset", preset).returncode == 0
    half = tmp_path / "m1-half.json"  # a /run without a kind still says nothing of what to run
    half.write_text(json.dumps({"preset": "m1", "run": {"duration": 0.1}}))
    out = run("run", str(half), "--out", str(tmp_path / "h"))
    assert out.returncode == 1 and "/run/kind" in out.stderr, out.stderr
    cfg = tmp_path / "m1-run.json"  # with its own /run/kind the preset is a starting point
    cfg.write_text(json.dumps({"preset": "m1", "run": {"kind": "pointmass", "duration": 0.1}}))
    out = run("run", str(cfg), "--out", str(tmp_path / "o"))
    assert out.returncode == 0, out.stderr


def test_long_run_reports_progress_on_stderr(tmp_path):
    # A run of more than PROGRESS_FIRST (2 s) wall time says how far it is on
    # stderr (simulated time, share, real-time factor); stdout keeps its one
    # summary line. Before, an hour-long run printed nothing until its end.
    # 200 s of the crank-angle point-mass launch take ~6 s wall here (33x real
    # time): a machine three times faster still passes the 2-s mark.
    cfg = tmp_path / "long.json"
    cfg.write_text(json.dumps({"preset": "accel-pointmass-conventional", "run": {"duration": 200}}))
    out = run("run", str(cfg), "--out", str(tmp_path / "o"))
    assert out.returncode == 0, out.stderr
    assert len(out.stdout.strip().splitlines()) == 1, out.stdout
    lines = [l for l in out.stderr.splitlines() if l.startswith("tanksim run: t = ")]
    assert lines, out.stderr
    assert " of 200.000 s (" in lines[0] and "x real time" in lines[0], lines


def test_ctrl_c_stops_at_a_whole_row_and_says_where(tmp_path):
    """CLI review, session 20: SIGINT left series.csv ending in half a row
    (35 of 65 columns) and printed nothing. Now the run stops after the row it
    is writing, says up to where series.csv holds rows, writes no summary and
    exits 128 + 2."""
    import signal
    import time
    out = tmp_path / "o"
    p = subprocess.Popen([TANKSIM, "run", "--preset", "bump-coupled-ivs5mph", "--out", str(out)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # rows on disk (stdio's first flush, 4 kB) mean the handler is installed:
    # a fixed sleep could land before it on a loaded machine
    deadline = time.time() + 60
    while time.time() < deadline and not (
            (out / "series.csv").exists() and (out / "series.csv").stat().st_size > 4096):
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, (p.returncode, err)
    assert "stopped by signal 2" in err and "holds the rows up to t =" in err, err
    rows = list(csv.reader(open(out / "series.csv")))
    assert len(rows) > 2 and all(len(r) == len(rows[0]) for r in rows), len(rows)
    said = float(err.split("holds the rows up to t = ")[1].split(" s")[0])
    assert abs(float(rows[-1][0]) - said) < 1e-9, (rows[-1][0], said)
    assert not (out / "summary.json").exists()


def test_summary_config_echo_reruns_bit_for_bit(tmp_path):
    """CLI review, session 20: the echo kept 10 digits, so a torque of
    8850.123456789012 came back as 8850.123457 and its re-run differed."""
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"preset": "bump-prescribed-static", "run": {"duration": 2.0},
                               "drive": {"torque": 8850.123456789012}}))
    assert run("run", str(cfg), "--out", str(tmp_path / "a")).returncode == 0
    echo = json.load(open(tmp_path / "a" / "summary.json"))["config"]
    assert echo["drive"]["torque"] == 8850.123456789012
    (tmp_path / "e.json").write_text(json.dumps(echo))
    assert run("run", str(tmp_path / "e.json"), "--out", str(tmp_path / "b")).returncode == 0
    assert open(tmp_path / "a" / "series.csv").read() == open(tmp_path / "b" / "series.csv").read()


def test_out_that_is_a_file_is_named_as_such(tmp_path):
    f = tmp_path / "f"
    f.write_text("")
    out = run("run", "--preset", "pointmass-prescribed", "--out", str(f))
    assert out.returncode == 1 and "is not a directory" in out.stderr, out.stderr


def test_engine_map_output_problems_are_found_first_and_named(tmp_path):
    """CLI review, session 20: an unwritable --out failed only after the whole
    sweep with no reason, /dev/full failed silently, and a full disk left an
    empty file. Now the file is opened first, errors carry strerror, a regular
    file appears only complete (written beside and renamed), and a device is
    written in place (never replaced)."""
    import stat
    import time
    t0 = time.time()
    out = run("engine-map", "--preset", "engine-map-conventional",
              "--out", str(tmp_path / "no" / "such" / "m.csv"))
    assert out.returncode == 1 and "No such file or directory" in out.stderr, out.stderr
    assert time.time() - t0 < 5 and "rpm" not in out.stderr  # no sweep ran
    out = run("engine-map", "--preset", "bump-coupled-rack90", "--out", "/dev/full")
    assert out.returncode == 1 and "No space left on device" in out.stderr, out.stderr
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)
    out = run("engine-map", "--preset", "bump-coupled-rack90", "--out", str(tmp_path / "m.csv"))
    assert out.returncode == 0, out.stderr
    assert sorted(os.listdir(tmp_path)) == ["m.csv", "m.csv.json"]  # and its sidecar, no .tmp


def test_a_directory_as_config_is_named_as_such(tmp_path):
    """CLI review, session 20: it read as a JSON error at line 1."""
    out = run("modes", str(tmp_path))
    assert out.returncode == 1 and "a directory, not a config file" in out.stderr, out.stderr


def test_course_dir_of_ones_own_is_read_even_for_a_shipped_name(tmp_path):
    """CLI review, session 20: with /terrain/course_dir set, a course file named
    like a shipped one (apg4-synth) was ignored for the built-in course, while
    the summary echoed the directory. Now the directory given is read."""
    (tmp_path / "apg4-synth.txt").write_text("length 100\n3 0.5 2\n")  # one 0.5-m bump at 3 m
    def peak(over):
        cfg = tmp_path / "c.json"
        cfg.write_text(json.dumps({"preset": "bump-prescribed-static", "run": {"duration": 1.0},
                                   "terrain": over}))
        out = run("run", str(cfg), "--out", str(tmp_path / "o"))
        assert out.returncode == 0, out.stderr
        return json.load(open(tmp_path / "o" / "summary.json"))["metrics"]["peak_tension"]["value"]
    shipped = peak({})
    own = peak({"course_dir": str(tmp_path)})
    assert own > 2 * shipped, (own, shipped)  # the shipped course's first bump is at 15 m


def test_engine_map_leaves_unmodelled_cells_empty(tmp_path):
    """CLI review, session 20: the map engine's sweep wrote 0 Pa peak pressure
    and 0 for eta_v/eta_i/q_wall, read as results. Empty now (null in JSON)."""
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"preset": "engine-map-conventional", "engine": {"fidelity": "map"}}))
    out = run("engine-map", str(cfg), "--out", str(tmp_path / "m.csv"))
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(open(tmp_path / "m.csv")))
    head = [h.split(" ")[0] for h in rows[0]]
    for r in rows[1:]:
        for name in ("peak_pressure", "eta_v", "eta_i", "q_wall", "energy_residual"):
            assert r[head.index(name)] == "", (name, r)
        assert float(r[head.index("torque")]) > 0 and float(r[head.index("bsfc")]) > 150
