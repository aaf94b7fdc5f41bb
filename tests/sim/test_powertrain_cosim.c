/*
 * test_powertrain_cosim.c — the crank-angle engine co-simulated with the
 * driveline (powertrain.h: ts_powertrain_engine_advance per macro step
 * /driveline/engine_macro_step, the driveline's RK4 sub-steps with the engine
 * held) against the monolithic path it replaces (every state, engine included,
 * in one RK4 at the engine's crank-angle step; engine_macro_step = 0), on
 * short runs: the point-mass launch (scenario_pointmass.c) and the powertrain
 * on its own integrator with a prescribed sprocket speed (ts_powertrain_sim,
 * the co-simulation leader's path).
 */
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/powertrain.h"
#include "sim/tanksim.h"

static void load(ts_config *c, double macro_step, double duration)
{
    ts_err err;
    json_t *doc = json_pack("{s:s,s:{s:s},s:{s:f},s:{s:f}}", "preset",
                            "accel-pointmass-conventional", "engine", "fidelity", "crank_angle",
                            "driveline", "engine_macro_step", macro_step, "run", "duration",
                            duration);
    if (tsa_config_load(doc, c, NULL, NULL, &err) != TS_OK) fail_msg("config: %s", err.msg);
    json_decref(doc);
}

typedef struct {
    ts_model *m;
    double *rows;
    long n;
    int nc;
} run;

static int keep(void *ud, long i, double t, const double *v, int n)
{
    (void)t;
    run *r = ud;
    if (i >= r->n) return 1;
    memcpy(r->rows + (size_t)i * (size_t)n, v, (size_t)n * sizeof *v);
    return 0;
}

static run run_config(const ts_config *c, double duration)
{
    ts_err err;
    run r = {0};
    r.m = ts_model_make(c, &err);
    if (!r.m) fail_msg("model: %s", err.msg);
    ts_data *d = ts_data_make(r.m, &err);
    assert_non_null(d);
    r.nc = ts_model_nchannel(r.m);
    r.n = (long)(duration / ts_model_sample_period(r.m) + 1.5);
    r.rows = calloc((size_t)r.n * (size_t)r.nc, sizeof *r.rows);
    assert_non_null(r.rows);
    assert_int_equal(ts_reset(r.m, d, &err), TS_OK);
    keep(&r, 0, 0, ts_latest(d), r.nc);
    if (ts_advance(r.m, d, duration, keep, &r, &err) != TS_OK) fail_msg("run: %s", err.msg);
    ts_data_free(d);
    return r;
}

static run run_pointmass(double macro_step, double duration)
{
    ts_config c;
    load(&c, macro_step, duration);
    return run_config(&c, duration);
}

static double at(const run *r, const char *ch, double t)
{
    int k = ts_model_channel_index(r->m, ch);
    assert_true(k >= 0);
    long i = (long)(t / ts_model_sample_period(r->m) + 0.5);
    assert_true(i >= 0 && i < r->n);
    return r->rows[i * r->nc + k];
}

/* EVIDENCE: numerical self-consistency (no paper figure): the co-simulated
 * engine (1 ms macro steps) against the monolithic RK4 of all states at the
 * 0.5-deg crank step over the first 1.2 s of the full-rack launch (converter
 * near stall, engine hesitation of Fig. 19): vehicle speed within 0.5 %,
 * engine and turbine speeds within 1 %, boost within 2 %. Measured: 0.4 % in
 * speed at 0.3 s, 0.25 % at 1.2 s, and the same with a 4x shorter macro step:
 * the residual is the engine integrators' difference (multirate BS3 vs RK4,
 * engine.h: 0.3 % in torque), not the exchange; the exchange error itself
 * (first order in the macro step) is checked against a 0.25-ms macro step:
 * within 0.1 %. The path is also what makes Table 2 fast (bench_pointmass:
 * Table 2 figures within 0.2 % of the monolithic path). */
static void pointmass_launch_matches_monolithic(void **state)
{
    (void)state;
    const double T = 1.2;
    run a = run_pointmass(0.0, T), b = run_pointmass(1e-3, T), q = run_pointmass(2.5e-4, T);
    for (double t = 0.3; t <= T + 1e-9; t += 0.3) {
        print_message("      t %.1f s: engine %.2f / %.2f rad/s, turbine %.2f / %.2f, v %.4f / %.4f "
                      "m/s, boost %.0f / %.0f Pa\n",
                      t, at(&a, "engine.speed", t), at(&b, "engine.speed", t),
                      at(&a, "tc.turbine.speed", t), at(&b, "tc.turbine.speed", t),
                      at(&a, "vehicle.speed", t), at(&b, "vehicle.speed", t),
                      at(&a, "intake.pressure", t), at(&b, "intake.pressure", t));
        assert_close(at(&b, "engine.speed", t), at(&a, "engine.speed", t), 0.01, 0);
        assert_close(at(&b, "tc.turbine.speed", t), at(&a, "tc.turbine.speed", t), 0.01, 0.5);
        assert_close(at(&b, "vehicle.speed", t), at(&a, "vehicle.speed", t), 0.005, 1e-3);
        assert_close(at(&b, "intake.pressure", t), at(&a, "intake.pressure", t), 0.02, 0);
        /* the exchange error proper: a 4x shorter macro step changes little */
        assert_close(at(&b, "engine.speed", t), at(&q, "engine.speed", t), 1e-3, 0);
        assert_close(at(&b, "vehicle.speed", t), at(&q, "vehicle.speed", t), 1e-3, 1e-4);
    }
    /* the engine observations of a sample come from the full engine model */
    assert_true(at(&b, "engine.torque", T) > 0);
    assert_true(at(&b, "engine.fuel_flow", T) > 0);
    free(a.rows);
    free(b.rows);
    free(q.rows);
    ts_model_free(a.m);
    ts_model_free(b.m);
    ts_model_free(q.m);
}

