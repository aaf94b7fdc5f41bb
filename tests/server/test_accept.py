"""Accept q-values are read as RFC 9110 section 12.4.2 writes them.

qvalue = ( "0" [ "." 0*3DIGIT ] ) / ( "1" [ "." 0*3("0") ] ). The daemon read the
q parameter with a bare strtod (server/routes.c accept_q), so "0.5x" weighed 0.5,
"2" and "1e0" outweighed a 1, "0x1" read as 1, "0.0001" as a weight above 0 and
"nan" compared false with everything. A range whose q is not a qvalue is now left
out, as if not sent (the daemon never answers 406: what no range accepts gets its
default representation, JSON for /series and SSE for /stream; a range it cannot
read is disregarded the same way, not refused with a 400).
"""
import pytest
import requests

JSON, CSV = "application/json", "text/csv"
SSE, NDJSON = "text/event-stream", "application/x-ndjson"

# (Accept, representation served by /series)
SERIES = [
    # malformed q: that range is left out (the strtod reading in the comment)
    ("text/csv;q=0.5x, application/json;q=0.4", JSON),  # was 0.5 >= 0.4: CSV
    ("application/json;q=0.9, text/csv;q=1e0", JSON),  # was 1: CSV
    ("text/csv;q=2", JSON),  # was 2: CSV
    ("text/csv;q=0.0001", JSON),  # four decimals: was above 0, CSV
    ("text/csv;q=+1", JSON),
    ("text/csv;q=.5", JSON),
    ("text/csv;q=1.5, application/json;q=0.1", JSON),  # was 1.5: CSV
    ("text/csv;q= 1", JSON),  # no blank after "q="
    ('text/csv;q="1"', JSON),
    ("text/csv;q=", JSON),
    ("application/json;q=0x1, text/csv;q=0.5", CSV),  # JSON's range left out; was 1: JSON
    ("application/json;q=nan, text/csv;q=0.5", CSV),  # was nan: JSON
    ("application/json;q=1.001, text/csv;q=0.1", CSV),  # was 1.001: JSON
    ("*/*;q=0.9x, text/csv;q=0.1", CSV),  # the catch-all left out: JSON unnamed
    # well-formed qvalues are read as before
    ("text/csv;q=1.000, application/json;q=0.999", CSV),
    ("text/csv;q=0.999, application/json;q=1.000", JSON),
    ("text/csv;Q=0.5, application/json;q=0.5", CSV),  # a tie goes to the one named
    ("text/csv;q=0., application/json", JSON),  # "0." is 0
    ("text/csv ; q=0.5 , application/json;q=0.4", CSV),  # blanks around ';' and ','
    ("text/csv;charset=utf-8;q=0.7, application/json;q=0.6", CSV),
    ("text/csv;q=1", CSV),
    ("text/csv;q=0", JSON),
]


@pytest.mark.parametrize("accept,ctype", SERIES)
def test_accept_q_values_for_series(daemon, sid, accept, ctype):
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/series",
                     params={"channels": "vehicle.speed", "to": 0.01},
                     headers={"Accept": accept}, timeout=10)
    assert r.status_code == 200, (accept, r.status_code, r.text[:200])
    assert r.headers["Content-Type"].startswith(ctype), (accept, r.headers["Content-Type"])


@pytest.mark.parametrize("accept,ctype", [
    (f"{NDJSON};q=0.5x, {SSE};q=0.4", SSE),  # was NDJSON
    (f"{SSE};q=1e0, {NDJSON};q=0.5", NDJSON),  # SSE's range left out; was SSE
    (f"{NDJSON};q=0.5, {SSE};q=0.4", NDJSON),
    (f"{NDJSON};q=0.4, {SSE};q=0.5", SSE),
])
def test_accept_q_values_for_stream(daemon, sid, accept, ctype):
    with requests.get(f"{daemon.url}/v1/sessions/{sid}/stream", params={"since": 20},
                      headers={"Accept": accept}, stream=True, timeout=10) as r:
        assert r.status_code == 200, (accept, r.status_code)
        assert r.headers["Content-Type"].startswith(ctype), (accept, r.headers["Content-Type"])
