/*
 * test_engine_fidelity.c — the map and mean-value fidelities, the engine as an
 * ODE integrated by a caller's integrator (CVODE through solver.h), and the
 * engine_dyno scenario through the generic model interface.
 */
#include "test_util.h"

#include <string.h>

#include "engine_test_util.h"
#include "sim/engine_impl.h"
#include "sim/solver.h"

/* EVIDENCE: the map fidelity's definition (engine_map.c): after a rack step
 * 0 -> 1 at held speed the boost-lag state follows z = 1 - exp(-t/tau) with
 * tau = /engine/spool_lag at this speed (1600 rpm is a spool speed: the
 * table's value), and the brake torque is min(1, a)(T_fl + T_f) - T_f with
 * a = pb_torque(speed, boost / map_boost), boost = p_amb + z (map_boost -
 * p_amb) (Willans line). Closed form, RK4 at 0.5 ms, tolerance 1e-6. The
 * part-boost table itself is derived from crank-angle spool-ups (not
 * calibrated); at table nodes the interpolation returns the node value. */
static void map_boost_lag_closed_form(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MAP);
    double x[3], work[15], xd[3];
    double w = c.engine.map_speed[8]; /* 1600 rpm, the 9th map speed */
    int is = -1;
    for (int i = 0; i < c.engine.spool_speed_n; i++)
        if (fabs(c.engine.spool_speed[i] - w) < 1e-2) is = i;
    assert_true(is >= 0);
    ts_engine_init_state(e, w, 101325, 298, x);
    ts_engine_inputs in = et_full_load();
    ts_err err;
    double tau = c.engine.spool_lag[is];
    assert_close(en_spool_lag(e, w), tau, 1e-4, 0);
    int nr = c.engine.spool_ratio_n;
    for (int j = 0; j < nr; j++) /* node values (speed node to 1e-3 rad/s) */
        assert_close(en_pb_interp(e, c.engine.map[0].pb_torque, c.engine.spool_speed[is],
                                  c.engine.spool_ratio[j]),
                     c.engine.map[0].pb_torque[is * nr + j], 1e-12, 0);
    assert_int_equal(ts_engine_advance(e, x, 0, tau, &in, work, &err), TS_OK);
    double z = 1 - exp(-1.0);
    ts_engine_outputs o;
    assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
    double t_fl = c.engine.map[0].torque[8], p_fl = c.engine.map[0].boost[8];
    double tf = o.friction_torque;
    assert_close(x[2], z, 1e-4, 0); /* tau interpolated at w, not exactly the node */
    double boost = in.p_amb + x[2] * (p_fl - in.p_amb);
    double a = en_pb_interp(e, c.engine.map[0].pb_torque, w, boost / p_fl);
    assert_close(o.boost, boost, 1e-12, 0);
    assert_close(o.brake_torque, fmin(1.0, a) * (t_fl + tf) - tf, 1e-9, 0);
    assert_true(a > 0.3 && a < 1.0); /* part boost: less than full-load torque */
    assert_int_equal(ts_engine_advance(e, x, 0, 20 * tau, &in, work, &err), TS_OK);
    assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
    a = en_pb_interp(e, c.engine.map[0].pb_torque, w, o.boost / p_fl);
    assert_close(o.brake_torque, fmin(1.0, a) * (t_fl + tf) - tf, 1e-9, 0);
    assert_close(o.brake_torque, t_fl, 0.01, 0); /* spool-up end ~ full-load sweep */
    ts_engine_free(e);
}

/* EVIDENCE: the map fidelity's air flow (engine_map.c): Eq. 14 read backwards
 * at full rack (the full-load fuel at this speed times (A/F)_s / phi_tgt,
 * Eq. 13) scaled by boost / map_boost (speed-density: at a fixed speed,
 * volumetric efficiency and charge temperature the trapped air mass is
 * proportional to the manifold pressure). At a partly built-up boost (z =
 * 0.4, and 0.1) air_flow phi_tgt / (A/F)_s = fuel_fl boost / map_boost, and
 * at z = 1 the full-load air flow itself. A commanded fuel per cycle burns
 * that fuel: half the full-load one gives half the fuel flow and half the
 * full-load indicated torque (Willans line). 1600 rpm is the 9th map speed
 * (a table node). Closed form, tolerance 1e-12. */
