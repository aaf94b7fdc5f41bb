"""POST /v1/modes (issue 7): the track eigenanalysis of `tanksim modes` over
HTTP. The daemon and the CLI build the document with the same function
(api/modes_json.c), so the numbers must agree (the CLI prints 6 significant
digits, the daemon 12). Config errors are problem+json naming the field; the
physics checks themselves (Fig. 5, Table 1) live in tests/cli/test_modes.py."""
import json
import subprocess

import pytest
import requests

from conftest import TANKSIM, is_problem


def close(a, b):
    if isinstance(a, dict):
        assert set(a) == set(b)
        for k in a:
            close(a[k], b[k])
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            close(x, y)
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-5, abs=1e-9)
    else:
        assert a == b


@pytest.mark.parametrize("preset", ["m1", "table1-span"])
def test_modes_over_http_equal_the_cli(daemon, preset):
    r = requests.post(daemon.url + "/v1/modes", json={"preset": preset})
    assert r.status_code == 200, r.text
    got = r.json()
    cli = subprocess.run([TANKSIM, "modes", "--preset", preset], capture_output=True, text=True,
                         timeout=120)
    assert cli.returncode == 0, cli.stderr
    close(got, json.loads(cli.stdout))
    assert got["circuit"]["frequencies_hz"] == sorted(got["circuit"]["frequencies_hz"])


def test_modes_config_errors_name_the_field(daemon):
    is_problem(requests.post(daemon.url + "/v1/modes",
                             json={"preset": "m1", "track": {"tension": -5}}), 400,
               "/track/tension")
    is_problem(requests.post(daemon.url + "/v1/modes", json={"preset": "nope"}), 400, "/preset")
    is_problem(requests.post(daemon.url + "/v1/modes", data="{"), 400)
