"""The CLI's mutation pass (session 28): each test here was seen to fail with
one small edit of cli/*.c applied (named in its docstring) and to pass on the
source; each is a behaviour a user of tanksim meets."""
import json
import os
import subprocess

from conftest import TANKSIM


def run(*args, cwd=None):
    return subprocess.run([TANKSIM, *args], capture_output=True, text=True, cwd=cwd, timeout=300)


def test_a_flag_right_after_the_command_is_taken(tmp_path):
    """tsc_flag searching from argv[2]: `tanksim render --no-overlay --preset ...`
    (the flag first) was an "unknown argument" and exit 2."""
    for flag in ("--no-overlay", "--antialias"):
        out = tmp_path / "f.png"
        r = run("render", flag, "--preset", "bump-prescribed-static", "--width", "32",
                "--height", "32", "--out", str(out))
        assert r.returncode == 0, (flag, r.stderr)
        assert out.exists()
        out.unlink()


def test_a_config_error_names_its_field_once(tmp_path):
    """print_line always putting the pointer first: a message that already
    starts with it read "/track/n_trans: /track/n_trans: integer in ..."."""
    cfg = tmp_path / "bad.json"
    cfg.write_text(json.dumps({"preset": "pointmass-prescribed", "track": {"n_trans": 99}}))
    r = run("run", str(cfg), "--out", str(tmp_path / "o"))
    assert r.returncode == 1
    line = [l for l in r.stderr.splitlines() if "/track/n_trans" in l]
    assert line == ["tanksim: config error: /track/n_trans: integer in [0, 16], got 99"], r.stderr


def test_a_second_config_is_refused_not_used(tmp_path):
    """tsc_load_config taking the last CONFIG.json, not the first: `tanksim run
    a.json b.json` ran b.json (or failed on it) instead of saying the second
    one is not understood."""
    a = tmp_path / "a.json"
    a.write_text(json.dumps({"preset": "pointmass-prescribed", "run": {"duration": 0.01}}))
    r = run("run", str(a), str(tmp_path / "b.json"), "--out", str(tmp_path / "o"))
    assert r.returncode == 2, r.stderr
    assert "unknown argument '%s'" % (tmp_path / "b.json") in r.stderr, r.stderr
    assert not (tmp_path / "o").exists()



def test_outputs_that_cannot_be_put_in_place_leave_no_temporaries(tmp_path):
    """tsc_out_close not removing its temporary: an engine map whose CSV name
    fits but whose sidecar's (FILE.csv.json, 5 characters more) is too long
    failed, and left the CSV's temporary (FILE.csv.XXXXXX) behind."""
    d = os.path.join(*["d" * 200] * 5)
    os.makedirs(tmp_path / d)
    csv = os.path.join(d, "m" * (1090 - len(d) - 5) + ".csv")  # 1090 characters: fits
    r = run("engine-map", "--preset", "bump-coupled-rack90", "--out", csv, cwd=tmp_path)
    assert r.returncode == 1 and "path too long" in r.stderr, r.stderr
    assert os.listdir(tmp_path / d) == []


def test_no_command_is_a_usage_error_and_h_is_help():
    """main: `tanksim` alone printed the usage but exited 0 (a script saw
    success); `tanksim -h` (for --help) was an unknown command."""
    r = run()
    assert r.returncode == 2 and r.stderr.startswith("usage: tanksim COMMAND"), r
    r = run("-h")
    assert r.returncode == 0 and r.stdout.startswith("usage: tanksim COMMAND"), r


def test_out_of_the_longest_length_is_taken(tmp_path):
    """run --out: 1 to 1000 characters (`>=` for `>` refused exactly 1000)."""
    out = os.path.join(*["o" * 199] * 4, "o" * 200)
    assert len(out) == 1000
    r = run("run", "--preset", "pointmass-prescribed", "--until", "0.01", "--out", out, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / out / "summary.json").exists()
    r = run("run", "--preset", "pointmass-prescribed", "--until", "0.01", "--out", out + "o",
            cwd=tmp_path)
    assert r.returncode == 2 and "1 to 1000 characters" in r.stderr, r.stderr


