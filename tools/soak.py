#!/usr/bin/python3
"""Soak test of tanksimd: a mixed, realistic client load for N minutes, with
resource sampling from /proc and optional mid-run restarts (SIGTERM / SIGKILL).

Stdlib + requests only.  Typical use (the script starts and owns the daemon):

  /usr/bin/python3 tools/soak.py --minutes 30 --port 18733 \
      --daemon-cmd 'build/tanksimd --port 18733 --data-dir /tmp/soak-data --max-sessions 200' \
      --data-dir /tmp/soak-data --restart term:10,kill:20 --out /tmp/soak-out

Or against a daemon already running (pass its pid for sampling):

  /usr/bin/python3 tools/soak.py --minutes 5 --url http://127.0.0.1:18733 --pid 1234 \
      --data-dir /tmp/soak-data --out /tmp/soak-out

Outputs in --out: samples.csv (RSS, HWM, threads, fds, store size, metrics
every --sample-every s), requests.csv (every request: time, endpoint,
status, latency), report.json (per-endpoint p50/p99/max, status counts, 5xx
and timeouts with details, restart checks), daemon.log (if started here).
"""
import argparse
import csv
import json
import os
import random
import shlex
import signal
import subprocess
import sys
import threading
import time

import requests

PRESETS = [
    # (preset, weight, run duration range [s], step size [s])
    ("pointmass-prescribed", 4, (2.0, 4.0), 0.5),
    ("bump-prescribed-static", 4, (2.0, 3.0), 0.5),
    ("flat-coupled-rack90", 1, (1.0, 2.0), 0.25),
    ("engine-map-conventional", 1, (0.3, 0.6), 0.1),  # engine dyno, 12.6 kHz
]
RENDERABLE = {"vehicle", "coupled"}


class Stats:
    def __init__(self, out):
        self.lock = threading.Lock()
        self.lat = {}          # endpoint -> list of seconds
        self.codes = {}        # endpoint -> {code: n}
        self.anomalies = []    # dicts
        self.req_f = open(os.path.join(out, "requests.csv"), "w", newline="")
        self.req_w = csv.writer(self.req_f)
        self.req_w.writerow(["t_wall", "thread", "method", "endpoint", "status", "latency_s", "bytes"])
        self.t0 = time.time()
        self.sessions_created = 0
        self.sessions_deleted = 0
        self.restarting = threading.Event()   # set while the daemon is being restarted

    def record(self, tname, method, ep, status, dt, nbytes):
        with self.lock:
            key = f"{method} {ep}"
            self.lat.setdefault(key, []).append(dt)
            c = self.codes.setdefault(key, {})
            c[str(status)] = c.get(str(status), 0) + 1
            self.req_w.writerow([f"{time.time() - self.t0:.3f}", tname, method, ep, status, f"{dt:.4f}", nbytes])

    def anomaly(self, kind, **kw):
        with self.lock:
            d = {"t": round(time.time() - self.t0, 1), "kind": kind}
            d.update(kw)
            self.anomalies.append(d)
        print("ANOMALY", json.dumps(d)[:400], file=sys.stderr, flush=True)


def text(r, n=300):
    """First n characters of a body, without requests' charset guessing (slow on big binaries)."""
    return r.content[:n].decode("utf-8", "replace")


