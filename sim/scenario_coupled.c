/*
 * scenario_coupled.c — the "coupled" run kind: the integrated M1 of paper
 * Section IV (coupled_system.h): powertrain + pitch-plane multibody vehicle
 * with its track on the terrain, a fixed rack or the IVS controller through
 * the fuel actuator, coupled leading–following or monolithically
 * (/coupling/method). The paper's runs (Figs. 28-35) are the presets
 * {flat,bump}-coupled-*.json.
 *
 * Channels: the vehicle scenario's (vehicle.x, vehicle.speed, hull.*, track
 * tension at the rear roller, roller force, sprocket torque/speed, anchor
 * force, span mid-span tension and transverse deflection, road-arm angles,
 * road-wheel loads), the powertrain's (engine, converter, transmission, drive
 * shaft; powertrain.h), and the driver's (rack demand before the governor,
 * measured speed, speed error, integral). Per side except torques at EACH
 * sprocket. Metrics: see metrics() — shift times, time to target speed,
 * speed error and rack range after reaching it, tension peaks, engine-speed
 * range.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "coupled_system.h"
#include "scenario.h"
#include "vehicle_channels.h"

enum {
    CH_V0 = 1, /* the vehicle channel block (vehicle_channels.h), after "t" */
    CH_SPEED = CH_V0 + VM_CH_SPEED,
    CH_AX = CH_V0 + VM_CH_AX,
    CH_T_RR = CH_V0 + VM_CH_T_RR,
    CH_N_RR = CH_V0 + VM_CH_N_RR,
    CH_TORQUE = CH_V0 + VM_NCH,
    CH_SPR_SPEED,
    CH_SPR_ACCEL,
    CH_RACK_DEMAND,
    CH_V_MEAS,
    CH_ERR,
    CH_INTEGRAL,
    CH_PT0 /* then ts_powertrain_nchannel channels */
};
/* indices into the powertrain block (ts_powertrain_channel_values order) */
enum { PT_ENGINE_SPEED = 0, PT_RACK = 4, PT_TURBINE_SPEED = 6, PT_GEAR = 13 };

typedef struct cpl_data {
    ts_coupled_run *r;
    ts_coupled_obs obs;
} cpl_data;

static ts_rc model_init(ts_model *m, ts_err *err)
{
    const ts_control_config *cc = &m->cfg.control;
    if (m->cfg.vehicle.grade != 0 &&
        !(cc->mode == TS_CONTROL_IVS && cc->schedule_var == TS_SCHEDULE_GRADE &&
          cc->schedule_n > 0)) /* it was ignored without a word */
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/grade",
                          "/vehicle/grade: the multibody vehicle takes its slope from the ground "
                          "(/terrain, e.g. a profile rising at the grade); a coupled run reads "
                          "/vehicle/grade only to pick the IVS gains of a grade schedule");
    ts_coupled *c = ts_coupled_make(&m->cfg, err);
    if (!c) return err ? err->code : TS_ERR_INTERNAL;
    m->impl = c;
    m->dof = vm_dof(ts_coupled_vehicle(c));
    m->nstate = vm_ny(ts_coupled_vehicle(c)) + ts_powertrain_nstate(ts_coupled_powertrain(c)) + 1;
    static const ts_channel ch[] = {
        {"sprocket.torque", "N*m", "powertrain torque applied at each sprocket (Figs. 28, 31)"},
        {"sprocket.speed", "rad/s", "sprocket speed relative to the hull (Fig. 34)"},
        {"sprocket.accel", "rad/s^2",
         "sprocket acceleration relative to the hull (reported to the powertrain)"},
        {"rack.demand", "1", "driver or IVS rack before the governor (Fig. 33)"},
        {"control.speed_measured", "m/s",
         "vehicle speed the controller sees: sprocket speed x pitch radius"},
        {"control.error", "m/s", "IVS speed error, target minus measured (0 in rack mode)"},
        {"control.integral", "m", "IVS integral of the speed error (Eq. 10)"},
    };
    ts_rc rc = vm_channels_declare(m, err);
    if (rc == TS_OK) rc = ts_model_add_channels(m, ch, (int)(sizeof ch / sizeof ch[0]), err);
    if (rc == TS_OK)
        rc = ts_model_add_channels(m, ts_powertrain_channels(ts_coupled_powertrain(c)),
                                   ts_powertrain_nchannel(ts_coupled_powertrain(c)), err);
    return rc;
}

