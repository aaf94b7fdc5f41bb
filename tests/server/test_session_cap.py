"""tanksimd --max-sessions under concurrent creates: the cap is checked and a
place reserved in one step, so however many creates race, at most the cap
succeed (201) and every other one gets the documented 429 problem+json
naming --max-sessions. Many worker threads (--threads 8) and a barrier
release all clients at once so that creates really overlap; before the
check and the insert were made one step, this test saw 4-6 sessions
created under a cap of 3."""
import threading

import requests

from conftest import BASE_PRESET, Daemon, is_problem

CAP = 3
CLIENTS = 24


def test_concurrent_creates_respect_the_cap(tmp_path):
    d = Daemon("--max-sessions", str(CAP), "--threads", "8", data_dir=str(tmp_path))
    try:
        for _round in range(3):  # a fresh race each round, after deleting all
            barrier = threading.Barrier(CLIENTS)
            results = [None] * CLIENTS

            def create(i):
                with requests.Session() as http:
                    barrier.wait()
                    results[i] = http.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET})

            threads = [threading.Thread(target=create, args=(i,)) for i in range(CLIENTS)]
            for t in threads:
                t.start()
            for t in threads:
                t.join(60)
            codes = [r.status_code for r in results]
            assert codes.count(201) == CAP, codes
            for r in results:
                if r.status_code != 201:
                    p = is_problem(r, 429)
                    assert "--max-sessions" in p["detail"]
            listed = requests.get(d.url + "/v1/sessions", params={"page_size": 100}).json()
            assert len(listed["sessions"]) == CAP
            for s in listed["sessions"]:
                assert requests.delete(f"{d.url}/v1/sessions/{s['id']}").status_code == 204
    finally:
        d.stop()


def test_paging_after_concurrent_creates_lists_each_session_once(tmp_path):
    """Concurrent creates draw their sequence numbers before storing and may
    reach the registry in another order; listing pages on the sequence number
    (page_token = last seq), so a registry out of seq order would skip
    sessions on later pages. Every created id must appear exactly once when
    paging one session per page."""
    d = Daemon("--threads", "8", data_dir=str(tmp_path))
    try:
        barrier = threading.Barrier(CLIENTS)
        ids = []

        def create():
            with requests.Session() as http:
                barrier.wait()
                r = http.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET})
                assert r.status_code == 201, r.text
                ids.append(r.json()["id"])

        threads = [threading.Thread(target=create) for _ in range(CLIENTS)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(60)
        assert len(ids) == CLIENTS
        seen, token = [], None
        for _ in range(2 * CLIENTS):
            params = {"page_size": 1, **({"page_token": token} if token else {})}
            page = requests.get(d.url + "/v1/sessions", params=params).json()
            seen += [s["id"] for s in page["sessions"]]
            token = page.get("next_page_token")
            if not token:
                break
        assert sorted(seen) == sorted(ids)
    finally:
        d.stop()
