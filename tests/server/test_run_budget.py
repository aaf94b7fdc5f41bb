"""tanksimd --max-run-wall S (found by the config fuzzer, session 4: configs
inside every range can keep a worker busy for hours): a run operation that has
used S wall seconds pauses with an error naming the flag; its rows are stored
and a further run continues from there. Without the flag runs are unbounded."""
import time

import requests

from conftest import BASE_PRESET, Daemon, wait_op


def test_run_pauses_at_its_wall_budget_and_continues():
    d = Daemon("--max-run-wall", "0.5")
    try:
        sid = requests.post(d.url + "/v1/sessions",
                            json={"preset": BASE_PRESET, "run": {"duration": 10.0}}).json()["id"]
        # paced at real time: 10 s of simulation would take 10 s of wall time
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run",
                           json={"real_time_factor": 1}).json()
        final = wait_op(d.url, op["id"], timeout=20)
        assert "--max-run-wall" in final["error"]["message"], final
        assert final["error"]["code"] == 8
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused" and 0.2 < s["t"] < 2.0, s
        assert "--max-run-wall" in s.get("error", ""), s
        # the stored rows are all there, and an unpaced run finishes within the budget
        rows = requests.get(f"{d.url}/v1/sessions/{sid}/series",
                            params={"channels": "vehicle.speed"}).json()
        assert rows["count"] == s["index"] + 1
        final = wait_op(d.url, requests.post(f"{d.url}/v1/sessions/{sid}/run",
                                             json={}).json()["id"])
        assert final["response"]["status"] == "done", final
    finally:
        d.stop()



def test_paced_run_publishes_no_row_early_and_hears_cancel_and_budget():
    """Review, session 20: a paced run (real_time_factor) computed the row due at
    t = 1 s at once, published it, reported a rate of ~190x against a cap of
    0.02 and queued its next slice for when that row was due: a cancel took
    49 s to act and --max-run-wall 2 paused the run after 20 s. Now the next row
    is computed only when it is due, a waiting run looks at cancel and the wall
    budget every 0.2 s, and the reported rate is the elapsed one."""
    d = Daemon("--max-run-wall", "1.5")
    try:
        def session():
            return requests.post(d.url + "/v1/sessions", json={
                "preset": BASE_PRESET, "run": {"duration": 10.0, "sample_rate": 1}}).json()["id"]
        sid = session()
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run",
                           json={"real_time_factor": 0.02}).json()  # row 1 due after 50 s
        time.sleep(1.0)
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "running" and s["t"] == 0 and s["samples"] == 1, s
        md = requests.get(f"{d.url}/v1/operations/{op['id']}").json()["metadata"]
        assert md["t"] == 0 and md["real_time_factor"] <= 0.02 and md["wall_time_s"] >= 0.9, md
        t_cancel = time.time()
        assert requests.post(f"{d.url}/v1/operations/{op['id']}:cancel").status_code == 200
        final = wait_op(d.url, op["id"], timeout=10)
        assert time.time() - t_cancel < 2.0, final  # was 49 s; 0.2-s polls, loaded CI
        assert requests.get(f"{d.url}/v1/sessions/{sid}").json()["status"] == "paused"
        # the last row ends the run: no wait for a row past the end (it waited
        # one more 0.2-s poll and reported 0.91 at a cap of 1)
        sid = requests.post(d.url + "/v1/sessions", json={
            "preset": BASE_PRESET, "run": {"duration": 1.0, "sample_rate": 1}}).json()["id"]
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run", json={"real_time_factor": 1}).json()
        final = wait_op(d.url, op["id"], timeout=10)
        assert final["response"]["status"] == "done", final
        # 1.0 s ideal (measured 1.001); the extra 0.2-s poll gave >= 1.2
        assert final["metadata"]["wall_time_s"] < 1.15, final["metadata"]
        # the wall budget: a run waiting 20 s for its next row pauses at 1.5 s
        sid = session()
        t_run = time.time()
        op = requests.post(f"{d.url}/v1/sessions/{sid}/run",
                           json={"real_time_factor": 0.05}).json()
        final = wait_op(d.url, op["id"], timeout=10)
        assert "--max-run-wall" in final["error"]["message"], final
        assert time.time() - t_run < 4.0, final  # was 20 s
    finally:
        d.stop()
