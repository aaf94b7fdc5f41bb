/*
 * scenario_pointmass.c — the point-mass vehicle (paper Section III.C: "vehicle
 * mass is lumped at the center of gravity"), driven either by a prescribed
 * sprocket torque (drive.h) or, with /drive/kind = "powertrain", by the engine
 * + torque converter + transmission + final drive (powertrain.h) — the paper's
 * full-throttle mobility study (Figs. 19-21, Table 2).
 *
 * Equations (x forward, v = dx/dt):
 *   M dv/dt = 2 T_s / r_s - m g (f_r(v) cos(grade) s(v) + sin(grade)) - 1/2 rho CdA v |v|
 *   f_r(v) = f0 + f1 |v|,   s(v) = tanh(v / v_eps)
 *   M = rotating_mass_factor m (+ (J_out - 2 J_sprocket) / r_s^2 with the
 *       powertrain: the factor already holds the sprockets)
 * Two sprockets (one per track) each carry T_s. Sprocket speed and vehicle
 * speed are tied by the pitch radius, w_s = v / r_s (no track slip). s(v)
 * smooths the sign of rolling resistance through standstill so that a vehicle
 * at rest with too little torque stays (nearly) at rest instead of being
 * pushed backwards; v_eps = /vehicle/rolling_resistance_smoothing (the multibody
 * model smooths its rolling resistance with the same row).
 *
 * With the powertrain the ODE is monolithic: [x, v, powertrain states]. Two
 * integration paths, chosen by ts_powertrain_explicit_step:
 *  - map and mean_value engines: CVODE (BDF); gear shifts are ROOT FUNCTIONS
 *    of this ODE, handled by re-initialising CVODE (powertrain.h);
 *  - crank_angle engine: co-simulated (powertrain.h, ts_powertrain_macro_step
 *    > 0): per macro step H the engine advances itself with the converter's
 *    pump torque as its load (ts_powertrain_engine_advance), then [x, v,
 *    turbine] by classical RK4 at the clutch's explicit stability limit with
 *    the engine speed held; the shift state machine is checked at every
 *    sub-step end (event time resolved to one sub-step, 100 us). With
 *    /driveline/engine_macro_step = 0: every state by RK4 at the engine's
 *    crank-angle step (~45 us at 1850 rpm), capped by the clutch limit.
 * The rack is /control/rack (held constant; the IVS controller is the control
 * module's).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "drive.h"
#include "governor.h"
#include "powertrain.h"
#include "scenario.h"
#include "solver.h"

#define KMH (1.0 / 3.6) /* m/s per km/h */

enum { X, V, NVEH };
enum { CH_X = 1, CH_SPEED, CH_ACCEL, CH_SPROCKET_TORQUE, CH_SPROCKET_SPEED, CH_TRACTION, NCH };

typedef struct pm_model {
    ts_powertrain *pt; /* NULL for a prescribed drive */
    int npt;           /* powertrain states */
    double mass_eff;   /* M [kg] */
    ts_governor gov;   /* /control's two-speed governor (off: the rack as set) */
} pm_model;

typedef struct pm_data {
    const ts_model *m; /* for the ODE callbacks */
    ts_ode *ode;
    int n;
    double *y, *ydot; /* n */
    double *k;        /* 5 n: RK4 stages and trial state */
    double t_int;     /* time the state y is at [s] */
    ts_powertrain_state ps;
    ts_powertrain_out out; /* scratch for sample */
    double *work;          /* engine co-simulation scratch */
} pm_data;

static double resistance(const ts_vehicle_config *vc, double v)
{
    double fr = vc->rolling_resistance + vc->rolling_resistance_speed * fabs(v);
    double sgn = tanh(v / vc->rolling_resistance_smoothing);
    return vc->mass * TS_GRAVITY * (fr * cos(vc->grade) * sgn + sin(vc->grade)) +
           0.5 * vc->air_density * vc->cda * v * fabs(v);
}

/* The rack the engine gets: /control/rack, through the fuel actuator's
 * two-speed governor (paper IV.B.2, governor.h) when /control/governor is on,
 * at the engine speed of the powertrain states yp. */
static double governed_rack(const ts_model *m, const double *yp)
{
    const pm_model *pm = m->impl;
    return ts_governor_rack(&pm->gov, m->cfg.control.rack,
                            yp[ts_powertrain_engine_speed_index(pm->pt)]);
}

/* Vehicle derivatives; with the powertrain also its derivatives into ydot + NVEH
 * and its shaft quantities into out (may be NULL). */
