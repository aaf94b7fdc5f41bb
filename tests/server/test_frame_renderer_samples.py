"""A renderer went back to the pool after frames of up to full HD counted in
pixels, though an antialiased one keeps its multisampled colour and depth
buffers (4 samples a pixel) besides the single-sampled pair: after one
1920 x 1080 antialiased frame the idle daemon held its ~4x larger buffers.
The bound now counts samples, so that renderer is freed with its frame."""

import pytest
import requests

import conftest
from conftest import Daemon


@pytest.fixture(scope="module")
def d():
    dm = Daemon()
    yield dm
    dm.stop()


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        return int(f.read().split("VmRSS:")[1].split()[0]) / 1024


@pytest.mark.skipif(conftest.SANITIZED, reason="resident size under a sanitizer's allocator is not the daemon's")
@pytest.mark.skipif(conftest.SANITIZED, reason="resident size under a sanitizer's allocator is not the daemon's")
def test_full_hd_antialiased_frame_leaves_no_renderer_behind(d):
    r = requests.post(d.url + "/v1/sessions",
                      json={"preset": "bump-prescribed-coupled", "run": {"sample_rate": 50, "duration": 1}})
    sid = r.json()["id"]
    assert requests.post(f"{d.url}/v1/sessions/{sid}/step", json={"duration": 0.2}).status_code == 200
    frame = f"{d.url}/v1/sessions/{sid}/frame.png"
    for t in (0.1, 0.12):  # a pooled renderer of the default size exists
        assert requests.get(frame, params={"t": t}).status_code == 200
    before = rss_mb(d.proc.pid)
    r = requests.get(frame, params={"t": 0.14, "width": 1920, "height": 1080, "antialias": 1})
    assert r.status_code == 200 and r.headers["Content-Type"] == "image/png"
    after = rss_mb(d.proc.pid)
    assert after - before < 40, (before, after)
    assert requests.get(frame, params={"t": 0.16}).status_code == 200
