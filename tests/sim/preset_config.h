/*
 * preset_config.h — test helpers: a shipped preset's configuration, optionally
 * with another track fidelity, through the same loader the CLI and the daemon
 * use (api/config_json.c); the multibody vehicle of a configuration, also
 * at its static equilibrium with one right-hand side evaluated there; and a
 * run of a configuration from its reset state
 * with every sampled row kept, as `tanksim run` keeps them. Shared by the
 * vehicle, coupled, point-mass and api tests. Test code only; a preset that
 * does not load or a run that fails fails the test.
 */
#ifndef TS_TEST_PRESET_CONFIG_H
#define TS_TEST_PRESET_CONFIG_H

#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/tanksim.h"
#include "sim/vehicle_model.h"

/* The configuration of preset; track_fidelity NULL keeps the preset's. */
static inline ts_config test_preset_config(const char *preset, const char *track_fidelity)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:s}", "preset", preset);
    if (track_fidelity)
        json_object_set_new(doc, "track", json_pack("{s:s}", "fidelity", track_fidelity));
    if (tsa_config_load(doc, &c, NULL, NULL, &err) != TS_OK)
        fail_msg("preset %s: %s %s", preset, err.pointer, err.msg);
    json_decref(doc);
    return c;
}

/* The multibody vehicle of c (vm_make, static equilibrium solved), which the
 * caller frees (vm_free). */
static inline vm *test_vm(const ts_config *c)
{
    ts_err err;
    vm *v = vm_make(c, &err);
    if (!v) fail_msg("vm_make: %s %s", err.pointer, err.msg);
    return v;
}

/* The vehicle of a configuration at its static equilibrium: the model, a
 * workspace, the state y (a copy of vm_equilibrium) and its rate yd, and dg,
 * the diagnostics of vm_rhs there. The caller may change y and evaluate again;
 * test_rest_free releases everything. */
typedef struct test_rest {
    vm *v;
    vm_work *w;
    int nq, ny;
    double *y, *yd;
    vm_diag dg;
} test_rest;

static inline test_rest test_rest_make(const ts_config *c)
{
    test_rest r = {.v = test_vm(c)};
    r.w = vm_work_make(r.v);
    r.nq = vm_nq(r.v);
    r.ny = vm_ny(r.v);
    r.y = malloc(sizeof(double) * (size_t)r.ny);
    r.yd = malloc(sizeof(double) * (size_t)r.ny);
    assert_true(r.w && r.y && r.yd);
    memcpy(r.y, vm_equilibrium(r.v), sizeof(double) * (size_t)r.ny);
    assert_int_equal(vm_rhs(r.v, r.w, 0, r.y, r.yd, &r.dg), 0);
    return r;
}

static inline void test_rest_free(test_rest *r)
{
    free(r->y);
    free(r->yd);
    vm_work_free(r->w);
    vm_free(r->v);
}

/* The model of c, run from reset for c.run.duration: rows r (row 0 at the
 * reset state, then every sample) in *r, which the caller frees
 * (ts_rows_free), as the model (ts_model_free). */
static inline ts_model *test_run_rows(const ts_config *c, ts_rows *r)
{
    ts_err err;
    ts_model *m = ts_model_make(c, &err);
    if (!m) fail_msg("model: %s %s", err.pointer, err.msg);
    ts_data *d = ts_data_make(m, &err);
    assert_non_null(d);
    *r = (ts_rows){0};
    assert_int_equal(ts_reset(m, d, &err), TS_OK);
    assert_int_equal(ts_rows_append(r, 0, 0, ts_latest(d), ts_model_nchannel(m)), 0);
    if (ts_advance(m, d, c->run.duration, ts_rows_append, r, &err) != TS_OK)
        fail_msg("run: %s", err.msg);
    ts_data_free(d);
    return m;
}

#endif
