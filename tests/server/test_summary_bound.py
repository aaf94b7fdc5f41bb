"""GET /v1/sessions/{id}/summary reads every stored row of every channel on
an HTTP thread (200,001 rows x 65 channels: 104 MB, 0.1 s): eight at once
held the rows of all eight and /v1/health 0.3-0.6 s. The rows summaries hold
together are bounded (128 MB; one alone always goes); one that would pass the
bound is answered 503 /problems/busy with Retry-After, and the one computed
is the same as alone. Small summaries run side by side: until session 33 the
bound was one summary at a time, and a soak test's 19-ms summaries of short
runs refused each other."""
import threading
import time

import requests

from conftest import is_problem

BURSTS = 5  # bursts of eight summaries asked at once, until one overlaps


def ask_at_once(path, n, meanwhile=None):
    """GET path from n threads released together (meanwhile, if given, runs
    on this thread once they are released); the n answers."""
    answers = []
    go = threading.Barrier(n + 1)

    def ask():
        go.wait()
        answers.append(requests.get(path, timeout=60))

    threads = [threading.Thread(target=ask) for _ in range(n)]
    for t in threads:
        t.start()
    go.wait()
    if meanwhile:
        meanwhile()
    for t in threads:
        t.join(60)
    assert len(answers) == n
    return answers


def test_one_summary_at_a_time_the_others_busy(daemon):
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "bump-coupled-rack90", "run": {"sample_rate": 20000, "duration": 5}})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    assert requests.post(f"{daemon.url}/v1/sessions/{sid}/step", json={"duration": 5}, timeout=120).status_code == 200
    path = f"{daemon.url}/v1/sessions/{sid}/summary"
    alone = requests.get(path)
    assert alone.status_code == 200 and alone.json()["rows"] == 100001
    health, bursts = [], []

    def burst():
        """Eight summaries at once and a /v1/health meanwhile: the answers."""
        def probe():
            time.sleep(0.01)
            t0 = time.time()
            assert requests.get(daemon.url + "/v1/health", timeout=10).status_code == 200
            health.append(time.time() - t0)

        return ask_at_once(path, 8, probe)

    # Whether the eight overlap is up to the scheduler: on a loaded 2-core
    # machine they were answered one after another (eight 200s, nothing to
    # refuse; seen in 1 of 10 runs). A burst that overlapped is what the test
    # needs, so it asks again until one does; a daemon that never refuses a
    # second summary fails every burst.
    for _ in range(BURSTS):
        answers = burst()
        bursts.append([a.status_code for a in answers])
        ok = [a for a in answers if a.status_code == 200]
        busy = [a for a in answers if a.status_code != 200]
        assert ok, bursts  # one is always computed
        for a in ok:
            assert a.content == alone.content
        for a in busy:
            p = is_problem(a, 503)
            assert p["type"].endswith("/problems/busy"), p
            assert int(a.headers["Retry-After"]) >= 1
        if busy:
            break
    assert busy, f"no summary was refused in {BURSTS} bursts of 8: {bursts}"
    assert min(health) < 0.2, health
    # retried, it is answered
    assert requests.get(path).content == alone.content


def test_small_summaries_at_once_are_all_answered(daemon):
    """Eight summaries of a short run asked at once (a 3-s crank-angle
    dynamometer run: 37,801 rows x 17 channels, 5.4 MB each, 44 MB together)
    are all computed, in each of five bursts, and each is the same as alone.
    On the one-at-a-time daemon overlapping ones were refused 503 (the soak
    test's reproduction: three of four)."""
    r = requests.post(daemon.url + "/v1/sessions",
                      json={"preset": "engine-map-conventional", "run": {"duration": 3}})
    assert r.status_code == 201, r.text
    sid = r.json()["id"]
    assert requests.post(f"{daemon.url}/v1/sessions/{sid}/step", json={"duration": 3},
                         timeout=120).status_code == 200
    path = f"{daemon.url}/v1/sessions/{sid}/summary"
    alone = requests.get(path)
    assert alone.status_code == 200, alone.text
    for _ in range(BURSTS):
        answers = ask_at_once(path, 8)
        assert [a.status_code for a in answers] == [200] * 8, [a.text for a in answers]
        for a in answers:
            assert a.content == alone.content
