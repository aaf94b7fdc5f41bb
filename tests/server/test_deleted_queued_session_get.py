"""GET /v1/sessions/{id} queued behind the first-use rebuild (after a
restart) of a session that a DELETE removes meanwhile answered 200 with
"status": "deleted", while /series, /fft, /summary answered 404 "was
deleted". run_built now answers that 404 for every route."""
import threading

import requests

from conftest import Daemon, is_problem, metric, stepped_session, wait_metric, wait_op


def test_get_session_queued_behind_the_rebuild_of_a_deleted_session_is_404(tmp_path):
    dd = str(tmp_path)
    with Daemon("--threads", "1", data_dir=dd) as d:
        sid = stepped_session(d.url, "bump-prescribed-coupled", step=0.2)
    with Daemon("--threads", "1", data_dir=dd) as d:
        # the one worker is busy with an engine map: the rebuild waits behind it
        r = requests.post(d.url + "/v1/engine-map", json={"preset": "engine-map-conventional"})
        assert r.status_code == 202, r.text
        op = r.json()["id"]
        busy = metric(d.url, "tanksimd_jobs_pending")  # the engine map, running
        answers = {}

        def ask(name, path):
            answers[name] = requests.get(d.url + path, timeout=60)

        threads = [threading.Thread(target=ask, args=a) for a in [
            ("session", f"/v1/sessions/{sid}"),
            ("series", f"/v1/sessions/{sid}/series"),
        ]]
        for t in threads:
            t.start()
        wait_metric(d.url, "tanksimd_jobs_pending", busy + len(threads))  # both wait for the rebuild
        assert not answers, {k: (v.status_code, v.text) for k, v in answers.items()}
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        requests.post(f"{d.url}/v1/operations/{op}:cancel")
        for t in threads:
            t.join(60)
        wait_op(d.url, op, timeout=60)
        for name, r in answers.items():
            p = is_problem(r, 404)
            assert "was deleted" in p["detail"], (name, p)
