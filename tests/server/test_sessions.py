"""tanksimd session API end to end (issue 7): presets, schema, create from every
preset, step, asynchronous runs as operations (progress, cancel), stored series
as JSON and CSV with units and paging, SSE stream resumed with Last-Event-ID,
NDJSON stream, FFT, delete, metrics. A real daemon on loopback; the physics is
whatever the preset's scenario computes — these tests check the plumbing:
times, indexes, units, counts and that values are passed through unchanged."""
import json
import os
import time

import pytest
import requests

from conftest import BASE_PRESET, is_problem, preset_names, sse_events, wait_op


def create(d, preset=BASE_PRESET, **overrides):
    r = requests.post(d.url + "/v1/sessions", json={"preset": preset, **overrides})
    assert r.status_code == 201, r.text
    s = r.json()
    assert r.headers["Location"] == f"/v1/sessions/{s['id']}"
    return s


def test_presets_list_and_each_preset(daemon):
    r = requests.get(daemon.url + "/v1/presets")
    assert r.status_code == 200
    listed = {p["name"]: p for p in r.json()["presets"]}
    assert sorted(listed) == preset_names()
    for name, p in listed.items():
        assert p["kind"], name
        one = requests.get(daemon.url + p["links"]["self"]).json()
        assert one["name"] == name and one["config"]["run"]["kind"] == p["kind"]
    is_problem(requests.get(daemon.url + "/v1/presets/no-such-preset"), 404)


def test_schema_is_generated_from_the_parameter_table(daemon):
    s = requests.get(daemon.url + "/v1/schema").json()
    assert s["$schema"].startswith("https://json-schema.org/")
    run = s["properties"]["run"]["properties"]
    assert run["duration"]["x-unit"] == "s" and "default" in run["duration"]
    assert s["additionalProperties"] is False


def test_schema_and_config_echo_round_trip_every_double(daemon):
    """The daemon wrote its JSON with 12 significant digits (session-29 review): the
    schema's defaults differed from `tanksim schema`'s (fmep_b 316.081716981 vs
    316.08171698050415) and a session's config echo, run by the CLI, gave another
    result. Every double now reads back as itself."""
    from conftest import BUILD
    import subprocess
    served = requests.get(daemon.url + "/v1/schema").json()
    cli = json.loads(subprocess.run([os.path.join(BUILD, "tanksim"), "schema"], check=True,
                                    capture_output=True, text=True).stdout)
    assert served == cli
    s = create(daemon, "accel-pointmass-conventional")
    try:
        preset = requests.get(daemon.url + "/v1/presets/accel-pointmass-conventional").json()
        assert s["config"]["engine"] == preset["config"]["engine"]
        phi = s["config"]["engine"]["phi_curvature"]
        assert repr(phi) == repr(float(repr(phi))) and len(repr(phi).replace("e-06", "")) > 14
    finally:
        requests.delete(daemon.url + s["links"]["self"])


def test_unknown_preset_in_a_body_is_a_bad_value(daemon):
    """An unknown preset named in a request body answered 404, which a client reads
    as a missing route (session-29 review); it is a bad value: 400 naming /preset.
    The preset route itself still answers 404 for a name it does not have."""
    for path in ("/v1/sessions", "/v1/tune", "/v1/engine-map"):
        p = is_problem(requests.post(daemon.url + path, json={"preset": "nosuch"}), 400, "/preset")
        assert "no preset named 'nosuch'" in p["errors"][0]["message"], path
    is_problem(requests.get(daemon.url + "/v1/presets/nosuch"), 404)


def test_openapi_is_served(daemon):
    r = requests.get(daemon.url + "/v1/openapi.yaml")
    assert r.status_code == 200 and r.text.startswith("openapi: 3.1")


def modes_only(preset):
    doc = json.load(open(os.path.join(os.path.dirname(__file__), "..", "..", "sim", "data",
                                      "presets", preset + ".json")))
    return "commands" in doc and "session" not in doc["commands"]