static void map_air_flow_follows_boost(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MAP);
    ts_fuel_law f = ts_fuel_law_from_config(&c.engine);
    double w = c.engine.map_speed[8];
    double fuel_fl = c.engine.map[0].fuel[8], p_fl = c.engine.map[0].boost[8];
    double phi = ts_fuel_phi_target(&f, w);
    ts_engine_inputs in = et_full_load();
    const double zs[3] = {0.4, 0.1, 1.0};
    for (int k = 0; k < 3; k++) {
        double x[3] = {w, 0, zs[k]}, xd[3];
        ts_engine_outputs o;
        assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
        double boost = in.p_amb + zs[k] * (p_fl - in.p_amb);
        assert_close(o.boost, boost, 1e-12, 0);
        assert_close(o.air_flow * phi / c.engine.afr_stoich, fuel_fl * boost / p_fl, 1e-12, 0);
    }
    /* a commanded fuel per cycle (the library's fuel input, beside the rack)
     * at full boost: half the full-load fuel per cycle burns half the
     * full-load fuel flow, and the Willans line gives half the full-load
     * indicated torque (engine_map.c) */
    double x[3] = {w, 0, 1.0}, xd[3];
    double cycles_per_s = w / (4 * ET_PI); /* four-stroke: one cycle per 4 pi rad */
    in.fuel_per_cycle = 0.5 * fuel_fl / (12 * cycles_per_s);
    ts_engine_outputs o;
    assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
    assert_close(o.fuel_flow, 0.5 * fuel_fl, 1e-12, 0);
    assert_close(o.fuel_per_cycle, in.fuel_per_cycle, 1e-12, 0);
    assert_close(o.indicated_torque, 0.5 * (c.engine.map[0].torque[8] + o.friction_torque), 1e-12,
                 0);
    ts_engine_free(e);
}

/* EVIDENCE: engine_impl.h: the part-boost tables are interpolated bilinearly
 * and "clamped at the edges" (engine_mean.c: en_pb_at): outside the spool
 * speeds (800-2200 rpm; the 650-rpm idle lies below) the value is the edge
 * speed row's, and outside the spool ratios (0.25-1.0) the edge ratio
 * node's; no extrapolation. Checked on the map's pb_torque and the
 * mean-value engine's pb_eta_i and pb_q_wall (conventional variant), whose edge rows and nodes
 * differ from their neighbours (so an extrapolation would show). Exact (the
 * same operations on the same nodes). */
static void part_boost_tables_clamp_at_the_edges(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MAP);
    const double *ws = c.engine.spool_speed, *rs = c.engine.spool_ratio;
    int ns = c.engine.spool_speed_n, nr = c.engine.spool_ratio_n;
    assert_true(ns >= 2 && nr >= 2);
    assert_true(ET_RPM(650) < ws[0]);
    const ts_engine_map_table *mt = &c.engine.map[0];
    const double *tabs[3] = {mt->pb_torque, mt->pb_eta_i, mt->pb_q_wall};
    for (int k = 0; k < 3; k++) {
        const double *y = tabs[k];
        /* speed: below the first and above the last spool speed */
        for (int j = 0; j < nr; j++) {
            double r = rs[j];
            double lo = en_pb_interp(e, y, ws[0], r), hi = en_pb_interp(e, y, ws[ns - 1], r);
            assert_true(en_pb_interp(e, y, 0.8 * ws[0], r) == lo);
            assert_true(en_pb_interp(e, y, ET_RPM(650), r) == lo);
            assert_true(en_pb_interp(e, y, 1.2 * ws[ns - 1], r) == hi);
        }
        /* ratio: below the first and above the last spool ratio */
        for (int i = 0; i < ns; i++) {
            double lo = en_pb_interp(e, y, ws[i], rs[0]),
                   hi = en_pb_interp(e, y, ws[i], rs[nr - 1]);
            assert_true(en_pb_interp(e, y, ws[i], 0.4 * rs[0]) == lo);
            assert_true(en_pb_interp(e, y, ws[i], 1.3 * rs[nr - 1]) == hi);
        }
    }
    /* the edges differ from their neighbours somewhere (else the test is blind) */
    const double *y = c.engine.map[0].pb_torque;
    int dw = 0, dr = 0;
    for (int j = 0; j < nr; j++)
        dw += y[j] != y[nr + j];
    for (int i = 0; i < ns; i++)
        dr += y[i * nr + nr - 1] != y[i * nr + nr - 2];
    assert_true(dw > 0 && dr > 0);
    ts_engine_free(e);
}

