"""tanksim's config files: JSON that does not parse names the member it
stopped in (JSON Pointer, as a bad field), then FILE:LINE:COLUMN."""
import subprocess

from conftest import TANKSIM


def run_config(tmp_path, text):
    cfg = tmp_path / "c.json"
    cfg.write_text(text)
    return subprocess.run([TANKSIM, "run", str(cfg), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=120)


def test_duplicate_key_names_the_pointer(tmp_path):
    out = run_config(tmp_path, '{"preset": "pointmass-prescribed",\n'
                               ' "run": {"duration": 1, "duration": 2}}')
    assert out.returncode == 1, out.stderr
    assert "tanksim: config: /run/duration: " in out.stderr, out.stderr
    assert "c.json:2:" in out.stderr and "duplicate object key" in out.stderr
    assert not (tmp_path / "o").exists()


def test_syntax_and_overflow_name_the_pointer(tmp_path):
    out = run_config(tmp_path, '{"preset": "pointmass-prescribed", "vehicle": {"mass": 1e999}}')
    assert out.returncode == 1 and "config: /vehicle/mass: " in out.stderr, out.stderr
    out = run_config(tmp_path, '{"preset": "pointmass-prescribed", "track": {"n_trans": }}')
    assert out.returncode == 1 and "config: /track/n_trans: " in out.stderr, out.stderr
    out = run_config(tmp_path, '{"preset": "pointmass-prescribed" "run": {}}')
    assert out.returncode == 1, out.stderr  # a ',' missing between members: the root, no pointer
    assert "tanksim: config: %s:1:" % (tmp_path / "c.json") in out.stderr, out.stderr


def test_config_from_a_pipe(tmp_path):
    # A config that can be read only once (a shell's <(...), a FIFO): it
    # parses, and a parse error still names its member. The file used to be
    # read twice, so the second read of a pipe found nothing and the error
    # named the root.
    good = '{"preset": "pointmass-prescribed", "run": {"duration": 0.5}}'
    bad = '{"preset": "pointmass-prescribed",\n "run": {"duration": 1, "duration": 2}}'
    for text, rc in ((good, 0), (bad, 1)):
        out = subprocess.run(["bash", "-c", 'exec "$0" run /dev/stdin --out "$1"', TANKSIM,
                              str(tmp_path / ("o%d" % rc))],
                             input=text, capture_output=True, text=True, timeout=120)
        assert out.returncode == rc, out.stderr
        if rc:
            assert "tanksim: config: /run/duration: " in out.stderr, out.stderr
            assert "duplicate object key" in out.stderr, out.stderr


def test_missing_and_oversized_config_files(tmp_path):
    out = subprocess.run([TANKSIM, "run", str(tmp_path / "none.json"), "--out", str(tmp_path / "o")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode != 0 and "cannot open '" in out.stderr and "none.json': No such file" in out.stderr, out.stderr
    exact = tmp_path / "exact.json"  # exactly 16 MiB: read (it failed at the bound once)
    head = '{"preset": "pointmass-prescribed", "run": {"duration": 0.1}, "description": "'
    exact.write_text(head + "x" * ((16 << 20) - len(head) - 2) + '"}')
    assert exact.stat().st_size == 16 << 20
    out = subprocess.run([TANKSIM, "run", str(exact), "--out", str(tmp_path / "e")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    big = tmp_path / "big.json"
    big.write_text('{"description": "%s"}' % ("x" * (16 << 20)))
    out = subprocess.run([TANKSIM, "run", str(big), "--out", str(tmp_path / "o")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode != 0 and "larger than 16 MiB" in out.stderr, out.stderr
