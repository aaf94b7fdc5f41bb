"""tanksimd start-up recovery when a stored session cannot be brought back
(project rule: nothing stored is lost). A session whose stored state snapshot
cannot be restored (written by a build with another state layout, or
corrupt), or whose stored config no longer builds a model, must keep every
stored sample row: the session is listed as failed with the reason, its
rows stay readable where the model exists, stepping and running it are
refused with a 409 problem naming why, and the "failed" is not written back
to the store — a build that can read the snapshot again (here: the blob put
back) continues the session where it was."""
import contextlib
import sqlite3

import pytest
import requests

from conftest import BASE_PRESET, Daemon, is_problem, sse_events


def stored(data_dir, sql, *args):
    with sqlite3.connect(f"{data_dir}/tanksimd.db") as c:
        return c.execute(sql, args).fetchall()


def stored_rows(data_dir, seq=1):
    return stored(data_dir, "SELECT idx, vals FROM samples WHERE seq=? ORDER BY idx", seq)


def make_stepped_session(data_dir):
    """One session stepped 0.5 s (rows 0..250 at 500 Hz); returns (id, series)."""
    d = Daemon(data_dir=data_dir)
    try:
        sid = requests.post(d.url + "/v1/sessions", json={"preset": BASE_PRESET}).json()["id"]
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.5})
        assert r.status_code == 200, r.text
        ser = requests.get(f"{d.url}/v1/sessions/{sid}/series").json()
        assert ser["index"] == list(range(251))
    finally:
        assert d.stop() == 0
    return sid, ser


def damage_row(data_dir, idx, seq=1):
    """Cut stored row idx short (40 bytes: not a row of any session's width)."""
    stored(data_dir, "UPDATE samples SET vals=substr(vals, 1, 40) WHERE seq=? AND idx=?", seq, idx)


@contextlib.contextmanager
def restarted_failed(data_dir, sid, why):
    """A daemon on data_dir in which session sid is failed with why in its
    error and a step is refused (409) naming why; yields (daemon, session);
    the stored rows are the same after it stopped."""
    rows_before = stored_rows(data_dir)
    d = Daemon(data_dir=data_dir)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed" and why in s["error"], s
        p = is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1}), 409)
        assert why in p["detail"], p
        yield d, s
    finally:
        assert d.stop() == 0
    assert stored_rows(data_dir) == rows_before


def test_corrupt_snapshot_keeps_rows_and_refuses_steps(tmp_path):
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    rows_before = stored_rows(data)
    assert len(rows_before) == 251
    (good_blob,) = stored(data, "SELECT blob FROM snapshots WHERE seq=1 ORDER BY idx DESC LIMIT 1")[0]
    # an older build's (shorter) state layout
    stored(data, "UPDATE snapshots SET blob=? WHERE seq=1", good_blob[:-8])

    d = Daemon(data_dir=data)
    try:
        assert stored_rows(data) == rows_before  # start-up deleted nothing
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed"
        assert "state cannot be restored" in s["error"], s
        assert s["index"] == 250 and s["samples"] == 251
        assert s["t"] == before["channels"][0]["values"][-1]
        after = requests.get(f"{d.url}/v1/sessions/{sid}/series").json()
        assert after == before  # every stored row is served, unchanged
        for path, body in (("step", {"duration": 0.1}), ("run", {})):
            p = is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/{path}", json=body), 409)
            assert "state cannot be restored" in p["detail"], p
        # frames are rebuilt from the snapshots this build cannot read: 409 with
        # the reason (not a 400 blaming the request)
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/frame.png"), 409)
        assert "state cannot be restored" in p["detail"], p
        assert stored_rows(data) == rows_before
    finally:
        assert d.stop() == 0
    # the failure was not written over the stored status
    assert stored(data, "SELECT status FROM sessions WHERE seq=1") == [("paused",)]
    assert stored_rows(data) == rows_before

    # a build that reads the snapshot again continues the session
    stored(data, "UPDATE snapshots SET blob=? WHERE seq=1", good_blob)
    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused" and s["index"] == 250 and "error" not in s
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 200 and r.json()["index"] == 300, r.text
        ser = requests.get(f"{d.url}/v1/sessions/{sid}/series").json()
        assert ser["index"] == list(range(301))
        assert ser["channels"][1]["values"][:251] == before["channels"][1]["values"]
    finally:
        d.stop()


def test_unbuildable_config_keeps_rows_and_status(tmp_path):
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    rows_before = stored_rows(data)
    ((config,),) = stored(data, "SELECT config FROM sessions WHERE seq=1")
    stored(data, "UPDATE sessions SET config=? WHERE seq=1", '{"run": {"kind": "no-such-kind"}}')

    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "failed" and "model cannot be rebuilt" in s["error"], s
        p = is_problem(requests.post(f"{d.url}/v1/sessions/{sid}/step",
                                     json={"duration": 0.1}), 409)
        assert "model cannot be rebuilt" in p["detail"], p
    finally:
        assert d.stop() == 0
    assert stored_rows(data) == rows_before
    assert stored(data, "SELECT status FROM sessions WHERE seq=1") == [("paused",)]

    stored(data, "UPDATE sessions SET config=? WHERE seq=1", config)
    d = Daemon(data_dir=data)
    try:
        s = requests.get(f"{d.url}/v1/sessions/{sid}").json()
        assert s["status"] == "paused" and s["index"] == 250
        assert requests.get(f"{d.url}/v1/sessions/{sid}/series").json() == before
        r = requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.1})
        assert r.status_code == 200 and r.json()["index"] == 300, r.text
    finally:
        d.stop()


