"""`make test` on a fresh Debian 12 machine (README "The two commands"): every
third-party Python module that a test suite or tool imports must come from a
Debian package in the Makefile's DEB_PACKAGES (installed by `make deps`), named
python3-MODULE. python3-yaml (tests/server/test_openapi.py) was missing: it was
only present on machines where something else had pulled it in."""
import ast
import os
import re
import sys

from conftest import REPO


def deb_packages():
    text = open(os.path.join(REPO, "Makefile")).read().replace("\\\n", " ")
    m = re.search(r"^DEB_PACKAGES\s*:=(.*)$", text, re.M)
    assert m, "no DEB_PACKAGES in the Makefile"
    return set(m.group(1).split())


def imported_modules():
    found = {}
    for top in ("tests", "tools"):
        for d, _, files in os.walk(os.path.join(REPO, top)):
            if "node_modules" in d:
                continue
            local = {f[:-3] for f in files if f.endswith(".py")}
            for f in files:
                if not f.endswith(".py"):
                    continue
                path = os.path.join(d, f)
                for node in ast.walk(ast.parse(open(path).read(), path)):
                    if isinstance(node, ast.Import):
                        names = [a.name for a in node.names]
                    elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                        names = [node.module]
                    else:
                        continue
                    for n in names:
                        mod = n.split(".")[0]
                        if mod not in sys.stdlib_module_names and mod not in local \
                                and mod != "conftest":
                            found.setdefault(mod, os.path.relpath(path, REPO))
    return found


def test_third_party_python_modules_are_in_deb_packages():
    pkgs = deb_packages()
    mods = imported_modules()
    assert "yaml" in mods and "requests" in mods  # the scan sees the suites' imports
    missing = {m: f for m, f in mods.items() if "python3-" + m.lower() not in pkgs}
    assert not missing, "add to DEB_PACKAGES: %s" % ", ".join(
        "python3-%s (imported by %s)" % (m.lower(), f) for m, f in sorted(missing.items()))
