"""Survivors of a mutation pass over api/ and the daemon's routing (server/):
each test below failed with its mutant applied and passes on the source.

- GET /v1/sessions?page_size=1000 (the documented maximum) was refused when
  the query integers' upper bound was read as exclusive;
- POST .../run {"until": 0} ran the whole run when 0 was taken for "absent";
- with every=N, a page's next_page_token was the last index + 1, not + N: the
  next page left the decimation grid;
- GET .../stream?since=-1 (the documented "from the first row") was a 400;
- an FFT over exactly --max-samples samples was refused as too long, one over
  a single sample lost its /from pointer, and its "to" was a sample late;
- frame.png at one sample period past the last stored sample was drawn (the
  half-period tolerance grew to 1.5);
- an animation of exactly 600 APNG frames was refused as more than 600;
- a query name that is the tail of an accepted one (series?ormat=csv) was
  silently ignored;
- a tuning schedule's grade unit, and a cancelled analysis's "failed" flag in
  the stored list;
- /v1/modes: a span list's names counted from 0, a speed reported for a
  standing (non-gyroscopic) analysis, the frequencies' unit, the field named
  by a span error;
- a stored session whose model now gives a channel another unit was restored
  and advanced under the model's unit;
- a tune refused by a range check of its own failed with code 13 (internal),
  not 3 (invalid argument).
"""
import json
import sqlite3
import time

import pytest
import requests

from conftest import Daemon, is_problem, stepped_session, wait_op


@pytest.fixture(scope="module")
def sid50(daemon):
    """A point-mass session at 50 Hz stepped 0.6 s (rows 0..30)."""
    return stepped_session(daemon.url, step=0.6)


def test_page_size_takes_its_maximum(daemon):
    r = requests.get(daemon.url + "/v1/sessions", params={"page_size": 1000})
    assert r.status_code == 200, r.text
    is_problem(requests.get(daemon.url + "/v1/sessions", params={"page_size": 1001}), 400,
               "/page_size")


def test_run_until_zero_runs_nothing(daemon):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "pointmass-prescribed",
                            "run": {"duration": 1, "sample_rate": 50}})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    r = requests.post(f"{daemon.url}/v1/sessions/{sid}/run", json={"until": 0})
    assert r.status_code == 202, r.text
    assert r.json()["metadata"]["until"] == 0
    op = wait_op(daemon.url, r.json()["id"])
    assert "error" not in op, op
    s = requests.get(f"{daemon.url}/v1/sessions/{sid}").json()
    assert s["t"] == 0 and s["index"] == 0, s


def test_next_page_token_stays_on_the_every_grid(daemon, sid50):
    url = f"{daemon.url}/v1/sessions/{sid50}/series"
    page = requests.get(url, params={"every": 3, "page_size": 2}).json()
    assert page["index"] == [0, 3] and page["next_page_token"] == "6", page
    page = requests.get(url, params={"every": 3, "page_size": 2,
                                     "page_token": page["next_page_token"]}).json()
    assert page["index"] == [6, 9], page


def test_stream_since_minus_one_is_from_the_first_row(daemon):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "pointmass-prescribed",
                            "run": {"duration": 0.1, "sample_rate": 50}})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    r = requests.post(f"{daemon.url}/v1/sessions/{sid}/run", json={})
    assert r.status_code == 202, r.text
    wait_op(daemon.url, r.json()["id"])
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/stream",
                     params={"since": -1, "format": "ndjson"}, timeout=30)
    assert r.status_code == 200, r.text
    rows = [line for line in r.text.splitlines() if line]
    assert len(rows) == 6 and rows[0].startswith('{"index":0,'), rows


