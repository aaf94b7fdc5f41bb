/*
 * test_powertrain_port.c — the powertrain subsystem (powertrain.h) through its
 * engine port, with a TEST DOUBLE for the engine (a flat brake-torque source,
 * one state): closed-form statics of the whole chain at converter stall, the
 * pump inertia on the crankshaft, and the shift sequence / event protocol a
 * caller (point mass, multibody, co-simulation) runs. The real engine is
 * exercised in test_powertrain_pointmass.c.
 */
#include "test_util.h"

#include <string.h>

#include "api/config_json.h"
#include "sim/powertrain.h"
#include "sim/solver.h"
#include "sim/tanksim.h"

#define RPM (3.14159265358979323846 / 30.0)

typedef struct flat_engine { /* test double: T_brake = rack * torque, inertia j */
    double torque, j, w0;
    double step; /* > 0: asks for fixed-step RK4 of this size [s] */
} flat_engine;

static double flat_step(void *ctx, const double *y)
{
    (void)y;
    return ((flat_engine *)ctx)->step;
}

static ts_rc flat_reset(void *ctx, double *y, ts_err *err)
{
    (void)err;
    y[0] = ((flat_engine *)ctx)->w0;
    return TS_OK;
}

static int flat_rhs(void *ctx, double t, const double *y, double rack, double load,
                    double *ydot, ts_engine_obs *obs)
{
    (void)t;
    flat_engine *e = ctx;
    double tb = rack * e->torque;
    ydot[0] = (tb - load) / e->j;
    *obs = (ts_engine_obs){.speed = y[0], .brake_torque = tb, .boost = 2e5};
    return 0;
}