/* EVIDENCE: crankshaft dynamics J dw/dt = T_brake(w) - T_load (Newton): with a
 * constant load of 5400 N*m at full rack the map engine settles where its
 * full-load torque equals the load (on the falling side above peak torque:
 * ~1850 rpm; full-load torque = the table's times the spool-up factor at full
 * boost, engine_map.c, its crossing found by bisection on the right-hand
 * side at held speed); tolerance 0.5 %. (5000 N*m until issue 5: the rated
 * torque is now 5036 N*m, so 5000 no longer crosses the table.) */
static void map_crank_dynamics_settle_on_load(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MAP);
    double x[3], work[15];
    ts_engine_init_state(e, ET_RPM(1700), 101325, 298, x);
    x[2] = 1.0;
    ts_engine_inputs in = et_full_load();
    in.hold_speed = 0;
    in.load_torque = 5400;
    ts_err err;
    assert_int_equal(ts_engine_advance(e, x, 0, 20, &in, work, &err), TS_OK);
    /* full-load brake torque at z = 1 (the spool-ups' factor at ratio 1,
     * engine_map.c); bisection on the falling side 1700-2100 rpm */
    double lo = ET_RPM(1700), hi = ET_RPM(2100), want = NAN;
    for (int k = 0; k < 60; k++) {
        double mid = 0.5 * (lo + hi), xs[3] = {mid, 0, 1.0}, xd[3];
        ts_engine_outputs o;
        ts_engine_inputs held = et_full_load();
        assert_int_equal(ts_engine_rhs(e, 0, xs, &held, xd, &o), 0);
        if (o.brake_torque > 5400) lo = mid; else hi = mid;
        want = 0.5 * (lo + hi);
    }
    assert_close(x[0], want, 0.005, 0);
    ts_engine_free(e);
}

/* EVIDENCE: slider-crank kinematics (Heywood 1988, Sec. 2.2; Taylor 1985,
 * Vol. 2 Ch. 8): a reciprocating mass m on crank radius a with rod l (lambda =
 * a/l) has the crank-referred inertia m (dx/dtheta)^2, whose mean over a
 * revolution is m a^2 (1/2 + lambda^2/8) to O(lambda^4) (the exact mean is
 * 6.3e-4 above it at lambda 0.265). Twelve cylinders: the cycle-averaged
 * fidelities' inertia is /engine/inertia + 12 m a^2 (1/2 + lambda^2/8)
 * within 1e-3 (0.2317 kg*m^2 here), and their crankshaft equation uses it:
 * J dw/dt = T_brake - T_load (the mean-value and map engines used the bare
 * 7.0 kg*m^2 until session 21, 3.3 % light). Closed form. */