def test_summary_counts_the_rows_and_keeps_metrics_not_reached(tmp_path):
    """run's summary.json: "samples" is the number of rows in series.csv (the
    count without the row at t = 0 was one short), and a figure the run did not
    reach (0-60 km/h in 0.05 s) is there as null (json_real(NaN) dropped it)."""
    r = run("run", "--preset", "pointmass-prescribed", "--until", "0.05", "--out",
            str(tmp_path / "o"))
    assert r.returncode == 0, r.stderr
    rows = open(tmp_path / "o" / "series.csv").read().splitlines()
    summary = json.load(open(tmp_path / "o" / "summary.json"))
    assert summary["samples"] == len(rows) - 1 == 26, (summary["samples"], len(rows))
    m = summary["metrics"]
    assert m["t_0_60_kmh_s"]["value"] is None and m["t_0_60_kmh_s"]["unit"] == "s", m
    assert m["speed_at_end_kmh"]["value"] > 0


def test_render_color_none_is_still_plain(tmp_path):
    """render --color: tension or plain, and "none", its word before plain,
    still taken (scripts of earlier sessions use it): it was refused, exit 2."""
    out = tmp_path / "f.png"
    r = run("render", "--preset", "bump-prescribed-static", "--width", "32", "--height", "32",
            "--color", "none", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_engine_map_progress_lines_are_the_rows_from_rated_down(tmp_path):
    """engine-map's stderr: one line per speed as it is done, from rated (2100
    rpm) down, each the row just finished (tools/wastegate_sweep.py reads the
    first, rated power); with the row index counted from the other end they
    began at 800 rpm with a row not yet computed."""
    r = run("engine-map", "--preset", "bump-coupled-rack90", "--out", str(tmp_path / "m.csv"))
    assert r.returncode == 0, r.stderr
    lines = [l.split() for l in r.stderr.splitlines() if l.strip().endswith("kW")]
    assert [int(l[0]) for l in lines] == list(range(2100, 799, -100)), r.stderr
    rows = [l.split(",") for l in open(tmp_path / "m.csv").read().splitlines()[1:]]
    torque = {int(row[0]): float(row[2]) for row in rows}
    for l in lines:
        assert abs(float(l[2]) - torque[int(l[0])]) < 0.06, (l, torque[int(l[0])])


def test_modes_config_errors_name_the_field_as_config_errors(tmp_path):
    """modes: a span the config makes impossible is a config error naming the
    field (/track/tension), as every command's, not "modes: ... (TS_ERR_...)"."""
    cfg = tmp_path / "m.json"
    cfg.write_text(json.dumps({"preset": "table1-span", "track": {"tension": 100}}))
    r = run("modes", str(cfg))
    assert r.returncode == 1 and r.stdout == "", r
    assert r.stderr.startswith("tanksim: config error: /track/tension: shallow-sag"), r.stderr
    assert "(TS_ERR" not in r.stderr, r.stderr


def test_tune_schedules_are_one_or_the_other():
    """tune: --schedule-mass and --schedule-grade together is a usage error
    (exit 2); without the check the grades were dropped without a word."""
    r = run("tune", "--preset", "bump-coupled-rack90", "--schedule-mass", "50000",
            "--schedule-grade", "0.1")
    assert r.returncode == 2 and "not both" in r.stderr, r.stderr
    assert r.stdout == ""


def test_render_draws_the_state_at_t_not_at_rest(tmp_path):
    """render --t T: the geometry is taken again after the run to T (without
    it every --t drew the state at rest, only the overlay's t changed)."""
    png = {}
    for t in ("0", "2"):
        out = tmp_path / f"f{t}.png"
        r = run("render", "--preset", "bump-prescribed-static", "--t", t, "--width", "160",
                "--height", "90", "--no-overlay", "--out", str(out))
        assert r.returncode == 0, r.stderr
        png[t] = out.read_bytes()
    assert png["0"] != png["2"]