class Client:
    """One load thread: cycles through session lifecycles."""

    def __init__(self, args, stats, name, kept, kept_lock, deleted, stop):
        self.a, self.st, self.name = args, stats, name
        self.s = requests.Session()
        self.kept, self.kept_lock, self.deleted = kept, kept_lock, deleted
        self.stop = stop
        self.rng = random.Random(hash(name) ^ args.seed)

    # -- HTTP helper: records latency per endpoint template, flags 5xx / timeouts
    def req(self, method, path, ep, expect=None, timeout=None, **kw):
        url = self.a.url + path
        t = time.monotonic()
        try:
            r = self.s.request(method, url, timeout=timeout or self.a.timeout, **kw)
            body = r.content
        except requests.exceptions.Timeout:
            dt = time.monotonic() - t
            self.st.record(self.name, method, ep, "timeout", dt, 0)
            if not self.st.restarting.is_set():
                self.st.anomaly("timeout", method=method, path=path, dt=round(dt, 2))
            return None
        except requests.exceptions.ConnectionError as e:
            dt = time.monotonic() - t
            self.st.record(self.name, method, ep, "connerr", dt, 0)
            if not self.st.restarting.is_set():
                self.st.anomaly("connerr", method=method, path=path, err=str(e)[:200])
            return None
        dt = time.monotonic() - t
        self.st.record(self.name, method, ep, r.status_code, dt, len(body))
        if r.status_code >= 500 and not (r.status_code == 503 and self.st.restarting.is_set()):
            if r.status_code == 503 and "busy" in text(r):
                pass  # documented back-pressure, counted in codes
            else:
                self.st.anomaly("5xx", method=method, path=path, status=r.status_code,
                                body=text(r), req=str(kw.get("data", ""))[:200])
        if dt > self.a.slow:
            self.st.anomaly("slow", method=method, path=path, status=r.status_code, dt=round(dt, 2))
        if expect and r.status_code not in expect:
            self.st.anomaly("unexpected-status", method=method, path=path, status=r.status_code,
                            expected=list(expect), body=text(r))
        return r

    def wait_if_restarting(self):
        while self.st.restarting.is_set() and not self.stop.is_set():
            time.sleep(0.5)

    def pick_preset(self):
        tot = sum(w for _, w, _, _ in PRESETS)
        x = self.rng.uniform(0, tot)
        for p in PRESETS:
            x -= p[1]
            if x <= 0:
                return p
        return PRESETS[0]

    def poll_op(self, op_id, limit=120.0):
        t_end = time.monotonic() + limit
        while time.monotonic() < t_end and not self.stop.is_set():
            r = self.req("GET", f"/v1/operations/{op_id}", "/v1/operations/{id}")
            if r is not None and r.status_code == 200 and r.json().get("done"):
                return r.json()
            if r is not None and r.status_code == 404:
                return None
            time.sleep(0.2)
        if not self.stop.is_set() and not self.st.restarting.is_set():
            self.st.anomaly("op-not-done", op=op_id, limit=limit)
        return None

    def stream_abandon(self, sid, fmt):
        path = f"/v1/sessions/{sid}/stream"
        params = {"format": fmt} if fmt == "ndjson" or self.rng.random() < 0.5 else {}
        if self.rng.random() < 0.3:
            params["since"] = str(self.rng.randint(-1, 50))
        t = time.monotonic()
        n = 0
        try:
            with self.s.get(self.a.url + path, params=params, stream=True, timeout=self.a.timeout,
                            headers={"Accept": "application/x-ndjson"} if fmt == "ndjson" else {}) as r:
                code = r.status_code
                limit = self.rng.randint(2_000, 60_000)
                for chunk in r.iter_content(4096):
                    n += len(chunk)
                    if n >= limit:
                        break   # abandon part way: close the connection
        except requests.exceptions.RequestException as e:
            code = "error"
            if not self.st.restarting.is_set():
                self.st.anomaly("stream-error", path=path, err=str(e)[:200])
        self.st.record(self.name, "GET", f"/v1/sessions/{{id}}/stream[{fmt}]", code, time.monotonic() - t, n)

    def bad_requests(self, sid):
        rb = self.rng.choice
        cases = [
            ("POST", "/v1/sessions", "bad:create-json", {"data": '{"preset": "pointmass-prescribed",'}),
            ("POST", "/v1/sessions", "bad:create-unknown", {"data": '{"preset":"pointmass-prescribed","bogus":{"x":1}}'}),
            ("POST", "/v1/sessions", "bad:create-dupkey", {"data": '{"run":{"duration":1,"duration":2}}'}),
            ("POST", "/v1/sessions", "bad:create-range", {"data": '{"preset":"bump-prescribed-static","track":{"n_trans":99}}'}),
            ("POST", "/v1/sessions", "bad:create-rows", {"data": '{"preset":"engine-map-conventional","run":{"duration":1e6}}'}),
            ("POST", f"/v1/sessions/{sid}/step", "bad:step-json", {"data": "{duration: 1}"}),
            ("POST", f"/v1/sessions/{sid}/step", "bad:step-unknown", {"data": '{"duration":0.5,"x":1}'}),
            ("POST", f"/v1/sessions/{sid}/step", "bad:step-huge", {"data": '{"duration":1e308}'}),
            ("POST", f"/v1/sessions/{sid}/run", "bad:run-until", {"data": '{"until":-5}'}),
            ("GET", f"/v1/sessions/{sid}/series?page_size=99999999999999999999999", "bad:series-pagesize", {}),
            ("GET", f"/v1/sessions/{sid}/series?every=1e400", "bad:series-every", {}),
            ("GET", f"/v1/sessions/{sid}/series?from=0x10", "bad:series-hex", {}),
            ("GET", f"/v1/sessions/{sid}/series?page_token=garbage%21%21", "bad:series-token", {}),
            ("GET", f"/v1/sessions/{sid}/series?channels=" + ",".join(["nope"] * 50), "bad:series-channels", {}),
            ("GET", f"/v1/sessions/{sid}/frame.png?width=100000&height=100000", "bad:frame-size", {}),
            ("GET", f"/v1/sessions/{sid}/frame.png?t=1e300", "bad:frame-t", {}),
            ("GET", f"/v1/sessions/{sid}/fft?channel=vehicle.speed&from=9" + "9" * 400, "bad:fft-from", {}),
            ("GET", f"/v1/sessions/{sid}/frames?fps=1000&from=0&to=100", "bad:frames-many", {}),
            ("GET", "/v1/sessions/" + "x" * 3000, "bad:long-id", {}),
            ("GET", "/v1/sessions?page_size=-1", "bad:list-pagesize", {}),
            ("GET", "/v1/sessions/abc%00def", "bad:nul-path", {}),
            ("DELETE", "/v1/presets", "bad:method", {}),
            ("POST", "/v1/engine-map", "bad:map-json", {"data": "[1,2"}),
            ("POST", "/v1/tune?schedule_mass=1,2,3", "bad:tune-sched", {"data": '{"preset":"bump-coupled-ivs5mph"}'}),
            ("GET", "/v1/sessions?" + "&".join(f"q{i}=1" for i in range(200)), "bad:many-params", {}),
            ("POST", "/v1/sessions", "bad:body-big", {"data": "{\"_c\":\"" + "a" * 1_100_000 + "\"}"}),
        ]
        for _ in range(self.rng.randint(1, 3)):
            m, p, ep, kw = rb(cases)
            r = self.req(m, p, ep, **kw)
            if r is not None and r.status_code < 400 and ep not in ("bad:frame-t", "bad:frames-many"):
                self.st.anomaly("bad-request-accepted", method=m, path=p[:200], status=r.status_code,
                                body=text(r, 200))
            if r is not None and r.status_code == 201:   # should not happen; clean up
                try:
                    self.req("DELETE", f"/v1/sessions/{r.json()['id']}", "/v1/sessions/{id} DELETE")
                except Exception:
                    pass

    def analysis(self):
        if self.rng.random() < 0.5:
            r = self.req("POST", "/v1/engine-map", "/v1/engine-map",
                         data=json.dumps({"preset": self.rng.choice(["engine-map-conventional", "engine-map-lhr05"]),
                                          "engine": {"fidelity": self.rng.choice(["mean_value", "map"])}}))
        else:
            q = self.rng.choice(["", "?schedule_mass=50000,60000", "?schedule_grade=0.05"])
            r = self.req("POST", "/v1/tune" + q, "/v1/tune",
                         data=json.dumps({"preset": "bump-coupled-ivs5mph", "engine": {"fidelity": "mean_value"}}))
        if r is None or r.status_code != 202:
            return
        op = r.json()["id"]
        if self.rng.random() < 0.2:
            time.sleep(0.05)
            self.req("POST", f"/v1/operations/{op}:cancel", "/v1/operations/{id}:cancel")
        self.poll_op(op, limit=60)
        self.req("GET", f"/v1/analyses/{op}", "/v1/analyses/{id}")
        self.req("GET", "/v1/analyses", "/v1/analyses")
        r = self.req("DELETE", f"/v1/analyses/{op}", "/v1/analyses/{id} DELETE")
        if r is not None and r.status_code == 409:   # still running (restart race): try later
            time.sleep(1)
            self.req("DELETE", f"/v1/analyses/{op}", "/v1/analyses/{id} DELETE")

    def lifecycle(self):
        preset, _, (dlo, dhi), step = self.pick_preset()
        rate_steps = self.rng.randint(int(dlo / step), int(dhi / step))
        duration = round(rate_steps * step, 6)
        body = {"preset": preset, "run": {"duration": duration}}
        r = self.req("POST", "/v1/sessions", "/v1/sessions POST", data=json.dumps(body))
        if r is None or r.status_code != 201:
            if r is not None and r.status_code not in (429, 503):
                self.st.anomaly("create-failed", status=r.status_code, body=text(r))
            time.sleep(0.5)
            return
        doc = r.json()
        sid, kind = doc["id"], doc["kind"]
        chans = [c["name"] for c in doc.get("channels", []) if c.get("name") != "t"]
        with self.st.lock:
            self.st.sessions_created += 1
        # synchronous steps
        for _ in range(self.rng.randint(1, 3)):
            self.req("POST", f"/v1/sessions/{sid}/step", "/v1/sessions/{id}/step",
                     data=json.dumps({"duration": step}))
        mode = self.rng.random()
        if mode < 0.55:      # run to completion, poll
            r = self.req("POST", f"/v1/sessions/{sid}/run", "/v1/sessions/{id}/run", data="{}")
            if r is not None and r.status_code == 202:
                if self.rng.random() < 0.3:
                    self.stream_abandon(sid, self.rng.choice(["sse", "ndjson"]))
                self.poll_op(r.json()["id"])
        elif mode < 0.8:     # slow live run, stream it part way, cancel
            r = self.req("POST", f"/v1/sessions/{sid}/run", "/v1/sessions/{id}/run",
                         data=json.dumps({"real_time_factor": self.rng.choice([1, 2, 5])}))
            if r is not None and r.status_code == 202:
                op = r.json()["id"]
                self.stream_abandon(sid, self.rng.choice(["sse", "ndjson"]))
                self.req("POST", f"/v1/operations/{op}:cancel", "/v1/operations/{id}:cancel")
                self.poll_op(op, limit=30)
        else:                # only the steps; delete while maybe streaming
            pass
        # reads
        if chans:
            ch = ",".join(self.rng.sample(chans, min(len(chans), self.rng.randint(1, 4))))
            params = {"channels": ch, "page_size": str(self.rng.choice([50, 200, 1000, 5000]))}
            if self.rng.random() < 0.3:
                params["every"] = str(self.rng.choice([2, 5, 10]))
            if self.rng.random() < 0.4:
                params["format"] = "csv"
            pages = 0
            while pages < 4:
                r = self.req("GET", f"/v1/sessions/{sid}/series", "/v1/sessions/{id}/series" +
                             ("[csv]" if params.get("format") == "csv" else "[json]"), params=params)
                pages += 1
                if r is None or r.status_code != 200:
                    break
                tok = None
                if params.get("format") == "csv":
                    tok = r.headers.get("X-Next-Page-Token") or None
                    lk = r.headers.get("Link", "")
                    if not tok and "page_token=" in lk:
                        tok = lk.split("page_token=")[1].split(">")[0].split("&")[0]
                else:
                    tok = r.json().get("next_page_token")
                if not tok:
                    break
                params["page_token"] = tok
            if self.rng.random() < 0.6:
                fp = {"channel": self.rng.choice(chans)}
                if self.rng.random() < 0.5:
                    fp.update(window="hann", detrend="linear")
                self.req("GET", f"/v1/sessions/{sid}/fft", "/v1/sessions/{id}/fft", params=fp)
        if self.rng.random() < 0.6:
            self.req("GET", f"/v1/sessions/{sid}/summary", "/v1/sessions/{id}/summary")
        self.req("GET", f"/v1/sessions/{sid}", "/v1/sessions/{id}")
        if kind in RENDERABLE and self.rng.random() < 0.35:
            for _ in range(self.rng.randint(1, 2)):
                self.req("GET", f"/v1/sessions/{sid}/frame.png", "/v1/sessions/{id}/frame.png",
                         params={"t": "0.5", "width": str(self.rng.choice([160, 320])),
                                 "height": str(self.rng.choice([90, 180])),
                                                                  "view": self.rng.choice(["side", "three_quarter"]),
                                 **({"color": "tension"} if self.rng.random() < 0.5 else {})})
            if self.rng.random() < 0.3:
                p = {"from": "0", "to": "0.4", "fps": "10", "width": "160", "height": "90"}
                if self.rng.random() < 0.3:
                    p["format"] = "multipart"
                self.req("GET", f"/v1/sessions/{sid}/frames", "/v1/sessions/{id}/frames" +
                         ("[multipart]" if "format" in p else "[apng]"), params=p, timeout=120)
        if self.rng.random() < 0.15:
            self.bad_requests(sid)
        if self.rng.random() < 0.05:
            self.req("GET", "/v1/sessions", "/v1/sessions", params={"page_size": "50"})
        # delete most, keep some (bounded)
        if self.rng.random() < 0.9:
            self.delete(sid)
        else:
            with self.kept_lock:
                self.kept.append(sid)
                old = self.kept.pop(0) if len(self.kept) > self.a.keep else None
            if old:
                self.delete(old)

    def delete(self, sid):
        r = self.req("DELETE", f"/v1/sessions/{sid}", "/v1/sessions/{id} DELETE")
        if r is not None and r.status_code == 204:
            with self.st.lock:
                self.st.sessions_deleted += 1
                self.deleted.append(sid)

    def run(self):
        while not self.stop.is_set():
            self.wait_if_restarting()
            try:
                if self.rng.random() < 0.04:
                    self.analysis()
                else:
                    self.lifecycle()
            except Exception as e:  # keep going; record
                if not self.st.restarting.is_set():
                    self.st.anomaly("client-exception", err=repr(e)[:300])
                time.sleep(0.5)


