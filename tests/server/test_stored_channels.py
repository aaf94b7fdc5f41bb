"""A stored session stays readable when this build cannot rebuild its model
(task: keep a stored session readable after an upgrade). Each session's
channel list (name, unit, description) and sample rate are stored with it at
creation (sessions.channels); when its config no longer builds a model — or
the model now has other channels — series (JSON and CSV, with units), stream
and spectrum are served from the stored rows and that stored list, while
step, run and frames are refused with 409 naming the reason. Stores written
before the column existed are migrated (column added, NULL): their sessions
take the channels from the model as before, and without a model their rows
cannot be labelled (409)."""
import json
import sqlite3

import requests

from conftest import BASE_PRESET, Daemon, is_problem


def db(data_dir, sql, *args):
    with sqlite3.connect(f"{data_dir}/tanksimd.db") as c:
        return c.execute(sql, args).fetchall()


def stepped(data_dir, duration=0.5):
    """Create and step one session; return (id, session, series JSON, series CSV, ndjson lines)."""
    d = Daemon(data_dir=data_dir)
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}).json()["id"]
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": duration})
        assert r.status_code == 200, r.text
        sess = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        ser = requests.get(f"{d.url}/v1/sessions/{sid}/series")
        csv = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"format": "csv"})
        nd = requests.get(f"{d.url}/v1/sessions/{sid}/stream", params={"format": "ndjson"})
        assert ser.status_code == csv.status_code == nd.status_code == 200
    finally:
        assert d.stop() == 0
    return sid, sess, ser.json(), csv.text, nd.text.splitlines()


def break_config(data_dir):
    db(data_dir, "UPDATE sessions SET config=? WHERE seq=1", '{"run": {"kind": "no-such-kind"}}')


def test_channel_list_is_stored_at_creation(tmp_path):
    data = str(tmp_path)
    sid, sess, _, _, _ = stepped(data, 0.1)
    ((text,),) = db(data, "SELECT channels FROM sessions WHERE seq=1")
    stored = json.loads(text)
    assert stored["channels"] == sess["channels"]
    assert stored["sample_rate"] == sess["sample_rate"]
    assert stored["channels"][0]["name"] == "t" and stored["channels"][0]["unit"] == "s"


def test_unbuildable_model_serves_stored_series_with_units(tmp_path):
    data = str(tmp_path)
    sid, sess, ser, csv, nd = stepped(data)
    assert ser["index"] == list(range(251))
    break_config(data)
    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed" and "model cannot be rebuilt" in s["error"], s
        assert s["channels"] == sess["channels"]  # names, units, descriptions
        assert s["sample_rate"] == sess["sample_rate"]
        assert s["latest"] == sess["latest"] and s["index"] == 250 and s["samples"] == 251
        # the full series, JSON and CSV (header "name [unit]"), as before the upgrade
        after = requests.get(f"{d.url}/v1/sessions/{sid}/series")
        assert after.status_code == 200, after.text
        assert after.json() == ser
        units = {c["name"]: c["unit"] for c in after.json()["channels"]}
        assert units["t"] == "s" and all(units.values())
        acsv = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"format": "csv"})
        assert acsv.status_code == 200 and acsv.headers["Content-Type"].startswith("text/csv")
        assert acsv.text == csv
        header = acsv.text.splitlines()[0].split(",")
        assert header == [f"{c['name']} [{c['unit']}]" for c in sess["channels"]]
        assert len(acsv.text.splitlines()) == 252
        # a channel selection and a page, from the stored list
        name = sess["channels"][1]["name"]
        part = requests.get(f"{d.url}/v1/sessions/{sid}/series",
                            params={"channels": name, "page_size": 100}).json()
        assert [c["name"] for c in part["channels"]] == ["t", name]
        assert part["index"] == list(range(100)) and part["next_page_token"] == "100"
        is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/series",
                                params={"channels": "no.such"}), 404, "/channels")
        # stream and spectrum
        assert requests.get(f"{d.url}/v1/sessions/{sid}/stream",
                            params={"format": "ndjson"}).text.splitlines() == nd
        f = requests.get(f"{d.url}/v1/sessions/{sid}/fft", params={"channel": name})
        assert f.status_code == 200, f.text
        assert f.json()["unit"] == sess["channels"][1]["unit"] and f.json()["n"] == 251
        # still nothing that needs the model
        p = is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}), 409)
        assert "model cannot be rebuilt" in p["detail"]
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/frame.png"), 409)
        assert "model cannot be rebuilt" in p["detail"]
        is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/frames"), 409)
    finally:
        assert d.stop() == 0


def test_changed_channels_are_served_as_stored(tmp_path):
    """The model builds but lists other channels than the rows were stored
    with (an upgrade renamed one): the rows are labelled by the stored list and
    the session is not advanced (new rows would not fit the old columns)."""
    data = str(tmp_path)
    sid, sess, ser, _, _ = stepped(data, 0.1)
    ((text,),) = db(data, "SELECT channels FROM sessions WHERE seq=1")
    stored = json.loads(text)
    old = stored["channels"][1]["name"]
    stored["channels"][1]["name"] = "old." + old
    db(data, "UPDATE sessions SET channels=? WHERE seq=1", json.dumps(stored))
    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed" and "other channels" in s["error"], s
        after = requests.get(f"{d.url}/v1/sessions/{sid}/series").json()
        assert after["channels"][1]["name"] == "old." + old
        assert after["channels"][1]["values"] == ser["channels"][1]["values"]
        is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}), 409)
    finally:
        assert d.stop() == 0


def test_store_without_channel_column_is_migrated(tmp_path):
    """A store from before sessions.channels: the column is added; a session
    with a model is served from the model, one without a model cannot label
    its rows (409 naming why), and nothing is deleted."""
    data = str(tmp_path)
    sid, sess, ser, _, _ = stepped(data, 0.1)
    db(data, "ALTER TABLE sessions DROP COLUMN channels")
    d = Daemon(data_dir=data)
    try:
        assert requests.get(f"{d.url}/v1/sessions/{sid}/series").json() == ser
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 200, r.text
    finally:
        assert d.stop() == 0
    cols = [c[1] for c in db(data, "PRAGMA table_info(sessions)")]
    assert "channels" in cols
    assert db(data, "SELECT channels FROM sessions WHERE seq=1") == [(None,)]
    n_rows = db(data, "SELECT COUNT(*) FROM samples WHERE seq=1")
    break_config(data)
    d = Daemon(data_dir=data)
    try:
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/series"), 409)
        assert "no stored channel list" in p["detail"] and "model cannot be rebuilt" in p["detail"]
    finally:
        assert d.stop() == 0
    assert db(data, "SELECT COUNT(*) FROM samples WHERE seq=1") == n_rows
