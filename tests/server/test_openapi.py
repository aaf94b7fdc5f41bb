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


# Media types the daemon makes whole before sending (server.c reply_buffer:
# tsd_reply_json, tsd_reply_owned); an answer of these of 64 KiB or more
# counts against the held-reply budget and can be 503 /problems/busy.
# Streams (SSE, NDJSON, multipart), the spec (sent from the binary), /metrics
# and the dashboard's files (sent from disk) are not counted.
MADE_WHOLE = {"application/json", "text/csv", "image/png", "image/apng"}
NEVER_LARGE = {("get", "/v1/health"): "two short strings",
               ("get", "/static/{file}"): "sent from the file, not counted"}
BUSY = ("#/components/responses/Busy", "#/components/responses/ShuttingDownOrBusy")


def test_every_answer_the_reply_budget_can_refuse_documents_busy():
    doc = openapi()
    subject = []
    for p, item in doc["paths"].items():
        for m, op in item.items():
            if m not in METHODS or (m, p) in NEVER_LARGE:
                continue
            types = {t for code, resp in op["responses"].items() if code.startswith("2")
                     for t in resp.get("content", {})}
            if types & MADE_WHOLE:
                subject.append((m, p))
                assert op["responses"].get("503", {}).get("$ref") in BUSY, (m, p)
    assert ("get", "/v1/sessions/{id}/series") in subject and ("get", "/v1/analyses") in subject
    assert ("get", "/v1/sessions/{id}/frame.png") in subject
    responses = doc["components"]["responses"]
    for ref in BUSY:
        r = responses[ref.rsplit("/", 1)[1]]
        assert "/problems/busy" in r["description"] and "Retry-After" in r["headers"]


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