@pytest.mark.parametrize("preset", preset_names())
def test_create_from_each_preset(daemon, preset):
    r = requests.post(daemon.url + "/v1/sessions", json={"preset": preset})
    if modes_only(preset):
        # m1 and table1-span set no run (they are the eigenanalyses of Fig. 5 and
        # Table 1): refused by name, not run as a default point-mass scenario
        p = is_problem(r, 400)
        assert p["errors"][0]["pointer"] == "/preset" and "modes" in p["errors"][0]["message"]
        listed = {x["name"]: x for x in requests.get(daemon.url + "/v1/presets").json()["presets"]}
        assert listed[preset]["commands"] == ["modes"]
        is_problem(requests.post(daemon.url + "/v1/sessions",
                                 json={"preset": preset, "run": {"duration": 0.2}}), 400, "/preset")
        # giving /run/kind makes it a run like any other
        r = requests.post(daemon.url + "/v1/sessions",
                          json={"preset": preset, "run": {"kind": "pointmass"}})
        if preset == "m1":
            assert r.status_code == 201, r.text
            requests.delete(daemon.url + r.json()["links"]["self"])
        return
    # every scenario kind is built, so every shipped preset must create
    assert r.status_code == 201, r.text
    s = r.json()
    assert s["status"] == "created" and s["t"] == 0 and s["index"] == 0 and s["samples"] == 1
    assert s["preset"] == preset and s["config"]["run"]["kind"] == s["kind"]
    names = [c["name"] for c in s["channels"]]
    assert names[0] == "t" and len(set(names)) == len(names)
    assert all(c["unit"] for c in s["channels"])
    assert set(s["latest"]) == set(names)
    for rel in ("self", "step", "run", "series", "stream", "fft"):
        assert s["links"][rel].startswith(f"/v1/sessions/{s['id']}")
    # one short step works for every scenario
    st = requests.post(daemon.url + s["links"]["step"], json={"duration": 0.01})
    assert st.status_code == 200, st.text
    rate = s["sample_rate"]
    assert st.json()["index"] == round(0.01 * rate)
    assert requests.delete(daemon.url + s["links"]["self"]).status_code == 204


def test_step_advances_time_and_returns_latest_values(daemon):
    s = create(daemon, drive={"torque": 5000.0})
    r = requests.post(daemon.url + s["links"]["step"], json={"duration": 0.5})
    assert r.status_code == 200
    st = r.json()
    assert st["status"] == "paused"
    assert st["t"] == pytest.approx(0.5) and st["index"] == 250
    assert st["values"]["t"] == pytest.approx(0.5)
    assert st["values"]["sprocket.torque"] == 5000.0
    assert st["values"]["vehicle.speed"] > 0
    work1 = requests.get(daemon.url + s["links"]["self"]).json()["integrators"]
    r2 = requests.post(daemon.url + s["links"]["step"], json={"duration": 0.25}).json()
    assert r2["t"] == pytest.approx(0.75) and r2["values"]["vehicle.speed"] > st["values"]["vehicle.speed"]
    got = requests.get(daemon.url + s["links"]["self"]).json()
    assert got["t"] == pytest.approx(0.75) and got["samples"] == 376
    assert got["latest"] == r2["values"]
    # the integrators' work counters grow with the run (openapi IntegratorStats)
    work2 = got["integrators"]
    assert [w["integrator"] for w in work2] == [w["integrator"] for w in work1] != []
    assert 0 < work1[0]["steps"] < work2[0]["steps"]
    assert work2[0]["rhs_evals"] >= work2[0]["steps"] and "CVODE" in work2[0]["method"]
    # every counter an integer, also a zero one (err_test_fails here; a survivor of the
    # session-26 mutation pass printed 0 as null)
    for w in work2:
        counts = {k: v for k, v in w.items() if k not in ("integrator", "method")}
        assert counts and all(type(v) is int and v >= 0 for v in counts.values()), w
    assert 0 in counts.values(), counts
    assert "integrators" not in requests.get(daemon.url + "/v1/sessions").json()["sessions"][0]


def test_session_during_a_long_step_says_paused_not_created(daemon):
    """Review, session 20: during a synchronous step the session said "created"
    (with t and samples growing) while the store already had it "paused"."""
    import threading
    s = create(daemon, "bump-coupled-ivs5mph", engine={"fidelity": "crank_angle"},
               run={"duration": 10.0, "sample_rate": 200})
    out = {}
    th = threading.Thread(target=lambda: out.setdefault(
        "r", requests.post(daemon.url + s["links"]["step"], json={"duration": 4.0})))
    th.start()
    seen = []
    while th.is_alive():
        g = requests.get(daemon.url + s["links"]["self"]).json()
        if g["samples"] > 1:
            seen.append(g["status"])
        time.sleep(0.02)
    th.join()
    assert out["r"].status_code == 200, out["r"].text
    assert seen and set(seen) == {"paused"}, seen