/* First sample time with transmission.gear above 1 (INFINITY: none). */
static double first_shift(const run *r)
{
    int k = ts_model_channel_index(r->m, "transmission.gear");
    assert_true(k >= 0);
    for (long i = 0; i < r->n; i++)
        if (r->rows[i * r->nc + k] > 1.0) return i * ts_model_sample_period(r->m);
    return INFINITY;
}

/* EVIDENCE: shift logic [P III.B.2, transmission.h]: the upshift starts when
 * the engine speed crosses shift_speed, on both crank-angle paths: the
 * monolithic RK4 (engine_macro_step = 0; the shift state machine at every
 * step end) starts the 1-2 shift within two samples of the co-simulated path
 * (their engine speeds agree to 0.1 % before it, above). Shift speed lowered
 * to 107 rad/s (downshifts off) so that the launch reaches it at ~0.9 s of a
 * 1.2-s run. Consistency check, nothing calibrated. Mutation pass ctl: the
 * monolithic path without its state machine (never leaving 1st gear) passed
 * every test, whose runs on that path end before the first shift. */
static void both_crank_angle_paths_upshift(void **state)
{
    (void)state;
    const double T = 1.2;
    double t_shift[2];
    for (int k = 0; k < 2; k++) {
        ts_config c;
        load(&c, k ? 1e-3 : 0.0, T);
        c.driveline.shift_speed = 107.0;
        c.driveline.downshift_speed = 0.0;
        run r = run_config(&c, T);
        t_shift[k] = first_shift(&r);
        free(r.rows);
        ts_model_free(r.m);
    }
    print_message("      1-2 shift starts: monolithic %.3f s, co-simulated %.3f s\n", t_shift[0],
                  t_shift[1]);
    assert_true(t_shift[1] < T);
    assert_close(t_shift[0], t_shift[1], 0, 0.025);
}

static double sprocket_speed(void *ud, double t)
{
    (void)ud;
    return 5.0 + 10.0 * t; /* rad/s: the vehicle pulling away */
}

/* EVIDENCE: numerical self-consistency: ts_powertrain_sim (the coupled run's
 * leader) with a prescribed sprocket-speed ramp, co-simulated engine against
 * the monolithic RK4, 0.6 s in 0.1-s calls: engine and turbine speed within
 * 1 %, sprocket torque within 2.5 % (measured 2.0 % at 0.1 s, 0.3 % from
 * 0.4 s: near the coupling point the converter's torque moves ~10x the
 * engine speed's relative difference, 0.1 %, through the K factor's slope in
 * speed ratio); the co-simulated path reports itself
 * (macro step, work) and the monolithic one does not. */
static void sim_ramp_matches_monolithic(void **state)
{
    (void)state;
    ts_config ca, cb;
    ts_err err;
    load(&ca, 0.0, 1.0);
    load(&cb, 1e-3, 1.0);
    ts_powertrain *pa = ts_powertrain_make(&ca, &err), *pb = ts_powertrain_make(&cb, &err);
    assert_non_null(pa);
    assert_non_null(pb);
    assert_true(ts_powertrain_macro_step(pa) == 0 && ts_powertrain_work_size(pa) == 0);
    assert_close(ts_powertrain_macro_step(pb), 1e-3, 0, 0);
    assert_true(ts_powertrain_work_size(pb) > 0);
    ts_powertrain_sim *sa = ts_powertrain_sim_make(pa, 1e-6, 1e-6, 0.0, &err);
    ts_powertrain_sim *sb = ts_powertrain_sim_make(pb, 1e-6, 1e-6, 0.0, &err);
    assert_non_null(sa);
    assert_non_null(sb);
    assert_int_equal(ts_powertrain_sim_reset(sa, 0.0, 5.0, &err), TS_OK);
    assert_int_equal(ts_powertrain_sim_reset(sb, 0.0, 5.0, &err), TS_OK);
    for (int k = 1; k <= 6; k++) {
        ts_powertrain_out oa, ob;
        double t = 0.1 * k;
        assert_int_equal(ts_powertrain_sim_advance(sa, t, sprocket_speed, NULL, 1.0, &oa, &err),
                         TS_OK);
        assert_int_equal(ts_powertrain_sim_advance(sb, t, sprocket_speed, NULL, 1.0, &ob, &err),
                         TS_OK);
        print_message("      t %.1f s: engine %.2f / %.2f rad/s, turbine %.2f / %.2f, sprocket "
                      "%.0f / %.0f N*m\n",
                      t, oa.engine_speed, ob.engine_speed, oa.turbine_speed, ob.turbine_speed,
                      oa.sprocket_torque, ob.sprocket_torque);
        assert_close(ts_powertrain_sim_time(sb), t, 1e-12, 1e-12);
        assert_close(ob.engine_speed, oa.engine_speed, 0.01, 0);
        assert_close(ob.turbine_speed, oa.turbine_speed, 0.01, 0.5);
        assert_close(ob.sprocket_torque, oa.sprocket_torque, 0.025, 0);
        assert_true(ob.engine_torque > 0 && ob.boost > 0);
    }
    ts_powertrain_sim_free(sa);
    ts_powertrain_sim_free(sb);
    ts_powertrain_free(pa);
    ts_powertrain_free(pb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pointmass_launch_matches_monolithic),
        cmocka_unit_test(both_crank_angle_paths_upshift),
        cmocka_unit_test(sim_ramp_matches_monolithic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
