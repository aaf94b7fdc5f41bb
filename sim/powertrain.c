/*
 * powertrain.c — engine + torque converter + transmission + final drive
 * (powertrain.h), paper Section III.B.2 and Fig. 17:
 *   crankshaft + pump:   (J_e + J_p) dw_e/dt = T_brake(w_e, rack, ...) - T_pump(w_e, w_t)
 *   turbine + input:     J_t dw_t/dt = T_turbine(w_e, w_t) - T_clutches(t, w_t, w_out)
 *   output:              w_out = i_f w_sprocket;  T_sprocket = 1/2 i_f eta_f^(+-1) T_out
 * "Pump speed is obtained as the solution of the engine dynamics equation,
 * while the transmission speed depends directly on the solution of vehicle
 * dynamics" [P III.B.2]: here the transmission output speed follows the
 * sprocket (an input), and the turbine is its own state coupled through the
 * range clutches (transmission.h), so the torque handover of a shift is
 * resolved in time.
 * Leaves out: shaft compliance and lash, converter lock-up, reverse gears.
 */
#include "powertrain.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "final_drive.h"
#include "solver.h"
#include "torque_converter.h"

struct ts_powertrain {
    ts_engine_port engine;
    ts_torque_converter tc;
    ts_transmission tr;
    ts_final_drive fd;
    double pump_inertia, turbine_inertia;
    double crank_share; /* J_e / (J_e + J_p): the engine's speed derivative rescaled for the pump */
    double macro_step; /* engine co-simulation step [s]; 0: engine in the RK4 */
    int nstate;
    ts_channel ch[TS_POWERTRAIN_NCHANNEL]; /* this engine's channels (ts_powertrain_channels) */
    int nch;
};

static void channels_of(ts_powertrain *pt); /* with the channel table, below */

/* The engine module (engine.h) seen through the port. The converter pump's
 * inertia is added by rescaling the engine's speed derivative with its
 * cycle-mean inertia (ts_engine_mean_inertia: /engine/inertia plus the
 * reciprocating parts' mean; the crank-angle engine's variation about it is
 * kept in its own derivative). */
typedef struct engine_ctx {
    ts_engine *e;
    double w0, p_amb, T_amb;
    double ca_step; /* crank-angle step of the explicit integration [rad] */
    double *idle;   /* idle steady state (ts_powertrain_idle_start), or NULL */
} engine_ctx;

static ts_rc engine_reset(void *ctx, double *y, ts_err *err)
{
    (void)err;
    const engine_ctx *c = ctx;
    if (c->idle)
        memcpy(y, c->idle, sizeof *y * (size_t)ts_engine_nstate(c->e));
    else
        ts_engine_init_state(c->e, c->w0, c->p_amb, c->T_amb, y);
    return TS_OK;
}

static int engine_rhs(void *ctx, double t, const double *y, double rack, double load_torque,
                      double *ydot, ts_engine_obs *obs)
{
    const engine_ctx *c = ctx;
    ts_engine_inputs in = {.rack = rack, .fuel_per_cycle = -1.0, .load_torque = load_torque,
                           .p_amb = c->p_amb, .T_amb = c->T_amb, .hold_speed = 0};
    ts_engine_outputs o;
    int rc = ts_engine_rhs(c->e, t, y, &in, ydot, &o);
    if (rc != 0) return rc;
    *obs = (ts_engine_obs){.speed = o.speed, .brake_torque = o.brake_torque, .boost = o.boost,
                           .exhaust_temp = o.exhaust_temp, .turbo_speed = o.turbo_speed,
                           .piston_temp = o.piston_surface_temp, .fuel_flow = o.fuel_flow};
    return 0;
}

static void engine_scale(void *ctx, double *scale)
{
    const engine_ctx *c = ctx;
    ts_engine_atol(c->e, 1.0, scale);
}

static double engine_explicit_step(void *ctx, const double *y)
{
    const engine_ctx *c = ctx;
    if (ts_engine_get_fidelity(c->e) != TS_ENGINE_CRANK_ANGLE) return 0.0;
    return c->ca_step / fmax(fabs(y[TS_ENGINE_X_SPEED]), TS_ENGINE_MIN_STEP_SPEED);
}

