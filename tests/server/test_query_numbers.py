"""Query numbers are plain decimal numerals (server/routes.c is_decimal).

strtod and strtol also take leading blanks and strtod hexadecimal ("0x10" reads
as 16): a client that sent such a value got an answer computed from a number it
may not have meant. Found by the HTTP fuzzer's BAD_NUMBERS list (session 5 noted
"0x10" and " 1" as accepted and left them). Each refused value must be a 400
problem naming the parameter; the decimal spellings must still work.
"""
import pytest
import requests

from conftest import is_problem


# (route under the session, parameter, kind) -- kind: number or integer
PARAMS = [("series", "from", "number"), ("series", "to", "number"),
          ("series", "every", "integer"), ("series", "page_size", "integer"),
          ("fft", "from", "number"), ("stream", "since", "integer")]


@pytest.mark.parametrize("route,param,kind", PARAMS)
@pytest.mark.parametrize("value", ["0x10", "0X1p2", "%201", "%091", "1%20", "1e", ".", "%2B", "--1",
                                   "1.5.2", "infinity", "nan"])
def test_non_decimal_query_number_is_400_naming_it(daemon, sid, route, param, kind, value):
    extra = "&channel=vehicle.speed" if route == "fft" else ""
    if route == "stream":
        extra = "&format=ndjson"
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/{route}?{param}={value}{extra}",
                     timeout=10)
    is_problem(r, 400, "/" + param)


@pytest.mark.parametrize("route,param,kind", PARAMS)
def test_decimal_spellings_are_taken(daemon, sid, route, param, kind):
    extra = "&channel=vehicle.speed" if route == "fft" else ""
    if route == "stream":
        extra = "&format=ndjson"
    # a bare "+" in a query reads as a blank, so the sign is sent as %2B
    values = ["1", "%2B1", "01"] if kind == "integer" else ["0", "%2B0.1", "00", ".1", "0.10",
                                                            "1e-1", "1E-1"]
    for v in values:
        r = requests.get(f"{daemon.url}/v1/sessions/{sid}/{route}?{param}={v}{extra}",
                         timeout=10)
        assert r.status_code == 200, (v, r.status_code, r.text[:200])


def test_fft_range_past_the_stored_end_names_from(daemon, sid):
    # 0.5 s stored at 50 Hz: from=1 lies past the end; the message said "-24 stored samples"
    r = requests.get(f"{daemon.url}/v1/sessions/{sid}/fft?channel=vehicle.speed&from=1",
                     timeout=10)
    p = is_problem(r, 400, "/from")
    assert "holds 0 stored samples" in p["detail"], p