def test_step_longer_than_limit_points_to_run(daemon):
    s = create(daemon)
    r = requests.post(daemon.url + s["links"]["step"], json={"duration": 11})
    p = is_problem(r, 422, "/duration")
    assert p["run"] == s["links"]["run"] and "run" in p["detail"]
    # the limit itself, in s, for clients that word their own advice (the dashboard)
    assert p["max_duration"] == 10.0


def test_run_to_completion_with_rising_progress(daemon):
    # Paced to take 2 s of wall time: the progress is seen rising by polling
    # it, so the run must outlast a few polls of a slow client (at 8x, 0.5 s,
    # a client starved on a loaded machine saw 3 or 4 values, the first 0.85).
    s = create(daemon, run={"duration": 4.0})
    r = requests.post(daemon.url + s["links"]["run"], json={"real_time_factor": 2})
    assert r.status_code == 202, r.text
    op = r.json()
    assert r.headers["Location"] == f"/v1/operations/{op['id']}"
    assert op["done"] is False and op["metadata"]["until"] == 4.0
    assert requests.get(daemon.url + s["links"]["self"]).json()["status"] == "running"
    seen = []
    final = wait_op(daemon.url, op["id"], seen=seen)
    progress = [m["progress"] for m in seen]
    assert progress == sorted(progress), progress            # never goes back
    assert len({round(p, 3) for p in progress}) >= 5, progress  # rises in steps
    assert 0 <= progress[0] < 0.5 and progress[-1] == 1.0
    assert "error" not in final and final["response"]["status"] == "done"
    md = final["metadata"]
    assert md["t"] == pytest.approx(4.0)
    assert 1 < md["real_time_factor"] < 2.1   # paced at (at most) 2x real time
    got = requests.get(daemon.url + s["links"]["self"]).json()
    assert got["status"] == "done" and got["samples"] == 2001
    is_problem(requests.post(daemon.url + s["links"]["step"], json={"duration": 0.1}), 409)


def test_run_until_pauses_then_runs_on(daemon):
    s = create(daemon, run={"duration": 3.0})
    op = requests.post(daemon.url + s["links"]["run"], json={"until": 1.0}).json()
    assert wait_op(daemon.url, op["id"])["response"]["status"] == "paused"
    assert requests.get(daemon.url + s["links"]["self"]).json()["t"] == pytest.approx(1.0)
    is_problem(requests.post(daemon.url + s["links"]["run"], json={"until": 0.5}), 400, "/until")
    is_problem(requests.post(daemon.url + s["links"]["run"], json={"until": 9.0}), 400, "/until")
    op = requests.post(daemon.url + s["links"]["run"], json={}).json()
    assert wait_op(daemon.url, op["id"])["response"]["status"] == "done"
    ser = requests.get(daemon.url + s["links"]["series"], params={"channels": "t"}).json()
    assert ser["index"] == list(range(1501))


def test_cancel_stops_a_run(daemon):
    s = create(daemon)
    op = requests.post(daemon.url + s["links"]["run"],
                       json={"until": 30, "real_time_factor": 5}).json()
    busy = requests.post(daemon.url + s["links"]["step"], json={"duration": 0.1})
    is_problem(busy, 409)
    while requests.get(f"{daemon.url}/v1/operations/{op['id']}").json()["metadata"]["t"] <= 0:
        time.sleep(0.02)
    c = requests.post(f"{daemon.url}/v1/operations/{op['id']}:cancel")
    assert c.status_code == 200
    final = wait_op(daemon.url, op["id"])
    assert final["error"]["code"] == 1 and final["error"]["status"] == 409
    got = requests.get(daemon.url + s["links"]["self"]).json()
    assert got["status"] == "paused" and 0 < got["t"] < 30
    # everything up to the stop is stored
    ser = requests.get(daemon.url + s["links"]["series"], params={"channels": "t"}).json()
    assert ser["index"] == list(range(got["index"] + 1))
    is_problem(requests.get(daemon.url + "/v1/operations/opnope"), 404)