static ts_rc engine_advance(void *ctx, double *y, double t, double dt, double rack,
                            double load_inertia, double (*load)(void *lud, double t, double speed),
                            void *lud, double *work, ts_err *err)
{
    const engine_ctx *c = ctx;
    ts_engine_inputs in = {.rack = rack, .fuel_per_cycle = -1.0, .load_torque = 0.0,
                           .p_amb = c->p_amb, .T_amb = c->T_amb, .hold_speed = 0,
                           .load_inertia = load_inertia};
    return ts_engine_advance_load(c->e, y, t, dt, &in, load, lud, work, err);
}

static void engine_free(void *ctx)
{
    engine_ctx *c = ctx;
    if (!c) return;
    ts_engine_free(c->e);
    free(c->idle);
    free(c);
}

static ts_rc bind_engine(const ts_config *cfg, ts_engine_port *port, ts_err *err)
{
    engine_ctx *c = calloc(1, sizeof *c);
    if (!c) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    c->e = ts_engine_make(cfg, err);
    if (!c->e) {
        free(c);
        return err ? err->code : TS_ERR_INTERNAL;
    }
    c->w0 = cfg->driveline.launch_engine_speed;
    c->p_amb = cfg->driveline.ambient_pressure;
    c->T_amb = cfg->driveline.ambient_temperature;
    c->ca_step = cfg->engine.ca_step;
    *port = (ts_engine_port){.ctx = c,
                             .nstate = ts_engine_nstate(c->e),
                             .speed_index = TS_ENGINE_X_SPEED,
                             .inertia = ts_engine_mean_inertia(c->e),
                             .reset = engine_reset,
                             .rhs = engine_rhs,
                             .scale = engine_scale,
                             .explicit_step = engine_explicit_step,
                             .free = engine_free,
                             .advance = engine_advance,
                             .work_size = ts_engine_work_size(c->e),
                             .models = ts_engine_models(c->e)};
    return TS_OK;
}

ts_powertrain *ts_powertrain_make_port(const ts_config *cfg, const ts_engine_port *port,
                                       ts_err *err)
{
    ts_powertrain *pt = calloc(1, sizeof *pt);
    if (!pt) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        if (port->free) port->free(port->ctx);
        return NULL;
    }
    pt->engine = *port;
    channels_of(pt);
    const ts_driveline_config *dc = &cfg->driveline;
    if (ts_torque_converter_init(&pt->tc, dc, err) != TS_OK ||
        ts_transmission_init(&pt->tr, dc, err) != TS_OK ||
        ts_final_drive_init(&pt->fd, dc, &cfg->vehicle, err) != TS_OK) {
        ts_powertrain_free(pt);
        return NULL;
    }
    if (port->nstate < 1 || port->speed_index < 0 || port->speed_index >= port->nstate ||
        !(port->inertia > 0) || !port->reset || !port->rhs) {
        ts_err_set(err, TS_ERR_INTERNAL, NULL, "engine port incomplete");
        ts_powertrain_free(pt);
        return NULL;
    }
    pt->pump_inertia = dc->pump_inertia;
    pt->turbine_inertia = dc->turbine_inertia;
    pt->crank_share = port->inertia / (port->inertia + pt->pump_inertia);
    pt->nstate = port->nstate + 1;
    /* co-simulate the engine when it asks for an explicit crank-angle step and
     * can advance itself */
    if (port->advance && port->explicit_step && dc->engine_macro_step > 0) {
        double *y0 = calloc((size_t)port->nstate, sizeof *y0);
        if (!y0) {
            ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
            ts_powertrain_free(pt);
            return NULL;
        }
        ts_rc rc = port->reset(port->ctx, y0, err);
        if (rc == TS_OK && port->explicit_step(port->ctx, y0) > 0)
            pt->macro_step = dc->engine_macro_step;
        free(y0);
        if (rc != TS_OK) {
            ts_powertrain_free(pt);
            return NULL;
        }
    }
    return pt;
}