class Daemon:
    def __init__(self, args, out):
        self.a = args
        self.proc = None
        self.pid = args.pid
        self.log = open(os.path.join(out, "daemon.log"), "ab") if args.daemon_cmd else None

    def start(self):
        if not self.a.daemon_cmd:
            return
        env = dict(os.environ)
        self.proc = subprocess.Popen(shlex.split(self.a.daemon_cmd), stdout=self.log, stderr=self.log, env=env)
        self.pid = self.proc.pid
        t_end = time.monotonic() + 30
        while time.monotonic() < t_end:
            try:
                if requests.get(self.a.url + "/v1/health", timeout=2).status_code == 200:
                    return
            except requests.exceptions.RequestException:
                pass
            time.sleep(0.1)
        raise SystemExit("daemon did not come up")

    def signal_and_wait(self, sig, timeout=60):
        t = time.monotonic()
        self.proc.send_signal(sig)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            rc = "hung"
        return rc, time.monotonic() - t


def proc_sample(pid, data_dir):
    d = {}
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                k, _, v = line.partition(":")
                if k in ("VmRSS", "VmHWM", "Threads"):
                    d[k] = int(v.split()[0])
        d["fds"] = len(os.listdir(f"/proc/{pid}/fd"))
    except OSError:
        pass
    if data_dir:
        tot = 0
        wal = 0
        for n in os.listdir(data_dir):
            try:
                s = os.path.getsize(os.path.join(data_dir, n))
            except OSError:
                continue
            tot += s
            if n.endswith("-wal"):
                wal = s
        d["store_bytes"], d["wal_bytes"] = tot, wal
    return d