def test_fft_over_exactly_max_samples_is_taken(tmp_path):
    # rows 0..30 (0.6 s at 50 Hz): 31 samples, the limit of the first daemon
    # and one past the second's
    for limit, status in ((31, 200), (30, 422)):
        (tmp_path / str(limit)).mkdir()
        with Daemon("--max-samples", str(limit), data_dir=str(tmp_path / str(limit))) as d:
            sid = stepped_session(d.url, step=0.6)
            r = requests.get(f"{d.url}/v1/sessions/{sid}/fft", params={"channel": "vehicle.speed"})
            if status == 200:
                assert r.status_code == 200, r.text
                assert r.json()["n"] == 31
            else:
                is_problem(r, 422, "/to")


def test_fft_range_and_its_edges(daemon, sid50):
    url = f"{daemon.url}/v1/sessions/{sid50}/fft"
    r = requests.get(url, params={"channel": "vehicle.speed", "from": 0, "to": 0.5})
    assert r.status_code == 200, r.text
    f = r.json()
    assert f["from"] == 0 and f["to"] == pytest.approx(0.5, abs=1e-12) and f["n"] == 26, f
    # a single sample: 400 naming /from, as a range past the stored end is
    p = is_problem(requests.get(url, params={"channel": "vehicle.speed", "from": 0.2, "to": 0.2}),
                   400, "/from")
    assert "at least 2" in p["detail"], p


def test_frame_one_period_past_the_last_sample_is_400(daemon, sid50):
    # rows 0..30 at 50 Hz: 0.6 s is the last; 0.61 (half a period on) is still
    # that sample, 0.62 (a whole period on) is not stored
    url = f"{daemon.url}/v1/sessions/{sid50}/frame.png"
    p = is_problem(requests.get(url, params={"t": 0.62}), 400, "/t")
    assert "at most 0.6 s" in p["detail"], p
    # the point mass draws no frames: a time it accepts gets that 422, not /t
    p = is_problem(requests.get(url, params={"t": 0.61}), 422)
    assert "geometry" in p["detail"], p


def test_apng_of_exactly_600_frames_is_not_refused_as_too_many(daemon, sid50):
    url = f"{daemon.url}/v1/sessions/{sid50}/frames"
    # 0.6 s at fps f: floor(0.6 f) + 1 frames; 999.1666 -> 600 (the limit), 1000 -> 601
    p = is_problem(requests.get(url, params={"fps": 1000}), 422, "/fps")
    assert "601 frames requested, at most 600" in p["detail"], p
    p = is_problem(requests.get(url, params={"fps": 999.1666}), 422)
    assert p["type"] != "/problems/limit" and "geometry" in p["detail"], p


def test_a_tail_of_an_accepted_query_name_is_unknown(daemon, sid50):
    for name in ("ormat", "o", "annels"):
        is_problem(requests.get(f"{daemon.url}/v1/sessions/{sid50}/series",
                                params={name: "csv"}), 400, "/" + name)


def test_grade_schedule_is_in_radians(daemon):
    r = requests.post(daemon.url + "/v1/tune?schedule_grade=0.01",
                      json={"preset": "bump-coupled-ivs5mph"}, timeout=30)
    assert r.status_code == 202, r.text
    op = wait_op(daemon.url, r.json()["id"], timeout=120)
    s = op["response"]["schedule"]
    assert s["var"] == "grade" and s["x"] == [0.01], s
    assert s["units"] == {"x": "rad", "kp": "1/(m/s)", "ti": "s"}, s


def test_a_cancelled_analysis_is_listed_as_failed(daemon):
    r = requests.post(daemon.url + "/v1/tune",
                      json={"preset": "bump-coupled-ivs5mph",
                            "engine": {"fidelity": "crank_angle"},
                            "control": {"tune_settle": 1800, "tune_duration": 1800}}, timeout=30)
    assert r.status_code == 202, r.text
    op_id = r.json()["id"]
    time.sleep(0.5)
    assert requests.post(f"{daemon.url}/v1/operations/{op_id}:cancel").status_code == 200
    op = wait_op(daemon.url, op_id, timeout=120)
    assert op["error"]["code"] == 1, op
    entry = requests.get(f"{daemon.url}/v1/analyses/{op_id}").json()
    assert entry["done"] is True and entry["error_code"] == 1, entry
    assert entry["failed"] is True, entry
    listed = [a for a in requests.get(daemon.url + "/v1/analyses").json()["analyses"]
              if a["id"] == op_id]
    assert listed and listed[0]["failed"] is True, listed


