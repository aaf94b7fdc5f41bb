"""tanksim modes (issue 3): span and upper-circuit eigenanalysis as JSON.

EVIDENCE: output contract of the brief ({"spans":[{name, length_m,
frequencies_hz:{longitudinal, transverse, coupled}}], "circuit":{frequencies_hz,
mode_shapes}}); paper Fig. 5 (3.7, 5.5, 7.3, 7.6 Hz, within 15 %) and Table 1
(7.2, 14.6 Hz, within 5 %) — both CALIBRATED: the layout's span lengths, the
test-span length and P0/rho were inferred from these frequencies (track.json
_about). Config errors exit non-zero naming the field.
"""
import json
import math
import subprocess

from conftest import TANKSIM


def run(*args):
    return subprocess.run([TANKSIM, *args], capture_output=True, text=True, timeout=120)


def modes(*args):
    out = run("modes", *args)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_modes_m1_structure_and_fig5():
    d = modes("--preset", "m1")
    assert len(d["spans"]) == 5
    # the upper circuit between road wheels 1 and 7, held at both ends, free between
    # (its "boundary" text; the last support's flag survived the session-26 mutation pass)
    sup = d["circuit"]["supports"]
    assert [s["name"] for s in (sup[0], sup[-1])] == ["road_wheel_1", "road_wheel_7"], sup
    assert [s["fixed"] for s in sup] == [True] + [False] * (len(sup) - 2) + [True], sup
    for s in d["spans"]:
        assert isinstance(s["name"], str) and s["length_m"] > 0
        f = s["frequencies_hz"]
        assert set(f) >= {"longitudinal", "transverse", "coupled"}
        assert len(f["longitudinal"]) == 4 and len(f["transverse"]) == 4
        assert len(f["coupled"]) == 8
        assert all(b >= a for a, b in zip(f["coupled"], f["coupled"][1:]))
        # longitudinal (bar) modes far above the transverse ones
        assert min(f["longitudinal"]) > 5 * max(f["transverse"][:1])
        # every span sags down: the shallow-cable sag rho g cos(inclination) L^2 /
        # (8 P0) below the chord, the same sign for the two slope spans (they
        # read negative until session 20)
        g, rho, p0 = 9.80665, d["track"]["mass_per_length_kg_m"], d["track"]["tension_n"]
        want = rho * g * math.cos(s["inclination_rad"]) * s["length_m"] ** 2 / (8 * p0)
        assert abs(s["sag_m"] - want) <= 0.05 * want, (s["name"], s["sag_m"], want)
    c = d["circuit"]
    freqs = c["frequencies_hz"]
    assert len(freqs) == 8 and len(c["mode_shapes"]) == 8
    for got, want in zip(freqs[:4], [3.7, 5.5, 7.3, 7.6]):
        assert abs(got - want) <= 0.15 * want, (got, want)
    m = c["mode_shapes"][0]
    assert m["character"] in ("transverse", "longitudinal")
    assert m["dominant_span"] in [s["name"] for s in d["spans"]]
    assert len(m["deflection"][m["dominant_span"]]["transverse"]) == 11
    total = m["energy_share"]["wheels"] + sum(
        v["transverse"] + v["longitudinal"] for k, v in m["energy_share"].items() if k != "wheels")
    assert abs(total - 1) < 1e-6


def test_modes_table1_span():
    d = modes("--preset", "table1-span")
    assert len(d["spans"]) == 1
    s = d["spans"][0]
    assert s["length_m"] == 1.39
    f = s["frequencies_hz"]["coupled"]
    assert abs(f[0] - 7.2) <= 0.05 * 7.2 and abs(f[1] - 14.6) <= 0.05 * 14.6


def test_modes_config_file_override(tmp_path):
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"preset": "m1", "track": {"span_length": [1.0, 2.0],
                                                         "span_inclination": [0.0, 0.5],
                                                         "n_long": 0, "n_trans": 3}}))
    d = modes(str(cfg))
    assert [s["length_m"] for s in d["spans"]] == [1.0, 2.0]
    assert d["spans"][0]["frequencies_hz"]["longitudinal"] == []
    assert len(d["spans"][1]["frequencies_hz"]["transverse"]) == 3
    # the 2 m span is half as stiff as the 1 m one (taut-string scaling, small sag)
    f1 = d["spans"][0]["frequencies_hz"]["transverse"][0]
    f2 = d["spans"][1]["frequencies_hz"]["transverse"][0]
    assert 1.9 < f1 / f2 < 2.05


def test_modes_bad_fields_name_the_field(tmp_path):
    cases = [
        ({"preset": "m1", "track": {"n_trans": 99}}, "/track/n_trans"),
        ({"track": {"span_length": [1.0], "span_inclination": []}}, "/track/span_inclination"),
        ({"track": {"span_length": [99.0], "span_inclination": [0]}}, "/track/span_length/0"),
        ({"track": {"tension": 150.0}}, "/track/tension"),  # sag no longer shallow
        ({"track": {"ea": "stiff"}}, "/track/ea"),
        # a layout out of the circuit's order: `run` refused it, `modes` printed a
        # 6.65-m road wheel 1 - idler span (review, session 24; sim/vehicle_layout.c)
        ({"preset": "m1", "vehicle": {"idler_x": -1.5}}, "/vehicle/idler_x"),
        ({"preset": "m1", "vehicle": {"road_wheel_z": 2.0}}, "/vehicle/road_wheel_z"),
    ]
    for doc, pointer in cases:
        cfg = tmp_path / "bad.json"
        cfg.write_text(json.dumps(doc))
        out = run("modes", str(cfg))
        assert out.returncode != 0, doc
        assert pointer in out.stderr, (doc, out.stderr)
        assert out.stdout == ""
