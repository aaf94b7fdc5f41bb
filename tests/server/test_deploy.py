"""`make install` and deploy/tanksimd.service (deployment review, session 11):
the unit named /usr/local/bin/tanksimd, a tanksim user and /var/lib/tanksim
that nothing created. Now `make install` puts the programs, the dashboard and
the unit in place (paths rewritten for PREFIX), the unit runs as a transient
user with a StateDirectory, and every flag it passes is one the daemon takes."""
import os
import re
import subprocess

from conftest import REPO, TANKSIMD


def test_make_install_puts_every_file_the_unit_names(tmp_path):
    dest, prefix = tmp_path / "root", "/opt/tanksim"
    out = subprocess.run(["make", "-s", "install", f"DESTDIR={dest}", f"PREFIX={prefix}"],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    unit = (dest / "etc/systemd/system/tanksimd.service").read_text()
    exec_start = re.search(r"^ExecStart=(.*)$", unit, re.M).group(1).split()
    assert exec_start[0] == prefix + "/bin/tanksimd"
    for prog in ("tanksimd", "tanksim"):
        assert os.access(dest / ("." + prefix) / "bin" / prog, os.X_OK)
    web_root = exec_start[exec_start.index("--web-root") + 1]
    assert (dest / ("." + web_root) / "index.html").is_file()
    assert (dest / ("." + web_root) / "app.js").is_file()
    # the store: a directory systemd creates for the transient user
    data_dir = exec_start[exec_start.index("--data-dir") + 1]
    assert "DynamicUser=yes" in unit and f"StateDirectory={os.path.basename(data_dir)}" in unit
    assert data_dir == "/var/lib/" + os.path.basename(data_dir)
    # every flag of ExecStart is one the daemon documents
    usage = subprocess.run([TANKSIMD, "--help"], capture_output=True, text=True).stdout
    for flag in (a for a in exec_start[1:] if a.startswith("--")):
        assert flag in usage, flag
    assert "/usr/local" not in unit.split("[Unit]")[1]  # rewritten for PREFIX
