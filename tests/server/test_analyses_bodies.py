"""Stored analyses keep their request once and without comment keys, and the
list carries no bodies. Before: each analysis stored its whole request body
twice (the request column and document.metadata.request, "_..." comment keys
included), GET /v1/analyses returned every body (200 analyses with 1 MB
bodies: a 200 MB answer, 856 MB RSS) and start-up recovery read every stored
request. Now the body is stored once (request column) without "_" keys, the
list gives `asked` (preset, engine fidelity, schedule) instead of the body,
GET /v1/analyses/{id} gives one entry with its whole request, and the
operation document still shows metadata.request."""
import json
import sqlite3

import requests

from conftest import Daemon, wait_op

DYNO = {"run": {"kind": "engine_dyno"}, "engine": {"fidelity": "mean_value", "_why": "fast"},
        "control": {"rack": 1.0}}


def without_comments(j):
    if isinstance(j, dict):
        return {k: without_comments(v) for k, v in j.items() if not k.startswith("_")}
    if isinstance(j, list):
        return [without_comments(v) for v in j]
    return j


def test_request_stored_once_without_comments_and_listed_without_body(tmp_path):
    dd = str(tmp_path)
    body = {**DYNO, "_note": "x" * 300_000}
    with Daemon("--threads", "2", data_dir=dd) as d:
        r = requests.post(d.url + "/v1/tune?schedule_mass=50000,60000", data=json.dumps(body))
        assert r.status_code == 202, r.text
        op = r.json()
        want = {"body": without_comments(body), "schedule_mass": "50000,60000"}
        assert op["metadata"]["request"] == want
        requests.post(f"{d.url}/v1/operations/{op['id']}:cancel")
        done = wait_op(d.url, op["id"], timeout=60)
        assert done["metadata"]["request"] == want
    con = sqlite3.connect(dd + "/tanksimd.db")
    req, doc = con.execute("SELECT request, document FROM analyses WHERE id=?", (op["id"],)).fetchone()
    con.close()
    assert json.loads(req) == want and "_note" not in req and "_why" not in req
    assert "request" not in json.loads(doc)["metadata"]  # once: in its column
    assert len(req) + len(doc) < 4000
    with Daemon("--threads", "2", data_dir=dd) as d:
        assert requests.get(f"{d.url}/v1/operations/{op['id']}").json() == done  # put back
        (a,) = requests.get(d.url + "/v1/analyses").json()["analyses"]
        assert "request" not in a
        assert a["asked"] == {"preset": None, "engine_fidelity": "mean_value",
                              "schedule_mass": "50000,60000"}
        one = requests.get(f"{d.url}/v1/analyses/{op['id']}").json()
        assert one == {**a, "request": want}
        assert requests.get(f"{d.url}/v1/analyses/op0000000000000000").status_code == 404


def test_listing_of_large_stored_bodies_stays_small(tmp_path):
    """Rows as an older daemon stored them: 20 bodies of 1 MB in both columns."""
    dd = str(tmp_path)
    with Daemon(data_dir=dd):
        pass  # make the store
    con = sqlite3.connect(dd + "/tanksimd.db")
    big = {"body": {"preset": "engine-map-conventional", "_note": "x" * 1_000_000}}
    for i in range(20):
        oid = f"op{i:016x}"
        doc = {"name": "operations/" + oid, "id": oid, "done": True,
               "metadata": {"kind": "engine_map", "created": 1e9 + i, "request": big,
                            "progress": 1, "parts_done": 14, "parts_total": 14, "wall_time_s": 1},
               "response": {}}
        con.execute("INSERT INTO analyses VALUES(?,?,?,?,?,?,?)",
                    (oid, "engine_map", 1e9 + i, 1, 0, json.dumps(big), json.dumps(doc)))
    con.commit()
    con.close()
    with Daemon(data_dir=dd) as d:
        r = requests.get(d.url + "/v1/analyses")
        assert r.status_code == 200
        lst = r.json()["analyses"]
        assert len(lst) == 20 and len(r.content) < 20 * 400, len(r.content)
        assert lst[0]["asked"] == {"preset": "engine-map-conventional", "engine_fidelity": None}
        one = requests.get(f"{d.url}/v1/analyses/{lst[0]['id']}").json()
        assert one["request"] == without_comments(big)
        op = requests.get(f"{d.url}/v1/operations/{lst[0]['id']}").json()
        assert op["metadata"]["request"] == without_comments(big)


def test_old_rows_are_shown_without_their_comment_keys(tmp_path):
    """A row an older daemon stored (its request with "_" keys, in its column and
    in the document): GET /v1/analyses/{id} and the operation show it without them,
    as the daemon stores requests now."""
    dd = str(tmp_path)
    with Daemon(data_dir=dd):
        pass  # make the store
    req = {"body": {**DYNO, "_comment": "old", "control": {"rack": 1.0, "_why": "full"},
                    "run": {"kind": "engine_dyno", "x": [{"_a": 1, "b": 2}]}},
           "schedule_mass": "50000"}
    oid = "op00000000000000aa"
    doc = {"name": "operations/" + oid, "id": oid, "done": True,
           "metadata": {"kind": "tune", "created": 1e9, "request": req,
                        "progress": 1, "parts_done": 1, "parts_total": 1, "wall_time_s": 1},
           "response": {}}
    con = sqlite3.connect(dd + "/tanksimd.db")
    con.execute("INSERT INTO analyses VALUES(?,?,?,?,?,?,?)",
                (oid, "tune", 1e9, 1, 0, json.dumps(req), json.dumps(doc)))
    con.commit()
    con.close()
    want = without_comments(req)
    assert want["body"]["run"]["x"] == [{"b": 2}] and "_why" not in json.dumps(want)
    with Daemon(data_dir=dd) as d:
        one = requests.get(f"{d.url}/v1/analyses/{oid}").json()
        assert one["request"] == want
        assert one["asked"]["engine_fidelity"] == "mean_value"
        op = requests.get(f"{d.url}/v1/operations/{oid}").json()
        assert op["metadata"]["request"] == want