static void cycle_mean_inertia_holds_the_reciprocating_parts(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    double a = c.engine.stroke / 2, lam = a / c.engine.rod_length;
    double j_recip = 12 * c.engine.recip_mass * a * a * (0.5 + lam * lam / 8);
    const int fid[2] = {TS_ENGINE_MEAN_VALUE, TS_ENGINE_MAP};
    for (int k = 0; k < 2; k++) {
        ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, fid[k]);
        double j = ts_engine_mean_inertia(e);
        assert_close(j - c.engine.inertia, j_recip, 1e-3, 0);
        int n = ts_engine_nstate(e);
        double x[64], xd[64];
        assert_true(n <= 64);
        ts_engine_init_state(e, ET_RPM(1600), 101325, 298, x);
        ts_engine_inputs in = et_full_load();
        in.hold_speed = 0;
        in.load_torque = 1000;
        in.load_inertia = 1.5;
        ts_engine_outputs o;
        assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &o), 0);
        assert_close(xd[TS_ENGINE_X_SPEED] * (j + 1.5), o.brake_torque - 1000, 1e-12, 1e-9);
        ts_engine_free(e);
    }
}

/* EVIDENCE: the map engine at full boost (z = 1) gives the crank-angle
 * full-load sweep's torque at EVERY map speed, 800-2100 rpm, within 3 % (the
 * spool-ups' factors at ratio 1 carry the launch's cold-wall loss: brake
 * torque 0.972 of the sweep's at 2100 rpm, 0.986-1.0 elsewhere). Review,
 * session 20: at 1000 rpm the spool-up stays on the low-boost branch, and the
 * unreached high-ratio bins held its factor 0.49, so the map engine gave 2755
 * N*m at 2.89 bar where the sweep has 6032 (the 1-2 upshift lands there); the
 * test checked 1600 rpm only. Derived tables, nothing calibrated. */
static void map_full_boost_matches_the_sweep_at_every_speed(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MAP);
    double worst = 1, worst_rpm = 0;
    for (int i = 0; i < c.engine.map_speed_n; i++) {
        double xs[3] = {c.engine.map_speed[i], 0, 1.0}, xd[3];
        ts_engine_outputs o;
        ts_engine_inputs held = et_full_load();
        assert_int_equal(ts_engine_rhs(e, 0, xs, &held, xd, &o), 0);
        double ratio = o.brake_torque / c.engine.map[0].torque[i];
        if (fabs(ratio - 1) > fabs(worst - 1)) worst = ratio, worst_rpm = c.engine.map_speed[i];
        assert_close(o.brake_torque, c.engine.map[0].torque[i], 0.03, 0);
    }
    print_message("      map / sweep torque at full boost: worst %.4f at %.0f rpm\n", worst,
                  worst_rpm * 30 / ET_PI);
    ts_engine_free(e);
}

/* EVIDENCE: cross-fidelity agreement (model.md: "faster fidelities from the
 * same physics"): the mean-value engine (cycle-averaged cylinders from the
 * crank-angle sweep's eta_v, eta_i, q_wall, with its OWN turbo, intercooler
 * and manifold solution) reproduces the crank-angle full-load torque (the map
 * table) within 3 % at 2100 and 1500 rpm, and the boost within 5 %. */
static void mean_value_matches_crank_angle_sweep(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    const double rpm[2] = {2100, 1500};
    const int idx[2] = {13, 7};
    for (int k = 0; k < 2; k++) {
        ts_engine *e;
        ts_engine_cycle cyc;
        double *x = et_steady(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE, rpm[k], &e, &cyc);
        print_message("      %4.0f rpm: mean-value %.0f N*m, %.2f bar; crank-angle %.0f N*m, %.2f bar\n",
                      rpm[k], cyc.mean.brake_torque, cyc.mean.boost / 1e5,
                      c.engine.map[0].torque[idx[k]], c.engine.map[0].boost[idx[k]] / 1e5);
        assert_close(cyc.mean.brake_torque, c.engine.map[0].torque[idx[k]], 0.03, 0);
        assert_close(cyc.mean.boost, c.engine.map[0].boost[idx[k]], 0.05, 0);
        ts_engine_free(e);
        free(x);
    }
}

typedef struct cv_ud {
    const ts_engine *e;
    ts_engine_inputs in;
} cv_ud;

static int cv_rhs(double t, const double *y, double *ydot, void *ud)
{
    cv_ud *u = ud;
    return ts_engine_rhs(u->e, t, y, &u->in, ydot, NULL);
}

