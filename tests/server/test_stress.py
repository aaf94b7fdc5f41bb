"""Many sessions on many threads at once (the ThreadSanitizer audit, `make tsan`):
paced runs on 4 workers, each followed by a live SSE stream; meanwhile other
clients cancel some runs, delete sessions whose runs and streams are live, step
busy sessions (409), read lists, metrics, series and rendered frames of a
vehicle session that is running; then SIGTERM with runs still in progress.

Checks: every stream of a session that is not deleted delivers rows 0..last
once each, in order, and ends; the streamed rows equal the stored series;
streams of deleted sessions end (no hang); cancelled runs end cancelled;
deleted sessions are gone; the daemon exits 0 on SIGTERM with nothing but its
usual lines on stderr. Under `make tsan` the daemon is the ThreadSanitizer
build and any race report fails the target (the Makefile collects them).
"""
import json
import threading

import requests

from conftest import BASE_PRESET, Daemon, sse_events, wait_op

NRUN = 6      # sessions run to the end, each with one stream
NCANCEL = 2   # of those, runs cancelled mid-way
NDELETE = 2   # sessions deleted while running and streamed
DURATION = 1.0
RTF = 4.0     # paced: the runs overlap in time


def create(url, **sections):
    r = requests.post(url + "/v1/sessions", json={"preset": BASE_PRESET, **sections}, timeout=60)
    assert r.status_code == 201, r.text
    return r.json()


def start_run(url, s, **body):
    r = requests.post(url + s["links"]["run"], json=body, timeout=60)
    assert r.status_code == 202, r.text
    return r.json()


def stream(url, s, out):
    """Collect the SSE events of s's live stream into out (list)."""
    try:
        with requests.get(url + s["links"]["stream"], params={"channels": "vehicle.speed"},
                          headers={"Accept": "text/event-stream"}, stream=True, timeout=60) as r:
            out.extend(sse_events(r))
    except requests.RequestException as e:  # a deleted session's stream may be cut
        out.append(("error", None, str(e)))


def test_many_sessions_streams_cancel_delete_frames_shutdown(tmp_path):
    d = Daemon("--threads", "4", data_dir=str(tmp_path))
    try:
        url = d.url
        runs = [create(url, run={"duration": DURATION}) for _ in range(NRUN)]
        doomed = [create(url, run={"duration": 30.0}) for _ in range(NDELETE)]
        vehicle = create(url, preset="bump-prescribed-static", run={"duration": 0.4})
        ops, streams, threads = {}, {}, []
        for s in runs + doomed:
            ops[s["id"]] = start_run(url, s, real_time_factor=RTF)
            streams[s["id"]] = []
            t = threading.Thread(target=stream, args=(url, s, streams[s["id"]]))
            t.start()
            threads.append(t)
        vop = start_run(url, vehicle)

        errors = []

        def chaos(k):
            try:
                chaos_body(k)
            except Exception as e:  # noqa: BLE001 — reported by the main thread
                errors.append(repr(e))

        def chaos_body(k):
            for s in runs[:NCANCEL]:
                r = requests.post(f"{url}/v1/operations/{ops[s['id']]['id']}:cancel", timeout=60)
                assert r.status_code == 200, r.text
            for s in runs:
                r = requests.post(url + s["links"]["step"], json={"duration": 0.01}, timeout=60)
                assert r.status_code in (200, 409), r.text
            for s in doomed:  # both clients delete: one gets 204, the other 404
                r = requests.delete(url + s["links"]["self"], timeout=60)
                assert r.status_code in (204, 404), r.text
            for _ in range(3):
                assert requests.get(url + "/v1/sessions", timeout=60).status_code == 200
                assert requests.get(url + "/metrics", timeout=60).status_code == 200
                f = requests.get(url + vehicle["links"]["self"] + "/frame.png",
                                 params={"width": 64, "height": 48}, timeout=120)
                assert f.status_code == 200, f.text

        workers = [threading.Thread(target=chaos, args=(k,)) for k in range(2)]
        for t in workers:
            t.start()
        for t in workers:
            t.join(timeout=300)
        for t in threads:
            t.join(timeout=300)
        assert not any(t.is_alive() for t in threads + workers)
        assert not errors, errors

        for s in doomed:
            assert requests.get(url + s["links"]["self"], timeout=60).status_code == 404
            assert streams[s["id"]], "a deleted session's stream must end, not hang"
        for i, s in enumerate(runs):
            final = wait_op(url, ops[s["id"]]["id"], timeout=120)
            got = requests.get(url + s["links"]["self"], timeout=60).json()
            if i < NCANCEL and "error" in final:
                assert final["error"]["code"] == 1, final  # cancelled (unless it ended first)
            ev = streams[s["id"]]
            assert ev and ev[-1][0] == "end", ev[-3:]
            ids = [int(e[1]) for e in ev if e[0] == "sample"]
            # rows stored when the run ended; a step that got in afterwards adds more
            assert ids == list(range(len(ids))) and len(ids) >= 2, ids[:5]
            ser = requests.get(url + s["links"]["series"], params={"channels": "vehicle.speed"},
                               timeout=60).json()
            stored = ser["channels"][1]["values"]
            streamed = [json.loads(e[2])["values"]["vehicle.speed"] for e in ev if e[0] == "sample"]
            assert streamed == stored[:len(streamed)]
            assert got["index"] + 1 == len(stored)
        assert wait_op(url, vop["id"], timeout=120)["done"]

        # shutdown with runs in progress
        late = [create(url, run={"duration": 30.0}) for _ in range(3)]
        late_ops = [start_run(url, s, real_time_factor=RTF) for s in late]
        wait_op_started = [requests.get(f"{url}/v1/operations/{o['id']}", timeout=60) for o in late_ops]
        assert all(r.status_code == 200 for r in wait_op_started)
    finally:
        rc = d.stop()
    assert rc == 0, d.stderr()
    assert "ThreadSanitizer" not in d.stderr() and "WARNING" not in d.stderr(), d.stderr()