def test_series_json_csv_units_decimation_and_paging(daemon):
    s = create(daemon)
    requests.post(daemon.url + s["links"]["step"], json={"duration": 2.0})
    url = daemon.url + s["links"]["series"]
    j = requests.get(url, params={"channels": "vehicle.speed,sprocket.torque",
                                  "from": 0.5, "to": 1.0}).json()
    names = [c["name"] for c in j["channels"]]
    assert names == ["t", "vehicle.speed", "sprocket.torque"]
    assert [c["unit"] for c in j["channels"]] == ["s", "m/s", "N*m"]
    assert j["index"] == list(range(250, 501)) and j["count"] == 251
    t = j["channels"][0]["values"]
    assert t[0] == 0.5 and t[-1] == 1.0
    assert "next_page_token" not in j
    # decimation keeps every 10th row from `from`
    d = requests.get(url, params={"channels": "vehicle.speed", "every": 10, "to": 1.0}).json()
    assert d["index"] == list(range(0, 501, 10))
    full = requests.get(url, params={"channels": "vehicle.speed", "to": 1.0}).json()
    assert d["channels"][1]["values"] == full["channels"][1]["values"][::10]
    # CSV: header with units, same numbers
    c = requests.get(url, params={"channels": "vehicle.speed", "to": 1.0, "format": "csv"})
    assert c.headers["Content-Type"].startswith("text/csv")
    lines = c.text.strip().split("\n")
    assert lines[0] == "t [s],vehicle.speed [m/s]" and len(lines) == 502
    assert [float(l.split(",")[1]) for l in lines[1:]] == pytest.approx(
        full["channels"][1]["values"], rel=1e-8)
    # by Accept, with its q values (a substring test served CSV to q=0 until
    # session 20): CSV when it is named and not below JSON's q
    for accept, ctype in (("text/csv", "text/csv"),
                          ("application/json, text/csv;q=0", "application/json"),
                          ("text/csv;q=0.5, application/json", "application/json"),
                          ("application/json;q=0.5, text/csv", "text/csv"),
                          ("*/*", "application/json")):
        h = requests.get(url, params={"channels": "vehicle.speed", "to": 0.01},
                         headers={"Accept": accept})
        assert h.status_code == 200 and h.headers["Content-Type"].startswith(ctype), accept
    # paging: pages of 300 cover all 1001 rows exactly once
    got, token = [], None
    while True:
        params = {"channels": "t", "page_size": 300}
        if token:
            params["page_token"] = token
        r = requests.get(url, params=params)
        page = r.json()
        got += page["index"]
        token = page.get("next_page_token")
        assert (r.headers.get("X-Next-Page-Token") or None) == token
        if not token:
            break
    assert got == list(range(1001))
    # to before from was a 200 with count 0: a range given backwards is a mistake
    p = is_problem(requests.get(url, params={"from": 1.5, "to": 0.5}), 400, "/to")
    assert "at least from = 1.5 s, got 0.5 s" in p["detail"]
    assert requests.get(url, params={"from": 1.0, "to": 1.0}).json()["count"] == 1


def test_series_is_capped_by_max_samples(tmp_path):
    from conftest import Daemon
    d = Daemon("--max-samples", "100", data_dir=str(tmp_path))
    try:
        s = create(d)
        requests.post(d.url + s["links"]["step"], json={"duration": 1.0})
        j = requests.get(d.url + s["links"]["series"]).json()
        assert j["count"] == 100 and j["next_page_token"] == "100"
        is_problem(requests.get(d.url + s["links"]["series"], params={"page_size": 101}), 400,
                   "/page_size")
        is_problem(requests.get(d.url + s["links"]["fft"], params={"channel": "vehicle.speed"}),
                   422, "/to")
    finally:
        d.stop()


def test_sse_stream_resumes_with_last_event_id_without_loss_or_duplicates(daemon):
    # paced at real time (2 s): the first stream's 300 rows are there after
    # 0.6 s, and the run must still be going when the client reconnects (at
    # 4x, 0.5 s in all, a client starved on a loaded machine found it done)
    s = create(daemon, run={"duration": 2.0})
    op = requests.post(daemon.url + s["links"]["run"], json={"real_time_factor": 1}).json()
    url = daemon.url + s["links"]["stream"]
    with requests.get(url, params={"channels": "vehicle.speed"}, stream=True,
                      headers={"Accept": "text/event-stream"}, timeout=30) as r:
        assert r.headers["Content-Type"] == "text/event-stream"
        first = sse_events(r, stop_after=300)
    first = [e for e in first if e[0] == "sample"]
    last_id = first[-1][1]
    assert requests.get(daemon.url + s["links"]["self"]).json()["status"] == "running"
    with requests.get(url, params={"channels": "vehicle.speed"}, stream=True,
                      headers={"Last-Event-ID": last_id}, timeout=30) as r:
        second = sse_events(r)
    assert second[-1][0] == "end" and json.loads(second[-1][2])["status"] == "done"
    samples = first + [e for e in second if e[0] == "sample"]
    ids = [int(e[1]) for e in samples]
    assert ids == list(range(1001))                 # none lost, none duplicated
    for e in samples:
        row = json.loads(e[2])
        assert row["index"] == int(e[1]) and set(row["values"]) == {"vehicle.speed"}
        assert row["t"] == pytest.approx(row["index"] / 500)
    # the streamed values are the stored ones
    ser = requests.get(daemon.url + s["links"]["series"], params={"channels": "vehicle.speed"}).json()
    assert [json.loads(e[2])["values"]["vehicle.speed"] for e in samples] == pytest.approx(
        ser["channels"][1]["values"], rel=1e-8)
    assert wait_op(daemon.url, op["id"])["done"]
    # ?since= resumes the same way
    with requests.get(url, params={"since": 995}, stream=True) as r:
        tail = [int(e[1]) for e in sse_events(r) if e[0] == "sample"]
    assert tail == [996, 997, 998, 999, 1000]


