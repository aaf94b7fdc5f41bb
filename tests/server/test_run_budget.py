"""tanksimd --max-run-wall S (found by the config fuzzer, session 4: configs
inside every range can keep a worker busy for hours): a run operation that has
used S wall seconds pauses with an error naming the flag; its rows are stored
and a further run continues from there. Without the flag runs are unbounded."""
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

