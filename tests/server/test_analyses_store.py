"""Stored analyses: an engine map or tuning (POST /v1/engine-map, /v1/tune)
outlives the daemon that computed it. Its operation document is written to
the store (table analyses) when it starts, after each part and when it ends,
so after a restart GET /v1/operations/{id} returns the finished result, and
an analysis a kill -9 cut short is reported done with an error saying how
far it got, instead of a 404. GET /v1/analyses lists them; DELETE
/v1/analyses/{id} removes a finished one (409 while it runs). The brief's
"nothing lost on a crash" for the daemon's second kind of work."""
import signal
import sqlite3
import time

import pytest
import requests

from conftest import Daemon, is_problem, wait_op

MEAN_VALUE_DYNO = {"run": {"kind": "engine_dyno"}, "engine": {"fidelity": "mean_value"},
                   "control": {"rack": 1.0}}
CRANK_MAP = {"preset": "engine-map-conventional"}  # crank-angle: 14 parts, ~3 s (slower in ASan)


def start(url, path, body, query=""):
    r = requests.post(url + path + query, json=body, timeout=30)
    assert r.status_code == 202, r.text
    return r.json()


def wait_parts(url, op_id, parts, timeout=120):
    """Poll until the operation has at least `parts` parts done; its document."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        op = requests.get(f"{url}/v1/operations/{op_id}", timeout=10).json()
        if op["metadata"]["parts_done"] >= parts or op["done"]:
            return op
        time.sleep(0.02)
    raise AssertionError(f"{op_id}: fewer than {parts} parts after {timeout} s")


def listed(url):
    r = requests.get(url + "/v1/analyses", timeout=10)
    assert r.status_code == 200, r.text
    return {a["id"]: a for a in r.json()["analyses"]}


def test_finished_analysis_survives_a_restart(tmp_path):
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d:
        op = start(d.url, "/v1/engine-map", MEAN_VALUE_DYNO)
        assert op["metadata"]["request"] == {"body": MEAN_VALUE_DYNO}
        assert op["metadata"]["created"] == pytest.approx(time.time(), abs=60)
        done = wait_op(d.url, op["id"], timeout=60)
        assert "response" in done, done
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d2:
        r = requests.get(f"{d2.url}/v1/operations/{op['id']}", timeout=10)
        assert r.status_code == 200, r.text
        assert r.json() == done  # the document as the first daemon answered it, bit for bit
        a = listed(d2.url)[op["id"]]
        assert a["kind"] == "engine_map" and a["done"] and not a["failed"] and a["error_code"] == 0
        assert a["name"] == "operations/" + op["id"] and "request" not in a  # no bodies listed
        assert a["asked"] == {"preset": MEAN_VALUE_DYNO.get("preset"),
                              "engine_fidelity": MEAN_VALUE_DYNO.get("engine", {}).get("fidelity")}
        one = requests.get(f"{d2.url}/v1/analyses/{op['id']}", timeout=10).json()
        assert one == {**a, "request": {"body": MEAN_VALUE_DYNO}}
        # cancelling a stored, finished analysis changes nothing
        r = requests.post(f"{d2.url}/v1/operations/{op['id']}:cancel", timeout=10)
        assert r.status_code == 200 and r.json() == done


def test_analysis_cut_short_by_kill_9_is_reported_not_lost(tmp_path):
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d:
        op = start(d.url, "/v1/engine-map", CRANK_MAP)
        seen = wait_parts(d.url, op["id"], 2)
        assert not seen["done"], "the crank-angle map finished before the kill: nothing to test"
        d.stop(sig=signal.SIGKILL)
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d2:
        got = requests.get(f"{d2.url}/v1/operations/{op['id']}", timeout=10).json()
        assert got["done"] and "response" not in got
        err = got["error"]
        # the daemon stopping is not the client's cancel: 14 UNAVAILABLE, a 503 problem
        assert err["code"] == 14 and "killed or crashed" in err["message"]
        assert err["status"] == 503 and err["type"] == "/problems/interrupted", err
        n = got["metadata"]["parts_done"]
        assert 2 <= n < 14 and f"after {n} of 14 parts" in err["message"]
        assert got["metadata"]["request"] == {"body": CRANK_MAP}
        a = listed(d2.url)[op["id"]]
        assert a["failed"] is True and a["error_code"] == 14
        assert f"analysis {op['id']} was interrupted" in d2.stderr()
    # a third start has nothing left to recover
    with Daemon(data_dir=str(tmp_path)) as d3:
        assert "was interrupted" not in d3.stderr()
        assert requests.get(f"{d3.url}/v1/operations/{op['id']}", timeout=10).json() == got


def test_shutdown_during_an_analysis_stores_why_it_ended(tmp_path):
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d:
        op = start(d.url, "/v1/engine-map", CRANK_MAP)
        wait_parts(d.url, op["id"], 1)
        assert d.stop() == 0  # SIGTERM: the map ends after the speed point in progress
    with Daemon(data_dir=str(tmp_path)) as d2:
        got = requests.get(f"{d2.url}/v1/operations/{op['id']}", timeout=10).json()
        assert got["done"] and got["error"]["code"] == 14, got["error"]
        assert got["error"]["status"] == 503 and "shut down" in got["error"]["message"], got["error"]
        assert "was interrupted" not in d2.stderr()  # it ended cleanly, nothing to recover


def test_list_newest_first_and_delete(tmp_path):
    with Daemon("--threads", "2", data_dir=str(tmp_path)) as d:
        a = start(d.url, "/v1/engine-map", MEAN_VALUE_DYNO)
        wait_op(d.url, a["id"], timeout=60)
        b = start(d.url, "/v1/tune", {"preset": "bump-coupled-ivs5mph",
                                      "engine": {"fidelity": "mean_value"}},
                  "?schedule_mass=50000,60000")
        assert b["metadata"]["request"]["schedule_mass"] == "50000,60000"
        wait_op(d.url, b["id"], timeout=120)
        ids = [x["id"] for x in requests.get(d.url + "/v1/analyses").json()["analyses"]]
        assert ids == [b["id"], a["id"]]
        c = start(d.url, "/v1/engine-map", CRANK_MAP)  # a running one cannot be deleted
        p = is_problem(requests.delete(f"{d.url}/v1/analyses/{c['id']}"), 409)
        assert ":cancel" in p["detail"]
        requests.post(f"{d.url}/v1/operations/{c['id']}:cancel")
        wait_op(d.url, c["id"], timeout=120)
        for x in (a, c):
            r = requests.delete(f"{d.url}/v1/analyses/{x['id']}")
            assert r.status_code == 204 and r.content == b""
            is_problem(requests.get(f"{d.url}/v1/operations/{x['id']}"), 404)
            is_problem(requests.delete(f"{d.url}/v1/analyses/{x['id']}"), 404)
        assert list(listed(d.url)) == [b["id"]]
        is_problem(requests.delete(f"{d.url}/v1/analyses/op0000000000000000"), 404)
    with Daemon(data_dir=str(tmp_path)) as d2:  # the deletes were stored too
        assert list(listed(d2.url)) == [b["id"]]


def test_a_run_operation_is_not_an_analysis(tmp_path):
    with Daemon(data_dir=str(tmp_path)) as d:
        s = requests.post(d.url + "/v1/sessions",
                          json={"preset": "pointmass-prescribed", "run": {"duration": 0.2}}).json()
        op = requests.post(f"{d.url}/v1/sessions/{s['id']}/run", json={}).json()
        wait_op(d.url, op["id"])
        is_problem(requests.delete(f"{d.url}/v1/analyses/{op['id']}"), 404)
        assert requests.get(f"{d.url}/v1/operations/{op['id']}").status_code == 200
        assert listed(d.url) == {}


def test_max_analyses_counts_stored_and_running_ones(tmp_path):
    """--max-analyses N: the store holds at most N analyses (running ones
    included); one more is 429 naming the flag and saying to delete some;
    the count is the store's, so it holds across a restart, and two
    requests racing for the last place cannot both take it (with the count
    taken outside analyses_lock this failed in 3 of 5 runs)."""
    with Daemon("--threads", "3", "--max-analyses", "2", data_dir=str(tmp_path)) as d:
        a = start(d.url, "/v1/engine-map", MEAN_VALUE_DYNO)
        b = start(d.url, "/v1/engine-map", CRANK_MAP)  # still running: it counts
        p = is_problem(requests.post(d.url + "/v1/engine-map", json=MEAN_VALUE_DYNO), 429)
        assert "--max-analyses" in p["detail"] and "2 stored analyses" in p["detail"], p
        assert "DELETE /v1/analyses/" in p["detail"], p
        requests.post(f"{d.url}/v1/operations/{b['id']}:cancel")
        wait_op(d.url, b["id"], timeout=120)
        wait_op(d.url, a["id"], timeout=60)
        assert requests.delete(f"{d.url}/v1/analyses/{b['id']}").status_code == 204
        c = start(d.url, "/v1/engine-map", MEAN_VALUE_DYNO)  # a place again
        wait_op(d.url, c["id"], timeout=60)
        assert set(listed(d.url)) == {a["id"], c["id"]}
    with Daemon("--threads", "3", "--max-analyses", "3", data_dir=str(tmp_path)) as d2:
        # a request the daemon refuses takes no place
        is_problem(requests.post(d2.url + "/v1/tune", json={"preset": "nonexistent"}), 400, "/preset")
        # one place left (2 stored from the first daemon); two maps race for it
        from concurrent.futures import ThreadPoolExecutor
        with ThreadPoolExecutor(2) as ex:
            codes = sorted(ex.map(lambda _: requests.post(d2.url + "/v1/engine-map",
                                                          json=CRANK_MAP).status_code, range(2)))
        assert codes == [202, 429], codes
        assert len(listed(d2.url)) == 3


def refuse(data_dir, name, when):
    """Make the store refuse, from now on, every analysis row written WHEN
    (an SQL condition on NEW): an SQLite trigger the daemon's own writes run,
    standing in for a disk that fills at that moment."""
    con = sqlite3.connect(data_dir + "/tanksimd.db")
    con.execute(f"CREATE TRIGGER {name} BEFORE INSERT ON analyses WHEN {when} "
                "BEGIN SELECT RAISE(ABORT, 'refused by the test'); END")
    con.commit()
    con.close()


def test_result_the_store_refuses_is_an_io_error_not_a_success(tmp_path):
    """tsd_op_finish_persisted (session-25 review: untested): a result whose
    final row the store refuses is answered as an I/O error (13) instead of
    a success that the next restart would lose; the store keeps that error."""
    dd = str(tmp_path)
    with Daemon("--threads", "2", data_dir=dd) as d:
        refuse(dd, "refuse_success", "NEW.done = 1 AND NEW.error_code = 0")
        op = start(d.url, "/v1/engine-map", MEAN_VALUE_DYNO)
        done = wait_op(d.url, op["id"], timeout=60)
        assert "response" not in done, done
        err = done["error"]
        assert err["code"] == 13 and "the store could not keep it" in err["message"], err
        assert done["metadata"]["parts_done"] == done["metadata"]["parts_total"]
    with Daemon(data_dir=dd) as d2:
        got = requests.get(f"{d2.url}/v1/operations/{op['id']}", timeout=10).json()
        assert got["done"] and got["error"]["code"] == 13, got
        assert "was interrupted" not in d2.stderr()


def test_interrupted_analysis_the_store_cannot_mark_is_reported_at_start(tmp_path):
    """recover_one (session-25 review: untested): an analysis a kill -9 cut
    short, whose 'interrupted' row the next start-up cannot store, is named
    on stderr with the warning, stays unfinished in the store, and is marked
    by the first start-up the store lets write."""
    dd = str(tmp_path)
    with Daemon("--threads", "2", data_dir=dd) as d:
        op = start(d.url, "/v1/engine-map", CRANK_MAP)
        seen = wait_parts(d.url, op["id"], 1)
        assert not seen["done"], "the crank-angle map finished before the kill: nothing to test"
        d.stop(sig=signal.SIGKILL)
    refuse(dd, "refuse_interrupted", "NEW.done = 1")
    with Daemon(data_dir=dd) as d2:
        assert "could not mark the stored analyses" in d2.stderr()
        assert "refused by the test" in d2.stderr()
        got = requests.get(f"{d2.url}/v1/operations/{op['id']}", timeout=10).json()
        assert not got["done"], got
    con = sqlite3.connect(dd + "/tanksimd.db")
    con.execute("DROP TRIGGER refuse_interrupted")
    con.commit()
    con.close()
    with Daemon(data_dir=dd) as d3:
        assert f"analysis {op['id']} was interrupted" in d3.stderr()
        got = requests.get(f"{d3.url}/v1/operations/{op['id']}", timeout=10).json()
        assert got["done"] and got["error"]["code"] == 14, got
