#!/usr/bin/python3
"""http_fuzz.py — adversarial HTTP client for tanksimd (normally the ASan/UBSan build).

Why: config_fuzz.py covers what a run config can do to the model; this covers
what a client can do to the daemon's HTTP layer (server/*.c, api/problem.c,
api/session_json.c): the route table, query parsing, bodies, framing, timing.
The contract checked (the "oracle"):

  - no ASan/UBSan/LeakSanitizer report in the daemon's stderr, no crash;
  - no hang: every request is answered, or its connection closed, within a
    timeout (a request the client deliberately leaves incomplete must be
    closed by the daemon within --timeout + slack);
  - every 4xx/5xx the daemon builds is an RFC 9457 problem: Content-Type
    application/problem+json, a JSON object with type, title, status (equal
    to the HTTP status) and detail; a 405 carries an Allow header;
  - a 4xx caused by one named query parameter or body member lists that
    parameter's JSON pointer ("/from", "/duration", ...) in "errors";
  - no 5xx for a client mistake (only 503 during shutdown is expected);
  - afterwards the daemon still answers /v1/health, exits 0 on SIGTERM, and
    a restart on the same --data-dir lists the same sessions.

Replies that libmicrohttpd itself writes before any tanksimd code runs
(malformed request line, header too large, bad chunk syntax, bad
Content-Length, HTTP/2 request line) are HTML pages from the library; they
are counted as class MHD, not as defects of the daemon.

Every case is generated from --seed (random.Random), so a pass is
reproducible request by request (thread interleavings in the race and
shutdown classes are not). The routes come from `tanksimd --routes`, so a new
row in server/routes.c is fuzzed without touching this script.

Usage:
  tests/fuzz/http_fuzz.py --bin build-asan/tanksimd [--seed 1] [--out DIR]
      [--subset] [--only CLASS,...] [--list]
Writes OUT/results.jsonl (one line per request: id, class, status, verdict)
and OUT/daemon*.log; prints a table of verdicts per class and exits 1 when
any verdict is a defect. --subset runs the short deterministic selection
used by suite_http_fuzz.sh in `make test`.
"""
import argparse
import collections
import json
import os
import random
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PRESET = "pointmass-prescribed"
# Small limits so that a pass stays cheap on a shared 2-core machine.
MAX_BODY = 4096
CONN_TIMEOUT = 3  # --timeout [s]
MAX_STEP = 0.5
DAEMON_FLAGS = ["--threads", "1", "--max-sessions", "12", "--max-step", str(MAX_STEP),
                "--max-run-wall", "2", "--max-body", str(MAX_BODY), "--timeout", str(CONN_TIMEOUT),
                "--max-samples", "2000", "--drain", "1"]
SANITIZER = re.compile(r"ERROR: (Address|Leak)Sanitizer|runtime error:|SUMMARY: \w+Sanitizer")
DEFECTS = ("CRASH", "SANITIZER", "HANG", "BADBODY", "5XX", "NOPTR", "NOALLOW", "UNEXPECTED",
           "RESTART")
CHEAP_CONFIG = {"preset": PRESET, "run": {"duration": 1.0, "sample_rate": 50}}
# a session with geometry, so that frame.png and frames really draw (small images)
GEOMETRY_CONFIG = {"preset": "bump-prescribed-static", "run": {"duration": 0.2, "sample_rate": 50}}
SMALL_VIEW = "width=32&height=24"


# ---- the daemon ------------------------------------------------------------------

def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Daemon:
    def __init__(self, binary, data_dir, log_path, extra=()):
        self.port = free_port()
        self.log_path = log_path
        self.log = open(log_path, "ab")
        env = dict(os.environ)
        env.setdefault("ASAN_OPTIONS", "detect_leaks=1")
        supp = os.path.join(ROOT, "tests", "lsan.supp")
        env.setdefault("LSAN_OPTIONS", f"suppressions={supp}:print_suppressions=0")
        self.proc = subprocess.Popen([binary, "--port", str(self.port), "--data-dir", data_dir,
                                      *DAEMON_FLAGS, *extra],
                                     stdout=subprocess.DEVNULL, stderr=self.log, env=env)
        deadline = time.time() + 30
        while time.time() < deadline:
            r = request(self.port, "GET", "/v1/health", timeout=2)
            if r.status == 200:
                return
            if self.proc.poll() is not None:
                break
            time.sleep(0.1)
        raise RuntimeError("tanksimd did not start; see " + log_path)

    def stop(self, sig=signal.SIGTERM, timeout=30):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
                self.log.close()
                return "HANG"
        self.log.close()
        return self.proc.returncode

    def stderr(self):
        with open(self.log_path, "rb") as f:
            return f.read().decode("utf-8", "replace")


# ---- a raw HTTP/1.1 client (full control over every byte) -------------------------

class Resp:
    def __init__(self):
        self.status = 0          # 0: no status line received
        self.headers = {}        # lower-case name -> value
        self.body = b""
        self.error = ""          # "timeout", "reset", "closed" (before a status line)
        self.elapsed = 0.0

    def json(self):
        return json.loads(self.body.decode("utf-8"))


def _read_response(sock, deadline, max_body=4 << 20, stream_bytes=None):
    """Read one response from sock; stream_bytes: stop after that many body bytes."""
    r = Resp()
    buf = b""
    def more():
        nonlocal buf
        left = deadline - time.time()
        if left <= 0:
            raise socket.timeout()
        sock.settimeout(left)
        b = sock.recv(65536)
        if not b:
            raise EOFError()
        buf += b
    try:
        while True:  # skip interim 1xx responses (100 Continue)
            while b"\r\n\r\n" not in buf:
                more()
            head, buf = buf.split(b"\r\n\r\n", 1)
            lines = head.decode("latin-1").split("\r\n")
            m = re.match(r"HTTP/1\.[01] (\d{3})", lines[0])
            r.status = int(m.group(1)) if m else -1
            if not 100 <= r.status < 200:
                break
        for ln in lines[1:]:
            k, _, v = ln.partition(":")
            r.headers[k.strip().lower()] = v.strip()
        if "content-length" in r.headers:
            n = int(r.headers["content-length"])
            while len(buf) < n:
                more()
            r.body = buf[:n]
        elif r.headers.get("transfer-encoding", "").lower() == "chunked":
            body = b""
            while True:
                while b"\r\n" not in buf:
                    more()
                size_line, buf = buf.split(b"\r\n", 1)
                size = int(size_line.split(b";")[0], 16)
                if size == 0:
                    break
                while len(buf) < size + 2:
                    more()
                body += buf[:size]
                buf = buf[size + 2:]
                if stream_bytes is not None and len(body) >= stream_bytes:
                    break
                if len(body) > max_body:
                    break
            r.body = body
        else:
            try:
                while len(buf) < max_body:
                    more()
            except EOFError:
                pass
            r.body = buf
    except socket.timeout:
        r.error = "timeout"
    except EOFError:
        r.error = "closed"
    except (ConnectionResetError, BrokenPipeError):
        r.error = "reset"
    return r