static void model_fini(ts_model *m)
{
    ts_coupled_free(m->impl);
    m->impl = NULL;
}

static ts_rc data_init(const ts_model *m, ts_data *d, ts_err *err)
{
    cpl_data *p = calloc(1, sizeof *p);
    if (!p) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    d->impl = p;
    p->r = ts_coupled_run_make(m->impl, m->cfg.coupling.method, err);
    if (p->r) return TS_OK;
    /* like the other scenarios, data_init undoes its own allocations on failure
     * (ts_data_make does not call data_fini then) */
    free(p);
    d->impl = NULL;
    return err ? err->code : TS_ERR_INTERNAL;
}

static void data_fini(const ts_model *m, ts_data *d)
{
    (void)m;
    cpl_data *p = d->impl;
    if (!p) return;
    ts_coupled_run_free(p->r);
    free(p);
    d->impl = NULL;
}

static ts_rc reset(const ts_model *m, ts_data *d, ts_err *err)
{
    (void)m;
    cpl_data *p = d->impl;
    return ts_coupled_run_reset(p->r, err);
}

static ts_rc step_to(const ts_model *m, ts_data *d, double t, ts_err *err)
{
    (void)m;
    cpl_data *p = d->impl;
    return ts_coupled_run_advance(p->r, t, err);
}

static ts_rc sample(const ts_model *m, const ts_data *d, double *out, ts_err *err)
{
    const ts_coupled *c = m->impl;
    cpl_data *p = d->impl;
    const vm *v = ts_coupled_vehicle(c);
    ts_coupled_obs *o = &p->obs;
    ts_rc rc = ts_coupled_run_observe(p->r, o, err);
    if (rc != TS_OK) return rc;
    vm_channels_fill(v, o->y_vehicle, o->ydot_vehicle, &o->diag, out + CH_V0);
    out[CH_TORQUE] = o->sprocket_torque;
    out[CH_SPR_SPEED] = o->sprocket_speed;
    out[CH_SPR_ACCEL] = o->sprocket_accel;
    out[CH_RACK_DEMAND] = o->rack_demand;
    out[CH_V_MEAS] = o->speed_measured;
    out[CH_ERR] = o->speed_error;
    out[CH_INTEGRAL] = o->integral;
    ts_powertrain_channel_values(ts_coupled_powertrain(c), &o->pt, out + CH_PT0);
    return TS_OK;
}

static int integrator_stats(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max)
{
    (void)m;
    const cpl_data *p = d->impl;
    return ts_coupled_run_integrators(p->r, out, max);
}

static size_t state_size(const ts_model *m)
{
    return ts_coupled_state_size(m->impl);
}

static ts_rc state_save(const ts_model *m, const ts_data *d, void *buf, ts_err *err)
{
    (void)m;
    (void)err;
    const cpl_data *p = d->impl;
    ts_coupled_run_save(p->r, buf);
    return TS_OK;
}

static ts_rc state_restore(const ts_model *m, ts_data *d, const void *buf, ts_err *err)
{
    (void)m;
    cpl_data *p = d->impl;
    return ts_coupled_run_restore(p->r, buf, err);
}

