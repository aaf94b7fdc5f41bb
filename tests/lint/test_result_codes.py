"""The brief's rule "every function that can fail returns an error code ...;
callers handle it" is enforced by the compiler: each public function that
returns a ts_rc result code is declared TS_MUST_CHECK (sim/errors.h:
warn_unused_result, an error under -Werror), so a call that drops the code
does not build. Marking them in session 33 found 22 calls that dropped one
(samples whose evaluation could fail unseen, the coupled run's observation
and reports, status writes to the store). This test keeps the rule for
functions added later: a header's ts_rc function without the mark fails.

Exempt are the error makers, whose result is the code they have just set
(written `return maker(...)`, or called for the record alone)."""
import glob
import os
import re

from conftest import REPO

ERROR_MAKERS = {
    "ts_err_set", "tsa_root_err", "tsa_json_parse_err", "tsd_err_store",
    "tsd_session_err_deleted", "tsd_err_shutdown", "vm_rhs_failed",
    "ts_engine_rhs_failed", "ts_powertrain_rhs_failed",
}

DECL = re.compile(r"^(TS_MUST_CHECK\s+)?ts_rc\s+([a-z_0-9]+)\(", re.M)


def declarations():
    for layer in ("sim", "api", "render", "server", "cli"):
        for h in sorted(glob.glob(os.path.join(REPO, layer, "*.h"))):
            for m in DECL.finditer(open(h).read()):
                yield os.path.relpath(h, REPO), m.group(2), bool(m.group(1))


def test_every_public_result_code_must_be_checked():
    decls = list(declarations())
    assert len(decls) > 80, "the header scan found too few ts_rc functions: %d" % len(decls)
    unmarked = [f"{h}: {name}" for h, name, marked in decls
                if not marked and name not in ERROR_MAKERS]
    assert not unmarked, "ts_rc functions without TS_MUST_CHECK:\n" + "\n".join(unmarked)


def test_error_makers_are_declared_and_unmarked():
    """The exemption list names functions that exist, as makers (a listed
    name that became an ordinary fallible call must lose its exemption)."""
    found = {name: marked for _, name, marked in declarations()}
    missing = sorted(ERROR_MAKERS - found.keys())
    assert not missing, f"exempted but not declared in a header: {missing}"
    marked = sorted(n for n in ERROR_MAKERS if found[n])
    assert not marked, f"exempted makers declared TS_MUST_CHECK: {marked}"