ts_powertrain *ts_powertrain_make(const ts_config *cfg, ts_err *err)
{
    ts_engine_port port;
    memset(&port, 0, sizeof port);
    if (bind_engine(cfg, &port, err) != TS_OK) return NULL;
    return ts_powertrain_make_port(cfg, &port, err);
}

ts_rc ts_powertrain_idle_start(ts_powertrain *pt, ts_err *err)
{
    if (pt->engine.reset != engine_reset) return TS_OK; /* an engine bound through a port */
    engine_ctx *c = pt->engine.ctx;
    if (ts_engine_get_fidelity(c->e) == TS_ENGINE_MAP || c->idle) return TS_OK;
    double *y = malloc(sizeof *y * (size_t)pt->engine.nstate);
    if (!y) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    ts_tc_point tc; /* the converter at stall: turbine at rest with the vehicle */
    ts_torque_converter_eval(&pt->tc, c->w0, 0.0, &tc);
    ts_rc rc = ts_engine_idle_state(c->e, c->w0, tc.pump_torque, c->p_amb, c->T_amb, y, NULL, err);
    if (rc != TS_OK) {
        if (rc == TS_ERR_DIVERGED && err && !err->pointer[0]) /* the launch speed sets the load */
            snprintf(err->pointer, sizeof err->pointer, "/driveline/launch_engine_speed");
        free(y);
        return rc;
    }
    c->idle = y;
    return TS_OK;
}

void ts_powertrain_free(ts_powertrain *pt)
{
    if (!pt) return;
    if (pt->engine.free) pt->engine.free(pt->engine.ctx);
    free(pt);
}

int ts_powertrain_nstate(const ts_powertrain *pt) { return pt->nstate; }
int ts_powertrain_nroots(const ts_powertrain *pt) { (void)pt; return TS_TRANSMISSION_NROOTS; }
int ts_powertrain_engine_speed_index(const ts_powertrain *pt) { return pt->engine.speed_index; }
double ts_powertrain_output_inertia(const ts_powertrain *pt) { return pt->fd.output_inertia; }
double ts_powertrain_sprocket_radius(const ts_powertrain *pt) { return pt->fd.sprocket_radius; }

double ts_powertrain_explicit_step(const ts_powertrain *pt, const double *y)
{
    double h = pt->macro_step > 0 ? pt->macro_step
               : pt->engine.explicit_step ? pt->engine.explicit_step(pt->engine.ctx, y)
                                          : 0.0;
    if (!(h > 0)) return 0.0;
    /* RK4 is stable for h |lambda| < 2.78; the applied clutch's regularised
     * friction gives lambda = C / (w_s J_t) on the turbine */
    double h_clutch = 2.0 * pt->tr.slip_speed * pt->turbine_inertia / pt->tr.clutch_capacity;
    return h < h_clutch ? h : h_clutch;
}

double ts_powertrain_macro_step(const ts_powertrain *pt) { return pt->macro_step; }

size_t ts_powertrain_work_size(const ts_powertrain *pt)
{
    return pt->macro_step > 0 ? pt->engine.work_size : 0;
}

/* The engine's load during a macro step: converter pump torque at the
 * engine's speed with the turbine speed held. */
typedef struct pump_load {
    const ts_powertrain *pt;
    double w_t;
} pump_load;

static double pump_torque(void *ud, double t, double w_e)
{
    (void)t;
    const pump_load *l = ud;
    ts_tc_point tc;
    ts_torque_converter_eval(&l->pt->tc, w_e, l->w_t, &tc);
    return tc.pump_torque;
}

ts_rc ts_powertrain_engine_advance(const ts_powertrain *pt, double t, double H, double *y,
                                   double rack, double *work, ts_err *err)
{
    if (!(pt->macro_step > 0))
        return ts_err_set(err, TS_ERR_INTERNAL, NULL, "engine is not co-simulated");
    pump_load l = {pt, y[pt->engine.nstate]};
    ts_rc rc = pt->engine.advance(pt->engine.ctx, y, t, H, rack, pt->pump_inertia, pump_torque, &l,
                                  work, err);
    if (rc == TS_OK && !isfinite(y[pt->engine.speed_index]))
        rc = ts_err_set(err, TS_ERR_DIVERGED, NULL, "engine speed not finite at t = %.6f s", t);
    return rc;
}