def metrics(url):
    try:
        txt = requests.get(url + "/metrics", timeout=10).text
    except requests.exceptions.RequestException:
        return {}
    m = {}
    for line in txt.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        k, _, v = line.rpartition(" ")
        try:
            m[k] = float(v)
        except ValueError:
            pass
    out = {"m_sessions": sum(v for k, v in m.items() if k.startswith("tanksimd_sessions{")),
           "m_created_total": m.get("tanksimd_sessions_created_total", ""),
           "m_samples_total": m.get("tanksimd_samples_stored_total", ""),
           "m_reply_held": m.get("tanksimd_reply_held_bytes", ""),
           "m_jobs_pending": m.get("tanksimd_jobs_pending", ""),
           "m_5xx": sum(v for k, v in m.items() if k.startswith('tanksimd_http_requests_total{code="5'))}
    return out


def snapshot(url):
    """Sessions (id -> (status, index)) and analyses (id -> done) as the daemon lists them."""
    ss, tok = {}, None
    while True:
        p = {"page_size": "100"}
        if tok:
            p["page_token"] = tok
        d = requests.get(url + "/v1/sessions", params=p, timeout=30).json()
        for s in d["sessions"]:
            ss[s["id"]] = (s["status"], s["index"])
        tok = d.get("next_page_token")
        if not tok:
            break
    an = {a["id"]: a.get("done") for a in requests.get(url + "/v1/analyses", timeout=30).json()["analyses"]}
    return ss, an


