"""Requests the daemon used to answer with something other than what was asked.

Found by a first-use review (session 11), each reproduced before the fix:
- a step of 0.0015 s at 500 Hz answered 200 and advanced nothing; a run to
  5.001 s stopped at 5.0 and reported done (sim/model.c rounds the end down to
  a sample): now 400 naming /duration or /until, with the two nearest times;
- an unknown query parameter (series?chanels=..., fft?window=hann) was ignored
  and a repeated one (frame.png?t=7.9&t=3) used its first value: now 400
  naming it, as unknown JSON body fields are;
- frame.png?width=100.5 drew 100 px and overlay=0.3 read as on: integers and
  0/1 flags are now checked as such (api/openapi.yaml types them so);
- a config the model cannot solve (no static equilibrium) was a 500, as if
  the server had failed: now 422;
- a config storing 72 million rows (3600 s at 20 kHz, ~24 GB) was accepted:
  --max-rows refuses it with 400 naming /run/duration;
- the spectrum gave no unit for its frequencies: now a units object.
"""
import json
import os

import pytest
import requests

from conftest import Daemon, is_problem, sse_events


@pytest.fixture(scope="module")
def sid500(daemon):
    """A point-mass session at the preset's 500 Hz, stepped 0.1 s."""
    r = requests.post(daemon.url + "/v1/sessions", json={"preset": "pointmass-prescribed"})
    assert r.status_code == 201, r.text
    s = r.json()["id"]
    r = requests.post(f"{daemon.url}/v1/sessions/{s}/step", json={"duration": 0.1})
    assert r.status_code == 200, r.text
    return s


def test_step_between_samples_is_400_naming_duration(daemon, sid500):
    url = f"{daemon.url}/v1/sessions/{sid500}"
    t0 = requests.get(url).json()["t"]
    p = is_problem(requests.post(url + "/step", json={"duration": 0.0015}), 400, "/duration")
    assert "0.002" in p["detail"], p  # the sample period and the nearest valid step
    assert requests.get(url).json()["t"] == pytest.approx(t0)  # nothing advanced
    r = requests.post(url + "/step", json={"duration": 0.004})
    assert r.status_code == 200 and r.json()["t"] == pytest.approx(t0 + 0.004), r.text


def test_run_to_a_time_between_samples_is_400_naming_until(daemon, sid500):
    url = f"{daemon.url}/v1/sessions/{sid500}"
    p = is_problem(requests.post(url + "/run", json={"until": 5.001}), 400, "/until")
    assert "5.002" in p["detail"] and "nearest 5 " in p["detail"], p


def test_unknown_query_parameter_is_400_naming_it(daemon, sid500):
    base = f"{daemon.url}/v1/sessions/{sid500}"
    for path, bad in [("/series?chanels=t&page_size=1", "/chanels"),
                      ("/fft?channel=vehicle.speed&taper=hann", "/taper"),
                      ("/series?max_samples=5", "/max_samples"),
                      ("?verbose=1", "/verbose")]:
        p = is_problem(requests.get(base + path), 400, bad)
        assert bad[1:] in p["detail"], p
    # what the route takes still works, and the health check takes anything
    assert requests.get(base + "/series?channels=t&page_size=1").status_code == 200
    assert requests.get(daemon.url + "/v1/health?probe=1").status_code == 200


def test_repeated_query_parameter_is_400(daemon, sid500):
    base = f"{daemon.url}/v1/sessions/{sid500}"
    is_problem(requests.get(base + "/series?channels=t&channels=vehicle.x"), 400, "/channels")
    is_problem(requests.get(base + "/frame.png?t=0.05&t=0.02"), 400, "/t")


@pytest.mark.parametrize("query,param", [("width=100.5", "width"), ("height=50.9", "height"),
                                         ("overlay=0.3", "overlay"), ("antialias=0.5", "antialias"),
                                         ("overlay=2", "overlay")])
def test_frame_integer_options_are_checked(daemon, sid500, query, param):
    r = requests.get(f"{daemon.url}/v1/sessions/{sid500}/frame.png?{query}")
    is_problem(r, 400, "/" + param)


def test_unsolvable_config_is_422_not_500(daemon):
    # an intercooler passage of 0.1 (in range): the crank-angle engine's launch
    # leaves its domain while the session is built, a fault of the request
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "accel-pointmass-conventional", "engine": {"ic_cda": 0.1}})
    p = is_problem(r, 422, "/engine/ca_step")
    assert p["type"] == "/problems/diverged", p


def test_start_with_no_equilibrium_is_422_naming_the_start(daemon):
    # a 0.8 x 2 m bump under the rear road wheels at t = 0: the bars keep their level-ground
    # preloads (session 31) and the wheels find no equilibrium on it; the request is refused
    # naming where the run starts, with the advice to start on level ground
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "bump-prescribed-coupled",
                            "terrain": {"kind": "bumps", "bump_start": [0.0],
                                        "bump_height": [0.8], "bump_length": [2.0]}})
    p = is_problem(r, 422, "/terrain/start_x")
    assert "start the run on level ground" in p["detail"], p


def test_layout_out_of_the_circuits_order_is_400(daemon):
    # road-wheel hubs above the support rollers (z 0.84 m): this once reached the static
    # equilibrium and failed there (422); the layout check names the field
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "bump-prescribed-static", "vehicle": {"road_wheel_z": 1.0}})
    p = is_problem(r, 400, "/vehicle/road_wheel_z")
    assert p["type"] == "/problems/invalid-config" and "below the support rollers" in p["detail"], p