/* EVIDENCE: engine.h's contract — the caller integrates x with its own
 * integrator. A 1-s free-running transient of the mean-value engine (rack
 * step on a 2500 N*m load from 1500 rpm with cold turbos) integrated by CVODE
 * (BDF, rtol 1e-8) agrees with the engine's fixed-step RK4 within 0.2 % in
 * crank and turbo speed. Two independent integrators of the same ODE. */
static void caller_integrates_with_cvode(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE);
    int n = ts_engine_nstate(e);
    double *x = calloc((size_t)n, sizeof *x), *x2 = calloc((size_t)n, sizeof *x2);
    double *atol = calloc((size_t)n, sizeof *atol);
    double *work = calloc(ts_engine_work_size(e), sizeof *work);
    cv_ud u = {e, et_full_load()};
    u.in.hold_speed = 0;
    u.in.load_torque = 2500;
    ts_engine_init_state(e, ET_RPM(1500), u.in.p_amb, u.in.T_amb, x);
    memcpy(x2, x, sizeof(double) * (size_t)n);
    ts_engine_atol(e, 1e-8, atol);
    ts_err err;
    ts_ode_opts o = {.rtol = 1e-8, .atol_v = atol};
    ts_ode *ode = ts_ode_make(n, cv_rhs, &u, &o, &err);
    assert_non_null(ode);
    assert_int_equal(ts_ode_init(ode, 0, x, &err), TS_OK);
    assert_int_equal(ts_ode_advance(ode, 1.0, NULL, NULL, &err), TS_OK);
    const double *y = ts_ode_y(ode);
    assert_int_equal(ts_engine_advance(e, x2, 0, 1.0, &u.in, work, &err), TS_OK);
    print_message("      CVODE %.3f rad/s, RK4 %.3f rad/s; turbo %.1f vs %.1f rad/s\n", y[0], x2[0],
                  y[10], x2[10]);
    assert_close(y[0], x2[0], 2e-3, 0);
    assert_close(y[10], x2[10], 2e-3, 0);
    assert_true(x2[0] != x[0]);
    ts_ode_free(ode);
    ts_engine_free(e);
    free(x);
    free(x2);
    free(atol);
    free(work);
}

/* EVIDENCE: engine.h's contract for the crank-angle fidelity: its 512 states
 * (12 cylinders with ignition/burn clocks that re-arm continuously, walls,
 * banks) form one ODE that a caller's stiff integrator can take. From the
 * rated steady state, 15 ms (three firings of cylinder 1's bank neighbours,
 * one combustion of cylinder 1) free-running on the mean load, integrated by
 * CVODE (BDF, rtol 1e-6, the engine's atol scales) agree with the fixed-step
 * RK4 within 0.1 % in crank speed and 1 % in cylinder 1 pressure. */