void ts_powertrain_scale(const ts_powertrain *pt, double *scale)
{
    int ne = pt->engine.nstate;
    if (pt->engine.scale) pt->engine.scale(pt->engine.ctx, scale);
    else
        for (int i = 0; i < ne; i++) scale[i] = 1.0;
    scale[ne] = 100.0; /* turbine speed, rad/s */
}

ts_rc ts_powertrain_reset(const ts_powertrain *pt, ts_powertrain_state *ps, double *y,
                          double w_sprocket, ts_err *err)
{
    ts_rc rc = pt->engine.reset(pt->engine.ctx, y, err);
    if (rc != TS_OK) return rc;
    ts_transmission_reset(&pt->tr, &ps->shift, 1);
    y[pt->engine.nstate] = pt->tr.ratio[0] * ts_final_drive_output_speed(&pt->fd, w_sprocket);
    return TS_OK;
}

/* Every shaft's speed and torque from the pieces of one evaluation. */
static void fill_out(const ts_powertrain *pt, double w_sprocket, double rack, double w_e,
                     double w_t, double w_out, const ts_tc_point *tc, const ts_tr_point *tp,
                     const ts_engine_obs *obs, ts_powertrain_out *out)
{
    out->sprocket_torque = ts_final_drive_sprocket_torque(&pt->fd, tp->output_torque);
    out->sprocket_speed = w_sprocket;
    out->rack = rack;
    out->engine_speed = w_e;
    out->engine_torque = obs->brake_torque;
    out->engine_power = obs->brake_torque * w_e;
    out->boost = obs->boost;
    out->exhaust_temp = obs->exhaust_temp;
    out->turbo_speed = obs->turbo_speed;
    out->piston_temp = obs->piston_temp;
    out->fuel_flow = obs->fuel_flow;
    out->pump_torque = tc->pump_torque;
    out->turbine_torque = tc->turbine_torque;
    out->turbine_speed = w_t;
    out->speed_ratio = w_e > 0 ? w_t / w_e : 0.0;
    out->torque_ratio = tc->torque_ratio;
    out->tc_efficiency = tc->efficiency;
    out->gear = tp->gear;
    out->clutch_offgoing = tp->offgoing_torque;
    out->clutch_oncoming = tp->oncoming_torque;
    out->out_speed = w_out;
    out->out_torque = tp->output_torque;
}

int ts_powertrain_rhs(const ts_powertrain *pt, const ts_powertrain_state *ps, double t,
                      const double *y, double w_sprocket, double rack, double *ydot,
                      ts_powertrain_out *out)
{
    const ts_engine_port *e = &pt->engine;
    int ne = e->nstate;
    double w_e = y[e->speed_index], w_t = y[ne];
    double w_out = ts_final_drive_output_speed(&pt->fd, w_sprocket);
    ts_tc_point tc;
    ts_torque_converter_eval(&pt->tc, w_e, w_t, &tc);
    ts_engine_obs obs;
    int rc = e->rhs(e->ctx, t, y, rack, tc.pump_torque, ydot, &obs);
    if (rc != 0) return rc;
    /* the pump turns with the crankshaft: same torque imbalance, larger inertia */
    ydot[e->speed_index] *= pt->crank_share;
    ts_tr_point tp;
    ts_transmission_eval(&pt->tr, &ps->shift, t, w_t, w_out, &tp);
    ydot[ne] = (tc.turbine_torque - tp.input_torque) / pt->turbine_inertia;
    if (out) fill_out(pt, w_sprocket, rack, w_e, w_t, w_out, &tc, &tp, &obs, out);
    return 0;
}

