/*
 * scenario_pointmass.c — the point-mass vehicle (paper Section III.C: "vehicle
 * mass is lumped at the center of gravity"), driven here by a prescribed
 * sprocket torque (drive.h). The powertrain drive is added by the driveline
 * module.
 *
 * Equations (x forward, v = dx/dt):
 *   m_eff dv/dt = 2 T_s / r_s - m g (f_r(v) cos(grade) s(v) + sin(grade)) - 1/2 rho CdA v |v|
 *   f_r(v) = f0 + f1 |v|,   s(v) = tanh(v / v_eps)
 * Two sprockets (one per track) each carry T_s; m_eff = rotating_mass_factor m.
 * s(v) smooths the sign of rolling resistance through standstill so that a
 * vehicle at rest with too little torque stays (nearly) at rest instead of
 * being pushed backwards; v_eps = 0.01 m/s.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "drive.h"
#include "scenario.h"
#include "solver.h"

#define GRAVITY 9.80665 /* standard gravity [m/s^2] */
#define V_EPS 0.01      /* standstill smoothing speed [m/s] */

enum { X, V, NSTATE };
enum { CH_X = 1, CH_SPEED, CH_ACCEL, CH_SPROCKET_TORQUE, CH_SPROCKET_SPEED, CH_TRACTION, NCH };

typedef struct pm_data {
    ts_ode *ode;
    double y[NSTATE];
} pm_data;

static double accel(const ts_config *c, double t, double v, double *thrust_out)
{
    const ts_vehicle_config *vc = &c->vehicle;
    double thrust = 2.0 * ts_drive_torque(&c->drive, t) / vc->sprocket_radius;
    double fr = vc->rolling_resistance + vc->rolling_resistance_speed * fabs(v);
    double resist = vc->mass * GRAVITY *
                        (fr * cos(vc->grade) * tanh(v / V_EPS) + sin(vc->grade)) +
                    0.5 * vc->air_density * vc->cda * v * fabs(v);
    if (thrust_out) *thrust_out = thrust;
    return (thrust - resist) / (vc->rotating_mass_factor * vc->mass);
}

static int rhs(double t, const double *y, double *ydot, void *ud)
{
    const ts_model *m = ud;
    ydot[X] = y[V];
    ydot[V] = accel(&m->cfg, t, y[V], NULL);
    return 0;
}

static ts_rc model_init(ts_model *m, ts_err *err)
{
    ts_rc rc = ts_drive_check(&m->cfg.drive, err);
    if (rc != TS_OK) return rc;
    if (m->cfg.drive.kind == TS_DRIVE_POWERTRAIN)
        return ts_err_set(err, TS_ERR_UNSUPPORTED, "/drive/kind",
                          "/drive/kind: the powertrain drive is not available for point-mass "
                          "runs in this build");
    m->dof = 1;
    m->nstate = NSTATE;
    static const struct {
        const char *name, *unit, *desc;
    } ch[] = {
        {"vehicle.x", "m", "distance travelled"},
        {"vehicle.speed", "m/s", "vehicle speed"},
        {"vehicle.accel", "m/s^2", "vehicle acceleration"},
        {"sprocket.torque", "N*m", "torque at each drive sprocket"},
        {"sprocket.speed", "rad/s", "sprocket angular speed (no slip)"},
        {"vehicle.traction", "N", "total tractive force of both tracks"},
    };
    for (size_t i = 0; i < sizeof ch / sizeof ch[0]; i++)
        if (ts_model_add_channel(m, ch[i].name, ch[i].unit, ch[i].desc, err) < 0)
            return err ? err->code : TS_ERR_INTERNAL;
    m->impl = m; /* no derived constants beyond the config */
    return TS_OK;
}

static void model_fini(ts_model *m) { m->impl = NULL; }

static ts_rc data_init(const ts_model *m, ts_data *d, ts_err *err)
{
    pm_data *p = calloc(1, sizeof *p);
    if (!p) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    ts_ode_opts o = {.rtol = m->cfg.run.rtol,
                     .atol = m->cfg.run.atol,
                     .max_step = m->cfg.run.max_step};
    p->ode = ts_ode_make(NSTATE, rhs, (void *)m, &o, err);
    if (!p->ode) {
        free(p);
        return err ? err->code : TS_ERR_SOLVER;
    }
    d->impl = p;
    return TS_OK;
}

static void data_fini(const ts_model *m, ts_data *d)
{
    (void)m;
    pm_data *p = d->impl;
    if (!p) return;
    ts_ode_free(p->ode);
    free(p);
    d->impl = NULL;
}

static ts_rc reset(const ts_model *m, ts_data *d, ts_err *err)
{
    (void)m;
    pm_data *p = d->impl;
    p->y[X] = 0.0;
    p->y[V] = 0.0;
    return ts_ode_init(p->ode, 0.0, p->y, err);
}

static ts_rc step_to(const ts_model *m, ts_data *d, double t, ts_err *err)
{
    (void)m;
    pm_data *p = d->impl;
    ts_rc rc = ts_ode_advance(p->ode, t, NULL, NULL, err);
    if (rc == TS_OK) memcpy(p->y, ts_ode_y(p->ode), sizeof p->y);
    return rc;
}

static void sample(const ts_model *m, const ts_data *d, double *out)
{
    const pm_data *p = d->impl;
    double thrust;
    out[CH_X] = p->y[X];
    out[CH_SPEED] = p->y[V];
    out[CH_ACCEL] = accel(&m->cfg, d->t, p->y[V], &thrust);
    out[CH_SPROCKET_TORQUE] = ts_drive_torque(&m->cfg.drive, d->t);
    out[CH_SPROCKET_SPEED] = p->y[V] / m->cfg.vehicle.sprocket_radius;
    out[CH_TRACTION] = thrust;
}

static size_t state_size(const ts_model *m)
{
    (void)m;
    return sizeof(double) * NSTATE;
}

static ts_rc state_save(const ts_model *m, const ts_data *d, void *buf, ts_err *err)
{
    (void)m;
    (void)err;
    const pm_data *p = d->impl;
    memcpy(buf, p->y, sizeof p->y);
    return TS_OK;
}

static ts_rc state_restore(const ts_model *m, ts_data *d, const void *buf, ts_err *err)
{
    (void)m;
    pm_data *p = d->impl;
    memcpy(p->y, buf, sizeof p->y);
    return ts_ode_init(p->ode, d->t, p->y, err);
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
    .geometry = NULL,
};
