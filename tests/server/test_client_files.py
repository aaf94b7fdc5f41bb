"""tanksimd opens no file a client names (found by the config fuzzer, session 4):
/terrain/profile_csv and a bump course outside the shipped ones would make the
daemon read any path on its machine (and tell by the error whether it exists).
By default such configs get 400 naming the field; `--client-files yes` allows
them for a trusted local daemon. Shipped courses and inline bumps always work."""
import requests

from conftest import Daemon, is_problem

PROFILE = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
           "terrain": {"kind": "profile"}}


def create(d, doc):
    return requests.post(d.url + "/v1/sessions", json=doc)


def pointers(p):
    return [e["pointer"] for e in p.get("errors", [])]


def test_client_named_files_are_refused_by_default(daemon, tmp_path):
    csv = tmp_path / "ground.csv"
    csv.write_text("distance_m,height_m\n0,0\n100,1\n")
    doc = {**PROFILE, "terrain": {"kind": "profile", "profile_csv": str(csv)}}
    p = is_problem(create(daemon, doc), 400)
    assert pointers(p) == ["/terrain/profile_csv"], p
    assert "--client-files" in p["errors"][0]["message"]
    # a course name that would leave the course directory
    doc = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
           "terrain": {"kind": "bumps", "course": "../../../../etc/hostname"}}
    p = is_problem(create(daemon, doc), 400)
    assert pointers(p) == ["/terrain/course"], p
    # the answer names the shipped courses (session-29 review: a user typed one blind)
    assert "(shipped: 'apg4-synth')" in p["errors"][0]["message"], p
    # a course directory of the client's (read from disk since session 20, even
    # for a shipped course name)
    doc = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
           "terrain": {"kind": "bumps", "course": "apg4-synth", "course_dir": str(tmp_path)}}
    p = is_problem(create(daemon, doc), 400)
    assert pointers(p) == ["/terrain/course_dir"], p
    assert "--client-files" in p["errors"][0]["message"]
    # what a client may always use: the shipped course and inline bumps
    assert create(daemon, {"preset": "bump-prescribed-static",
                           "run": {"duration": 0.02}}).status_code == 201
    inline = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
              "terrain": {"kind": "bumps", "bump_start": [20.0], "bump_height": [0.1],
                          "bump_length": [2.0]}}
    assert create(daemon, inline).status_code == 201


def test_schema_lists_the_shipped_courses(daemon):
    """The dashboard's course field was free text (dash4 review): a user typed a
    name blind until the 400 listed the shipped ones. /v1/schema gives them as
    /terrain/course's examples (not an enum: --client-files yes reads others),
    the same names the 400 lists, and each runs."""
    course = requests.get(daemon.url + "/v1/schema").json()[
        "properties"]["terrain"]["properties"]["course"]
    assert "enum" not in course, course
    assert course["examples"] == ["apg4-synth"], course
    doc = {"preset": "bump-prescribed-static", "run": {"duration": 0.02},
           "terrain": {"kind": "bumps", "course": "no-such-course"}}
    msg = is_problem(create(daemon, doc), 400)["errors"][0]["message"]
    listed = ", ".join(f"'{n}'" for n in course["examples"])
    assert f"(shipped: {listed})" in msg, msg
    for name in course["examples"]:
        doc["terrain"]["course"] = name
        r = create(daemon, doc)
        assert r.status_code == 201, r.text


def test_client_files_yes_reads_the_profile(tmp_path):
    csv = tmp_path / "ground.csv"
    csv.write_text("distance_m,height_m\n0,0\n100,1\n")
    d = Daemon("--client-files", "yes")
    try:
        doc = {**PROFILE, "terrain": {"kind": "profile", "profile_csv": str(csv)}}
        r = create(d, doc)
        assert r.status_code == 201, r.text
    finally:
        d.stop()

