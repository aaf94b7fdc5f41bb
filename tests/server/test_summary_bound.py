"""GET /v1/sessions/{id}/summary reads every stored row of every channel on
an HTTP thread (200,001 rows x 65 channels: 104 MB, 0.1 s): eight at once
held the rows of all eight and /v1/health 0.3-0.6 s. One summary is computed
at a time now; another asked for meanwhile is answered 503 /problems/busy
with Retry-After, and the one computed is the same as alone."""
import threading
import time

import requests

from conftest import is_problem


def test_one_summary_at_a_time_the_others_busy(daemon):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "bump-coupled-rack90", "run": {"sample_rate": 20000, "duration": 5}})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    assert requests.post(f"{daemon.url}/v1/sessions/{sid}/step", json={"duration": 5}, timeout=120).status_code == 200
    path = f"{daemon.url}/v1/sessions/{sid}/summary"
    alone = requests.get(path)
    assert alone.status_code == 200 and alone.json()["rows"] == 100001
    answers, health = [], []
    go = threading.Barrier(9)

    def ask():
        go.wait()
        answers.append(requests.get(path, timeout=60))

    threads = [threading.Thread(target=ask) for _ in range(8)]
    for t in threads:
        t.start()
    go.wait()
    time.sleep(0.01)
    t0 = time.time()
    assert requests.get(daemon.url + "/v1/health", timeout=10).status_code == 200
    health.append(time.time() - t0)
    for t in threads:
        t.join(60)
    ok = [a for a in answers if a.status_code == 200]
    busy = [a for a in answers if a.status_code != 200]
    assert ok and busy, [a.status_code for a in answers]
    for a in ok:
        assert a.content == alone.content
    for a in busy:
        p = is_problem(a, 503)
        assert p["type"].endswith("/problems/busy"), p
        assert int(a.headers["Retry-After"]) >= 1
    assert health[0] < 0.2, health
    # retried, it is answered
    assert requests.get(path).content == alone.content
