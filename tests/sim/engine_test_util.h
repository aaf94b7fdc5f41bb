/*
 * engine_test_util.h — shared set-up for the engine tests: the default config
 * (sim/data defaults through the api loader) and a steady full-load state on
 * the dynamometer found the way `tanksim engine-map` finds it.
 */
#ifndef TS_ENGINE_TEST_UTIL_H
#define TS_ENGINE_TEST_UTIL_H

#include <stdlib.h>

#include "api/config_json.h"
#include "sim/engine.h"
#include "sim/tanksim.h"

#define ET_PI 3.14159265358979323846
#define ET_RPM(n) ((n) * ET_PI / 30.0)
#define ET_HP 745.7 /* W per hp */

static inline ts_config et_defaults(void)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s}}", "run", "kind", "engine_dyno");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

static inline ts_engine_inputs et_full_load(void)
{
    ts_engine_inputs in = {.rack = 1.0, .fuel_per_cycle = -1.0, .load_torque = 0.0,
                           .p_amb = 101325.0, .T_amb = 298.15, .hold_speed = 1};
    return in;
}

/* The engine of the default config with this variant and fidelity (caller frees). */
static inline ts_engine *et_make(int variant, int fidelity)
{
    ts_config c = et_defaults();
    c.engine.variant = variant;
    c.engine.fidelity = fidelity;
    ts_err err;
    ts_engine *e = ts_engine_make(&c, &err);
    assert_non_null(e);
    return e;
}

/* An engine with a state x initialised at speed w (rad/s) in the standard
 * ambient of et_full_load, and a derivative buffer xd of the same length;
 * et_bench_free frees the three. */
typedef struct {
    ts_engine *e;
    double *x, *xd;
} et_bench;

static inline et_bench et_bench_at(int variant, int fidelity, double w)
{
    et_bench b = {et_make(variant, fidelity), NULL, NULL};
    size_t nx = (size_t)ts_engine_nstate(b.e);
    b.x = calloc(nx, sizeof *b.x);
    b.xd = calloc(nx, sizeof *b.xd);
    assert_non_null(b.x);
    assert_non_null(b.xd);
    ts_engine_inputs in = et_full_load();
    ts_engine_init_state(b.e, w, in.p_amb, in.T_amb, b.x);
    return b;
}

static inline void et_bench_free(et_bench *b)
{
    free(b->x);
    free(b->xd);
    ts_engine_free(b->e);
}

/* Steady full-load state at rpm for variant/fidelity; x allocated (caller frees). */
static inline double *et_steady(int variant, int fidelity, double rpm, ts_engine **e_out,
                                ts_engine_cycle *cyc)
{
    ts_err err;
    ts_engine *e = et_make(variant, fidelity);
    double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
    assert_non_null(x);
    ts_engine_inputs in = et_full_load();
    ts_engine_init_state(e, ET_RPM(rpm), in.p_amb, in.T_amb, x);
    ts_engine_set_turbo_speed(e, x, 8000.0);
    assert_int_equal(ts_engine_steady(e, x, ET_RPM(rpm), &in, 80, 5e-4, cyc, &err), TS_OK);
    *e_out = e;
    return x;
}

#endif