static int derivs(const ts_model *m, const ts_powertrain_state *ps, double t, const double *y,
                  double *ydot, ts_powertrain_out *out, double *thrust_out, double *ts_out)
{
    const pm_model *pm = m->impl;
    const ts_vehicle_config *vc = &m->cfg.vehicle;
    double t_s;
    if (pm->pt) {
        ts_powertrain_out o;
        int rc = ts_powertrain_rhs(pm->pt, ps, t, y + NVEH, y[V] / vc->sprocket_radius,
                                   governed_rack(m, y + NVEH), ydot + NVEH, &o);
        if (rc != 0) return rc;
        t_s = o.sprocket_torque;
        if (out) *out = o;
    } else {
        t_s = ts_drive_torque(&m->cfg.drive, t);
    }
    double thrust = 2.0 * t_s / vc->sprocket_radius;
    ydot[X] = y[V];
    ydot[V] = (thrust - resistance(vc, y[V])) / pm->mass_eff;
    if (thrust_out) *thrust_out = thrust;
    if (ts_out) *ts_out = t_s;
    return 0;
}

static int rhs(double t, const double *y, double *ydot, void *ud)
{
    const pm_data *p = ud;
    return derivs(p->m, &p->ps, t, y, ydot, NULL, NULL, NULL);
}

static int roots(double t, const double *y, double *g, void *ud)
{
    const pm_data *p = ud;
    const pm_model *pm = p->m->impl;
    ts_powertrain_roots(pm->pt, &p->ps, t, y + NVEH, y[V] / p->m->cfg.vehicle.sprocket_radius, g);
    return 0;
}

static ts_rc model_init(ts_model *m, ts_err *err)
{
    ts_rc rc = ts_drive_check(&m->cfg.drive, err);
    if (rc != TS_OK) return rc;
    if (m->cfg.terrain.kind != TS_TERRAIN_FLAT) /* it was ignored without a word */
        return ts_err_set(err, TS_ERR_PARAM, "/terrain/kind",
                          "/terrain/kind: the point mass runs on flat ground or a constant "
                          "/vehicle/grade; bump courses and profiles need the multibody vehicle "
                          "(run.kind vehicle or coupled)");
    /* both tracks: half the weight on each (the normal force on the grade) */
    rc = ts_drive_check_traction(&m->cfg.drive, m->cfg.vehicle.sprocket_radius,
                                 0.5 * m->cfg.vehicle.mass * TS_GRAVITY * cos(m->cfg.vehicle.grade),
                                 m->cfg.vehicle.traction_limit, err);
    if (rc != TS_OK) return rc;
    pm_model *pm = calloc(1, sizeof *pm);
    if (!pm) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    m->impl = pm;
    const ts_vehicle_config *vc = &m->cfg.vehicle;
    pm->mass_eff = vc->rotating_mass_factor * vc->mass;
    m->dof = 1;
    m->nstate = NVEH;
    if (m->cfg.drive.kind == TS_DRIVE_POWERTRAIN) {
        rc = ts_governor_of_config(&m->cfg.control, &pm->gov, err);
        if (rc != TS_OK) return rc;
        pm->pt = ts_powertrain_make(&m->cfg, err);
        if (!pm->pt) return err ? err->code : TS_ERR_INTERNAL;
        pm->npt = ts_powertrain_nstate(pm->pt);
        /* the driveline's output inertia includes both sprockets, which
         * rotating_mass_factor already counts: only the rest is added (the
         * multibody model takes the larger of the two per sprocket,
         * coupled_system.c) */
        double r = vc->sprocket_radius;
        double j_rest = ts_powertrain_output_inertia(pm->pt) - 2.0 * vc->sprocket_inertia;
        if (j_rest > 0) pm->mass_eff += j_rest / (r * r);
        m->dof = 3; /* vehicle, crankshaft + pump, turbine + transmission input */
        m->nstate = NVEH + pm->npt;
        /* the launch starts from standstill with the engine at its idle
         * steady state (powertrain.h ts_powertrain_idle_start); the LHR's
         * insulated walls idle much hotter than the conventional engine's,
         * the charge heating of Fig. 21 in the launch phase */
        rc = ts_powertrain_idle_start(pm->pt, err);
        if (rc != TS_OK) return rc;
    }
    static const ts_channel ch[] = {
        {"vehicle.x", "m", "distance travelled"},
        {"vehicle.speed", "m/s", "vehicle speed"},
        {"vehicle.accel", "m/s^2", "vehicle acceleration"},
        {"sprocket.torque", "N*m", "torque at each drive sprocket"},
        {"sprocket.speed", "rad/s", "sprocket angular speed (no slip)"},
        {"vehicle.traction", "N", "total tractive force of both tracks"},
    };
    rc = ts_model_add_channels(m, ch, (int)(sizeof ch / sizeof ch[0]), err);
    if (rc == TS_OK && pm->pt)
        rc = ts_model_add_channels(m, ts_powertrain_channels(pm->pt),
                                   ts_powertrain_nchannel(pm->pt), err);
    return rc;
}