def test_ndjson_stream(daemon):
    s = create(daemon, run={"duration": 1.0})
    requests.post(daemon.url + s["links"]["run"], json={"real_time_factor": 5})
    with requests.get(daemon.url + s["links"]["stream"], params={"channels": "sprocket.torque"},
                      headers={"Accept": "application/x-ndjson"}, stream=True, timeout=30) as r:
        assert r.headers["Content-Type"] == "application/x-ndjson"
        rows = [json.loads(l) for l in r.iter_lines() if l]
    assert [x["index"] for x in rows] == list(range(501))
    assert all(x["values"]["sprocket.torque"] == 6000.0 for x in rows)
    # format= (api/openapi.yaml: sse | ndjson) chooses over the Accept header
    url = daemon.url + s["links"]["stream"]
    with requests.get(url, params={"format": "ndjson", "since": 499}, stream=True,
                      headers={"Accept": "text/event-stream"}, timeout=30) as r:
        assert r.headers["Content-Type"] == "application/x-ndjson"
        assert [json.loads(l)["index"] for l in r.iter_lines() if l] == [500]
    # q=0 refuses NDJSON: SSE (a substring test served NDJSON until session 20)
    with requests.get(url, params={"since": 499}, stream=True, timeout=30,
                      headers={"Accept": "text/event-stream, application/x-ndjson;q=0"}) as r:
        assert r.headers["Content-Type"].startswith("text/event-stream")
    with requests.get(url, params={"format": "sse", "since": 499}, stream=True,
                      headers={"Accept": "application/x-ndjson"}, timeout=30) as r:
        assert r.headers["Content-Type"] == "text/event-stream"


def test_fft_amplitude_spectrum(daemon):
    s = create(daemon)
    requests.post(daemon.url + s["links"]["step"], json={"duration": 2.0})
    r = requests.get(daemon.url + s["links"]["fft"],
                     params={"channel": "vehicle.speed", "from": 0, "to": 1.998})
    assert r.status_code == 200, r.text
    f = r.json()
    assert f["n"] == 1000 and f["unit"] == "m/s"
    assert f["df"] == pytest.approx(0.5)
    assert len(f["frequency"]) == len(f["amplitude"]) == 501
    assert f["frequency"][-1] == pytest.approx(250.0)
    # speed rises almost linearly: a ramp's spectrum falls off as 1/f
    a = f["amplitude"]
    assert a[0] == pytest.approx(0, abs=1e-12)  # mean removed
    assert a[1] > a[2] > a[4] > a[8]
    # the fft route's parameter is "channel" (http_fuzz finding; it named "/channels")
    is_problem(requests.get(daemon.url + s["links"]["fft"], params={"channel": "nope"}), 404,
               "/channel")
    is_problem(requests.get(daemon.url + s["links"]["fft"]), 400, "/channel")