def build(method, path, body=None, headers=None, version="HTTP/1.1", host=True):
    h = [] if headers is None else list(headers)
    names = {k.lower() for k, _ in h}
    if host and "host" not in names:
        h.insert(0, ("Host", "127.0.0.1"))
    if "connection" not in names:
        h.append(("Connection", "close"))
    if body is not None and "content-length" not in names and "transfer-encoding" not in names:
        h.append(("Content-Length", str(len(body))))
    p = path.encode("latin-1") if isinstance(path, str) else path
    m = method.encode("latin-1") if isinstance(method, str) else method
    out = m + b" " + p + b" " + version.encode() + b"\r\n"
    for k, v in h:
        out += k.encode("latin-1") + b": " + (v.encode("latin-1") if isinstance(v, str) else v) + b"\r\n"
    out += b"\r\n"
    if body is not None:
        out += body if isinstance(body, bytes) else body.encode("utf-8")
    return out


def send_raw(port, data, timeout=15, pieces=None, delay=0.0, abort_after_send=False,
             stream_bytes=None):
    """Send data (or pieces, with delay between them) and read one response."""
    t0 = time.time()
    r = Resp()
    try:
        sock = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    except OSError as e:
        r.error = "connect: " + str(e)
        return r
    try:
        for i, p in enumerate(pieces if pieces is not None else [data]):
            if i and delay:
                time.sleep(delay)
            sock.sendall(p)
        if abort_after_send:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
            sock.close()
            r.error = "aborted"
            return r
        r = _read_response(sock, t0 + timeout, stream_bytes=stream_bytes)
    except (ConnectionResetError, BrokenPipeError) as e:
        r.error = "reset"
    except socket.timeout:
        r.error = "timeout"
    finally:
        try:
            sock.close()
        except OSError:
            pass
    r.elapsed = time.time() - t0
    return r


def request(port, method, path, body=None, headers=None, timeout=15):
    return send_raw(port, build(method, path, body, headers), timeout=timeout)


def jbody(obj):
    return json.dumps(obj).encode()


# ---- the oracle ------------------------------------------------------------------

def classify(case, r):
    """Verdict of one response: OK, MHD (libmicrohttpd's own page), or a defect."""
    if r.error == "aborted":
        return "OK"
    if r.error == "timeout":
        return "HANG"
    if r.status == 0:
        # closed without a reply: within the contract (answered or closed), but
        # counted apart; expected for garbage and requests left incomplete
        return "OK" if case.get("close_ok") else "CLOSED"
    st = r.status
    if st >= 400:
        ctype = r.headers.get("content-type", "")
        if ctype != "application/problem+json":
            if b"<html>" in r.body and "content-type" not in r.headers:
                return "MHD"  # libmicrohttpd's own page (no tanksimd code ran)
            if case["method"] == "HEAD" and not r.body:
                pass  # HEAD: headers only; the type is checked above
            else:
                return "BADBODY"
        if r.body or case["method"] != "HEAD":
            try:
                p = r.json()
                ok = (isinstance(p, dict) and p.get("status") == st and
                      isinstance(p.get("type"), str) and isinstance(p.get("title"), str) and
                      isinstance(p.get("detail"), str))
            except ValueError:
                ok = False
            if not ok:
                return "BADBODY"
            if st != 503 and case.get("param") and st in (400, 404, 422) and case["expect"] == "4xx":
                ptrs = [e.get("pointer") for e in p.get("errors", []) if isinstance(e, dict)]
                if "/" + case["param"] not in ptrs:
                    return "NOPTR"
        if st == 405 and "allow" not in r.headers:
            return "NOALLOW"
    if st >= 500 and not (st == 503 and case.get("allow503")):
        return "5XX"
    exp = case["expect"]
    if exp == "2xx" and not 200 <= st < 300:
        return "UNEXPECTED"
    if exp == "4xx" and not 400 <= st < 500:
        return "UNEXPECTED"
    return "OK"


# ---- the cases -------------------------------------------------------------------

METHODS = ["GET", "POST", "PUT", "DELETE", "PATCH", "HEAD", "OPTIONS", "TRACE", "get", "FOO",
           "X" * 300]
BAD_NUMBERS = ["", "-1", "-0", "0", "NaN", "nan", "inf", "-inf", "Infinity", "1e309", "-1e309",
               "1e-320", "9" * 40, "0x10", " 1", "1 ", "1,2", "1.5.2", "%00", "%ff", "%ff%fe",
               "%C0%AF", "a" * 3000, "1e12", "2e12", "9223372036854775807",
               "9223372036854775808", "-9223372036854775809", "18446744073709551616",
               "4611686018427387904", "+1", "1e-5", "0.5", "%0a", "1%00"]
QUERY_PARAMS = {
    "sessions": ["page_size", "page_token"],
    "series": ["from", "to", "channels", "every", "format", "page_size", "page_token", "limit",
               "offset"],
    "stream": ["from", "to", "channels", "since", "format", "rate"],
    "fft": ["from", "to", "channel"],
    "frame.png": ["t", "from", "to", "width", "height", "view", "exaggeration", "color", "text",
                  "overlay", "antialias"],
    "frames": ["from", "to", "fps", "format", "width", "height"],
}
# parameters the handlers read: a bad value must be refused naming it
READ = {"page_size", "page_token", "from", "to", "channels", "every", "format", "since",
        "channel", "t", "width", "height", "view", "exaggeration", "color", "overlay",
        "antialias", "fps"}
TEXT_OK = {"channels", "channel", "text", "format", "view", "color"}  # strings, not numbers


