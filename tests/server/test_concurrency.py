"""tanksimd under concurrent clients (issue 7): 50 sessions created and stepped
from 8 client threads at once. Sessions come in 5 groups of 10 with different
prescribed torques; every session of a group must report exactly the same
values at every step (same config, same steps -> same numbers), the torque
channel must be the session's own, and times must be the session's own —
any cross-talk between sessions or workers would break one of these."""
from concurrent.futures import ThreadPoolExecutor

import requests

from conftest import BASE_PRESET, Daemon

STEPS = 4
DT = 0.2


def life(url, i):
    torque = 2000.0 + 1000.0 * (i % 5)
    with requests.Session() as http:
        r = http.post(url + "/v1/sessions", json={"preset": BASE_PRESET,
                                                  "drive": {"torque": torque}})
        assert r.status_code == 201, r.text
        sid = r.json()["id"]
        out = []
        for k in range(STEPS):
            r = http.post(f"{url}/v1/sessions/{sid}/step", json={"duration": DT})
            assert r.status_code == 200, r.text
            v = r.json()
            assert v["id"] == sid and v["index"] == round((k + 1) * DT * 500)
            assert v["values"]["sprocket.torque"] == torque
            out.append(v["values"])
        return i % 5, out


def test_50_sessions_8_threads(tmp_path):
    d = Daemon("--threads", "2", data_dir=str(tmp_path))
    try:
        with ThreadPoolExecutor(max_workers=8) as ex:
            results = list(ex.map(lambda i: life(d.url, i), range(50)))
        groups = {}
        for g, out in results:
            groups.setdefault(g, []).append(out)
        assert len(groups) == 5
        for g, outs in groups.items():
            assert len(outs) == 10
            assert all(o == outs[0] for o in outs), f"group {g} differs"
        speeds = [groups[g][0][-1]["vehicle.speed"] for g in range(5)]
        assert speeds == sorted(speeds) and len(set(speeds)) == 5
        s = requests.get(d.url + "/v1/sessions", params={"page_size": 100}).json()["sessions"]
        assert len(s) == 50 and all(x["status"] == "paused" for x in s)
        assert " 500 " not in d.stderr()
    finally:
        d.stop()
