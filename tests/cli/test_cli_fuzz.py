"""tanksim schema and the CLI side of the config-fuzz findings (tests/fuzz/config_fuzz.py):
the schema lists every table row with its range; model errors print the JSON Pointer of the
field at fault (cli.h's "tanksim: <pointer>: message"); a terrain file that is a device
returns at once with the field named instead of reading forever."""
import json
import re
import subprocess

from conftest import TANKSIM


def run(*args, cwd=None, timeout=120):
    return subprocess.run([TANKSIM, *args], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout)


def test_schema_lists_every_section_with_ranges():
    out = run("schema")
    assert out.returncode == 0, out.stderr
    schema = json.loads(out.stdout)
    props = schema["properties"]
    for sec in ("run", "track", "vehicle", "terrain", "drive", "engine", "driveline", "control",
                "coupling"):
        assert props[sec]["type"] == "object" and props[sec]["properties"], sec
    dur = props["run"]["properties"]["duration"]
    assert dur["minimum"] == 1e-3 and dur["maximum"] == 3600 and dur["x-unit"] == "s"
    assert "coupled" in props["track"]["properties"]["fidelity"]["enum"]
    assert run("schema", "extra").returncode == 2


def test_every_numeric_config_field_has_an_si_unit():
    # The brief's "SI units everywhere": phi_curvature, fmep_b and id_a had
    # their correlations' units (1/rpm^2, Pa/rpm, ms) and /control/schedule_x
    # none (session-26 walkthrough). Each unit is built of SI symbols only.
    si = {"1", "m", "s", "kg", "K", "N", "Pa", "J", "W", "rad", "Hz", "or"}
    seen = []

    def walk(f, ptr):
        for name, sub in f.get("properties", {}).items():
            walk(sub, f"{ptr}/{name}")
        numeric = f.get("type") in ("number", "integer") or (
            f.get("type") == "array" and f.get("items", {}).get("type") == "number")
        if numeric:
            unit = f.get("x-unit")
            assert unit, f"{ptr} has no unit"
            tokens = set(re.split(r"[*/^() .0-9-]+", unit)) - {""}
            assert tokens <= si, (ptr, unit)
            seen.append(ptr)
    walk(json.loads(run("schema").stdout), "")
    assert len(seen) > 150 and "/engine/id_a" in seen and "/control/schedule_x" in seen, seen


def test_model_error_prints_the_field_pointer(tmp_path):
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"preset": "accel-pointmass-conventional", "run": {"duration": 0.05},
                               "engine": {"ca_step": 0.1}}))
    out = run("run", str(cfg), "--out", str(tmp_path / "o"))
    assert out.returncode == 1
    assert "/engine/ca_step:" in out.stderr, out.stderr


def test_device_as_terrain_profile_fails_fast(tmp_path):
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"preset": "bump-prescribed-static", "run": {"duration": 0.05},
                               "terrain": {"kind": "profile", "profile_csv": "/dev/zero"}}))
    out = run("run", str(cfg), "--out", str(tmp_path / "o"), timeout=30)
    assert out.returncode == 1
    assert "/terrain/profile_csv" in out.stderr and "not a regular file" in out.stderr, out.stderr