def restart(kind, args, daemon, stats, deleted, log):
    """Restart the daemon mid-load and check what the README promises."""
    stats.restarting.set()
    time.sleep(args.quiesce)            # let clients' in-flight requests end (they pause at the next cycle)
    before, an_before = snapshot(args.url)
    # a run in flight at the moment of the signal: it must come back interrupted
    r = requests.post(args.url + "/v1/sessions", timeout=30,
                      data=json.dumps({"preset": "bump-prescribed-static", "run": {"duration": 20}}))
    live = r.json()["id"]
    requests.post(args.url + f"/v1/sessions/{live}/run", data=json.dumps({"real_time_factor": 2}), timeout=30)
    time.sleep(1.5)
    live_idx = requests.get(args.url + f"/v1/sessions/{live}", timeout=30).json()["index"]
    with stats.lock:
        dels = list(deleted)
    sig = signal.SIGTERM if kind == "term" else signal.SIGKILL
    rc, dt_stop = daemon.signal_and_wait(sig)
    t = time.monotonic()
    daemon.start()
    dt_up = time.monotonic() - t
    after, an_after = snapshot(args.url)
    res = {"kind": kind, "t": round(time.time() - stats.t0, 1), "exit_rc": rc, "stop_s": round(dt_stop, 2),
           "up_s": round(dt_up, 2), "sessions_before": len(before), "sessions_after": len(after) - 1,
           "analyses_before": len(an_before), "analyses_after": len(an_after), "problems": []}
    for sid, (st, idx) in before.items():
        if sid not in after:
            res["problems"].append(f"session {sid} ({st}) lost")
            continue
        st2, idx2 = after[sid]
        if idx2 < idx:
            res["problems"].append(f"session {sid} index {idx} -> {idx2}")
        if st == "running" and st2 != "interrupted":
            res["problems"].append(f"session {sid} running -> {st2}")
        if st != "running" and st2 != st:
            res["problems"].append(f"session {sid} {st} -> {st2}")
    st2, idx2 = after.get(live, (None, None))
    res["live_run"] = {"before_index": live_idx, "after": [st2, idx2]}
    if st2 != "interrupted" or idx2 is None or idx2 < live_idx:
        res["problems"].append(f"live run session {live}: before index>={live_idx}, after {st2} {idx2}")
    back = [d for d in dels if d in after]
    if back:
        res["problems"].append(f"{len(back)} sessions deleted with 204 came back: {back[:5]}")
    for aid, done in an_before.items():
        if done and aid not in an_after:
            res["problems"].append(f"finished analysis {aid} lost")
    # the interrupted session can be run on
    rr = requests.post(args.url + f"/v1/sessions/{live}/step", data='{"duration":0.5}', timeout=60)
    res["live_step_after"] = rr.status_code
    if rr.status_code != 200:
        res["problems"].append(f"step on interrupted session: {rr.status_code} {text(rr, 200)}")
    requests.delete(args.url + f"/v1/sessions/{live}", timeout=30)
    stats.restarting.clear()
    log.append(res)
    print("RESTART", json.dumps(res), file=sys.stderr, flush=True)