static void model_fini(ts_model *m)
{
    pm_model *pm = m->impl;
    if (pm) ts_powertrain_free(pm->pt);
    free(pm);
    m->impl = NULL;
}

static void data_fini(const ts_model *m, ts_data *d);

static ts_rc data_init(const ts_model *m, ts_data *d, ts_err *err)
{
    const pm_model *pm = m->impl;
    pm_data *p = calloc(1, sizeof *p);
    if (!p) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    d->impl = p;
    p->n = m->nstate;
    p->m = m;
    p->y = calloc((size_t)p->n * 8, sizeof *p->y);
    if (!p->y) {
        data_fini(m, d);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    size_t nw = pm->pt ? ts_powertrain_work_size(pm->pt) : 0;
    if (nw && !(p->work = malloc(nw * sizeof *p->work))) {
        data_fini(m, d);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    p->ydot = p->y + p->n;
    double *atol = p->y + 2 * p->n;
    p->k = p->y + 3 * p->n;
    atol[X] = atol[V] = m->cfg.run.atol;
    if (pm->pt) {
        ts_powertrain_scale(pm->pt, atol + NVEH);
        for (int i = NVEH; i < p->n; i++)
            atol[i] *= m->cfg.run.atol;
    }
    ts_ode_opts o = {.rtol = m->cfg.run.rtol,
                     .atol = m->cfg.run.atol,
                     .atol_v = atol,
                     .max_step = m->cfg.run.max_step,
                     .nroots = pm->pt ? ts_powertrain_nroots(pm->pt) : 0,
                     .roots = pm->pt ? roots : NULL};
    p->ode = ts_ode_make(p->n, rhs, p, &o, err);
    if (!p->ode) {
        data_fini(m, d);
        return err ? err->code : TS_ERR_SOLVER;
    }
    return TS_OK;
}

static void data_fini(const ts_model *m, ts_data *d)
{
    (void)m;
    pm_data *p = d->impl;
    if (!p) return;
    ts_ode_free(p->ode);
    free(p->work);
    free(p->y);
    free(p);
    d->impl = NULL;
}

/* Run the discrete updates at (t, y) until nothing changes; re-init when it did. */
static ts_rc settle_events(const ts_model *m, pm_data *p, double t, ts_err *err)
{
    const pm_model *pm = m->impl;
    if (!pm->pt) return TS_OK;
    return ts_powertrain_update(pm->pt, &p->ps, t, p->y + NVEH,
                                p->y[V] / m->cfg.vehicle.sprocket_radius)
               ? ts_ode_init(p->ode, t, p->y, err)
               : TS_OK;
}

/* One classical RK4 step of size h from (p->t_int, p->y). */
static ts_rc rk4_step(pm_data *p, double h, ts_err *err)
{
    double t = p->t_int;
    int rc = ts_rk4_step(p->n, rhs, p, t, h, p->y, p->k);
    if (rc)
        return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                          "powertrain state left its domain at t = %.6f s (RK4 step %.3g s)", t, h);
    p->t_int = t + h;
    return TS_OK;
}

/* Fixed-step path: RK4 to exactly t, the shift state machine at each step end. */
static ts_rc step_to_explicit(const ts_model *m, pm_data *p, double t, ts_err *err)
{
    const pm_model *pm = m->impl;
    const double r_s = m->cfg.vehicle.sprocket_radius;
    while (p->t_int < t - 1e-12 * (1.0 + t)) {
        double h = ts_powertrain_explicit_step(pm->pt, p->y + NVEH);
        if (p->t_int + h > t) h = t - p->t_int;
        ts_rc rc = rk4_step(p, h, err);
        if (rc != TS_OK) return rc;
        ts_powertrain_update(pm->pt, &p->ps, p->t_int, p->y + NVEH, p->y[V] / r_s);
    }
    p->t_int = t;
    return TS_OK;
}

/* Vehicle + turbine derivatives with the engine states held (co-simulation);
 * rack: the macro step's, which the engine was advanced with (it only labels
 * the outputs here). */
static void derivs_driveline(const ts_model *m, const pm_data *p, double t, const double *y,
                             double rack, double *ydot)
{
    const pm_model *pm = m->impl;
    const ts_vehicle_config *vc = &m->cfg.vehicle;
    ts_powertrain_out o;
    ts_powertrain_rhs_driveline(pm->pt, &p->ps, t, y + NVEH, y[V] / vc->sprocket_radius, rack,
                                ydot + NVEH, &o);
    ydot[X] = y[V];
    ydot[V] = (2.0 * o.sprocket_torque / vc->sprocket_radius - resistance(vc, y[V])) / pm->mass_eff;
}

/* derivs_driveline as a ts_rhs_fn (ts_rk4_step_subset). */
typedef struct {
    const ts_model *m;
    const pm_data *p;
    double rack; /* the macro step's governed rack */
} held_ctx;

static int rhs_held(double t, const double *y, double *ydot, void *ud)
{
    const held_ctx *h = ud;
    derivs_driveline(h->m, h->p, t, y, h->rack, ydot);
    return 0;
}

/* Co-simulation path: macro steps of the engine, RK4 sub-steps of x, v and
 * the turbine (the last state) with the engine held; shifts at sub-step ends. */
static ts_rc step_to_cosim(const ts_model *m, pm_data *p, double t, ts_err *err)
{
    const pm_model *pm = m->impl;
    const double r_s = m->cfg.vehicle.sprocket_radius;
    const int idx[3] = {X, V, p->n - 1}; /* the states the RK4 integrates */
    double *y = p->y, work[15];
    held_ctx ctx = {m, p, 0.0};
    while (p->t_int < t - 1e-12 * (1.0 + t)) {
        double t_end = p->t_int + ts_powertrain_macro_step(pm->pt);
        if (t_end > t - 1e-12 * (1.0 + t)) t_end = t;
        /* the governor acts per macro step, at the engine speed it starts from */
        ctx.rack = governed_rack(m, y + NVEH);
        ts_rc rc = ts_powertrain_engine_advance(pm->pt, p->t_int, t_end - p->t_int, y + NVEH,
                                                ctx.rack, p->work, err);
        if (rc != TS_OK) return rc;
        while (p->t_int < t_end - 1e-12 * (1.0 + t_end)) {
            double h = ts_powertrain_explicit_step(pm->pt, y + NVEH), t0 = p->t_int;
            if (t0 + h > t_end) h = t_end - t0;
            if (ts_rk4_step_subset(3, idx, rhs_held, &ctx, t0, h, y, p->ydot, work))
                return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                                  "driveline state left its domain at t = %.6f s", t0);
            p->t_int = t0 + h;
            ts_powertrain_update(pm->pt, &p->ps, p->t_int, y + NVEH, y[V] / r_s);
        }
        p->t_int = t_end;
    }
    p->t_int = t;
    return TS_OK;
}