static ts_config defaults(void)
{
    ts_config c;
    ts_err err;
    json_t *doc = json_pack("{s:{s:s}}", "run", "kind", "pointmass");
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

static ts_powertrain *make(const ts_config *c, flat_engine *fe)
{
    ts_engine_port port = {.ctx = fe, .nstate = 1, .speed_index = 0, .inertia = fe->j,
                           .reset = flat_reset, .rhs = flat_rhs, .explicit_step = flat_step};
    ts_err err;
    ts_powertrain *pt = ts_powertrain_make_port(c, &port, &err);
    assert_non_null(pt);
    return pt;
}

/* A caller: powertrain states with the sprocket speed prescribed as w_s(t) = a t. */
typedef struct drive {
    ts_powertrain *pt;
    ts_powertrain_state ps;
    double a, rack;
} drive;

static int drive_rhs(double t, const double *y, double *ydot, void *ud)
{
    drive *d = ud;
    return ts_powertrain_rhs(d->pt, &d->ps, t, y, d->a * t, d->rack, ydot, NULL);
}

static int drive_roots(double t, const double *y, double *g, void *ud)
{
    drive *d = ud;
    ts_powertrain_roots(d->pt, &d->ps, t, y, d->a * t, g);
    return 0;
}

/* Integrate to t_end handling shift events; records shift-start engine speeds. */
static void run(drive *d, ts_ode *ode, double t_end, double *shift_w, int *nshift)
{
    ts_err err;
    double t = 0;
    while (t < t_end) {
        int root = 0;
        assert_int_equal(ts_ode_advance(ode, t_end, &t, &root, &err), TS_OK);
        if (!root) break;
        double *y = ts_ode_y(ode);
        if (ts_powertrain_update(d->pt, &d->ps, t, y, d->a * t)) {
            if (d->ps.shift.target && *nshift < 8) shift_w[(*nshift)++] = y[0];
            assert_int_equal(ts_ode_init(ode, t, y, &err), TS_OK);
        }
    }
}

/* EVIDENCE: converter stall with the sprockets held, closed form: the engine
 * settles where T_brake = (w/K0)^2, w* = K0 sqrt(T) (170.3 rad/s for 5,000
 * N*m and K0 = 23 rpm/sqrt(N*m)); turbine torque TR0 T = 2.8 T, and each
 * sprocket gets 1/2 i_f eta_f r_1 eta_1 TR0 T. Inputs [E], nothing calibrated.
 * Tol 0.5 % (the locked clutch creeps a little, SR ~ 1e-3). */
static void stall_statics_of_the_chain(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fe = {5000, 8.5, 68, 0.0};
    ts_powertrain *pt = make(&c, &fe);
    drive d = {pt, {{0}}, 0.0, 1.0};
    int n = ts_powertrain_nstate(pt);
    assert_int_equal(n, 2);
    double y[2];
    ts_err err;
    assert_int_equal(ts_powertrain_reset(pt, &d.ps, y, 0.0, &err), TS_OK);
    ts_ode_opts o = {.rtol = 1e-8, .atol = 1e-8, .nroots = ts_powertrain_nroots(pt),
                     .roots = drive_roots};
    ts_ode *ode = ts_ode_make(n, drive_rhs, &d, &o, &err);
    assert_int_equal(ts_ode_init(ode, 0, y, &err), TS_OK);
    double sw[8];
    int ns = 0;
    run(&d, ode, 10.0, sw, &ns);
    assert_int_equal(ns, 0); /* stall is below the 1850-rpm shift speed */
    double ydot[2];
    ts_powertrain_out out;
    assert_int_equal(ts_powertrain_rhs(pt, &d.ps, 10.0, ts_ode_y(ode), 0.0, 1.0, ydot, &out), 0);
    double k0 = c.driveline.tc_k_factor[0];
    assert_close(out.engine_speed, k0 * sqrt(5000.0), 5e-3, 0);
    assert_close(out.turbine_torque, 2.8 * 5000, 5e-3, 0);
    const ts_driveline_config *dl = &c.driveline;
    assert_close(out.sprocket_torque,
                 0.5 * dl->final_ratio * dl->final_efficiency * dl->gear_ratio[0] *
                     dl->gear_efficiency[0] * 2.8 * 5000, 5e-3, 0);
    assert_close(out.gear, 1, 0, 0);
    ts_ode_free(ode);
    ts_powertrain_free(pt);
}

/* EVIDENCE: the pump turns with the crankshaft [P III.B.2 "the effective polar
 * moment of inertia of the engine and T/C pump wheel"]: dw/dt = (T_b - T_p) /
 * (J_e + J_p), closed form at one state; turbine: J_t dw_t/dt = T_t - T_clutch.
 * Tol 1e-12. */
static void pump_inertia_on_the_crankshaft(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fe = {5000, 7.0, 68, 0.0};
    ts_powertrain *pt = make(&c, &fe);
    ts_powertrain_state ps;
    double y[2], ydot[2];
    assert_int_equal(ts_powertrain_reset(pt, &ps, y, 0.0, NULL), TS_OK);
    y[0] = 150;
    y[1] = 60;
    ts_powertrain_out o;
    assert_int_equal(ts_powertrain_rhs(pt, &ps, 0, y, 5.0, 0.7, ydot, &o), 0);
    assert_close(ydot[0], (0.7 * 5000 - o.pump_torque) / (7.0 + c.driveline.pump_inertia), 1e-12, 0);
    assert_close(ydot[1], (o.turbine_torque - o.clutch_offgoing) / c.driveline.turbine_inertia,
                 1e-12, 0);
    assert_close(o.out_speed, c.driveline.final_ratio * 5.0, 1e-12, 0);
    ts_powertrain_free(pt);
}

/* EVIDENCE: shift logic [P III.B.2, III.C.1]: with the sprocket speed ramped
 * up, the transmission upshifts 1->2->3->4 whenever the engine is at or above
 * 1850 rpm (first shift at its root, tol 1e-4), never beyond 4th, and in 4th
 * "transmission-in and -out speeds become the same" (ratio 1; tol 0.5 %, the
 * applied clutch's creep). Logic/closed form; test-double engine. */
static void upshifts_at_shift_speed_and_unity_fourth(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fe = {5000, 8.5, 68, 0.0};
    ts_powertrain *pt = make(&c, &fe);
    drive d = {pt, {{0}}, 2.8, 1.0};
    double y[2];
    ts_err err;
    assert_int_equal(ts_powertrain_reset(pt, &d.ps, y, 0.0, &err), TS_OK);
    ts_ode_opts o = {.rtol = 1e-7, .atol = 1e-7, .nroots = ts_powertrain_nroots(pt),
                     .roots = drive_roots};
    ts_ode *ode = ts_ode_make(2, drive_rhs, &d, &o, &err);
    assert_int_equal(ts_ode_init(ode, 0, y, &err), TS_OK);
    double sw[8];
    int ns = 0;
    run(&d, ode, 20.0, sw, &ns);
    assert_int_equal(ns, 3);
    /* the first by its root at 1850 rpm; with this flat-torque double the engine
     * can still be above 1850 rpm when a shift ends, and the next starts at once */
    assert_close(sw[0] / RPM, 1850.0, 1e-4, 0);
    for (int i = 1; i < ns; i++) assert_true(sw[i] / RPM >= 1850.0 * (1 - 1e-4));
    assert_int_equal(d.ps.shift.gear, 4);
    assert_int_equal(d.ps.shift.target, 0);
    assert_int_equal(d.ps.shift.shifts, 3);
    ts_powertrain_out out;
    double ydot[2];
    assert_int_equal(ts_powertrain_rhs(pt, &d.ps, 20.0, ts_ode_y(ode), d.a * 20.0, 1.0, ydot, &out),
                     0);
    assert_close(out.turbine_speed, out.out_speed, 5e-3, 0);
    ts_ode_free(ode);
    ts_powertrain_free(pt);
}

/* EVIDENCE: transmission.h through the powertrain's event protocol
 * (ts_powertrain_update): an upshift's clutch capacity is Cs =
 * shift_capacity_factor x |the input-shaft torque at its start| (1.5 x the
 * engaged clutch's torque, 40 kN*m tanh(1 rad/s / 2 rad/s) = 18.5 kN*m here;
 * 1e-12), and a shift that ends with the upshift armed and the engine still
 * at shift_speed chains into the next at the same event (the shift-end root),
 * not one root later. Closed form of the law; test-double engine. Mutation
 * pass ctl: Cs from a zero input torque (every shift clutch at the 2-kN*m
 * floor) and one discrete update per event (the chained 2-3 upshift waiting
 * for the 1-2 clutch's ramp-end root, 0.6 s later) both passed. */
static void update_sets_shift_capacity_and_chains_shifts(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fe = {5000, 8.5, 68, 0.0};
    ts_powertrain *pt = make(&c, &fe);
    ts_powertrain_state ps;
    double y[2], ydot[2];
    ts_err err;
    assert_int_equal(ts_powertrain_reset(pt, &ps, y, 0.0, &err), TS_OK);
    const double w_s = 5.0, r1 = c.driveline.gear_ratio[0], i_f = c.driveline.final_ratio;
    y[0] = c.driveline.shift_speed + 1.0; /* engine above the upshift speed */
    y[1] = r1 * i_f * w_s + 1.0;          /* 1st-gear clutch slipping by 1 rad/s */
    ts_powertrain_out out;
    assert_int_equal(ts_powertrain_rhs(pt, &ps, 1.0, y, w_s, 1.0, ydot, &out), 0);
    double t_in = out.clutch_offgoing + out.clutch_oncoming;
    assert_close(t_in, c.driveline.clutch_capacity * tanh(1.0 / c.driveline.clutch_slip_speed),
                 1e-12, 0);
    assert_int_equal(ts_powertrain_update(pt, &ps, 1.0, y, w_s), 1);
    assert_int_equal(ps.shift.target, 2);
    assert_close(ps.shift.capacity, c.driveline.shift_capacity_factor * fabs(t_in), 1e-12, 0);
    /* the engine dips to the re-arm speed during the shift and is back above
     * shift_speed at its end: 1-2 ends and 2-3 starts at that one event */
    double dip[2] = {c.driveline.shift_speed - c.driveline.shift_hysteresis - 1.0, y[1]};
    assert_int_equal(ts_powertrain_update(pt, &ps, 1.3, dip, w_s), 1);
    assert_int_equal(ps.shift.armed, 1);
    assert_int_equal(ps.shift.target, 2);
    double t_end = 1.0 + c.driveline.shift_time;
    assert_int_equal(ts_powertrain_update(pt, &ps, t_end, y, w_s), 1);
    assert_int_equal(ps.shift.shifts, 1);
    assert_int_equal(ps.shift.gear, 2);
    assert_int_equal(ps.shift.target, 3);
    assert_close(ps.shift.t_start, t_end, 0, 0);
    ts_powertrain_free(pt);
}

static double ramp(void *ud, double t) { return *(const double *)ud * t; }

/* EVIDENCE: the powertrain on its own integrator (the co-simulation leader's
 * view), called in 50-ms macro steps, reproduces the single-integrator run
 * of the same problem (engine and turbine speed at 20 s, tol 1e-3; same gear
 * and shift count), and a saved/restored state replays it (tol 1e-6: restore
 * re-initialises CVODE). Consistency check, nothing calibrated; test double. */
static void own_integrator_matches_and_restores(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fe = {5000, 8.5, 68, 0.0};
    ts_powertrain *pt = make(&c, &fe);
    /* reference: one integration to 20 s */
    drive d = {pt, {{0}}, 2.8, 1.0};
    double y[2];
    ts_err err;
    assert_int_equal(ts_powertrain_reset(pt, &d.ps, y, 0.0, &err), TS_OK);
    ts_ode_opts o = {.rtol = 1e-8, .atol = 1e-8, .nroots = ts_powertrain_nroots(pt),
                     .roots = drive_roots};
    ts_ode *ode = ts_ode_make(2, drive_rhs, &d, &o, &err);
    assert_int_equal(ts_ode_init(ode, 0, y, &err), TS_OK);
    double sw[8];
    int ns = 0;
    run(&d, ode, 20.0, sw, &ns);
    /* the same through ts_powertrain_sim in macro steps */
    ts_powertrain_sim *s = ts_powertrain_sim_make(pt, 1e-8, 1e-8, 0.0, &err);
    assert_non_null(s);
    assert_int_equal(ts_powertrain_sim_reset(s, 0.0, 0.0, &err), TS_OK);
    double a = 2.8;
    char snap[256];
    assert_true(ts_powertrain_sim_state_size(s) <= sizeof snap);
    ts_powertrain_out out10 = {0}, out20, again;
    for (int k = 1; k <= 400; k++) {
        assert_int_equal(ts_powertrain_sim_advance(s, 0.05 * k, ramp, &a, 1.0, &out20, &err), TS_OK);
        if (k == 200) {
            ts_powertrain_sim_save(s, snap);
            out10 = out20;
        }
    }
    assert_true(out10.engine_speed > 0);
    assert_close(ts_powertrain_sim_time(s), 20.0, 1e-12, 0);
    assert_close(out20.engine_speed, ts_ode_y(ode)[0], 1e-3, 0);
    assert_close(out20.turbine_speed, ts_ode_y(ode)[1], 1e-3, 0);
    assert_int_equal(ts_powertrain_sim_state(s)->shift.gear, d.ps.shift.gear);
    assert_int_equal(ts_powertrain_sim_state(s)->shift.shifts, 3);
    assert_int_equal(ts_powertrain_sim_restore(s, snap, &err), TS_OK);
    assert_close(ts_powertrain_sim_time(s), 10.0, 1e-12, 0);
    for (int k = 201; k <= 400; k++)
        assert_int_equal(ts_powertrain_sim_advance(s, 0.05 * k, ramp, &a, 1.0, &again, &err), TS_OK);
    assert_close(again.engine_speed, out20.engine_speed, 1e-6, 0);
    assert_close(again.sprocket_torque, out20.sprocket_torque, 1e-6, 0);
    ts_powertrain_sim_free(s);
    ts_ode_free(ode);
    ts_powertrain_free(pt);
}

/* EVIDENCE: the explicit path (an engine asking for fixed-step RK4, as the
 * crank-angle engine does; shift state machine at step ends) agrees with the
 * CVODE/root path on the same problem: engine and turbine speed at 20 s
 * within 0.5 %, same gear, three shifts. Consistency check; test double. */
static void explicit_path_matches_root_path(void **state)
{
    (void)state;
    ts_config c = defaults();
    flat_engine fi = {5000, 8.5, 68, 0.0}, fx = {5000, 8.5, 68, 5e-5};
    ts_powertrain *pi = make(&c, &fi), *px = make(&c, &fx);
    assert_close(ts_powertrain_explicit_step(pi, (double[]){100, 0}), 0, 0, 0);
    assert_close(ts_powertrain_explicit_step(px, (double[]){100, 0}), 5e-5, 1e-12, 0);
    ts_err err;
    ts_powertrain_sim *si = ts_powertrain_sim_make(pi, 1e-8, 1e-8, 0.0, &err);
    ts_powertrain_sim *sx = ts_powertrain_sim_make(px, 1e-8, 1e-8, 0.0, &err);
    assert_int_equal(ts_powertrain_sim_reset(si, 0.0, 0.0, &err), TS_OK);
    assert_int_equal(ts_powertrain_sim_reset(sx, 0.0, 0.0, &err), TS_OK);
    double a = 2.8;
    ts_powertrain_out oi, ox;
    for (int k = 1; k <= 20; k++) {
        assert_int_equal(ts_powertrain_sim_advance(si, k, ramp, &a, 1.0, &oi, &err), TS_OK);
        assert_int_equal(ts_powertrain_sim_advance(sx, k, ramp, &a, 1.0, &ox, &err), TS_OK);
    }
    assert_close(ox.engine_speed, oi.engine_speed, 5e-3, 0);
    assert_close(ox.turbine_speed, oi.turbine_speed, 5e-3, 0);
    assert_int_equal(ts_powertrain_sim_state(sx)->shift.shifts, 3);
    assert_int_equal(ts_powertrain_sim_state(sx)->shift.gear, ts_powertrain_sim_state(si)->shift.gear);
    ts_powertrain_sim_free(si);
    ts_powertrain_sim_free(sx);
    ts_powertrain_free(pi);
    ts_powertrain_free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stall_statics_of_the_chain),
        cmocka_unit_test(pump_inertia_on_the_crankshaft),
        cmocka_unit_test(upshifts_at_shift_speed_and_unity_fourth),
        cmocka_unit_test(update_sets_shift_capacity_and_chains_shifts),
        cmocka_unit_test(own_integrator_matches_and_restores),
        cmocka_unit_test(explicit_path_matches_root_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