def pct(xs, p):
    xs = sorted(xs)
    if not xs:
        return None
    k = min(len(xs) - 1, max(0, int(round(p / 100.0 * (len(xs) - 1)))))
    return xs[k]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=30, help="load duration in minutes (default 30)")
    ap.add_argument("--url", default=None, help="daemon base URL (default http://127.0.0.1:PORT)")
    ap.add_argument("--port", type=int, default=18733)
    ap.add_argument("--threads", type=int, default=3, help="concurrent client threads, 2-4 (default 3)")
    ap.add_argument("--daemon-cmd", default=None, help="start (and own) the daemon with this command line")
    ap.add_argument("--pid", type=int, default=None, help="pid of a daemon started elsewhere (for sampling)")
    ap.add_argument("--data-dir", default=None, help="the daemon's --data-dir (store size)")
    ap.add_argument("--out", default="soak-out", help="output directory")
    ap.add_argument("--sample-every", type=float, default=20, help="seconds between /proc samples")
    ap.add_argument("--restart", default="", help="e.g. term:10,kill:20 (minutes from start; needs --daemon-cmd)")
    ap.add_argument("--keep", type=int, default=30, help="sessions kept alive at most (the rest deleted)")
    ap.add_argument("--timeout", type=float, default=60, help="per-request timeout [s]")
    ap.add_argument("--slow", type=float, default=5, help="latency counted as an anomaly [s]")
    ap.add_argument("--quiesce", type=float, default=8, help="seconds of pause before a restart")
    ap.add_argument("--seed", type=int, default=33)
    ap.add_argument("--stop-signal", default="term", choices=["term", "int", "none"],
                    help="how to stop a daemon started here at the end")
    a = ap.parse_args()
    a.url = a.url or f"http://127.0.0.1:{a.port}"
    os.makedirs(a.out, exist_ok=True)
    stats = Stats(a.out)
    daemon = Daemon(a, a.out)
    daemon.start()
    restarts = []
    for item in filter(None, a.restart.split(",")):
        k, _, m = item.partition(":")
        restarts.append((float(m) * 60, k))
    restarts.sort()
    stop = threading.Event()
    kept, kept_lock, deleted = [], threading.Lock(), []
    clients = [Client(a, stats, f"c{i}", kept, kept_lock, deleted, stop) for i in range(a.threads)]
    ths = [threading.Thread(target=c.run, daemon=True) for c in clients]
    for t in ths:
        t.start()
    sf = open(os.path.join(a.out, "samples.csv"), "w", newline="")
    cols = ["t_s", "pid", "rss_kb", "hwm_kb", "threads", "fds", "store_bytes", "wal_bytes",
            "sessions_created", "sessions_deleted", "requests", "m_sessions", "m_created_total",
            "m_samples_total", "m_reply_held", "m_jobs_pending", "m_5xx"]
    sw = csv.DictWriter(sf, fieldnames=cols)
    sw.writeheader()
    restart_log = []
    t_end = stats.t0 + a.minutes * 60
    next_sample = time.time()
    try:
        while time.time() < t_end:
            now = time.time()
            if restarts and now - stats.t0 >= restarts[0][0]:
                _, k = restarts.pop(0)
                try:
                    restart(k, a, daemon, stats, deleted, restart_log)
                except Exception as e:
                    stats.restarting.clear()
                    stats.anomaly("restart-failed", kind=k, err=repr(e)[:300])
                next_sample = time.time()
            if now >= next_sample:
                d = proc_sample(daemon.pid, a.data_dir)
                if not stats.restarting.is_set():
                    d.update(metrics(a.url))
                with stats.lock:
                    nreq = sum(len(v) for v in stats.lat.values())
                    row = {"t_s": round(now - stats.t0, 1), "pid": daemon.pid, "rss_kb": d.get("VmRSS"),
                           "hwm_kb": d.get("VmHWM"), "threads": d.get("Threads"), "fds": d.get("fds"),
                           "store_bytes": d.get("store_bytes"), "wal_bytes": d.get("wal_bytes"),
                           "sessions_created": stats.sessions_created, "sessions_deleted": stats.sessions_deleted,
                           "requests": nreq}
                    stats.req_f.flush()
                for k in cols[11:]:
                    row[k] = d.get(k, "")
                sw.writerow(row)
                sf.flush()
                print("SAMPLE", json.dumps(row), file=sys.stderr, flush=True)
                next_sample += a.sample_every
            time.sleep(0.5)
    except KeyboardInterrupt:
        pass
    stop.set()
    for t in ths:
        t.join(a.timeout + 10)
    hung = [c.name for c, t in zip(clients, ths) if t.is_alive()]
    if hung:
        stats.anomaly("client-thread-hung", threads=hung)
    # final sample after load stops
    d = proc_sample(daemon.pid, a.data_dir)
    final = {"rss_kb": d.get("VmRSS"), "hwm_kb": d.get("VmHWM"), "threads": d.get("Threads"), "fds": d.get("fds"),
             "store_bytes": d.get("store_bytes")}
    report = {"minutes": a.minutes, "threads": a.threads, "sessions_created": stats.sessions_created,
              "sessions_deleted": stats.sessions_deleted, "final_idle": final, "restarts": restart_log,
              "endpoints": {}, "anomalies": stats.anomalies}
    for k in sorted(stats.lat):
        xs = stats.lat[k]
        report["endpoints"][k] = {"n": len(xs), "p50_ms": round(1000 * pct(xs, 50), 1),
                                  "p99_ms": round(1000 * pct(xs, 99), 1), "max_ms": round(1000 * max(xs), 1),
                                  "codes": stats.codes[k]}
    if daemon.proc is not None and a.stop_signal != "none":
        sig = signal.SIGTERM if a.stop_signal == "term" else signal.SIGINT
        rc, dt = daemon.signal_and_wait(sig)
        report["final_stop"] = {"rc": rc, "s": round(dt, 2)}
    stats.req_f.close()
    with open(os.path.join(a.out, "report.json"), "w") as f:
        json.dump(report, f, indent=1)
    print(json.dumps({k: report[k] for k in ("sessions_created", "sessions_deleted", "final_idle")}))
    print(f"anomalies: {len(stats.anomalies)}; report in {a.out}/report.json")


if __name__ == "__main__":
    main()
