/*
 * scenario_engine_dyno.c — the virtual V-12 on a dynamometer (paper Section
 * III.B.3, Fig. 18): crank speed held at /engine/dyno_speed, fuel from the
 * rack /control/rack through the engine's default fuel law (Eqs. 13-14).
 *
 * ts_reset brings the engine to its periodic steady state at that speed and
 * rack (ts_engine_steady: turbo, manifolds, walls, coolant and oil settled),
 * so a run shows steady operation: at a high sample rate (12.6 kHz = one
 * sample per deg CA at 2100 rpm) the cylinder channels trace the diesel cycle
 * of cylinder 1. The search starts with the rotors spun up (TS_ENGINE_SEARCH_TURBO) so
 * it finds the full-load high-boost turbo match (see ts_engine_set_turbo_speed). Integration: the
 * engine's fixed crank-angle RK4 (ts_engine_advance), any fidelity. Metrics: cycle-mean brake
 * torque and power, peak cylinder pressure.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "engine.h"
#include "scenario.h"

enum {
    CH_SPEED = 1,
    CH_TORQUE,
    CH_POWER,
    CH_BOOST,
    CH_EXHAUST_T,
    CH_INTAKE_T,
    CH_AIR,
    CH_FUEL,
    CH_PHI,
    CH_TURBO,
    CH_ANGLE,
    CH_CYL_P,
    CH_CYL_T,
    CH_HRR,
    CH_PISTON_T,
    CH_RACK
};
/* Each channel and what the engine must model for it (engine.h
 * TS_ENGINE_MODELS_* bits; 0: every engine): the cylinder channels need the
 * crank-angle engine, the manifold temperatures and the turbo speed an engine
 * with manifolds and turbochargers (not the map engine). */
static const ts_channel_need channels[CH_RACK + 1] = {
    [CH_SPEED] = {{"engine.speed", "rad/s", "crankshaft speed (held by the dynamometer)"}, 0},
    [CH_TORQUE] = {{"engine.torque", "N*m", "brake torque, instantaneous (indicated - friction)"},
                   0},
    [CH_POWER] = {{"engine.power", "W", "brake power, instantaneous"}, 0},
    [CH_BOOST] = {{"intake.pressure", "Pa", "intake manifold pressure (boost), mean of the banks"},
                  0},
    [CH_EXHAUST_T] = {{"exhaust.temperature", "K",
                       "exhaust manifold temperature, mean of the banks"},
                      TS_ENGINE_MODELS_MANIFOLDS},
    [CH_INTAKE_T] = {{"intake.temperature", "K", "intake manifold temperature, mean of the banks"},
                     TS_ENGINE_MODELS_MANIFOLDS},
    [CH_AIR] = {{"engine.air_flow", "kg/s", "compressor air mass flow, both banks"}, 0},
    [CH_FUEL] = {{"engine.fuel_flow", "kg/s", "fuel mass flow injected"}, 0},
    [CH_PHI] = {{"engine.phi", "1", "delivered fuel/air equivalence ratio"}, 0},
    [CH_TURBO] = {{"turbo.speed", "rad/s", "turbocharger rotor speed, mean of the banks"},
                  TS_ENGINE_MODELS_MANIFOLDS},
    [CH_ANGLE] = {{"engine.crank_angle", "rad", "crank angle from cylinder 1 firing TDC, 0..4 pi"},
                  0},
    [CH_CYL_P] = {{"cylinder.pressure", "Pa", "cylinder 1 pressure"}, TS_ENGINE_MODELS_CYLINDERS},
    [CH_CYL_T] = {{"cylinder.temperature", "K", "cylinder 1 bulk gas temperature"},
                  TS_ENGINE_MODELS_CYLINDERS},
    [CH_HRR] = {{"cylinder.heat_release", "W", "cylinder 1 fuel energy release rate"},
                TS_ENGINE_MODELS_CYLINDERS},
    [CH_PISTON_T] = {{"piston.surface_temperature", "K",
                      "cylinder 1 piston gas-side surface temperature"},
                     TS_ENGINE_MODELS_CYLINDERS},
    [CH_RACK] = {{"rack", "1", "rack (driver demand)"}, 0},
};