def test_modes_names_units_speed_and_error_fields(daemon):
    url = daemon.url + "/v1/modes"
    # a span list of the config's own: its spans are span_1, span_2 (counted from 1)
    r = requests.post(url, json={"preset": "m1", "track": {"span_length": [1.0, 2.0],
                                                           "span_inclination": [0, 0.1]}})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert [s["name"] for s in doc["spans"]] == ["span_1", "span_2"]
    assert doc["units"]["frequencies_hz"] == "Hz" and doc["units"]["length_m"] == "m"
    # a speed without the translation terms is not a moving-track analysis: speed 0
    r = requests.post(url, json={"preset": "m1", "track": {"modes_speed": 5}})
    assert r.status_code == 200, r.text
    c = r.json()["circuit"]
    assert c["gyroscopic"] is False and c["speed_m_s"] == 0, c["speed_m_s"]
    # a tension one of the listed spans refuses (20 m: the shallow-sag
    # condition) names /track/tension, not the span's own /span/tension
    p = is_problem(requests.post(url, json={"preset": "m1", "track": {
        "span_length": [1.0, 20.0], "span_inclination": [0, 0], "tension": 10000}}), 400,
        "/track/tension")
    assert [e["pointer"] for e in p["errors"]] == ["/track/tension"], p


def test_a_changed_unit_is_served_as_stored(tmp_path):
    """The model builds and has the same channel names, but one unit differs
    from the stored list (an upgrade changed it): the rows keep the stored
    unit and the session is not advanced, as for a renamed channel
    (test_stored_channels.py)."""
    data = str(tmp_path)
    d = Daemon(data_dir=data)
    try:
        sid = stepped_session(d.url, step=0.2)
    finally:
        assert d.stop() == 0
    with sqlite3.connect(f"{data}/tanksimd.db") as c:
        ((text,),) = c.execute("SELECT channels FROM sessions WHERE seq=1").fetchall()
        stored = json.loads(text)
        name = stored["channels"][1]["name"]
        stored["channels"][1]["unit"] = "old-" + stored["channels"][1]["unit"]
        c.execute("UPDATE sessions SET channels=? WHERE seq=1", (json.dumps(stored),))
    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed" and "other channels" in s["error"], s
        ser = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"channels": name}).json()
        assert ser["channels"][1]["unit"] == stored["channels"][1]["unit"], ser["channels"]
        is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}), 409)
    finally:
        assert d.stop() == 0


def test_a_tune_its_range_refuses_fails_as_invalid_argument(daemon):
    # settle + step response past a run's longest (3600 s): refused before the
    # tune is queued (session 32; it was a 202 and an operation that failed)
    r = requests.post(daemon.url + "/v1/tune",
                      json={"preset": "bump-coupled-ivs5mph",
                            "control": {"tune_settle": 3000, "tune_duration": 1000}}, timeout=30)
    is_problem(r, 400, "/control/tune_duration")
    # a range refusal only the runs can find (the full-rack speed still rising
    # after 2 s): TS_ERR_RANGE in the operation, an invalid argument (code 3)
    # like a TS_ERR_PARAM, not an internal error (13)
    r = requests.post(daemon.url + "/v1/tune",
                      json={"preset": "bump-coupled-ivs5mph", "control": {"tune_duration": 2}},
                      timeout=30)
    assert r.status_code == 202, r.text
    op = wait_op(daemon.url, r.json()["id"], timeout=60)
    e = op["error"]
    assert e["code"] == 3 and e["status"] == 400, e
    assert "/control/tune_duration" in e["message"], e