def test_rows_without_a_snapshot_are_kept(tmp_path):
    """Rows stored but no snapshot at all (a store edited by hand, or a bug):
    the rows are kept and the session is failed, not reset to row 0."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    stored(data, "DELETE FROM snapshots WHERE seq=1")
    with restarted_failed(data, sid, "no stored state") as (d, _):
        assert requests.get(f"{d.url}/v1/sessions/{sid}/series").json() == before


def test_rows_past_the_latest_snapshot_are_kept(tmp_path):
    """Session 25 probe: with its latest snapshot removed (a store changed
    outside the daemon), the first read of the session rebuilt it from the
    previous snapshot and DELETED the stored rows past it (a log line was the
    only trace). Rows and snapshot are stored in one transaction, so this is
    never a crash's leftover: the rows are kept and the session is failed."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    snaps = [i for (i,) in stored(data, "SELECT idx FROM snapshots WHERE seq=1 ORDER BY idx")]
    assert snaps[-1] == 250 and len(snaps) >= 2, snaps
    stored(data, "DELETE FROM snapshots WHERE seq=1 AND idx=250")
    with restarted_failed(data, sid, "go on to 250") as (d, s):
        assert s["index"] == 250 and s["samples"] == 251, s
        assert requests.get(f"{d.url}/v1/sessions/{sid}/series").json() == before


def test_config_that_is_not_json_builds_no_model(tmp_path):
    """Session 25 probe: a stored config that is not JSON was replaced by {}
    and the DEFAULT model built from it (a point mass), so the session said
    "other channels than this build's model" (and, without a stored channel
    list, labelled the vehicle's rows with the point mass's channels)."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    stored(data, "UPDATE sessions SET config=? WHERE seq=1", '{"preset":')
    with restarted_failed(data, sid, "stored config is not JSON") as (d, _):
        assert requests.get(f"{d.url}/v1/sessions/{sid}/series").json() == before
    stored(data, "UPDATE sessions SET channels=NULL WHERE seq=1")
    with restarted_failed(data, sid, "stored config is not JSON") as (d, s):
        # no labels for its rows: refused, not served under another model's channels
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/series"), 409)
        assert "names and units of its stored rows are unknown" in p["detail"], p
        assert s["index"] == 250 and s["samples"] == 251, s


def test_damaged_row_is_an_error_not_zeros(tmp_path):
    """Session 25 probe: a stored row cut short was served zero-filled (on a vehicle run: 25 of
    37 channels as 0, status 200) by /series, /summary and /fft."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    damage_row(data, 200)
    d = Daemon(data_dir=data)
    try:
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/series"), 500)
        assert "row 200" in p["detail"] and "damaged" in p["detail"], p
        ok = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"to": 0.3})
        assert ok.status_code == 200 and ok.json()["index"] == list(range(151))
        p = is_problem(requests.get(f"{d.url}/v1/sessions/{sid}/summary"), 500)
        assert "row 200" in p["detail"], p
    finally:
        assert d.stop() == 0


def test_unknown_stored_status_says_so(tmp_path):
    """Session 25 probe: a status this build does not know read as failed with
    an empty reason ("failed earlier: ")."""
    data = str(tmp_path)
    sid, _ = make_stepped_session(data)
    stored(data, "UPDATE sessions SET status='bogus' WHERE seq=1")
    with restarted_failed(data, sid, "'bogus'"):
        pass


def test_damaged_last_row_fails_the_session_without_zeros(tmp_path):
    """Review of the session-25 fix: a damaged LAST row still reached the
    session's `latest` as zeros (its session listed as paused until its first
    use); it fails the session at start-up, with no latest values, on both
    ways a session is loaded (with its stored channel list, and without)."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    damage_row(data, 250)
    for phase in ("stored channels", "no stored channels"):
        if phase == "no stored channels":
            stored(data, "UPDATE sessions SET channels=NULL WHERE seq=1")
        with restarted_failed(data, sid, "last stored row (250) is damaged") as (d, s):
            assert "latest" not in s and s["index"] == 250 and s["t"] == 0.5, (phase, s)
            ok = requests.get(f"{d.url}/v1/sessions/{sid}/series", params={"to": 0.498})
            assert ok.status_code == 200 and ok.json()["index"] == list(range(250)), phase


def test_stream_sends_the_rows_before_a_damaged_one_then_says_why(tmp_path):
    """Review of the session-25 fix: a damaged row cut /stream at once, with
    no reason and without the good rows of its 256-row chunk."""
    data = str(tmp_path)
    sid, before = make_stepped_session(data)
    damage_row(data, 200)
    d = Daemon(data_dir=data)
    try:
        lines = []
        with requests.get(f"{d.url}/v1/sessions/{sid}/stream", params={"since": 149},
                          stream=True, timeout=30) as r:
            assert r.status_code == 200
            with pytest.raises(requests.exceptions.ChunkedEncodingError):
                for line in r.iter_lines(decode_unicode=True):  # cut after the error event
                    lines.append(line)
        events = sse_events(lines)
        ids = [int(e[1]) for e in events if e[0] == "sample"]
        assert ids == list(range(150, 200)), ids
        err = [e for e in events if e[0] == "error"]
        assert len(err) == 1 and "stored row 200" in err[0][2] and "damaged" in err[0][2], events[-2:]
    finally:
        assert d.stop() == 0