def test_fft_window_and_detrend_words(daemon):
    # each query word picks its sim/fft.h window or detrend and is named back
    # (api: "mean removed", "line removed"); the defaults are rect and mean;
    # an unknown word is a 400 listing the words (server/routes.c fft_windows,
    # fft_detrends)
    s = create(daemon)
    requests.post(daemon.url + s["links"]["step"], json={"duration": 1.0})
    url = daemon.url + s["links"]["fft"]

    def fft(**words):
        r = requests.get(url, params={"channel": "vehicle.speed", **words})
        assert r.status_code == 200, r.text
        return r.json()

    got = {(w, d): fft(window=w, detrend=d) for w in ("rect", "hann")
           for d in ("none", "mean", "linear")}
    for (w, d), f in got.items():
        assert f["window"] == w
        assert f["detrend"] == {"none": "none", "mean": "mean removed",
                                "linear": "line removed"}[d]
    # the speed's mean stays at 0 Hz without detrend (rect: removed exactly)
    assert got[("rect", "mean")]["amplitude"][0] == pytest.approx(0, abs=1e-12)
    for w in ("rect", "hann"):
        assert got[(w, "none")]["amplitude"][0] > 10 * got[(w, "mean")]["amplitude"][0]
        assert got[(w, "linear")]["amplitude"][1] != got[(w, "mean")]["amplitude"][1]
    for d in ("none", "mean", "linear"):  # the window changes the spectrum
        assert got[("rect", d)]["amplitude"][2] != got[("hann", d)]["amplitude"][2]
    assert fft() == got[("rect", "mean")]
    p = is_problem(requests.get(url, params={"channel": "t", "window": "kaiser"}), 400, "/window")
    assert "rect or hann expected" in p["detail"], p
    p = is_problem(requests.get(url, params={"channel": "t", "detrend": "cubic"}), 400, "/detrend")
    assert "none, mean or linear expected" in p["detail"], p


def test_list_sessions_paged(daemon):
    ids = {create(daemon)["id"] for _ in range(5)}
    seen, token = [], None
    while True:
        params = {"page_size": 2}
        if token:
            params["page_token"] = token
        page = requests.get(daemon.url + "/v1/sessions", params=params).json()
        assert len(page["sessions"]) <= 2
        seen += [x["id"] for x in page["sessions"]]
        token = page.get("next_page_token")
        if not token:
            break
    assert ids <= set(seen) and len(seen) == len(set(seen))


def test_delete_removes_session_and_data(daemon):
    s = create(daemon)
    requests.post(daemon.url + s["links"]["run"], json={"until": 20, "real_time_factor": 10})
    r = requests.delete(daemon.url + s["links"]["self"])
    assert r.status_code == 204
    is_problem(requests.get(daemon.url + s["links"]["self"]), 404)
    is_problem(requests.get(daemon.url + s["links"]["series"]), 404)
    is_problem(requests.delete(daemon.url + s["links"]["self"]), 404)


def test_metrics_count_sessions_runs_requests_and_time(daemon):
    before = requests.get(daemon.url + "/metrics").text
    s = create(daemon)
    requests.post(daemon.url + s["links"]["step"], json={"duration": 1.0})
    requests.get(daemon.url + "/nope")
    m = requests.get(daemon.url + "/metrics")
    assert m.headers["Content-Type"].startswith("text/plain")

    def value(text, name):
        for line in text.splitlines():
            if line.startswith(name + " "):
                return float(line.split()[-1])
        return 0.0

    assert value(m.text, "tanksimd_sessions_created_total") == value(before, "tanksimd_sessions_created_total") + 1
    assert value(m.text, "tanksimd_simulated_seconds_total") >= value(before, "tanksimd_simulated_seconds_total") + 1.0 - 1e-9
    assert value(m.text, 'tanksimd_http_requests_total{code="404"}') >= 1
    assert value(m.text, 'tanksimd_sessions{status="paused"}') >= 1


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_waiting_streams_do_not_spin(daemon):
    """Four streams wait on a run paced at 1/100 of real time: the daemon must
    sleep between batches (suspended connections), not poll."""
    s = create(daemon)
    op = requests.post(daemon.url + s["links"]["run"],
                       json={"until": 30, "real_time_factor": 0.01}).json()
    streams = [requests.get(daemon.url + s["links"]["stream"], stream=True, timeout=30)
               for _ in range(4)]
    try:
        time.sleep(0.3)
        c0, w0 = cpu_seconds(daemon.proc.pid), time.time()
        time.sleep(1.5)
        used = cpu_seconds(daemon.proc.pid) - c0
        assert used < 0.25 * (time.time() - w0), f"daemon used {used:.2f} s CPU while idle"
        assert all(r.status_code == 200 for r in streams)
    finally:
        requests.post(f"{daemon.url}/v1/operations/{op['id']}:cancel")
        for r in streams:
            r.close()
    assert wait_op(daemon.url, op["id"])["error"]["code"] == 1