void ts_powertrain_rhs_driveline(const ts_powertrain *pt, const ts_powertrain_state *ps, double t,
                                 const double *y, double w_sprocket, double rack, double *ydot,
                                 ts_powertrain_out *out)
{
    int ne = pt->engine.nstate;
    double w_e = y[pt->engine.speed_index], w_t = y[ne];
    double w_out = ts_final_drive_output_speed(&pt->fd, w_sprocket);
    ts_tc_point tc;
    ts_torque_converter_eval(&pt->tc, w_e, w_t, &tc);
    ts_tr_point tp;
    ts_transmission_eval(&pt->tr, &ps->shift, t, w_t, w_out, &tp);
    ydot[ne] = (tc.turbine_torque - tp.input_torque) / pt->turbine_inertia;
    if (out) {
        ts_engine_obs obs = {.speed = w_e};
        fill_out(pt, w_sprocket, rack, w_e, w_t, w_out, &tc, &tp, &obs, out);
    }
}

ts_rc ts_powertrain_rhs_failed(double t, ts_err *err)
{
    return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                      "the powertrain's equations cannot be evaluated at t = %.6f s (the "
                      "engine's state is outside its domain)",
                      t);
}

void ts_powertrain_roots(const ts_powertrain *pt, const ts_powertrain_state *ps, double t,
                         const double *y, double w_sprocket, double *g)
{
    ts_transmission_roots(&pt->tr, &ps->shift, t, y[pt->engine.speed_index],
                          ts_final_drive_output_speed(&pt->fd, w_sprocket), g);
}

static int update_once(const ts_powertrain *pt, ts_powertrain_state *ps, double t,
                       const double *y, double w_sprocket)
{
    double w_e = y[pt->engine.speed_index], w_t = y[pt->engine.nstate];
    /* input torque now, for the shift-clutch capacity */
    double w_out = ts_final_drive_output_speed(&pt->fd, w_sprocket);
    ts_tr_point tp;
    ts_transmission_eval(&pt->tr, &ps->shift, t, w_t, w_out, &tp);
    return ts_transmission_update(&pt->tr, &ps->shift, t, w_e, w_out, tp.input_torque);
}

#define MAX_EVENTS_AT_ONCE 8 /* discrete updates at one event time */

int ts_powertrain_update(const ts_powertrain *pt, ts_powertrain_state *ps, double t,
                         const double *y, double w_sprocket)
{
    int changed = 0;
    for (int k = 0; k < MAX_EVENTS_AT_ONCE && update_once(pt, ps, t, y, w_sprocket); k++)
        changed = 1;
    return changed;
}

/* Each channel and what the engine must model for it (engine.h TS_ENGINE_MODELS_*
 * bits; 0: every engine). */
static const ts_channel_need channels[TS_POWERTRAIN_NCHANNEL] = {
    {{"engine.speed", "rad/s", "crankshaft speed (= converter pump speed)"}, 0},
    {{"engine.torque", "N*m", "engine brake torque"}, 0},
    {{"engine.power", "W", "engine brake power"}, 0},
    {{"intake.pressure", "Pa", "intake manifold pressure (boost)"}, 0},
    {{"rack", "1", "fuel rack (driver demand) seen by the engine"}, 0},
    {{"tc.pump.speed", "rad/s", "torque-converter pump speed"}, 0},
    {{"tc.turbine.speed", "rad/s", "torque-converter turbine speed (= transmission input)"}, 0},
    {{"tc.pump.torque", "N*m", "torque-converter pump torque (load on the engine)"}, 0},
    {{"tc.turbine.torque", "N*m", "torque-converter turbine (output) torque"}, 0},
    {{"tc.speed_ratio", "1", "converter speed ratio turbine/pump"}, 0},
    {{"tc.torque_ratio", "1", "converter torque ratio turbine/pump"}, 0},
    {{"tc.efficiency", "1", "converter efficiency TR*SR"}, 0},
    {{"tc.slip", "rad/s", "converter slip, pump minus turbine speed"}, 0},
    {{"transmission.gear", "1", "engaged gear (fractional while a shift is in progress)"}, 0},
    {{"transmission.out.speed", "rad/s", "transmission output speed"}, 0},
    {{"transmission.out.torque", "N*m", "transmission output (propshaft) torque"}, 0},
    {{"transmission.clutch.offgoing", "N*m", "engaged/off-going range-clutch torque, input side"},
     0},
    {{"transmission.clutch.oncoming", "N*m",
      "on-coming range-clutch torque during a shift, input side"},
     0},
    {{"driveshaft.torque", "N*m", "torque in each drive shaft, differential to sprocket"}, 0},
    {{"driveshaft.speed", "rad/s", "drive-shaft (= sprocket) speed"}, 0},
    {{"exhaust.temperature", "K", "exhaust manifold temperature (Fig. 21c)"},
     TS_ENGINE_MODELS_MANIFOLDS},
    {{"turbo.speed", "rad/s", "turbocharger rotor speed"}, TS_ENGINE_MODELS_MANIFOLDS},
    {{"piston.surface_temperature", "K", "piston gas-side surface temperature (Fig. 21b)"},
     TS_ENGINE_MODELS_CYLINDERS},
    {{"engine.fuel_flow", "kg/s", "fuel mass flow, whole engine"}, 0},
};