def routes(binary):
    out = subprocess.run([binary, "--routes"], capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        left = line.split("\t")[0]
        m, _, pat = left.partition(" ")
        rows.append((m, pat))
    return rows


def fill(pattern, ids):
    p = pattern.replace("{id}:cancel", ids["op"] + ":cancel")
    if p.startswith("/v1/operations/"):
        p = p.replace("{id}", ids["op"])
    return p.replace("{id}", ids["sid"]).replace("{name}", PRESET).replace("{file}", "app.js")


def gen_cases(rng, rts, ids, subset):
    """Static request cases (no timing): list of dicts {id, cls, method, raw, expect, ...}."""
    cases = []
    def add(cls, name, method, raw, expect="any", **kw):
        c = {"id": f"{cls}/{name}", "cls": cls, "method": method, "raw": raw, "expect": expect}
        c.update(kw)
        cases.append(c)

    sid, rsid = ids["sid"], ids["rsid"]
    paths = sorted({p for _, p in rts})
    allowed = collections.defaultdict(set)
    for m, p in rts:
        allowed[p].add(m)

    # 1. methods: every route path with every method it does not answer
    for p in paths:
        for m in METHODS:
            if m in allowed[p] or (m == "HEAD" and "GET" in allowed[p]):  # HEAD = GET, no body
                continue
            fp = fill(p, ids)
            add("method", f"{m[:8]}_{p}", m, build(m, fp, b"{}" if m in ("POST", "PUT") else None),
                "4xx")

    # 2. paths: unknown, overlong, percent-encoded, dot-dot, odd ids
    odd = ["/", "//", "/v1", "/v1/", "/v1/health/", "/v1//health", "/V1/HEALTH", "/v1/health?",
           "/v1/health#x", "/v1/%68ealth", "/v1/health%00", "/v1/%00", "/v1/%ff", "/v1/\xff",
           "/v1/health/..", "/v1/sessions/../health", "/v1/sessions/%2e%2e/health",
           "/v1/sessions/%2F", "/static/../../etc/passwd", "/static/..%2f..%2fetc%2fpasswd",
           "/static/%2e%2e%2fMakefile", "/static/.hidden.js", "/static/app.js%00.png",
           "/static/" + "a" * 200 + ".js", "/static/", "/v1/presets/..%2fdefaults%2frun",
           "/v1/presets/%ff", "/v1/presets/" + "p" * 127, "/v1/presets/" + "p" * 128,
           "/v1/presets/" + "\xc3\xa9", "/v1/sessions/" + "s" * 127, "/v1/sessions/" + "s" * 500,
           f"/v1/sessions/{sid}/", f"/v1/sessions/{sid}:cancel", f"/v1/sessions/{sid}/series/x",
           f"/v1/sessions/{sid}%2Fseries", "/v1/sessions/%ff%fe/series", "/v1/sessions/%00/series",
           "/v1/operations/op%ff:cancel", "/v1/operations/:cancel", "/v1/operations/x:cancel:cancel",
           "/v1/operations/" + "o" * 300, "*", "http://127.0.0.1/v1/health",
           "/" + "a" * 1000, "/" + "a" * 8000, "/v1/" + "%41" * 3000,
           "/v1/sessions?%ff=%ff", "/v1/sessions?=&=&", "/v1/sessions?page_size=1;page_size=2"]
    for p in odd:
        for m in (["GET", "POST"] if not subset else ["GET"]):
            add("path", f"{m}_{p[:60]}", m, build(m, p, b"{}" if m == "POST" else None), "any")
    # more query arguments than libmicrohttpd's per-connection memory holds: it closes
    add("path", "GET_500_query_args", "GET", build("GET", "/v1/sessions?" + "a=1&" * 500), "any",
        close_ok=1)

    # 3. query parameters (one bad parameter at a time; duplicates)
    targets = [(r, rsid, "") for r in QUERY_PARAMS]
    targets += [(r, ids["gsid"], "g") for r in ("frame.png", "frames")]  # drawn for real
    for route, on, tag in targets:
        params = QUERY_PARAMS[route]
        base = "/v1/sessions" if route == "sessions" else f"/v1/sessions/{on}/{route}"
        for prm in params:
            vals = BAD_NUMBERS if not subset else BAD_NUMBERS[:: 5]
            for v in vals:
                q = f"{base}?{prm}={v}"
                if route == "fft" and prm != "channel":
                    q += "&channel=vehicle.speed"
                if tag and prm not in ("width", "height"):
                    q += "&" + SMALL_VIEW
                elif tag:
                    q += "&width=32" if prm == "height" else "&height=24"
                expect = "any"
                # a value no reading accepts: must be refused, naming the parameter
                # ("%00" reads as an empty value, i.e. absent; numbers are plain decimal,
                # so "0x10" is refused too)
                if prm in READ and prm not in TEXT_OK and v in ("NaN", "nan", "inf", "-inf",
                                                               "Infinity", "1e309", "%ff", "0x10",
                                                               "%ff%fe", "%C0%AF", "a" * 3000):
                    expect = "4xx"
                if prm in ("channels", "channel") and v not in ("", "%00"):
                    expect = "4xx"  # no channel has such a name
                add("query", f"{tag}{route}_{prm}={v[:24]}", "GET", build("GET", q), expect,
                    param=prm if prm in READ else None)
            if not subset:
                add("query", f"{tag}{route}_{prm}_dup", "GET",
                    build("GET", f"{base}?{prm}=1&{prm}=zz&{prm}=%ff"), "any")
        if not subset:
            add("query", f"{tag}{route}_all_bad", "GET",
                build("GET", base + "?" + "&".join(f"{p}=NaN" for p in params)), "4xx")
    add("query", "stream_last_event_id_bad", "GET",
        build("GET", f"/v1/sessions/{rsid}/stream", headers=[("Last-Event-ID", "\xff\xfe")]), "4xx",
        param="Last-Event-ID")
    add("query", "stream_last_event_id_huge", "GET",
        build("GET", f"/v1/sessions/{rsid}/stream", headers=[("Last-Event-ID", "9" * 30)]), "4xx",
        param="Last-Event-ID")
    g = ids["gsid"]
    for name, q in [("text_control", "text=%01%02"), ("text_bad_utf8", "text=%ff%fe"),
                    ("text_95", "text=" + "x" * 95), ("text_96", "text=" + "x" * 96),
                    ("text_3000", "text=" + "x" * 3000), ("view_three_quarter", "view=three_quarter"),
                    ("overlay_all", "overlay=1&antialias=1&color=tension&text=hi&exaggeration=1000"),
                    ("t_past_end", "t=0.3"), ("t_between", "t=0.0101"), ("from_after_to", "from=0.2&to=0.1"),
                    ("huge_width", "width=4096&height=16"), ("tiny", "width=16&height=16")]:
        add("query", f"gframe.png_{name}", "GET", build("GET", f"/v1/sessions/{g}/frame.png?{SMALL_VIEW}&{q}"
                                                        if "width" not in q else f"/v1/sessions/{g}/frame.png?{q}"), "any")
    for name, q in [("fps_1000_multipart", "fps=1000&format=multipart"), ("fps_1000_apng", "fps=1000"),
                    ("fps_min", "fps=0.01"), ("one_frame", "from=0.1&to=0.1"),
                    ("from_after_to", "from=0.2&to=0.1"), ("format_bad", "format=gif")]:
        add("query", f"gframes_{name}", "GET", build("GET", f"/v1/sessions/{g}/frames?{SMALL_VIEW}&{q}"), "any")
    add("query", "frame_etag_roundtrip_wrong", "GET",
        build("GET", f"/v1/sessions/{g}/frame.png?{SMALL_VIEW}", headers=[("If-None-Match", '"x"')]), "2xx")
    add("query", "frame_if_none_match_long", "GET",
        build("GET", f"/v1/sessions/{rsid}/frame.png", headers=[("If-None-Match", "x" * 6000)]),
        "any")

    # 4. bodies of the POST routes
    big = MAX_BODY
    pad = lambda n: b'{"preset":"' + PRESET.encode() + b'","x":"' + b"a" * (n - len(PRESET) - 20) + b'"}'
    bodies = [
        ("empty", b"", "4xx", ""), ("not_json", b"hello", "4xx", ""),
        ("trailing", b"{} x", "4xx", ""), ("array", b"[]", "4xx", ""), ("string", b'"s"', "4xx", ""),
        ("number", b"1", "4xx", ""), ("null", b"null", "4xx", ""), ("true", b"true", "4xx", ""),
        ("deep_array", b"[" * 5000 + b"]" * 5000, "4xx", ""),
        ("deep_object", b'{"a":' * 1000 + b"1" + b"}" * 1000, "4xx", ""),
        ("nul_byte", b'{"a":1}\x00', "4xx", ""), ("nul_inside", b'{"a\x00":1}', "4xx", ""),
        ("escaped_nul", b'{"a\\u0000":1}', "4xx", ""),
        ("bad_utf8", b'{"\xff\xfe":1}', "4xx", ""), ("overlong_utf8", b'{"\xc0\xaf":1}', "4xx", ""),
        ("lone_surrogate", b'{"\\ud800":1}', "4xx", ""), ("bom", b"\xef\xbb\xbf{}", "any", ""),
        ("dup_keys", b'{"a":1,"a":2}', "4xx", ""),
        ("huge_number", b'{"duration":1e400}', "4xx", ""),
        ("huge_int", b'{"duration":123456789012345678901234567890}', "4xx", ""),
        ("at_max_body", pad(big), "4xx", ""), ("over_max_body", pad(big + 1), "4xx", ""),
        ("way_over", b"{" * (big * 8), "4xx", ""),
    ]
    posts = [p for m, p in rts if m == "POST"]
    for p in posts:
        fp = fill(p, ids).replace(ids["sid"], ids["bsid"])
        for name, b, exp, prm in bodies:
            if fp.endswith(":cancel"):
                exp = "any"  # cancel reads no body
            if fp.endswith(("/modes", "/engine-map", "/tune")) and name in ("empty",):
                exp = "any"  # optional body: {} is the default config
            if fp.endswith("/run") and name == "empty":
                exp = "any"
            add("body", f"{fp.split('/')[-1]}_{name}", "POST", build("POST", fp, b), exp,
                param=prm or None)
        for ctype in ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data",
                      "application/json; charset=latin1", None]:
            hdr = [("Content-Type", ctype)] if ctype else []
            add("body", f"{fp.split('/')[-1]}_ctype_{ctype}", "POST",
                build("POST", fp, b'{"zzz":1}', headers=hdr), "any" if ":cancel" in fp else "4xx")
    # numeric members: wrong types and limits, each naming the member
    step = f"/v1/sessions/{ids['bsid']}/step"
    run = f"/v1/sessions/{ids['bsid']}/run"
    for path, member, vals in [(step, "duration", ['"1"', "null", "[]", "{}", "true", "-1", "-0.0",
                                                   "1e308", "-1e308", "5e-324", str(MAX_STEP + 1e-9),
                                                   "1e9"]),
                               (run, "until", ['"1"', "null", "[]", "-1", "1e308", "1e12", "5e-324"]),
                               (run, "real_time_factor", ['"1"', "null", "0", "-1", "1e-9", "1e308"])]:
        for v in vals:
            b = f'{{"{member}":{v}}}'.encode()
            exp = "4xx" if v not in ("-0.0", "5e-324") else "any"
            if member == "duration" and v in ("5e-324",):
                exp = "any"
            add("body", f"{path.split('/')[-1]}_{member}={v}", "POST", build("POST", path, b), exp,
                param=member if exp == "4xx" else None)
    add("body", "step_unknown_member", "POST", build("POST", step, b'{"duration":0.1,"zz":1}'),
        "4xx", param="zz")
    # session creation documents
    creates = [("preset_number", {"preset": 1}), ("preset_unknown", {"preset": "nope"}),
               ("preset_long", {"preset": "p" * 3000}), ("preset_bad_utf8_escape", {"preset": "\udcff"}),
               ("section_string", {"preset": PRESET, "run": "x"}),
               ("section_array", {"preset": PRESET, "run": []}),
               ("unknown_section", {"preset": PRESET, "zz": {}}),
               ("unknown_field", {"preset": PRESET, "run": {"zz": 1}}),
               ("duration_neg", {"preset": PRESET, "run": {"duration": -1}}),
               ("duration_string", {"preset": PRESET, "run": {"duration": "1"}}),
               ("rate_zero", {"preset": PRESET, "run": {"sample_rate": 0}}),
               ("kind_bad", {"preset": PRESET, "run": {"kind": "zz"}}),
               ("profile_file", {"preset": PRESET, "terrain": {"kind": "profile", "profile_csv": "/etc/passwd"}}),
               ("course_file", {"preset": PRESET, "terrain": {"kind": "bumps", "course": "../../etc/passwd"}}),
               ("unicode_field", {"preset": PRESET, "run": {"\u00e9" * 300: 1}}),
               ("unicode_section", {"preset": PRESET, "\u00e9" * 300: {}}),
               ("unicode_preset", {"preset": "\u00e9" * 300}),
               ("unicode_course", {"preset": PRESET, "terrain": {"kind": "bumps", "course": "\u00e9" * 100}}),
               ("unicode_enum", {"preset": PRESET, "run": {"kind": "\u00e9" * 300}})]
    for name, doc in creates:
        try:
            b = json.dumps(doc).encode()
        except UnicodeEncodeError:
            b = json.dumps(doc, ensure_ascii=False).encode("utf-8", "surrogateescape")
        add("body", f"create_{name}", "POST", build("POST", "/v1/sessions", b), "4xx")

    # 5. framing: chunked bodies, Content-Length lies, odd request lines
    ok_body = jbody(CHEAP_CONFIG)
    def chunked(parts, tail=b"0\r\n\r\n"):
        return b"".join(b"%x\r\n%s\r\n" % (len(p), p) for p in parts) + tail
    modes = "/v1/modes"
    te = [("Transfer-Encoding", "chunked")]
    framing = [
        ("chunked_ok", build("POST", modes, headers=te) + chunked([b"{", b"}"]), "2xx", {}),
        ("chunked_1byte", build("POST", modes, headers=te) + chunked([bytes([c]) for c in b'{"zz":1}']), "4xx", {}),
        ("chunked_ext", build("POST", modes, headers=te) + b"2;x=y\r\n{}\r\n0\r\n\r\n", "any", {}),
        ("chunked_bad_size", build("POST", modes, headers=te) + b"zz\r\n{}\r\n0\r\n\r\n", "4xx", {"close_ok": 1}),
        ("chunked_huge_size", build("POST", modes, headers=te) + b"ffffffffffffffff\r\n{}\r\n", "4xx", {"close_ok": 1, "timeout": CONN_TIMEOUT + 8}),
        ("chunked_over_max", build("POST", modes, headers=te) + chunked([b" " * 1000] * 6), "4xx", {}),
        ("chunked_trailer", build("POST", modes, headers=te) + b"2\r\n{}\r\n0\r\nX-T: 1\r\n\r\n", "any", {}),
        ("cl_and_te", build("POST", modes, headers=te + [("Content-Length", "2")]) + chunked([b"{}"]), "any", {"close_ok": 1}),
        ("cl_short", build("POST", modes, headers=[("Content-Length", "1")]) + b"{}", "any", {}),
        ("cl_negative", build("POST", modes, headers=[("Content-Length", "-1")]) + b"{}", "4xx", {"close_ok": 1}),
        ("cl_huge", build("POST", modes, headers=[("Content-Length", "99999999999999999999")]) + b"{}", "4xx", {"close_ok": 1}),
        ("cl_over_max_no_body", build("POST", modes, headers=[("Content-Length", str(MAX_BODY * 100))]), "any", {"close_ok": 1, "timeout": CONN_TIMEOUT + 8}),
        ("cl_two", build("POST", modes, headers=[("Content-Length", "2"), ("Content-Length", "3")]) + b"{}", "any", {"close_ok": 1, "timeout": CONN_TIMEOUT + 8}),
        ("expect_continue", build("POST", modes, headers=[("Expect", "100-continue"), ("Content-Length", "2")]) + b"{}", "any", {}),
        ("http10", build("GET", "/v1/health", version="HTTP/1.0", host=False), "2xx", {}),
        ("http2_line", build("GET", "/v1/health", version="HTTP/2.0"), "any", {"close_ok": 1}),
        ("no_host", build("GET", "/v1/health", host=False), "any", {}),
        ("garbage", b"\x00\xff\x16\x03\x01 hello\r\n\r\n", "any", {"close_ok": 1}),
        ("tls_hello", b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03" + b"\x00" * 64, "any", {"close_ok": 1, "timeout": CONN_TIMEOUT + 8}),
        ("lf_only", b"GET /v1/health HTTP/1.1\nHost: x\nConnection: close\n\n", "any", {"close_ok": 1}),
        ("header_no_colon", b"GET /v1/health HTTP/1.1\r\nHost: x\r\nBroken\r\nConnection: close\r\n\r\n", "any", {"close_ok": 1}),
        ("header_huge", build("GET", "/v1/health", headers=[("X-Big", "a" * 40000)]), "any", {"close_ok": 1}),
        ("many_headers", build("GET", "/v1/health", headers=[(f"X-{i}", "v") for i in range(2000)]), "any", {"close_ok": 1}),
        ("header_bad_utf8", build("GET", "/v1/health", headers=[("X-U", "\xff\xfe")]), "2xx", {}),
        ("auth_garbage", build("GET", "/v1/sessions", headers=[("Authorization", "Bearer " + "\xff" * 50)]), "2xx", {}),
        ("pipelined", build("GET", "/v1/health", headers=[("Connection", "keep-alive")]) + build("GET", "/v1/presets"), "2xx", {}),
        ("pipelined_bad_body", build("POST", modes, b"{", headers=[("Connection", "keep-alive")]) + build("GET", "/v1/health"), "4xx", {}),
    ]
    for name, raw, exp, kw in framing:
        add("framing", name, "POST" if b"POST" in raw[:5] else "GET", raw, exp, **kw)

    # 6. random combinations: 1-4 parameters, valid and bad values mixed, on any GET route
    good = {"from": ["0", "0.1", "0.25"], "to": ["0.2", "0.5", "1"], "every": ["1", "2", "7"],
            "channels": ["vehicle.speed", "t,vehicle.x", "vehicle.speed,vehicle.speed,t", ",,"],
            "channel": ["vehicle.speed", "t"], "format": ["json", "csv", "sse", "ndjson", "apng",
                                                          "multipart"],
            "page_size": ["1", "3", "2000"], "page_token": ["0", "5", "99"], "since": ["-1", "3", "50"],
            "t": ["0", "0.1", "0.2"], "fps": ["1", "25"], "view": ["side", "three_quarter"],
            "color": ["tension", "plain"], "overlay": ["0", "1"], "antialias": ["0", "1"],
            "exaggeration": ["0", "5"], "text": ["hi", ""]}
    gets = [(r, rsid) for r in ("series", "stream", "fft", "sessions")] + \
           [(r, ids["gsid"]) for r in ("frame.png", "frames")]
    for i in range(60 if subset else 1500):
        route, on = rng.choice(gets)
        base = "/v1/sessions" if route == "sessions" else f"/v1/sessions/{on}/{route}"
        params = QUERY_PARAMS[route]
        q = []
        for prm in rng.sample(params, rng.randint(1, min(4, len(params)))):
            pool = good.get(prm, ["1"])
            v = rng.choice(pool) if rng.random() < 0.6 else rng.choice(BAD_NUMBERS)
            q.append(f"{prm}={v}")
        if route in ("frame.png", "frames"):
            q.append(SMALL_VIEW)
        if route == "fft" and not any(x.startswith("channel=") for x in q):
            q.append("channel=vehicle.speed")
        hdr = [("Accept", rng.choice(["text/csv", "application/x-ndjson", "*/*"]))]
        add("combo", f"{i}_{route}", "GET", build("GET", base + "?" + "&".join(q), headers=hdr),
            "any", timeout=30)

    # 7. mutated bodies: byte flips, cuts, duplications and insertions of valid documents
    seeds = [(f"/v1/sessions/{ids['bsid']}/step", b'{"duration": 0.05}'),
             (f"/v1/sessions/{ids['bsid']}/run", b'{"until": 0.1, "real_time_factor": 50}'),
             ("/v1/modes", b'{"preset": "table1-span"}'),
             ("/v1/sessions", jbody({"preset": PRESET, "run": {"duration": 0.1, "sample_rate": 20},
                                     "drive": {"kind": "constant", "torque": 100.0}}))]
    inserts = [b"\x00", b"\xff", b"\\u0000", b"\\ud800", b"[", b"{", b"\"", b",", b"1e999", b"-",
               b"\xc3", b"null", b"NaN", b" " * 100]
    for i in range(40 if subset else 600):
        path, b = rng.choice(seeds)
        b = bytearray(b)
        for _ in range(rng.randint(1, 4)):
            op = rng.randrange(4)
            at = rng.randrange(len(b) + 1)
            if op == 0 and b:
                b[min(at, len(b) - 1)] = rng.randrange(256)
            elif op == 1:
                b = b[:at]
            elif op == 2:
                b[at:at] = rng.choice(inserts)
            else:
                b = b[:at] + b[at // 2:]
        add("mutate", f"{i}_{path.split('/')[-1]}", "POST", build("POST", path, bytes(b)), "any",
            timeout=30)
    return cases


def run_cases(port, cases, results, log):
    """Each case on its own connection, in order; the few the daemon answers only
    by closing at --timeout (garbage, incomplete bodies) run alongside, in threads."""
    lock = threading.Lock()
    def one(c):
        r = send_raw(port, c["raw"], timeout=c.get("timeout", 15))
        head = c["raw"][:40]
        if r.status == 202 and (b"/v1/engine-map" in head or b"/v1/tune" in head):
            # an analysis the fuzzer started holds the fuzz daemon's one worker
            # (--threads 1) until its current part ends, seconds (tens under TSan):
            # cancel it and wait for it, so later checks do not queue behind it
            try:
                op = r.json()["id"]
                send_raw(port, build("POST", f"/v1/operations/{op}:cancel"), timeout=15)
                end = time.time() + 180
                while time.time() < end:
                    g = send_raw(port, build("GET", f"/v1/operations/{op}"), timeout=15)
                    if g.status != 200 or g.json().get("done"):
                        break
                    time.sleep(0.1)
            except (ValueError, KeyError):
                pass
        v = classify(c, r)
        rec = {"id": c["id"], "cls": c["cls"], "status": r.status, "error": r.error,
               "verdict": v, "ms": round(1e3 * r.elapsed)}
        if v in DEFECTS:
            rec["body"] = r.body[:600].decode("utf-8", "replace")
            rec["headers"] = r.headers
        with lock:
            results.append(rec)
            log.write(json.dumps(rec) + "\n")
    waits = [threading.Thread(target=one, args=(c,)) for c in cases if c.get("close_ok")]
    for t in waits:
        t.start()
    for c in cases:
        if not c.get("close_ok"):
            one(c)
    for t in waits:
        t.join()


# ---- timing classes: slowloris, aborts, streams, races, shutdown -----------------

def rec(results, log, cls, name, verdict, **kw):
    d = {"id": f"{cls}/{name}", "cls": cls, "verdict": verdict, **kw}
    results.append(d)
    log.write(json.dumps(d) + "\n")


def rec_resp(results, log, cls, name, case, r, verdict=None):
    v = verdict or classify(case, r)
    extra = {}
    if v in DEFECTS:
        extra = {"body": r.body[:600].decode("utf-8", "replace"), "headers": r.headers}
    rec(results, log, cls, name, v, status=r.status, error=r.error, **extra)


def health_ok(port, timeout=5):
    r = request(port, "GET", "/v1/health", timeout=timeout)
    return r.status == 200


def create(port, doc=None):
    r = request(port, "POST", "/v1/sessions", jbody(doc or CHEAP_CONFIG), timeout=60)
    if r.status != 201:
        raise RuntimeError(f"create failed: {r.status} {r.body[:300]!r}")
    return r.json()["id"]


def slow_cases(port, rng, results, log, subset):
    """Slowloris-style partial requests: the daemon must close them within its
    --timeout and keep answering everyone else meanwhile."""
    n_idle = 8 if subset else 40
    stalled = []
    def stall():  # a body that stalls past --timeout: closed, no reply needed
        req = build("POST", "/v1/modes", headers=[("Content-Length", "50")]) + b"{"
        stalled.append(send_raw(port, req, timeout=CONN_TIMEOUT + 8))
    st = threading.Thread(target=stall)
    st.start()
    socks = []
    for i in range(n_idle):
        s = socket.create_connection(("127.0.0.1", port), timeout=5)
        part = [b"GET /v1/hea", b"POST /v1/modes HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\n{",
                b"GET /v1/health HTTP/1.1\r\nHost: x\r\nX-Slow: "][i % 3]
        s.sendall(part)
        socks.append(s)
    t0 = time.time()
    ok = health_ok(port, timeout=5)
    rec(results, log, "slow", f"health_with_{n_idle}_idle", "OK" if ok else "HANG",
        ms=round(1e3 * (time.time() - t0)))
    # each idle connection must be closed by the daemon within timeout + slack
    closed = 0
    deadline = time.time() + CONN_TIMEOUT + 8
    for s in socks:
        try:
            s.settimeout(max(0.1, deadline - time.time()))
            while s.recv(4096):
                pass
            closed += 1
        except socket.timeout:
            pass
        except OSError:
            closed += 1
        s.close()
    rec(results, log, "slow", f"idle_closed_{closed}_of_{n_idle}",
        "OK" if closed == n_idle else "HANG")
    # a request trickled byte by byte (faster than the idle timeout) is answered
    req = build("GET", "/v1/health")
    pieces = [req[i:i + 8] for i in range(0, len(req), 8)]
    r = send_raw(port, None, pieces=pieces, delay=0.05, timeout=20)
    rec(results, log, "slow", "trickled_request", "OK" if r.status == 200 else "HANG",
        status=r.status)
    st.join()
    r = stalled[0]
    rec(results, log, "slow", "stalled_body", "HANG" if r.error == "timeout" else "OK",
        status=r.status, error=r.error)


def keepalive_cases(port, rng, ids, results, log, subset):
    """Many requests on one kept-alive connection, errors among them (a 413 whose
    body is skipped, deferred replies, a 405): each answered in turn."""
    sid, rsid = ids["bsid"], ids["rsid"]
    ka = [("Connection", "keep-alive")]
    seq = [("GET", "/v1/health", None, "2xx"), ("GET", "/nope", None, "4xx"),
           ("PUT", "/v1/health", b"{}", "4xx"),
           ("POST", "/v1/modes", b'{"x":"' + b"a" * (2 * MAX_BODY) + b'"}', "4xx"),
           ("POST", f"/v1/sessions/{sid}/step", b'{"duration":0.02}', "any"),
           ("GET", f"/v1/sessions/{rsid}/series?format=csv&every=5", None, "2xx"),
           ("GET", f"/v1/sessions/{rsid}/series?from=NaN", None, "4xx"),
           ("POST", "/v1/modes", b"{", "4xx"), ("POST", "/v1/modes", b"{}", "2xx"),
           ("GET", f"/v1/sessions/{rsid}/fft?channel=vehicle.speed", None, "2xx"),
           ("POST", "/v1/sessions", b'{"preset":"nope"}', "4xx"),
           ("GET", f"/v1/sessions/{ids['gsid']}/frame.png?{SMALL_VIEW}", None, "2xx"),
           ("DELETE", "/v1/sessions/nope", None, "4xx")]
    for k in range(2 if subset else 10):
        order = seq[:]
        rng.shuffle(order)
        sock = socket.create_connection(("127.0.0.1", port), timeout=20)
        for i, (m, p, b, exp) in enumerate(order):
            try:
                sock.sendall(build(m, p, b, headers=ka))
                r = _read_response(sock, time.time() + 20)
            except OSError:
                r = Resp()
                r.error = "reset"
            v = classify({"method": m, "expect": exp}, r)
            if r.headers.get("connection", "").lower() == "close" and i < len(order) - 1:
                v = "OK" if v == "OK" else v
                rec_resp(results, log, "keepalive", f"k{k}_{i}_{m}_{p[:40]}", {"method": m, "expect": exp}, r, v)
                sock.close()
                sock = socket.create_connection(("127.0.0.1", port), timeout=20)
                continue
            rec_resp(results, log, "keepalive", f"k{k}_{i}_{m}_{p[:40]}", {"method": m, "expect": exp}, r, v)
        sock.close()


def abort_cases(port, rng, ids, results, log, subset):
    """Requests the client abandons: closed right after sending (RST), for every
    kind of handler including the deferred ones (create, step, modes, frames)."""
    sid = create(port)
    reqs = [build("POST", "/v1/sessions", jbody(CHEAP_CONFIG)),
            build("POST", f"/v1/sessions/{sid}/step", b'{"duration":0.2}'),
            build("POST", "/v1/modes", b"{}"),
            build("GET", f"/v1/sessions/{ids['rsid']}/series"),
            build("GET", f"/v1/sessions/{ids['rsid']}/stream"),
            build("GET", f"/v1/sessions/{ids['rsid']}/fft?channel=vehicle.speed"),
            build("GET", f"/v1/sessions/{ids['rsid']}/frame.png"),
            build("GET", f"/v1/sessions/{ids['gsid']}/frame.png?{SMALL_VIEW}"),
            build("GET", f"/v1/sessions/{ids['gsid']}/frames?{SMALL_VIEW}&fps=200"),
            build("GET", f"/v1/sessions/{ids['gsid']}/frames?{SMALL_VIEW}&fps=500&format=multipart"),
            build("GET", "/v1/presets"), build("GET", "/v1/schema"),
            build("POST", "/v1/modes", headers=[("Content-Length", "10")]) + b"{",
            build("POST", "/v1/modes", headers=[("Transfer-Encoding", "chunked")]) + b"5\r\n{"]
    rounds = 2 if subset else 6
    for k in range(rounds):
        for i, q in enumerate(reqs):
            send_raw(port, q, abort_after_send=True)
            if k == 0:
                rec(results, log, "abort", f"req{i}", "OK")
    # multipart animations read in part, then dropped
    for k in range(2 if subset else 6):
        r = send_raw(port, build("GET", f"/v1/sessions/{ids['gsid']}/frames?{SMALL_VIEW}&fps=500&format=multipart"),
                     timeout=20, stream_bytes=200 * (k + 1))
        rec(results, log, "abort", f"multipart_cut_{k}", "HANG" if r.error == "timeout" else "OK",
            status=r.status, error=r.error)
    time.sleep(1.0)
    rec(results, log, "abort", "health_after", "OK" if health_ok(port) else "HANG")
    # sessions created by aborted requests are real sessions: delete them all but the fixtures
    cleanup(port, ids)


def cleanup(port, ids):
    keep = {ids["sid"], ids["rsid"], ids["bsid"], ids["gsid"]}
    r = request(port, "GET", "/v1/sessions?page_size=1000")
    for s in r.json()["sessions"] if r.status == 200 else []:
        if s["id"] not in keep:
            request(port, "DELETE", f"/v1/sessions/{s['id']}")


def stream_cases(port, rng, ids, results, log, subset):
    """Streams cut mid-way, while a run produces rows and after it ended."""
    for k in range(2 if subset else 5):
        sid = create(port, {"preset": PRESET, "run": {"duration": 1.0, "sample_rate": 200}})
        r = request(port, "POST", f"/v1/sessions/{sid}/run", b'{"real_time_factor":2}')
        if r.status != 202:
            rec(results, log, "stream", f"run{k}", "UNEXPECTED", status=r.status)
            continue
        fmt = ["sse", "ndjson"][k % 2]
        got = []
        def reader(n):
            got.append(send_raw(port, build("GET", f"/v1/sessions/{sid}/stream?format={fmt}"),
                                timeout=15, stream_bytes=n))
        ts = [threading.Thread(target=reader, args=(n,)) for n in (50, 2000, 100000)]
        for t in ts:
            t.start()
        # and a few that vanish without reading
        for _ in range(3):
            send_raw(port, build("GET", f"/v1/sessions/{sid}/stream"), abort_after_send=True)
        time.sleep(0.2 * k)
        if k % 2:
            request(port, "DELETE", f"/v1/sessions/{sid}")  # delete under the streams
        for t in ts:
            t.join(20)
        for i, rr in enumerate(got):
            v = "HANG" if rr.error == "timeout" else ("OK" if rr.status in (200, 404) or rr.error else "UNEXPECTED")
            rec(results, log, "stream", f"run{k}_{fmt}_reader{i}", v, status=rr.status, error=rr.error,
                bytes=len(rr.body))
        request(port, "DELETE", f"/v1/sessions/{sid}")


def race_cases(port, rng, results, log, subset):
    """Concurrent create/step/run/cancel/delete/read on the same session."""
    rounds = 3 if subset else 40
    for k in range(rounds):
        geometry = k % 2 == 1  # odd rounds: a session with frames to draw
        sid = create(port, GEOMETRY_CONFIG if geometry else None)
        ops = []
        def op(kind):
            if kind == "step":
                return request(port, "POST", f"/v1/sessions/{sid}/step", b'{"duration":0.1}', timeout=30)
            if kind == "run":
                return request(port, "POST", f"/v1/sessions/{sid}/run", b"{}", timeout=30)
            if kind == "cancel":
                s = request(port, "GET", f"/v1/sessions/{sid}", timeout=30)
                opid = s.json().get("operation") if s.status == 200 else None
                return request(port, "POST", f"/v1/operations/{opid or 'opnone'}:cancel", timeout=30)
            if kind == "delete":
                return request(port, "DELETE", f"/v1/sessions/{sid}", timeout=30)
            if kind == "series":
                return request(port, "GET", f"/v1/sessions/{sid}/series?every=3", timeout=30)
            if kind == "stream":
                return send_raw(port, build("GET", f"/v1/sessions/{sid}/stream?format=ndjson"), timeout=30)
            if kind == "fft":
                return request(port, "GET", f"/v1/sessions/{sid}/fft?channel=vehicle.speed", timeout=30)
            if kind == "create":
                return request(port, "POST", "/v1/sessions", jbody(CHEAP_CONFIG), timeout=60)
            if kind == "frame":
                return request(port, "GET", f"/v1/sessions/{sid}/frame.png?{SMALL_VIEW}", timeout=30)
            if kind == "frames":
                return send_raw(port, build("GET", f"/v1/sessions/{sid}/frames?{SMALL_VIEW}&fps=100&format=multipart"),
                                timeout=30)
            return request(port, "GET", f"/v1/sessions/{sid}", timeout=30)
        kinds = ["step", "step", "run", "cancel", "series", "stream", "fft", "get", "create"]
        if k % 3 != 2:
            kinds.append("delete")
        if k % 4 == 1:
            kinds += ["delete", "run", "cancel", "stream"]  # double delete, run vs run
        if geometry:
            kinds += ["frame", "frames", "frames"]
        rng.shuffle(kinds)
        out = {}
        def worker(i, kind):
            time.sleep(rng.random() * 0.05)
            out[i] = (kind, op(kind))
        ts = [threading.Thread(target=worker, args=(i, kd)) for i, kd in enumerate(kinds)]
        for t in ts:
            t.start()
        for t in ts:
            t.join(60)
        for i, (kind, rr) in sorted(out.items()):
            case = {"method": "GET", "expect": "any", "allow503": False}
            rec_resp(results, log, "race", f"r{k}_{i}_{kind}", case, rr)
        if len(out) != len(kinds):
            rec(results, log, "race", f"r{k}_threads", "HANG")
        request(port, "DELETE", f"/v1/sessions/{sid}")
        # the create in the race made one more session: remove it
        for i, (kind, rr) in out.items():
            if kind == "create" and rr.status == 201:
                request(port, "DELETE", f"/v1/sessions/{rr.json()['id']}")
    # creates racing for the last places under --max-sessions: 429, never more sessions
    cap = int(DAEMON_FLAGS[DAEMON_FLAGS.index("--max-sessions") + 1])
    got = []
    def mk():
        got.append(request(port, "POST", "/v1/sessions", jbody(CHEAP_CONFIG), timeout=60))
    ts = [threading.Thread(target=mk) for _ in range(cap + 4)]
    for t in ts:
        t.start()
    for t in ts:
        t.join(90)
    for i, rr in enumerate(got):
        rec_resp(results, log, "race", f"cap_create_{i}", {"method": "POST", "expect": "any"}, rr)
    n = len(session_ids(port))
    rec(results, log, "race", f"cap_{n}_of_{cap}", "OK" if n <= cap else "UNEXPECTED")
    for rr in got:
        if rr.status == 201:
            request(port, "DELETE", f"/v1/sessions/{rr.json()['id']}")
    rec(results, log, "race", "health_after", "OK" if health_ok(port) else "HANG")


def shutdown_case(d, rng, ids, results, log, subset):
    """Requests during SIGTERM: every one answered (503 allowed) or closed; exit 0."""
    port = d.port
    sid = create(port, {"preset": PRESET, "run": {"duration": 1.0, "sample_rate": 100}})
    request(port, "POST", f"/v1/sessions/{sid}/run", b'{"real_time_factor":1}')
    out = []
    lock = threading.Lock()
    def worker(kind, i):
        time.sleep(0.02 * i)
        for _ in range(reps):
            if not one(kind):
                break
    def one(kind):
        if kind == "stream":
            r = send_raw(port, build("GET", f"/v1/sessions/{sid}/stream"), timeout=20)
        elif kind == "step":
            r = request(port, "POST", f"/v1/sessions/{ids['bsid']}/step", b'{"duration":0.05}', timeout=20)
        elif kind == "create":
            r = request(port, "POST", "/v1/sessions", jbody(CHEAP_CONFIG), timeout=20)
        elif kind == "modes":
            r = request(port, "POST", "/v1/modes", b"{}", timeout=20)
        elif kind == "series":
            r = request(port, "GET", f"/v1/sessions/{sid}/series?every=7", timeout=20)
        elif kind == "frames":
            r = send_raw(port, build("GET", f"/v1/sessions/{ids['gsid']}/frames?{SMALL_VIEW}&fps=200&format=multipart"),
                         timeout=20)
        else:
            r = request(port, "GET", "/v1/health", timeout=20)
        with lock:
            out.append((kind, r))
        time.sleep(0.05)
        return not r.error.startswith("connect")  # stop once the daemon is gone
    reps = 10 if subset else 40
    kinds = ["stream", "step", "create", "modes", "series", "frames", "health"] * (1 if subset else 3)
    ts = [threading.Thread(target=worker, args=(kd, i)) for i, kd in enumerate(kinds)]
    for t in ts:
        t.start()
    time.sleep(0.15)
    before = session_ids(port)
    rc = d.stop(timeout=40)
    for t in ts:
        t.join(30)
    for i, (kind, r) in enumerate(out):
        case = {"method": "GET", "expect": "any", "allow503": True, "close_ok": True}
        v = None
        if r.error.startswith("connect"):
            v = "OK"  # after the daemon stopped listening
        elif kind == "health" and r.status == 503:
            # /v1/health is a status document, not a problem: {"status": "stopping"}
            try:
                v = "OK" if r.json().get("status") == "stopping" else "BADBODY"
            except ValueError:
                v = "BADBODY"
        rec_resp(results, log, "shutdown", f"{kind}_{i}", case, r, v)
    rec(results, log, "shutdown", "exit", "OK" if rc == 0 else ("HANG" if rc == "HANG" else "CRASH"),
        rc=rc)
    return before


def session_ids(port):
    r = request(port, "GET", "/v1/sessions?page_size=1000")
    return sorted(s["id"] for s in r.json()["sessions"])


# ---- main ------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build-asan", "tanksimd"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None)
    ap.add_argument("--subset", action="store_true", help="the short selection for make test")
    ap.add_argument("--only", default="", help="comma-separated classes")
    ap.add_argument("--list", action="store_true", help="print the static cases and exit")
    ap.add_argument("--per-class", action="store_true",
                    help="final line counts request classes (a class passes when all its checks do)"
                    " instead of single checks: how make test counts this suite")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    out = a.out or tempfile.mkdtemp(prefix="http_fuzz-")
    os.makedirs(out, exist_ok=True)
    only = set(filter(None, a.only.split(",")))
    want = lambda c: not only or c in only
    rts = routes(a.bin)
    data = os.path.join(out, "data")
    d = Daemon(a.bin, data, os.path.join(out, "daemon.log"))
    t_start = time.time()
    results = []
    t_phase = [time.time()]
    def phase(name):
        print(f"  {name}: {time.time() - t_phase[0]:.1f} s", file=sys.stderr)
        t_phase[0] = time.time()
    log = open(os.path.join(out, "results.jsonl"), "w", buffering=1)
    try:
        ids = {"sid": create(d.port), "bsid": create(d.port),
               "rsid": create(d.port, {"preset": PRESET, "run": {"duration": 1.0, "sample_rate": 100}}),
               "gsid": create(d.port, GEOMETRY_CONFIG)}
        request(d.port, "POST", f"/v1/sessions/{ids['rsid']}/step", b'{"duration":0.5}', timeout=60)
        request(d.port, "POST", f"/v1/sessions/{ids['gsid']}/step", b'{"duration":0.2}', timeout=60)
        r = request(d.port, "POST", f"/v1/sessions/{ids['sid']}/run", b'{"until":0.2}')
        ids["op"] = r.json()["id"].split("/")[-1] if r.status == 202 else "opnone"
        time.sleep(0.5)
        cases = gen_cases(rng, rts, ids, a.subset)
        cases = [c for c in cases if want(c["cls"])]
        if a.list:
            for c in cases:
                print(c["id"])
            print(len(cases), "cases", file=sys.stderr)
            return 0
        rng.shuffle(cases)
        run_cases(d.port, cases, results, log)
        phase('run_cases')
        cleanup(d.port, ids)
        if want("slow"):
            slow_cases(d.port, rng, results, log, a.subset)
            phase('slow_cases')
        if want("keepalive"):
            keepalive_cases(d.port, rng, ids, results, log, a.subset)
            phase("keepalive")
        if want("abort"):
            abort_cases(d.port, rng, ids, results, log, a.subset)
            phase('abort_cases')
        if want("stream"):
            stream_cases(d.port, rng, ids, results, log, a.subset)
            phase('stream_cases')
        if want("race"):
            race_cases(d.port, rng, results, log, a.subset)
            phase('race_cases')
            cleanup(d.port, ids)
        rec(results, log, "after", "health", "OK" if health_ok(d.port) else "HANG")
        before = session_ids(d.port)
        if want("shutdown"):
            before = shutdown_case(d, rng, ids, results, log, a.subset)
            phase('shutdown_case')
        else:
            rc = d.stop()
            rec(results, log, "after", "exit", "OK" if rc == 0 else "CRASH", rc=rc)
        # restart on the same store: the same sessions
        d2 = Daemon(a.bin, data, os.path.join(out, "daemon2.log"))
        after = session_ids(d2.port)
        # sessions whose create was in flight at SIGTERM may legitimately add to the list
        lost = sorted(set(before) - set(after))
        rec(results, log, "after", "restart_sessions", "OK" if not lost else "RESTART",
            before=len(before), after=len(after), lost=lost)
        rc2 = d2.stop()
        rec(results, log, "after", "restart_exit", "OK" if rc2 == 0 else "CRASH", rc=rc2)
        for name, path in (("daemon", d.log_path), ("daemon2", d2.log_path)):
            with open(path, "rb") as f:
                text = f.read().decode("utf-8", "replace")
            hits = SANITIZER.findall(text)
            rec(results, log, "after", f"{name}_sanitizer", "SANITIZER" if hits else "OK",
                hits=len(hits))
    finally:
        if d.proc.poll() is None:
            d.stop()
    # summary
    table = collections.defaultdict(collections.Counter)
    for r in results:
        table[r["cls"]][r["verdict"]] += 1
    verdicts = sorted({v for c in table.values() for v in c})
    print(f"seed {a.seed}, {len(results)} checks, {time.time() - t_start:.0f} s, out {out}")
    print("class      " + " ".join(f"{v:>10}" for v in verdicts))
    for cls in sorted(table):
        print(f"{cls:10} " + " ".join(f"{table[cls][v]:>10}" for v in verdicts))
    codes = collections.defaultdict(collections.Counter)
    for r in results:
        if "status" in r:
            codes[r["cls"]][r["status"] or r.get("error") or "closed"] += 1
    for cls in sorted(codes):
        print(f"  {cls:9} " + " ".join(f"{k}:{n}" for k, n in sorted(codes[cls].items(), key=str)))
    bad = [r for r in results if r["verdict"] in DEFECTS]
    for r in bad[:60]:
        print("DEFECT", r["verdict"], r["id"], r.get("status"), (r.get("body") or "")[:200])
    if a.per_class:
        failed = {r["cls"] for r in bad}
        print(f"{len(table) - len(failed)} passed, {len(failed)} failed")
    else:
        print(f"{len(results) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
