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


def routing_table(with_query=False):
    """{(method, path): summary}, or {(method, path): accepted query names} ("*": any)."""
    out = subprocess.run([TANKSIMD, "--routes"], capture_output=True, text=True, check=True)
    rows = {}
    for line in out.stdout.splitlines():
        left, summary, query = line.split("\t")
        method, path = left.split(" ", 1)
        rows[(method, path)] = (query if query == "*" else set(query.split())) if with_query \
            else summary
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


def test_query_parameters_equal_what_each_route_accepts():
    """The daemon answers 400 to a query parameter its route does not take
    (routes.c check_query), so the document must list exactly those."""
    doc = openapi()
    accepted = routing_table(with_query=True)

    def resolve(param):
        if "$ref" in param:
            node = doc
            for part in param["$ref"].lstrip("#/").split("/"):
                node = node[part]
            return node
        return param

    for p, item in doc["paths"].items():
        shared = [resolve(x) for x in item.get("parameters", [])]
        for m, op in item.items():
            if m not in METHODS:
                continue
            params = shared + [resolve(x) for x in op.get("parameters", [])]
            documented = {x["name"] for x in params if x["in"] == "query"}
            want = accepted[(m.upper(), p)]
            if want == "*":
                continue
            assert documented == want, (m, p, "only documented:", documented - want,
                                        "only accepted:", want - documented)