/* Whether channel i of the table above is one of pt's (its engine models it). */
static int present(const ts_powertrain *pt, int i)
{
    return ts_engine_models_all(pt->engine.models, channels[i].needs);
}

/* The channels of pt's engine, in the order above (stored sessions match it
 * by name and order, server/channels.c). */
static void channels_of(ts_powertrain *pt)
{
    pt->nch = 0;
    for (int i = 0; i < TS_POWERTRAIN_NCHANNEL; i++)
        if (present(pt, i)) pt->ch[pt->nch++] = channels[i].ch;
}

const ts_channel *ts_powertrain_channels(const ts_powertrain *pt)
{
    return pt->ch;
}

int ts_powertrain_nchannel(const ts_powertrain *pt)
{
    return pt->nch;
}

void ts_powertrain_channel_values(const ts_powertrain *pt, const ts_powertrain_out *o, double *v)
{
    double row[TS_POWERTRAIN_NCHANNEL] = {
        o->engine_speed,
        o->engine_torque,
        o->engine_power,
        o->boost,
        o->rack,
        o->engine_speed,
        o->turbine_speed,
        o->pump_torque,
        o->turbine_torque,
        o->speed_ratio,
        o->torque_ratio,
        o->tc_efficiency,
        o->engine_speed - o->turbine_speed,
        o->gear,
        o->out_speed,
        o->out_torque,
        o->clutch_offgoing,
        o->clutch_oncoming,
        o->sprocket_torque,
        o->sprocket_speed,
        o->exhaust_temp,
        o->turbo_speed,
        o->piston_temp,
        o->fuel_flow /* no trailing comma: clang-format keeps the columns */
    };
    for (int i = 0, k = 0; i < TS_POWERTRAIN_NCHANNEL; i++)
        if (present(pt, i)) v[k++] = row[i];
}

/* ---- the powertrain on its own integrator ---------------------------------- */


struct ts_powertrain_sim {
    const ts_powertrain *pt;
    ts_ode *ode;
    ts_powertrain_state ps;
    double t, rack;
    ts_sprocket_speed_fn w;
    void *w_ud;
    double *y;   /* nstate: state at t */
    double *tmp; /* nstate: scratch (derivatives, tolerances) */
    double *k;   /* 5 nstate: RK4 stages (explicit path) */
    double *work; /* engine co-simulation scratch (ts_powertrain_work_size) */
};

static double sim_w(const ts_powertrain_sim *s, double t)
{
    return s->w ? s->w(s->w_ud, t) : 0.0;
}

static int sim_rhs(double t, const double *y, double *ydot, void *ud)
{
    const ts_powertrain_sim *s = ud;
    return ts_powertrain_rhs(s->pt, &s->ps, t, y, sim_w(s, t), s->rack, ydot, NULL);
}

static int sim_roots(double t, const double *y, double *g, void *ud)
{
    const ts_powertrain_sim *s = ud;
    ts_powertrain_roots(s->pt, &s->ps, t, y, sim_w(s, t), g);
    return 0;
}