static int metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max)
{
    const ts_coupled *c = m->impl;
    int nc = m->nchannel, n = 0;
    if (nrows < 2) return 0;
    double vmax = 0, tmax = 0, tq_max = 0;
    for (long i = 0; i < nrows; i++) {
        const double *r = rows + i * nc;
        vmax = fmax(vmax, r[CH_SPEED]);
        tmax = fmax(tmax, r[CH_T_RR]);
        tq_max = fmax(tq_max, r[CH_TORQUE]);
    }
    const double *last = rows + (nrows - 1) * nc;
    n = ts_metric_add(out, n, max, "dof", "1", m->dof, "vehicle mechanical degrees of freedom");
    n = ts_metric_add(out, n, max, "top_speed_mph", "mph", vmax / TS_MPH, "top speed");
    n = ts_metric_add(out, n, max, "final_speed_mph", "mph", last[CH_SPEED] / TS_MPH,
                      "speed at the end of the run");
    n = ts_metric_add(
        out, n, max, "static_tension", "N", vm_static_tension(ts_coupled_vehicle(c)),
        "rear-roller tension at rest at t = 0 (the tensioner setting on level ground)");
    n = ts_metric_add(out, n, max, "peak_tension", "N", tmax, "peak rear-roller tension");
    n = ts_metric_add(out, n, max, "peak_tension_lb", "lbf", tmax / TS_LBF, "the same in lbf");
    n = ts_metric_add(out, n, max, "peak_sprocket_torque", "N*m", tq_max,
                      "peak torque at each sprocket (Fig. 28 converter multiplication)");
    n = vm_channels_span_metrics(rows, nrows, nc, CH_V0, out, n, max);
    n = vm_channels_traction_metrics(rows, nrows, nc, CH_V0, m->cfg.vehicle.traction_limit, out, n,
                                     max);
    n = ts_metric_add_upshifts(rows, nrows, nc, CH_PT0 + PT_GEAR, out, n, max);
    if (m->cfg.control.mode == TS_CONTROL_IVS) {
        double vt = m->cfg.control.target_speed;
        double t_hit = ts_rows_first_crossing(rows, nrows, nc, CH_SPEED, vt);
        n = ts_metric_add(
            out, n, max, "time_to_target", "s", t_hit,
            "first time the vehicle reaches the IVS set speed (paper Fig. 33: < 8 s; the "
            "presets' K_p is calibrated to Fig. 33's saturated launch [C Fig. 33])");
        double se = 0, sa = 0, rmin = INFINITY, rmax = -INFINITY, wmin = INFINITY, wmax = -INFINITY;
        long k = 0;
        for (long i = 0; i < nrows; i++) {
            const double *r = rows + i * nc;
            if (!(r[0] >= t_hit)) continue;
            se += r[CH_SPEED] - vt;
            sa += fabs(r[CH_SPEED] - vt);
            rmin = fmin(rmin, r[CH_RACK_DEMAND]);
            rmax = fmax(rmax, r[CH_RACK_DEMAND]);
            wmin = fmin(wmin, r[CH_PT0 + PT_ENGINE_SPEED]);
            wmax = fmax(wmax, r[CH_PT0 + PT_ENGINE_SPEED]);
            k++;
        }
        double rl = 0;
        for (long i = 0; i < nrows && rows[i * nc] <= 1.0; i++)
            rl = fmax(rl, rows[i * nc + CH_RACK_DEMAND]);
        n = ts_metric_add(out, n, max, "rack_at_launch", "1", rl,
                          "largest rack demand in the first second (Fig. 33: 1.0)");
        n = ts_metric_add(out, n, max, "mean_speed_error_mph", "mph", k ? se / k / TS_MPH : NAN,
                          "mean (speed - target) after first reaching the target");
        n = ts_metric_add(out, n, max, "mean_abs_speed_error_mph", "mph", k ? sa / k / TS_MPH : NAN,
                          "mean |speed - target| after first reaching the target");
        n = ts_metric_add(out, n, max, "rack_min", "1", k ? rmin : NAN,
                          "smallest rack demand after reaching the target (Fig. 33: ~0.1)");
        n = ts_metric_add(out, n, max, "rack_max", "1", k ? rmax : NAN,
                          "largest rack demand after reaching the target (Fig. 33: 1.0)");
        n = ts_metric_add(out, n, max, "engine_speed_min", "rad/s", k ? wmin : NAN,
                          "lowest engine speed after reaching the target (Fig. 34)");
        n = ts_metric_add(out, n, max, "engine_speed_max", "rad/s", k ? wmax : NAN,
                          "highest engine speed after reaching the target (Fig. 34)");
    }
    return n;
}

static ts_rc geometry(const ts_model *m, const ts_data *d, ts_geom *out, ts_err *err)
{
    const ts_coupled *c = m->impl;
    cpl_data *p = d->impl;
    ts_coupled_obs *o = &p->obs;
    ts_rc rc = ts_coupled_run_observe(p->r, o, err);
    if (rc != TS_OK) return rc;
    vm_work *w = vm_work_make(ts_coupled_vehicle(c));
    if (!w) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    vm_geometry(ts_coupled_vehicle(c), w, d->t, o->y_vehicle, out);
    vm_work_free(w);
    return TS_OK;
}

const ts_scenario_ops ts_scenario_coupled = {
    .kind = "coupled",
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
    .geometry = geometry,
    .integrator_stats = integrator_stats,
};
