"""GET /v1/sessions/{id}/series pages are bounded by cells (rows x (channels
+ the index)), not only by rows: a page of a wide session used to be the whole
--max-samples rows (100001 rows x 65 channels: a 70 MB answer built in 1.3 s
on an HTTP thread, eight of them held /v1/health 5-16 s). Now a page holds at
most 10^6 cells (~11 MB of JSON) and ends with next_page_token, which clients
follow as before; following it yields every row once. A narrow selection
still gets its rows in one page; page_size still caps rows below that."""

import pytest
import requests

from conftest import wide_session

PAGE_CELLS = 1_000_000


@pytest.fixture(scope="module")
def wide(daemon):
    """A session of 20001 rows x 65 channels (1 s at 20 kHz: ~0.4 s to make)."""
    sid = wide_session(daemon.url)
    assert requests.get(f"{daemon.url}/v1/sessions/{sid}").json()["index"] == 20000
    return sid


def test_wide_page_is_bounded_by_cells_and_tokens_give_every_row(daemon, wide):
    r = requests.get(f"{daemon.url}/v1/sessions/{wide}/series")
    assert r.status_code == 200, r.text
    page = r.json()
    nch = len(page["channels"])
    assert nch > 50
    assert page["count"] * (nch + 1) <= PAGE_CELLS
    assert page["count"] >= PAGE_CELLS // (nch + 1) - 1  # not needlessly small
    assert len(r.content) < 16 << 20
    assert page["next_page_token"] == str(page["index"][-1] + 1)
    index, speed, pages = list(page["index"]), list(page["channels"][2]["values"]), 1
    while "next_page_token" in page:
        page = requests.get(f"{daemon.url}/v1/sessions/{wide}/series",
                            params={"page_token": page["next_page_token"]}).json()
        index += page["index"]
        speed += page["channels"][2]["values"]
        pages += 1
    assert index == list(range(20001)) and pages == 2
    # the same rows as one narrow page (2 cells a row: no cap reached)
    one = requests.get(f"{daemon.url}/v1/sessions/{wide}/series",
                       params={"channels": page["channels"][2]["name"]}).json()
    assert one["count"] == 20001 and "next_page_token" not in one
    assert one["channels"][1]["values"] == speed


def test_every_and_page_size_still_apply_under_the_cap(daemon, wide):
    page = requests.get(f"{daemon.url}/v1/sessions/{wide}/series", params={"every": 3}).json()
    assert page["index"][:3] == [0, 3, 6]
    assert page["count"] == 6667 and "next_page_token" not in page  # 6667 x 66 cells: one page
    small = requests.get(f"{daemon.url}/v1/sessions/{wide}/series", params={"page_size": 10}).json()
    assert small["count"] == 10 and small["next_page_token"] == "10"


def test_csv_page_is_bounded_too(daemon, wide):
    r = requests.get(f"{daemon.url}/v1/sessions/{wide}/series", params={"format": "csv"})
    assert r.status_code == 200
    lines = r.text.strip().split("\n")
    ncol = len(lines[0].split(","))
    assert (len(lines) - 1) * (ncol + 1) <= PAGE_CELLS
    assert r.headers["X-Next-Page-Token"] == str(len(lines) - 1)


def test_short_range_of_a_wide_session(daemon, wide):
    r = requests.get(f"{daemon.url}/v1/sessions/{wide}/series", params={"to": 0})
    assert r.status_code == 200
    page = r.json()
    assert page["count"] == 1 and page["index"] == [0] and "next_page_token" not in page
