"""POST /v1/engine-map and POST /v1/tune: the engine's full-load map (paper
Fig. 18, `tanksim engine-map`) and the IVS Ziegler-Nichols tuning (Eqs. 11-12,
Figs. 26-27, `tanksim tune`) over HTTP, as operations (202, progress in
parts, the document as the response, :cancel). The CLI and the daemon build
the documents with the same code (api/analysis_json.c), so their numbers must
agree; the physics checks themselves live in tests/cli/test_engine_map.py,
tests/cli/test_tune_coupled.py and tests/sim/test_analysis_calls.c."""
import csv
import json
import math
import subprocess
import time

import pytest
import requests

from conftest import TANKSIM, Daemon, is_problem, wait_op

MEAN_VALUE_DYNO = {"run": {"kind": "engine_dyno"}, "engine": {"fidelity": "mean_value"},
                   "control": {"rack": 1.0}}
CRANK_MAP = {"preset": "engine-map-conventional"}  # crank-angle: ~3 s on this machine


@pytest.fixture(scope="module")
def daemon():
    d = Daemon("--threads", "2")  # analyses cap = threads - 1 = 1
    yield d
    d.stop()


def start(url, path, body, query=""):
    r = requests.post(url + path + query, json=body, timeout=30)
    assert r.status_code == 202, r.text
    op = r.json()
    assert r.headers["Location"] == "/v1/operations/" + op["id"]
    return op


def close(a, b, rel=1e-5):
    if isinstance(a, dict):
        assert set(a) == set(b), (set(a) ^ set(b))
        for k in a:
            close(a[k], b[k], rel)
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            close(x, y, rel)
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=rel, abs=1e-9)
    else:
        assert a == b