static void caller_integrates_crank_angle_with_cvode(void **state)
{
    (void)state;
    ts_engine *e;
    ts_engine_cycle cyc;
    double *x = et_steady(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE, 2100, &e, &cyc);
    int n = ts_engine_nstate(e);
    double *x2 = calloc((size_t)n, sizeof *x2), *xd = calloc((size_t)n, sizeof *xd);
    double *atol = calloc((size_t)n, sizeof *atol);
    double *work = calloc(ts_engine_work_size(e), sizeof *work);
    memcpy(x2, x, sizeof(double) * (size_t)n);
    cv_ud u = {e, et_full_load()};
    u.in.hold_speed = 0;
    u.in.load_torque = cyc.mean.brake_torque;
    ts_engine_atol(e, 1e-6, atol);
    ts_err err;
    ts_ode_opts o = {.rtol = 1e-6, .atol_v = atol, .max_steps = 200000};
    ts_ode *ode = ts_ode_make(n, cv_rhs, &u, &o, &err);
    assert_non_null(ode);
    assert_int_equal(ts_ode_init(ode, 0, x, &err), TS_OK);
    assert_int_equal(ts_ode_advance(ode, 0.015, NULL, NULL, &err), TS_OK);
    assert_int_equal(ts_engine_advance(e, x2, 0, 0.015, &u.in, work, &err), TS_OK);
    ts_engine_outputs oc, orr;
    assert_int_equal(ts_engine_rhs(e, 0, ts_ode_y(ode), &u.in, xd, &oc), 0);
    assert_int_equal(ts_engine_rhs(e, 0, x2, &u.in, xd, &orr), 0);
    ts_ode_stats st;
    ts_ode_get_stats(ode, &st);
    print_message("      CVODE %ld steps: speed %.4f vs %.4f rad/s, p_cyl %.2f vs %.2f bar\n",
                  st.steps, oc.speed, orr.speed, oc.cyl_pressure / 1e5, orr.cyl_pressure / 1e5);
    assert_close(oc.speed, orr.speed, 1e-3, 0);
    assert_close(oc.cyl_pressure, orr.cyl_pressure, 0.01, 0);
    ts_ode_free(ode);
    ts_engine_free(e);
    free(x);
    free(x2);
    free(xd);
    free(atol);
    free(work);
}

/* EVIDENCE: the engine_dyno scenario through model.h: channels with SI units,
 * speed held at /engine/dyno_speed, no cylinder or wall channels or metrics (the map
 * engine has neither: they read 0 K / 0 Pa before they were dropped), no
 * manifold temperature or turbo speed channels (it has no manifolds or
 * turbochargers: exhaust 0 K, intake the intercooler wall's 325 K and turbo
 * 0 rad/s until session 22; its outputs are NaN), and for
 * the map fidelity at rack 1 the
 * sampled torque equals the map's full-load torque (definition, 1e-6) and
 * power = torque x speed. */
static void dyno_scenario_map_fidelity(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    c.engine.fidelity = TS_ENGINE_MAP;
    c.engine.dyno_speed = ET_RPM(2100);
    c.run.sample_rate = 1000;
    ts_err err;
    ts_model *m = ts_model_make(&c, &err);
    assert_non_null(m);
    ts_data *d = ts_data_make(m, &err);
    assert_non_null(d);
    assert_int_equal(ts_reset(m, d, &err), TS_OK);
    ts_rows rows = {0};
    assert_int_equal(ts_advance(m, d, 0.05, ts_rows_append, &rows, &err), TS_OK);
    int it = ts_model_channel_index(m, "engine.torque");
    int is = ts_model_channel_index(m, "engine.speed");
    int ip = ts_model_channel_index(m, "engine.power");
    assert_true(it > 0 && is > 0 && ip > 0);
    assert_true(ts_model_channel_index(m, "intake.pressure") > 0);
    assert_int_equal(ts_model_channel_index(m, "rack"),
                     ts_model_channel_index(m, "engine.crank_angle") + 1);
    assert_true(ts_model_channel_index(m, "cylinder.pressure") < 0);
    assert_true(ts_model_channel_index(m, "piston.surface_temperature") < 0);
    assert_true(ts_model_channel_index(m, "exhaust.temperature") < 0);
    assert_true(ts_model_channel_index(m, "intake.temperature") < 0);
    assert_true(ts_model_channel_index(m, "turbo.speed") < 0);
    assert_int_equal(ts_model_channel_index(m, "engine.air_flow"),
                     ts_model_channel_index(m, "intake.pressure") + 1);
    assert_string_equal(ts_model_channel(m, it)->unit, "N*m");
    const double *v = ts_latest(d);
    assert_close(v[is], ET_RPM(2100), 1e-12, 0);
    /* steady full load: the table's torque times the spool-ups' factor at
     * ratio 1 when below 1 (engine_map.c), within 4 % of the table */
    ts_engine *e = ts_engine_make(&c, &err);
    assert_non_null(e);
    double xs[3] = {ET_RPM(2100), 0, 1.0}, xd[3];
    ts_engine_outputs o;
    ts_engine_inputs full = et_full_load();
    assert_int_equal(ts_engine_rhs(e, 0, xs, &full, xd, &o), 0);
    assert_int_equal(ts_engine_models(e), 0);
    assert_true(isnan(o.intake_temp) && isnan(o.exhaust_temp) && isnan(o.turbo_speed));
    double a = fmin(1.0, en_pb_interp(e, c.engine.map[0].pb_torque, ET_RPM(2100), 1.0));
    double tf = o.friction_torque;
    assert_close(v[it], a * (c.engine.map[0].torque[13] + tf) - tf, 1e-6, 0);
    assert_close(v[it], c.engine.map[0].torque[13], 0.04, 0);
    ts_engine_free(e);
    assert_close(v[ip], v[it] * v[is], 1e-12, 0);
    /* the rack, in the place the cylinder pressure has for the crank-angle
     * engine, was read as a 1-Pa peak cylinder pressure: no such metric now */
    ts_metric mt[8];
    int nm = ts_model_metrics(m, rows.v, rows.n, mt, 8);
    assert_int_equal(nm, 2);
    for (int i = 0; i < nm; i++)
        assert_string_not_equal(mt[i].name, "peak_cylinder_pressure");
    ts_rows_free(&rows);
    ts_data_free(d);
    ts_model_free(m);
}

