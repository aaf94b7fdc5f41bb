"""GET /v1/sessions/{id} queued behind the first-use rebuild (after a
restart) of a session that a DELETE removes meanwhile answered 200 with
"status": "deleted", while /series, /fft, /summary answered 404 "was
deleted". run_built now answers that 404 for every route."""
import tempfile
import threading
import time

import requests

from conftest import Daemon, is_problem, wait_op


def start(*args, **kw):
    return Daemon(*args, **kw)


def test_get_session_queued_behind_the_rebuild_of_a_deleted_session_is_404():
    dd = tempfile.mkdtemp(prefix="tanksimd-")
    with start("--threads", "1", data_dir=dd) as d:
        r = requests.post(d.url + "/v1/sessions",
                          json={"preset": "bump-prescribed-coupled", "run": {"duration": 1.0, "sample_rate": 50}})
        assert r.status_code == 201, r.text
        sid = r.json()["id"]
        assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.2}).status_code == 200
    with start("--threads", "1", data_dir=dd) as d:
        # the one worker is busy with an engine map: the rebuild waits behind it
        r = requests.post(d.url + "/v1/engine-map", json={"preset": "engine-map-conventional"})
        assert r.status_code == 202, r.text
        op = r.json()["id"]
        answers = {}

        def ask(name, path):
            answers[name] = requests.get(d.url + path, timeout=60)

        threads = [threading.Thread(target=ask, args=a) for a in [
            ("session", f"/v1/sessions/{sid}"),
            ("series", f"/v1/sessions/{sid}/series"),
        ]]
        for t in threads:
            t.start()
        time.sleep(0.5)  # both wait for the rebuild
        assert not answers, {k: (v.status_code, v.text) for k, v in answers.items()}
        assert requests.delete(f"{d.url}/v1/sessions/{sid}").status_code == 204
        requests.post(f"{d.url}/v1/operations/{op}:cancel")
        for t in threads:
            t.join(60)
        wait_op(d.url, op, timeout=60)
        for name, r in answers.items():
            p = is_problem(r, 404)
            assert "was deleted" in p["detail"], (name, p)