static ts_rc reset(const ts_model *m, ts_data *d, ts_err *err)
{
    const pm_model *pm = m->impl;
    pm_data *p = d->impl;
    memset(p->y, 0, sizeof *p->y * (size_t)p->n);
    if (pm->pt) {
        ts_rc rc = ts_powertrain_reset(pm->pt, &p->ps, p->y + NVEH, 0.0, err);
        if (rc != TS_OK) return rc;
    }
    p->t_int = 0.0;
    ts_rc rc = ts_ode_init(p->ode, 0.0, p->y, err);
    if (rc != TS_OK) return rc;
    return settle_events(m, p, 0.0, err);
}

static ts_rc step_to(const ts_model *m, ts_data *d, double t, ts_err *err)
{
    const pm_model *pm = m->impl;
    pm_data *p = d->impl;
    if (pm->pt && ts_powertrain_macro_step(pm->pt) > 0) return step_to_cosim(m, p, t, err);
    if (pm->pt && ts_powertrain_explicit_step(pm->pt, p->y + NVEH) > 0)
        return step_to_explicit(m, p, t, err);
    for (;;) {
        double tr;
        int root = 0;
        ts_rc rc = ts_ode_advance(p->ode, t, &tr, pm->pt ? &root : NULL, err);
        if (rc != TS_OK) return rc;
        memcpy(p->y, ts_ode_y(p->ode), sizeof *p->y * (size_t)p->n);
        p->t_int = tr;
        if (!root) return TS_OK;
        rc = settle_events(m, p, tr, err);
        if (rc != TS_OK) return rc;
        if (tr >= t) return TS_OK;
    }
}

