"""api/openapi.yaml matches the daemon (issue 7): the set of (method, path) in
the document equals the routing table printed by `tanksimd --routes`, each
operation's summary is the table's, and the daemon serves the same file it
was built with. (Schema validity is checked by suite_openapi.sh with
@apidevtools/swagger-parser.)"""
import os
import subprocess

import requests
import yaml

from conftest import REPO, TANKSIMD

METHODS = {"get", "put", "post", "delete", "patch", "head", "options"}


def routing_table():
    out = subprocess.run([TANKSIMD, "--routes"], capture_output=True, text=True, check=True)
    rows = {}
    for line in out.stdout.splitlines():
        left, _, summary = line.partition("\t")
        method, path = left.split(" ", 1)
        rows[(method, path)] = summary
    return rows


def openapi():
    with open(os.path.join(REPO, "api", "openapi.yaml")) as f:
        return yaml.safe_load(f)


def test_paths_equal_routing_table():
    doc = openapi()
    assert doc["openapi"].startswith("3.1")
    documented = {(m.upper(), p): op["summary"] for p, item in doc["paths"].items()
                  for m, op in item.items() if m in METHODS}
    table = routing_table()
    assert set(documented) == set(table), (
        "only in openapi.yaml: %s; only in routes.c: %s"
        % (sorted(set(documented) - set(table)), sorted(set(table) - set(documented))))
    for key, summary in table.items():
        assert documented[key] == summary, key


def test_every_operation_documents_errors_as_problems():
    doc = openapi()
    for p, item in doc["paths"].items():
        for m, op in item.items():
            if m not in METHODS or op.get("security") == []:
                continue  # public operations (health, dashboard files) never answer 401
            assert "401" in op["responses"], (m, p)
            for code, resp in op["responses"].items():
                if code.startswith(("4", "5")):
                    assert resp["$ref"].startswith("#/components/responses/"), (m, p, code)


def test_served_file_is_the_source_file(daemon):
    r = requests.get(daemon.url + "/v1/openapi.yaml")
    assert r.status_code == 200 and r.headers["Content-Type"].startswith("application/yaml")
    with open(os.path.join(REPO, "api", "openapi.yaml")) as f:
        assert r.text == f.read()