/* EVIDENCE: the crank-angle dynamometer's channels keep the order sessions
 * stored before session 19 have (server/channels.c matches stored channels by
 * name and order): the cylinder channels after the crank angle, rack last. */
static void dyno_scenario_crank_angle_channel_order(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    c.engine.fidelity = TS_ENGINE_CRANK_ANGLE;
    ts_err err;
    ts_model *m = ts_model_make(&c, &err);
    assert_non_null(m);
    int ia = ts_model_channel_index(m, "engine.crank_angle");
    assert_int_equal(ia, 11);
    assert_int_equal(ts_model_channel_index(m, "exhaust.temperature"), 5);
    assert_int_equal(ts_model_channel_index(m, "intake.temperature"), 6);
    assert_int_equal(ts_model_channel_index(m, "turbo.speed"), 10);
    assert_int_equal(ts_model_channel_index(m, "cylinder.pressure"), ia + 1);
    assert_int_equal(ts_model_channel_index(m, "piston.surface_temperature"), ia + 4);
    assert_int_equal(ts_model_channel_index(m, "rack"), ia + 5);
    assert_int_equal(ts_model_nchannel(m), ia + 6);
    ts_model_free(m);
    /* the mean-value engine models its manifolds and turbochargers: their
     * channels stay, in the same places; the cylinder ones go */
    c.engine.fidelity = TS_ENGINE_MEAN_VALUE;
    m = ts_model_make(&c, &err);
    assert_non_null(m);
    assert_int_equal(ts_model_channel_index(m, "exhaust.temperature"), 5);
    assert_int_equal(ts_model_channel_index(m, "turbo.speed"), 10);
    assert_int_equal(ts_model_channel_index(m, "rack"), 12);
    assert_int_equal(ts_model_nchannel(m), 13);
    ts_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(map_boost_lag_closed_form),
        cmocka_unit_test(map_air_flow_follows_boost),
        cmocka_unit_test(part_boost_tables_clamp_at_the_edges),
        cmocka_unit_test(map_crank_dynamics_settle_on_load),
        cmocka_unit_test(map_full_boost_matches_the_sweep_at_every_speed),
        cmocka_unit_test(mean_value_matches_crank_angle_sweep),
        cmocka_unit_test(cycle_mean_inertia_holds_the_reciprocating_parts),
        cmocka_unit_test(caller_integrates_with_cvode),
        cmocka_unit_test(caller_integrates_crank_angle_with_cvode),
        cmocka_unit_test(dyno_scenario_map_fidelity),
        cmocka_unit_test(dyno_scenario_crank_angle_channel_order),
    };
    return cmocka_run_group_tests_name("engine_fidelity", tests, NULL, NULL);
}