static ts_rc sample(const ts_model *m, const ts_data *d, double *out, ts_err *err)
{
    const pm_model *pm = m->impl;
    pm_data *p = d->impl;
    double thrust = 0.0, t_s = 0.0;
    if (derivs(m, &p->ps, d->t, p->y, p->ydot, &p->out, &thrust, &t_s) != 0)
        return ts_powertrain_rhs_failed(d->t, err);
    out[CH_X] = p->y[X];
    out[CH_SPEED] = p->y[V];
    out[CH_ACCEL] = p->ydot[V];
    out[CH_SPROCKET_TORQUE] = t_s;
    out[CH_SPROCKET_SPEED] = p->y[V] / m->cfg.vehicle.sprocket_radius;
    out[CH_TRACTION] = thrust;
    if (pm->pt) ts_powertrain_channel_values(pm->pt, &p->out, out + NCH);
    return TS_OK;
}

/* The CVODE path only: the explicit and co-simulated powertrain paths step by
 * RK4 at the engine's own fixed step and keep no counters. */
static int integrator_stats(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max)
{
    (void)max;
    const pm_model *pm = m->impl;
    const pm_data *p = d->impl;
    if (pm->pt && (ts_powertrain_macro_step(pm->pt) > 0 ||
                   ts_powertrain_explicit_step(pm->pt, p->y + NVEH) > 0))
        return 0;
    ts_integrator_stats_of_ode(p->ode, "pointmass", "CVODE BDF, Newton, dense LU", out);
    return 1;
}

static size_t state_size(const ts_model *m)
{
    return sizeof(double) * (size_t)m->nstate + sizeof(ts_powertrain_state);
}

static ts_rc state_save(const ts_model *m, const ts_data *d, void *buf, ts_err *err)
{
    (void)err;
    const pm_data *p = d->impl;
    memcpy(buf, p->y, sizeof(double) * (size_t)m->nstate);
    memcpy((char *)buf + sizeof(double) * (size_t)m->nstate, &p->ps, sizeof p->ps);
    return TS_OK;
}

static ts_rc state_restore(const ts_model *m, ts_data *d, const void *buf, ts_err *err)
{
    pm_data *p = d->impl;
    memcpy(p->y, buf, sizeof(double) * (size_t)m->nstate);
    memcpy(&p->ps, (const char *)buf + sizeof(double) * (size_t)m->nstate, sizeof p->ps);
    p->t_int = d->t;
    return ts_ode_init(p->ode, d->t, p->y, err);
}

/* Value of col at time t (linear interpolation), NAN outside the run. */
static double value_at(const double *rows, long nrows, int ncol, int col, double t)
{
    for (long i = 1; i < nrows; i++) {
        double ta = rows[(i - 1) * ncol], tb = rows[i * ncol];
        if (ta <= t && t <= tb) {
            double a = rows[(i - 1) * ncol + col], b = rows[i * ncol + col];
            return tb > ta ? a + (b - a) * (t - ta) / (tb - ta) : b;
        }
    }
    return NAN;
}

/* Table 2 figures from the series (predicted; see driveline.json for which
 * inputs are calibrated). */
static int metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max)
{
    int nc = m->nchannel, n = 0;
    double t20 = ts_rows_first_crossing(rows, nrows, nc, CH_SPEED, 20 * KMH);
    double t60 = ts_rows_first_crossing(rows, nrows, nc, CH_SPEED, 60 * KMH);
    n = ts_metric_add(
        out, n, max, "speed_at_20s_kmh", "km/h", value_at(rows, nrows, nc, CH_SPEED, 20.0) * 3.6,
        "vehicle speed 20 s after the start (Table 2 column 1; the conventional row is "
        "calibrated to it [C Table 2]: final ratio, constant rolling resistance)");
    n = ts_metric_add(out, n, max, "t_0_60_kmh_s", "s", t60,
                      "time from standstill to 60 km/h (Table 2 column 2; conventional: same "
                      "calibration [C Table 2])");
    n = ts_metric_add(out, n, max, "t_20_60_kmh_s", "s", t60 - t20,
                      "time from 20 to 60 km/h (Table 2 column 3; conventional: same calibration "
                      "[C Table 2])");
    n = ts_metric_add(out, n, max, "speed_at_end_kmh", "km/h",
                      rows[(nrows - 1) * nc + CH_SPEED] * 3.6,
                      "vehicle speed at the end of the run");
    int ig = ts_model_channel_index(m, "transmission.gear");
    if (ig > 0) n = ts_metric_add_upshifts(rows, nrows, nc, ig, out, n, max);
    return n;
}

const ts_scenario_ops ts_scenario_pointmass = {
    .kind = "pointmass",
    .model_init = model_init,
    .model_fini = model_fini,
    .data_init = data_init,
    .data_fini = data_fini,
    .reset = reset,
    .step_to = step_to,
    .sample = sample,
    .state_size = state_size,
    .state_save = state_save,
    .state_restore = state_restore,
    .metrics = metrics,
    .geometry = NULL,
    .integrator_stats = integrator_stats,
};