def test_fft_states_the_unit_of_every_number(daemon, sid500):
    r = requests.get(f"{daemon.url}/v1/sessions/{sid500}/fft?channel=vehicle.speed")
    assert r.status_code == 200, r.text
    j = r.json()
    assert j["units"] == {"frequency": "Hz", "df": "Hz", "from": "s", "to": "s",
                          "amplitude": "m/s"}, j["units"]
    assert j["unit"] == "m/s"


def test_max_rows_refuses_a_run_that_would_fill_the_disk():
    d = Daemon("--max-rows", "1000")
    try:
        big = {"preset": "pointmass-prescribed", "run": {"duration": 3600, "sample_rate": 20000}}
        p = is_problem(requests.post(d.url + "/v1/sessions", json=big), 400, "/run/duration")
        assert "72000001" in p["detail"] and "--max-rows" in p["detail"], p
        # 2 s at 500 Hz is 1001 rows: one over; 1.998 s is exactly 1000
        over = {"preset": "pointmass-prescribed", "run": {"duration": 2.0}}
        is_problem(requests.post(d.url + "/v1/sessions", json=over), 400, "/run/duration")
        ok = {"preset": "pointmass-prescribed", "run": {"duration": 1.998}}
        assert requests.post(d.url + "/v1/sessions", json=ok).status_code == 201
    finally:
        d.stop()


def test_delete_leaves_no_write_ahead_log_behind():
    """A deleted session's rows went through the WAL page by page and stayed
    there (the review saw the store grow 321 -> 606 MB after a DELETE);
    server/db.c now checkpoints and truncates the log after a delete."""
    d = Daemon()
    try:
        r = requests.post(d.url + "/v1/sessions",
                          json={"preset": "pointmass-prescribed", "run": {"sample_rate": 5000}})
        assert r.status_code == 201, r.text
        s = r.json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{s}/step", json={"duration": 10}).status_code == 200
        wal = os.path.join(d.data_dir, "tanksimd.db-wal")
        assert os.path.getsize(wal) > 0
        assert requests.delete(f"{d.url}/v1/sessions/{s}").status_code == 204
        assert os.path.getsize(wal) == 0
    finally:
        d.stop()


def test_sse_stream_says_the_units_of_its_rows(daemon, sid500):
    # sample rows carry names only; the first event lists the selected
    # channels with their units (the review found no unit in the stream)
    r = requests.get(f"{daemon.url}/v1/sessions/{sid500}/stream?channels=vehicle.speed",
                     stream=True, timeout=10)
    assert r.status_code == 200
    events = sse_events(r, stop_after=1)
    r.close()
    assert events[0][0] == "channels", events[:2]
    listed = json.loads(events[0][2])
    assert [(c["name"], c["unit"]) for c in listed] == [("t", "s"), ("vehicle.speed", "m/s")]
    assert all(c["description"] for c in listed), listed
    assert events[1][0] == "sample"


@pytest.mark.parametrize("vehicle,pointer", [
    ({"damper_station": [9]}, "/vehicle/damper_station/0"),       # 7 road wheels
    ({"damper_station": [1, 1.5]}, "/vehicle/damper_station/1"),  # was rounded to 2
    ({"bump_stop_station": [0]}, "/vehicle/bump_stop_station/0"),
])
def test_road_arm_stations_are_whole_and_exist(daemon, vehicle, pointer):
    """Review, session 20: a damper at station 9 of 7 was taken (201) and went
    nowhere; station 1.5 was silently rounded to 2."""
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "bump-prescribed-static", "vehicle": vehicle})
    p = is_problem(r, 400, pointer)
    assert "station" in p["detail"], p


def test_description_must_be_a_string(daemon):
    """Review, session 20: "description": 5 was taken (201) and dropped."""
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "pointmass-prescribed", "description": 5})
    is_problem(r, 400, "/description")
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "pointmass-prescribed", "description": "a note"})
    assert r.status_code == 201, r.text


def test_the_nearest_times_suggested_are_on_the_grid(daemon):
    """Review, session 20: at 3 Hz a step of 0.333333 s was told "nearest 0 or
    0.333333 s", and 0.333333 was refused again (6 digits). 15 now."""
    import re
    r = requests.post(daemon.url + "/v1/sessions", json={
        "preset": "pointmass-prescribed", "run": {"duration": 2.0, "sample_rate": 3}})
    assert r.status_code == 201, r.text
    s = r.json()
    p = is_problem(requests.post(daemon.url + s["links"]["step"], json={"duration": 0.333333}),
                   400, "/duration")
    m = re.search(r"nearest (\S+) or (\S+) s", p["detail"])
    assert m, p
    r = requests.post(daemon.url + s["links"]["step"], json={"duration": float(m.group(2))})
    assert r.status_code == 200 and r.json()["index"] == 1, r.text


@pytest.mark.parametrize("duration", [0, 1e-300])
def test_a_step_of_no_sample_period_is_400(daemon, sid500, duration):
    """Review, session 20: a step of 0 or 1e-300 s (on the grid at row 0)
    answered 200, advanced nothing and turned a created session paused."""
    p = is_problem(requests.post(f"{daemon.url}/v1/sessions/{sid500}/step",
                                 json={"duration": duration}), 400, "/duration")
    assert "at least 1 sample period" in p["detail"], p


def test_point_mass_refuses_terrain_it_cannot_drive(daemon):
    """CLI review, session 20: a point-mass run with a bump course or a profile
    ran on flat ground while its config said otherwise."""
    r = requests.post(daemon.url + "/v1/sessions", json={
        "preset": "pointmass-prescribed", "terrain": {"kind": "bumps"}})
    p = is_problem(r, 400, "/terrain/kind")
    assert "point mass" in p["detail"], p