ts_powertrain_sim *ts_powertrain_sim_make(const ts_powertrain *pt, double rtol, double atol,
                                          double max_step, ts_err *err)
{
    ts_powertrain_sim *s = calloc(1, sizeof *s);
    int n = pt->nstate;
    if (s) s->y = calloc(7 * (size_t)n, sizeof *s->y);
    if (!s || !s->y) {
        free(s);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    s->pt = pt;
    size_t nw = ts_powertrain_work_size(pt);
    if (nw && !(s->work = malloc(nw * sizeof *s->work))) {
        ts_powertrain_sim_free(s);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    s->tmp = s->y + n;
    s->k = s->y + 2 * n;
    ts_powertrain_scale(pt, s->tmp);
    for (int i = 0; i < n; i++) s->tmp[i] *= atol;
    ts_ode_opts o = {.rtol = rtol, .atol = atol, .atol_v = s->tmp, .max_step = max_step,
                     .nroots = ts_powertrain_nroots(pt), .roots = sim_roots};
    s->ode = ts_ode_make(n, sim_rhs, s, &o, err);
    if (!s->ode) {
        ts_powertrain_sim_free(s);
        return NULL;
    }
    return s;
}

void ts_powertrain_sim_free(ts_powertrain_sim *s)
{
    if (!s) return;
    ts_ode_free(s->ode);
    free(s->work);
    free(s->y);
    free(s);
}

static ts_rc sim_settle(ts_powertrain_sim *s, ts_err *err)
{
    return ts_powertrain_update(s->pt, &s->ps, s->t, s->y, sim_w(s, s->t))
               ? ts_ode_init(s->ode, s->t, s->y, err)
               : TS_OK;
}

ts_rc ts_powertrain_sim_reset(ts_powertrain_sim *s, double t0, double w0, ts_err *err)
{
    ts_rc rc = ts_powertrain_reset(s->pt, &s->ps, s->y, w0, err);
    if (rc != TS_OK) return rc;
    s->t = t0;
    return ts_ode_init(s->ode, t0, s->y, err);
}

/* Explicit path (crank-angle engine): RK4 at ts_powertrain_explicit_step, the
 * shift state machine at every step end (as scenario_pointmass.c). */
static ts_rc sim_advance_explicit(ts_powertrain_sim *s, double t_to, ts_err *err)
{
    while (s->t < t_to - 1e-12 * (1.0 + fabs(t_to))) {
        double h = ts_powertrain_explicit_step(s->pt, s->y), t = s->t;
        if (t + h > t_to) h = t_to - t;
        if (ts_rk4_step(s->pt->nstate, sim_rhs, s, t, h, s->y, s->k))
            return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                              "powertrain state left its domain at t = %.6f s", t);
        s->t = t + h;
        ts_powertrain_update(s->pt, &s->ps, s->t, s->y, sim_w(s, s->t));
    }
    s->t = t_to;
    return TS_OK;
}

/* The driveline's right-hand side with the engine held (ts_rk4_step_subset). */
static int sim_rhs_driveline(double t, const double *y, double *ydot, void *ud)
{
    ts_powertrain_sim *s = ud;
    ts_powertrain_rhs_driveline(s->pt, &s->ps, t, y, sim_w(s, t), s->rack, ydot, NULL);
    return 0;
}

/* Co-simulation path (powertrain.h): per macro step the engine advances
 * itself, then RK4 sub-steps of the turbine with the engine speed held. */
static ts_rc sim_advance_cosim(ts_powertrain_sim *s, double t_to, ts_err *err)
{
    const ts_powertrain *pt = s->pt;
    const int it = pt->nstate - 1; /* turbine */
    double *y = s->y, work[5];
    while (s->t < t_to - 1e-12 * (1.0 + fabs(t_to))) {
        double t_end = s->t + pt->macro_step;
        if (t_end > t_to - 1e-12 * (1.0 + fabs(t_to))) t_end = t_to;
        ts_rc rc = ts_powertrain_engine_advance(pt, s->t, t_end - s->t, y, s->rack, s->work, err);
        if (rc != TS_OK) return rc;
        while (s->t < t_end - 1e-12 * (1.0 + fabs(t_end))) {
            double h = ts_powertrain_explicit_step(pt, y), t = s->t;
            if (t + h > t_end) h = t_end - t;
            if (ts_rk4_step_subset(1, &it, sim_rhs_driveline, s, t, h, y, s->tmp, work))
                return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                                  "turbine speed not finite at t = %.6f s", t);
            s->t = t + h;
            ts_powertrain_update(pt, &s->ps, s->t, y, sim_w(s, s->t));
        }
        s->t = t_end;
    }
    s->t = t_to;
    return TS_OK;
}

