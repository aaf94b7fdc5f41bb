"""A pooled renderer kept the buffers of the largest frame it drew: after one
frame.png?width=4096&height=4096&antialias=1 the idle daemon held ~700 MB
more (RSS 100 -> 818 MB) until a smaller frame was drawn on that renderer. A
renderer that drew more than full HD went to be freed instead of pooled; then
the bound counted pixels, though an antialiased renderer also keeps its
multisampled colour and depth buffers (4 samples a pixel): after one
1920 x 1080 antialiased frame the idle daemon held +79 MB. The bound now
counts samples, so both renderers are freed with their frame; frames of the
usual sizes keep reusing theirs."""

import pytest
import requests

import conftest
from conftest import rss_kb, stepped_session


@pytest.mark.skipif(conftest.SANITIZED, reason="resident size under a sanitizer's allocator is not the daemon's")
@pytest.mark.parametrize("width, height, bound_mb", [(4096, 4096, 150), (1920, 1080, 40)])
def test_large_frame_leaves_no_large_renderer_behind(daemon, width, height, bound_mb):
    sid = stepped_session(daemon.url, "bump-prescribed-coupled", step=0.2)
    frame = f"{daemon.url}/v1/sessions/{sid}/frame.png"
    for t in (0.1, 0.12):  # a pooled renderer of the default size exists
        assert requests.get(frame, params={"t": t}).status_code == 200
    before = rss_kb(daemon.proc.pid) / 1024
    r = requests.get(frame, params={"t": 0.14, "width": width, "height": height, "antialias": 1})
    assert r.status_code == 200 and r.headers["Content-Type"] == "image/png"
    after = rss_kb(daemon.proc.pid) / 1024
    assert after - before < bound_mb, (before, after)
    assert requests.get(frame, params={"t": 0.16}).status_code == 200
