"""tanksimd serves the dashboard: GET / and GET /static/FILE from --web-root
(server/static_files.c). Checks content types, the default root beside the
binary, a custom --web-root, the 404 naming `make web` when the dashboard is
not built, that static files need no token, and that nothing outside the web
root (traversal, dot files, symlinks, unknown types) is served."""
import os

import requests

from conftest import Daemon


def test_index_and_assets_from_default_root(daemon):
    r = requests.get(daemon.url + "/")
    assert r.status_code == 200
    assert r.headers["Content-Type"].startswith("text/html")
    assert "/static/app.js" in r.text
    for name, ctype in [("app.js", "text/javascript"), ("app.css", "text/css")]:
        a = requests.get(daemon.url + "/static/" + name)
        assert a.status_code == 200, name
        assert a.headers["Content-Type"].startswith(ctype)
        assert len(a.content) > 100


def test_no_traversal_or_hidden_files(daemon):
    for path in ["/static/..%2FMakefile", "/static/%2e%2e%2fMakefile", "/static/../Makefile",
                 "/static/.gitignore", "/static/README.md", "/static/", "/static/a/b.js",
                 "/static/nope.js"]:
        r = requests.get(daemon.url + path)
        # an encoded slash (%2F) is refused before routing (400 /problems/bad-path)
        assert r.status_code in ((400,) if "%2f" in path.lower() else (404, 405)), path
        assert r.headers["Content-Type"] == "application/problem+json", path


def test_custom_web_root_and_symlinks(tmp_path):
    (tmp_path / "index.html").write_text("<!doctype html><title>custom</title>")
    (tmp_path / "x.js").write_text("export const x = 1;")
    secret = tmp_path.parent / "secret.js"
    secret.write_text("leak")
    os.symlink(secret, tmp_path / "link.js")
    d = Daemon("--web-root", str(tmp_path))
    try:
        assert "custom" in requests.get(d.url + "/").text
        assert requests.get(d.url + "/static/x.js").text == "export const x = 1;"
        assert requests.get(d.url + "/static/link.js").status_code == 404
    finally:
        d.stop()


def test_missing_dashboard_names_make_web(tmp_path):
    d = Daemon("--web-root", str(tmp_path / "none"))
    try:
        r = requests.get(d.url + "/")
        assert r.status_code == 404
        assert "make web" in r.json()["detail"]
    finally:
        d.stop()


def test_static_files_need_no_token():
    d = Daemon("--token", "sekrit")
    try:
        assert requests.get(d.url + "/").status_code == 200
        assert requests.get(d.url + "/static/app.js").status_code == 200
        assert requests.get(d.url + "/v1/presets").status_code == 401
    finally:
        d.stop()


def test_which_names_are_served_and_how(tmp_path):
    """static_files.h: the type comes from the last extension (a hashed or
    minified asset, app.min.js, is served as JavaScript), every file carries
    no-cache and nosniff, and a dot file with a served extension, a
    directory with one, and a name over 100 characters are not served
    (the survivors of the session-28 mutation pass: each was served, or the
    headers missing, with its check removed)."""
    (tmp_path / "index.html").write_text("<!doctype html><title>t</title>")
    (tmp_path / "app.min.js").write_text("export const y = 2;")
    (tmp_path / ".secret.js").write_text("leak")
    (tmp_path / "d.js").mkdir()
    (tmp_path / ("a" * 97 + ".js")).write_text("ok")   # 100 characters
    (tmp_path / ("a" * 98 + ".js")).write_text("long")  # 101
    d = Daemon("--web-root", str(tmp_path))
    try:
        r = requests.get(d.url + "/static/app.min.js")
        assert r.status_code == 200
        assert r.headers["Content-Type"].startswith("text/javascript")
        assert r.headers["Cache-Control"] == "no-cache"
        assert r.headers["X-Content-Type-Options"] == "nosniff"
        assert requests.get(d.url + "/static/" + "a" * 97 + ".js").text == "ok"
        for name in [".secret.js", "d.js", "a" * 98 + ".js"]:
            r = requests.get(d.url + "/static/" + name)
            assert r.status_code == 404, name
            assert r.headers["Content-Type"] == "application/problem+json", name
    finally:
        d.stop()