/* Whether m's engine models channel c. */
static int modelled(const ts_model *m, int c)
{
    return ts_engine_models_all(ts_engine_models(m->impl), channels[c].needs);
}

/* The column of channel c in m's rows (column 0 is time), or -1 when m has
 * no such channel: the channels m's engine does not model are left out and
 * the others keep the crank-angle order, which stored sessions match by name
 * and order (server/channels.c). */
static int column(const ts_model *m, int c)
{
    if (!modelled(m, c)) return -1;
    int k = 0;
    for (int i = CH_SPEED; i <= c; i++)
        k += modelled(m, i);
    return k;
}

typedef struct dyno_data {
    double *x, *xdot, *work;
} dyno_data;

static ts_engine_inputs inputs(const ts_model *m)
{
    ts_engine_inputs in = {.rack = m->cfg.control.rack,
                           .fuel_per_cycle = -1.0,
                           .load_torque = 0.0,
                           .p_amb = m->cfg.driveline.ambient_pressure,
                           .T_amb = m->cfg.driveline.ambient_temperature,
                           .hold_speed = 1};
    return in;
}

static ts_rc model_init(ts_model *m, ts_err *err)
{
    ts_engine *e = ts_engine_make(&m->cfg, err);
    if (!e) return err ? err->code : TS_ERR_PARAM;
    m->impl = e;
    m->dof = 1;
    m->nstate = ts_engine_nstate(e);
    ts_rc rc = TS_OK;
    for (int c = CH_SPEED; c <= CH_RACK && rc == TS_OK; c++)
        if (modelled(m, c)) rc = ts_model_add_channels(m, &channels[c].ch, 1, err);
    return rc;
}

static void model_fini(ts_model *m)
{
    ts_engine_free(m->impl);
    m->impl = NULL;
}

