"""A session deleted while the first-use rebuild of its model (after a
restart) was queued behind other work: the requests that waited for that
rebuild — a step, a frame, a summary — answered 409 "cannot be advanced by
this daemon: the session was deleted (its stored rows are kept and can be
read)" / "has no frames here", which is false: the rows are gone. They now
answer 404 "session ... was deleted", as a step a DELETE cuts short does.
A GET of the session itself queued the same way answered 200 with "status":
"deleted" while /series answered 404; run_built now answers that 404 for every
route. A frame whose session is deleted while it is drawn answers the same
404, not one naming /t ("no stored state at or before t").

The one worker is held by a tune that cannot end before the test cancels it
(a 1800-s crank-angle settle: minutes of work; it hears a cancel within a
second). The queue is known before the requests are sent: jobs_pending counts
a job until its worker returns, after its reply (the step that made the
session can still be counted when its 200 is read), so a count read at one
instant could include it; the test waits for the analysis alone instead."""
import threading

import requests

from conftest import Daemon, is_problem, stepped_session, wait_metric, wait_op

# holds the one worker until cancelled: minutes of work, a cancel heard at once
BLOCKER = {"preset": "bump-coupled-ivs5mph", "engine": {"fidelity": "crank_angle"},
           "control": {"tune_settle": 1800, "tune_duration": 1800}}


def hold_the_worker(d):
    """Start the blocking tune on d and wait until it is the only pool job; its id."""
    r = requests.post(d.url + "/v1/tune", json=BLOCKER)
    assert r.status_code == 202, r.text
    wait_metric(d.url, "tanksimd_jobs_pending", 1)  # the tune, running; nothing else
    return r.json()["id"]


def released(d, op):
    """Cancel the blocking tune; assert it was still running (it held the worker)."""
    requests.post(f"{d.url}/v1/operations/{op}:cancel")
    done = wait_op(d.url, op, timeout=60)
    assert done["error"]["code"] == 1, done  # cancelled, not finished: it held the worker


def test_requests_queued_behind_the_rebuild_of_a_deleted_session_answer_404(tmp_path):
    dd = str(tmp_path)
    with Daemon("--threads", "1", data_dir=dd) as d:
        sid = stepped_session(d.url, "bump-prescribed-coupled", step=0.2)
    with Daemon("--threads", "1", data_dir=dd) as d:
        # the one worker is busy with a tune: the rebuild waits behind it
        op = hold_the_worker(d)
        answers = {}

        def ask(name, method, path, **kw):
            answers[name] = requests.request(method, d.url + path, timeout=60, **kw)

        threads = [threading.Thread(target=ask, args=a, kwargs=kw) for a, kw in [
            (("step", "POST", f"/v1/sessions/{sid}/step"), {"json": {"duration": 0.1}}),
            (("frame", "GET", f"/v1/sessions/{sid}/frame.png?t=0.1"), {}),
            (("summary", "GET", f"/v1/sessions/{sid}/summary"), {}),
            (("session", "GET", f"/v1/sessions/{sid}"), {}),
            (("series", "GET", f"/v1/sessions/{sid}/series"), {}),
        ]]
        for t in threads:
            t.start()
        wait_metric(d.url, "tanksimd_jobs_pending", 1 + len(threads))  # all of them wait for the rebuild
        assert not answers, {k: (v.status_code, v.text) for k, v in answers.items()}
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        released(d, op)
        for t in threads:
            t.join(60)
        assert len(answers) == len(threads), answers  # every request was answered
        for name, r in answers.items():
            p = is_problem(r, 404)
            assert "was deleted" in p["detail"] and "kept" not in p["detail"], (name, p)
            assert not p.get("errors"), (name, p)
        assert requests.get(f"{d.url}/v1/sessions/{sid}").status_code == 404


def test_frame_of_a_loaded_session_deleted_before_it_is_drawn_is_404_without_t():
    with Daemon("--threads", "1") as d:
        sid = stepped_session(d.url, "bump-prescribed-coupled", step=0.2)  # built: no first-use rebuild
        op = hold_the_worker(d)  # after the step's job has ended
        got = []
        t = threading.Thread(target=lambda: got.append(
            requests.get(f"{d.url}/v1/sessions/{sid}/frame.png?t=0.1", timeout=60)))
        t.start()
        wait_metric(d.url, "tanksimd_jobs_pending", 2)  # the draw waits behind the tune
        assert not got
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204  # rows go now
        released(d, op)
        t.join(60)
        assert got, "no answer to the frame"
        p = is_problem(got[0], 404)
        assert "was deleted" in p["detail"] and not p.get("errors"), p