/* The outputs at the end of an advance (out may be NULL). */
static ts_rc sim_out(ts_powertrain_sim *s, double rack, ts_powertrain_out *out, ts_err *err)
{
    if (out && ts_powertrain_rhs(s->pt, &s->ps, s->t, s->y, sim_w(s, s->t), rack, s->tmp, out) != 0)
        return ts_powertrain_rhs_failed(s->t, err);
    return TS_OK;
}

ts_rc ts_powertrain_sim_advance(ts_powertrain_sim *s, double t_to, ts_sprocket_speed_fn w,
                                void *ud, double rack, ts_powertrain_out *out, ts_err *err)
{
    int n = s->pt->nstate;
    if (ts_powertrain_explicit_step(s->pt, s->y) > 0) {
        s->w = w;
        s->w_ud = ud;
        s->rack = rack;
        ts_rc rc = s->pt->macro_step > 0 ? sim_advance_cosim(s, t_to, err)
                                         : sim_advance_explicit(s, t_to, err);
        return rc == TS_OK ? sim_out(s, rack, out, err) : rc;
    }
    int inputs_changed = s->w != w || s->w_ud != ud || s->rack != rack;
    s->w = w;
    s->w_ud = ud;
    s->rack = rack;
    ts_rc rc = TS_OK;
    /* new input functions are a discontinuity of the right-hand side */
    if (inputs_changed) rc = ts_ode_init(s->ode, s->t, s->y, err);
    if (rc == TS_OK) rc = sim_settle(s, err);
    while (rc == TS_OK && s->t < t_to) {
        int root = 0;
        rc = ts_ode_advance(s->ode, t_to, &s->t, &root, err);
        if (rc != TS_OK) break;
        memcpy(s->y, ts_ode_y(s->ode), sizeof *s->y * (size_t)n);
        if (root) rc = sim_settle(s, err);
    }
    return rc == TS_OK ? sim_out(s, rack, out, err) : rc;
}

double ts_powertrain_sim_time(const ts_powertrain_sim *s) { return s->t; }
const double *ts_powertrain_sim_y(const ts_powertrain_sim *s) { return s->y; }
const ts_powertrain_state *ts_powertrain_sim_state(const ts_powertrain_sim *s) { return &s->ps; }

size_t ts_powertrain_sim_state_size(const ts_powertrain_sim *s)
{
    return sizeof(double) * (1 + (size_t)s->pt->nstate) + sizeof(ts_powertrain_state);
}

void ts_powertrain_sim_save(const ts_powertrain_sim *s, void *buf)
{
    char *b = buf;
    memcpy(b, &s->t, sizeof(double));
    memcpy(b + sizeof(double), s->y, sizeof(double) * (size_t)s->pt->nstate);
    memcpy(b + sizeof(double) * (1 + (size_t)s->pt->nstate), &s->ps, sizeof s->ps);
}

ts_rc ts_powertrain_sim_restore(ts_powertrain_sim *s, const void *buf, ts_err *err)
{
    const char *b = buf;
    memcpy(&s->t, b, sizeof(double));
    memcpy(s->y, b + sizeof(double), sizeof(double) * (size_t)s->pt->nstate);
    memcpy(&s->ps, b + sizeof(double) * (1 + (size_t)s->pt->nstate), sizeof s->ps);
    return ts_ode_init(s->ode, s->t, s->y, err);
}
