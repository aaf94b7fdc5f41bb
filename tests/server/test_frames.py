"""Rendered frames over HTTP (issue 7): GET /v1/sessions/{id}/frame.png and the
/frames animation (an APNG by default, or multipart/x-mixed-replace of PNGs). For every preset whose
scenario draws (has running gear in its geometry snapshot) a frame is a valid
PNG of the asked size, a past time gives the same bytes whether asked before
or after the run went on (the state is rebuilt from the stored trajectory),
and an animation has one PNG part per 1/fps. Scenarios without geometry give
422 problem+json; bad view parameters give 400 naming the parameter."""
import struct

import pytest
import requests

from conftest import BASE_PRESET, is_problem, preset_names, wait_op


def png_size(data):
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def parts(body, boundary=b"--frame"):
    """Split a multipart/x-mixed-replace body into [(headers dict, payload)]."""
    out = []
    for chunk in body.split(boundary + b"\r\n")[1:]:
        head, _, rest = chunk.partition(b"\r\n\r\n")
        hdrs = dict(l.split(": ", 1) for l in head.decode().split("\r\n"))
        n = int(hdrs["Content-Length"])
        out.append((hdrs, rest[:n]))
    assert body.rstrip().endswith(boundary + b"--")
    return out


def test_pointmass_has_no_frames(daemon):
    s = requests.post(daemon.url + "/v1/sessions", json={"preset": BASE_PRESET}).json()
    if s.get("kind") != "pointmass":
        pytest.skip("base preset is not the pointmass scenario")
    p = is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frame.png"), 422)
    assert "geometry" in p["detail"]
    is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frames"), 422)
    for q, ptr in [({"width": 3}, "/width"), ({"view": "top"}, "/view"),
                   ({"color": "red"}, "/color"), ({"t": -1}, "/t"), ({"t": 99}, "/t"),
                   ({"exaggeration": 1e6}, "/exaggeration")]:
        is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frame.png", params=q),
                   400, ptr)
    p = is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frame.png",
                                params={"t": 99}), 400, "/t")
    # was "time at most, got '0 s (the last stored sample)'": the bound and the value swapped
    assert "at most 0 s (the last stored sample), got '99'" in p["detail"], p["detail"]
    requests.post(daemon.url + s["links"]["step"], json={"duration": 4.0})
    p = is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frames",
                                params={"fps": 1000}), 422, "/fps")
    assert "4001 frames" in p["detail"]
    is_problem(requests.get(daemon.url + f"/v1/sessions/{s['id']}/frames",
                            params={"format": "gif"}), 400, "/format")


def drawable_sessions(d):
    """(preset, session) for every preset whose scenario is built and draws."""
    out = []
    for name in preset_names():
        r = requests.post(d.url + "/v1/sessions", json={"preset": name, "run": {"duration": 1.0}})
        if r.status_code != 201:
            continue
        s = r.json()
        # the session links to its frames (it did not: the walkthrough of session 26)
        assert s["links"]["frames"] == s["links"]["self"] + "/frames"
        f = requests.get(d.url + s["links"]["frame.png"], params={"width": 64, "height": 48})
        if f.status_code == 422:
            continue
        out.append((name, s))
    return out


def test_frames_of_every_drawable_preset(daemon):
    found = drawable_sessions(daemon)
    names = [name for name, _ in found]
    assert "bump-prescribed-static" in names, f"vehicle presets must draw frames, got {names}"
    for name, s in found:
        base = daemon.url + s["links"]["self"]
        op = requests.post(base + "/run", json={"until": 0.2}).json()
        wait_op(daemon.url, op["id"], timeout=600)
        r = requests.get(base + "/frame.png", params={"t": 0.1, "width": 320, "height": 200,
                                                     "color": "tension"})
        assert r.status_code == 200 and r.headers["Content-Type"] == "image/png", (name, r.text)
        assert png_size(r.content) == (320, 200)
        first = r.content
        op = requests.post(base + "/run", json={"until": 0.4}).json()
        wait_op(daemon.url, op["id"], timeout=600)
        again = requests.get(base + "/frame.png", params={"t": 0.1, "width": 320, "height": 200,
                                                         "color": "tension"}).content
        assert again == first, name   # rebuilt from the stored trajectory: same picture
        # a stored time's frame is immutable: strong ETag, cacheable, 304 on revalidation
        etag = r.headers["ETag"]
        assert etag.startswith('"') and "immutable" in r.headers["Cache-Control"]
        nm = requests.get(base + "/frame.png", params={"t": 0.1, "width": 320, "height": 200,
                                                      "color": "tension"},
                          headers={"If-None-Match": etag})
        assert nm.status_code == 304 and nm.content == b"" and nm.headers["ETag"] == etag
        # RFC 9110 13.1.2: a list, weak comparison, "*" (each got the whole PNG
        # until session 20: the header was compared as one string)
        for inm in ('W/' + etag, '"other", ' + etag, '*'):
            nm = requests.get(base + "/frame.png", params={"t": 0.1, "width": 320, "height": 200,
                                                          "color": "tension"},
                              headers={"If-None-Match": inm})
            assert nm.status_code == 304, (inm, nm.status_code)
        other = requests.get(base + "/frame.png", params={"t": 0.1, "width": 320, "height": 200},
                             headers={"If-None-Match": etag})
        assert other.status_code == 200 and other.headers["ETag"] != etag   # other options
        apng = requests.get(base + "/frames", params={"from": 0, "to": 0.4, "fps": 10,
                                                      "width": 160, "height": 100})
        assert apng.status_code == 200 and apng.headers["Content-Type"] == "image/apng"
        assert png_size(apng.content) == (160, 100)
        actl = apng.content.index(b"acTL")
        assert int.from_bytes(apng.content[actl + 4:actl + 8], "big") == 5   # num_frames
        assert apng.content.count(b"fcTL") == 5 and apng.content.count(b"fdAT") >= 4

        def delays(content):  # each fcTL's delay_num / delay_den [s] (APNG spec, PNG 3rd ed.)
            out, i = [], content.find(b"fcTL")
            while i >= 0:
                num = int.from_bytes(content[i + 24:i + 26], "big")
                den = int.from_bytes(content[i + 26:i + 28], "big")
                out.append(num / den)
                i = content.find(b"fcTL", i + 4)
            return out
        assert delays(apng.content) == pytest.approx([0.1] * 5, rel=1e-12)
        # above 65.5 fps the 16-bit denominator of 1000 / (1000 fps) was capped: 100 and 1000
        # fps played at 65.5 (15.3 ms a frame); its replacement k / (k fps) then gave the
        # slow rates 5 digits only (0.5 fps: 65535 / 32768 s). Every one exact now.
        for fps in (0.01, 0.5, 29.97, 100, 1000):
            fast = requests.get(base + "/frames", params={"from": 0, "to": 0.002, "fps": fps,
                                                          "width": 16, "height": 16})
            assert fast.status_code == 200
            assert delays(fast.content) == pytest.approx([1 / fps] * len(delays(fast.content)),
                                                         rel=1e-12), fps
        a = requests.get(base + "/frames", params={"from": 0, "to": 0.4, "fps": 10,
                                                   "width": 160, "height": 100,
                                                   "format": "multipart"})
        assert a.headers["Content-Type"].startswith("multipart/x-mixed-replace")
        ps = parts(a.content)
        assert len(ps) == 5
        assert [float(h["X-Frame-Time"]) for h, _ in ps] == pytest.approx([0, 0.1, 0.2, 0.3, 0.4])
        for h, png in ps:
            assert png_size(png) == (160, 100)