static ts_rc data_init(const ts_model *m, ts_data *d, ts_err *err)
{
    const ts_engine *e = m->impl;
    size_t n = (size_t)ts_engine_nstate(e);
    dyno_data *p = calloc(1, sizeof *p);
    if (p) {
        p->x = calloc(n, sizeof(double));
        p->xdot = calloc(n, sizeof(double));
        p->work = calloc(ts_engine_work_size(e), sizeof(double));
    }
    if (!p || !p->x || !p->xdot || !p->work) {
        if (p) {
            free(p->x);
            free(p->xdot);
            free(p->work);
        }
        free(p);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    d->impl = p;
    return TS_OK;
}

static void data_fini(const ts_model *m, ts_data *d)
{
    (void)m;
    dyno_data *p = d->impl;
    if (!p) return;
    free(p->x);
    free(p->xdot);
    free(p->work);
    free(p);
    d->impl = NULL;
}

static ts_rc reset(const ts_model *m, ts_data *d, ts_err *err)
{
    const ts_engine *e = m->impl;
    dyno_data *p = d->impl;
    ts_engine_inputs in = inputs(m);
    double w = m->cfg.engine.dyno_speed;
    ts_engine_init_state(e, w, in.p_amb, in.T_amb, p->x);
    ts_engine_set_turbo_speed(e, p->x, TS_ENGINE_SEARCH_TURBO);
    ts_rc rc =
        ts_engine_steady(e, p->x, w, &in, TS_ENGINE_STEADY_CYCLES, TS_ENGINE_STEADY_TOL, NULL, err);
    if (rc != TS_OK) return rc;
    p->x[TS_ENGINE_X_ANGLE] = fmod(p->x[TS_ENGINE_X_ANGLE], 4.0 * TS_PI);
    return TS_OK;
}

static ts_rc step_to(const ts_model *m, ts_data *d, double t, ts_err *err)
{
    dyno_data *p = d->impl;
    ts_engine_inputs in = inputs(m);
    return ts_engine_advance(m->impl, p->x, d->t, t - d->t, &in, p->work, err);
}

static ts_rc sample(const ts_model *m, const ts_data *d, double *out, ts_err *err)
{
    dyno_data *p = d->impl;
    ts_engine_inputs in = inputs(m);
    ts_engine_outputs o;
    if (ts_engine_rhs(m->impl, d->t, p->x, &in, p->xdot, &o) != 0)
        return ts_engine_rhs_failed(m->impl, d->t, p->x, err);
    double row[CH_RACK + 1] = {
        [CH_SPEED] = o.speed,
        [CH_TORQUE] = o.brake_torque,
        [CH_POWER] = o.brake_torque * o.speed,
        [CH_BOOST] = o.boost,
        [CH_EXHAUST_T] = o.exhaust_temp,
        [CH_INTAKE_T] = o.intake_temp,
        [CH_AIR] = o.air_flow,
        [CH_FUEL] = o.fuel_flow,
        [CH_PHI] = o.phi,
        [CH_TURBO] = o.turbo_speed,
        [CH_ANGLE] = fmod(p->x[TS_ENGINE_X_ANGLE], 4.0 * TS_PI),
        [CH_CYL_P] = o.cyl_pressure,
        [CH_CYL_T] = o.cyl_temp,
        [CH_HRR] = o.heat_release,
        [CH_PISTON_T] = o.piston_surface_temp,
        [CH_RACK] = in.rack,
    };
    for (int c = CH_SPEED, k = CH_SPEED; c <= CH_RACK; c++)
        if (modelled(m, c)) out[k++] = row[c]; /* k: column(m, c) */
    return TS_OK;
}

static size_t state_size(const ts_model *m) { return sizeof(double) * (size_t)m->nstate; }

static ts_rc state_save(const ts_model *m, const ts_data *d, void *buf, ts_err *err)
{
    (void)err;
    const dyno_data *p = d->impl;
    memcpy(buf, p->x, state_size(m));
    return TS_OK;
}

static ts_rc state_restore(const ts_model *m, ts_data *d, const void *buf, ts_err *err)
{
    (void)err;
    dyno_data *p = d->impl;
    memcpy(p->x, buf, state_size(m));
    return TS_OK;
}

static int metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max)
{
    int nc = m->nchannel, ip = column(m, CH_CYL_P);
    int itq = column(m, CH_TORQUE), ipw = column(m, CH_POWER);
    int n = ip > 0 ? 3 : 2; /* no cylinder pressure without cylinders */
    if (nrows < 2) return 0;
    double tq = 0, pw = 0, pk = 0;
    for (long r = 0; r < nrows; r++) {
        const double *v = rows + (size_t)r * (size_t)nc;
        tq += v[itq];
        pw += v[ipw];
        if (ip > 0 && v[ip] > pk) pk = v[ip];
    }
    tq /= (double)nrows;
    pw /= (double)nrows;
    ts_metric mt[3] = {
        {"brake_torque_mean", "N*m", tq,
         "mean brake torque over the sampled rows (predicted but for the conventional "
         "engine at 2100 rpm, full rack: calibrated to the paper's 1484 hp, 9.9 % over 1350 hp)"},
        {"brake_power_mean", "W", pw,
         "mean brake power over the sampled rows (predicted but for the conventional "
         "engine at 2100 rpm, full rack: calibrated to the paper's 1484 hp, 9.9 % over 1350 hp)"},
        {"peak_cylinder_pressure", "Pa", pk, "largest sampled cylinder 1 pressure (predicted)"},
    };
    if (max > 0) memcpy(out, mt, sizeof mt[0] * (size_t)(max < n ? max : n));
    return n; /* how many there are, even when out holds fewer (ts_model_metrics) */
}

const ts_scenario_ops ts_scenario_engine_dyno = {
    .kind = "engine_dyno",
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
};