def test_engine_map_operation_matches_the_cli_csv(daemon, tmp_path):
    op = start(daemon.url, "/v1/engine-map", MEAN_VALUE_DYNO)
    assert op["metadata"]["kind"] == "engine_map" and op["metadata"]["parts_total"] == 14
    seen = []
    op = wait_op(daemon.url, op["id"], timeout=60, seen=seen)
    assert "error" not in op, op
    assert op["metadata"]["progress"] == 1.0 and op["metadata"]["parts_done"] == 14
    doc = op["response"]
    cols = [c["name"] for c in doc["columns"]]
    units = {c["name"]: c["unit"] for c in doc["columns"]}
    assert units["torque"] == "N*m" and units["power"] == "W" and units["boost"] == "Pa"
    assert [r[cols.index("speed_rpm")] for r in doc["rows"]] == list(range(800, 2101, 100))
    cfg = tmp_path / "cfg.json"
    cfg.write_text(json.dumps(MEAN_VALUE_DYNO))
    out = subprocess.run([TANKSIM, "engine-map", str(cfg), "--out", str(tmp_path / "m.csv")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(open(tmp_path / "m.csv")))
    # the CSV header is "name [unit]" of the same column table
    assert rows[0] == [f"{c['name']} [{c['unit']}]" for c in doc["columns"]]
    for got, want in zip(doc["rows"], rows[1:]):
        for g, w in zip(got, want):  # the CSV rounds to its printed digits
            if w == "":  # not modelled by this fidelity: null in the document
                assert g is None, (got, want)
                continue
            assert g == pytest.approx(float(w), rel=2e-3, abs=2e-3 + 1e-3 * abs(float(w)))
    rated = doc["rated"]
    assert rated["speed_rpm"] == 2100
    assert rated["power_w"] == pytest.approx(doc["rows"][-1][cols.index("power")])
    assert rated["units"] == {"speed_rpm": "rpm", "power_w": "W", "power_hp": "hp",
                              "torque": "N*m"}
    assert rated["power_hp"] == pytest.approx(rated["power_w"] / 745.699872, rel=1e-6)
    assert rated["power_w"] == pytest.approx(rated["torque"] * 2100 * math.pi / 30, rel=1e-6)


def test_tune_operation_equals_the_cli(daemon):
    op = start(daemon.url, "/v1/tune", {"preset": "bump-coupled-ivs5mph"})
    assert op["metadata"]["kind"] == "tune" and op["metadata"]["parts_total"] == 1
    op = wait_op(daemon.url, op["id"], timeout=60)
    assert "error" not in op, op
    cli = subprocess.run([TANKSIM, "tune", "--preset", "bump-coupled-ivs5mph"],
                         capture_output=True, text=True, timeout=120)
    assert cli.returncode == 0, cli.stderr
    close(op["response"], json.loads(cli.stdout))


def test_tune_schedule_over_mass(daemon):
    # EVIDENCE: Fig. 27's schedule; the same three masses as tests/cli/test_tune_coupled.py
    op = start(daemon.url, "/v1/tune", {"preset": "bump-coupled-ivs5mph"},
               "?schedule_mass=50000,60000,70000")
    assert op["metadata"]["parts_total"] == 4
    op = wait_op(daemon.url, op["id"], timeout=60)
    s = op["response"]["schedule"]
    assert s["var"] == "mass" and s["x"] == [50000.0, 60000.0, 70000.0]
    assert s["kp"][0] < s["kp"][1] < s["kp"][2]
    assert s["units"] == {"x": "kg", "kp": "1/(m/s)", "ti": "s"}
    assert set(op["response"]["units"]) >= {"x", "y", "kp", "ti", "ti_factor"}


@pytest.mark.parametrize("query,pointer", [
    ("?schedule_mass=abc", "/schedule_mass"),
    ("?schedule_mass=50000,", "/schedule_mass"),
    ("?schedule_mass=0x10", "/schedule_mass"),
    ("?schedule_mass=1e9", "/schedule_mass"),          # beyond /vehicle/mass's range
    ("?schedule_grade=0.9", "/schedule_grade"),        # beyond /vehicle/grade's range
    ("?schedule_mass=" + ",".join(str(50000 + 1000 * i) for i in range(17)), "/schedule_mass"),  # more than 16
    ("?schedule_mass=60000,50000", "/schedule_mass"),  # not increasing (it becomes /control/schedule_x)
    ("?schedule_mass=60000&schedule_grade=0.1", "/schedule_grade"),
    ("?schedule=60000", "/schedule"),                  # a parameter the route does not take
])
def test_tune_schedule_errors_name_the_parameter(daemon, query, pointer):
    r = requests.post(daemon.url + "/v1/tune" + query, json={"preset": "bump-coupled-ivs5mph"})
    is_problem(r, 400, pointer)


def test_config_errors_name_the_field(daemon):
    for path in ("/v1/engine-map", "/v1/tune"):
        is_problem(requests.post(daemon.url + path, json={"preset": "nope"}), 400, "/preset")
        is_problem(requests.post(daemon.url + path, json={"engine": {"fidelity": "warp"}}), 400,
                   "/engine/fidelity")
        # m1 is a preset for `modes` only
        is_problem(requests.post(daemon.url + path, json={"preset": "m1"}), 400, "/preset")
        is_problem(requests.post(daemon.url + path, data="{"), 400)


def test_cancel_stops_after_the_part_in_progress(daemon):
    op = start(daemon.url, "/v1/engine-map", CRANK_MAP)
    r = requests.post(f"{daemon.url}/v1/operations/{op['id']}:cancel")
    assert r.status_code == 200, r.text
    t0 = time.time()
    op = wait_op(daemon.url, op["id"], timeout=30)
    assert time.time() - t0 < 10  # one ~0.3-s speed point, not the whole ~3-s sweep
    assert op["error"]["code"] == 1 and "cancelled after" in op["error"]["message"]
    assert op["metadata"]["parts_done"] < 14 and op["metadata"]["progress"] < 1


def test_cancel_stops_a_tune_inside_its_step_response(daemon):
    # A probe (session 24) tuned with 1800-s settle and step runs: the cancel
    # took 74-349 s, because the tune asked only between its parts. Its runs
    # now ask every 16 samples (ts_ivs_tune_polled): a 3600-s crank-angle
    # response (~100 s of work) stops within a few seconds of the cancel.
    op = start(daemon.url, "/v1/tune", {"preset": "bump-coupled-ivs5mph",
                                        "engine": {"fidelity": "crank_angle"},
                                        "control": {"tune_settle": 1800, "tune_duration": 1800}})
    time.sleep(1.0)
    r = requests.post(f"{daemon.url}/v1/operations/{op['id']}:cancel")
    assert r.status_code == 200, r.text
    t0 = time.time()
    op = wait_op(daemon.url, op["id"], timeout=60)
    assert time.time() - t0 < 5, time.time() - t0
    assert op["error"]["code"] == 1 and "cancelled" in op["error"]["message"], op["error"]


def test_one_analysis_at_a_time_with_two_workers(daemon):
    first = start(daemon.url, "/v1/engine-map", CRANK_MAP)
    r = requests.post(daemon.url + "/v1/tune", json={"preset": "bump-coupled-ivs5mph"})
    p = is_problem(r, 429)
    assert "at most 1" in p["detail"]
    # session runs still have a worker meanwhile
    s = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "pointmass-prescribed",
                            "run": {"duration": 1.0, "sample_rate": 50}})
    assert s.status_code == 201, s.text
    r = requests.post(f"{daemon.url}/v1/sessions/{s.json()['id']}/step", json={"duration": 1.0})
    assert r.status_code == 200, r.text
    requests.post(f"{daemon.url}/v1/operations/{first['id']}:cancel")
    wait_op(daemon.url, first["id"], timeout=30)
    # the slot is free again
    op = start(daemon.url, "/v1/tune", {"preset": "bump-coupled-ivs5mph"})
    assert "error" not in wait_op(daemon.url, op["id"], timeout=60)


def test_shutdown_ends_a_running_analysis():
    d = Daemon()
    try:
        start(d.url, "/v1/engine-map", CRANK_MAP)
        time.sleep(0.3)
        t0 = time.time()
        assert d.stop() == 0
        assert time.time() - t0 < 10  # stops after the speed point in progress
    finally:
        d.stop()
