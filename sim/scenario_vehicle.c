/*
 * scenario_vehicle.c — the "vehicle" run kind: the pitch-plane M1 of paper
 * Section II (vehicle_model.h) on a terrain (terrain.h), driven by a prescribed
 * sprocket torque (drive.h), integrated by CVODE (solver.h) from its static
 * equilibrium. Section II.D's runs are the presets bump-prescribed-*.json.
 *
 * Channels: fixed names, a stable API (vehicle.x, vehicle.speed, hull.z,
 * hull.pitch, hull.accel_x, track.tension.rear_roller, roller.rear.normal_force,
 * sprocket.torque, sprocket.speed) plus per-span mid-span tension and dynamic
 * transverse deflection, every road-arm angle and road-wheel load, the anchor
 * force, the quasi-static (massless-track) rear-roller tension of the current
 * support positions. Values are per side (one track) except the torque, which
 * is at EACH sprocket. Metrics: top speed, static and peak rear-roller
 * tension, the dynamic amplification over the quasi-static tension (Fig. 12),
 * spectra peaks (fft.h).
 * Leaves out: the powertrain drive (kind "powertrain" is refused here).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "drive.h"
#include "fft.h"
#include "scenario.h"
#include "vehicle_channels.h"
#include "solver.h"
#include "vehicle_model.h"


enum {
    CH_V0 = 1, /* the vehicle channel block (vehicle_channels.h), after "t" */
    CH_SPEED = CH_V0 + VM_CH_SPEED,
    CH_AX = CH_V0 + VM_CH_AX,
    CH_T_RR = CH_V0 + VM_CH_T_RR,
    CH_N_RR = CH_V0 + VM_CH_N_RR,
    CH_T_QS = CH_V0 + VM_CH_T_QS,
    CH_TORQUE = CH_V0 + VM_NCH,
    CH_SPR_SPEED,
    NCH
};

typedef struct veh_model {
    vm *v;
} veh_model;

typedef struct veh_data {
    ts_ode *ode;
    vm_work *w;
    double *y, *ydot, *atol;
} veh_data;

static int rhs(double t, const double *y, double *ydot, void *ud)
{
    const ts_data *d = ud;
    const veh_model *vm_ = d->m->impl;
    veh_data *p = d->impl;
    return vm_rhs(vm_->v, p->w, t, y, ydot, NULL);
}

static ts_rc model_init(ts_model *m, ts_err *err)
{
    ts_rc rc = ts_drive_check(&m->cfg.drive, err);
    if (rc != TS_OK) return rc;
    if (m->cfg.drive.kind == TS_DRIVE_POWERTRAIN)
        return ts_err_set(err, TS_ERR_UNSUPPORTED, "/drive/kind",
                          "/drive/kind: the vehicle scenario takes a prescribed torque; the "
                          "powertrain drive belongs to the coupled run");
    if (m->cfg.vehicle.grade != 0) /* it was ignored without a word */
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/grade",
                          "/vehicle/grade: the multibody vehicle takes its slope from the ground "
                          "(/terrain, e.g. a profile rising at the grade); /vehicle/grade is the "
                          "point mass's");
    veh_model *vmm = calloc(1, sizeof *vmm);
    if (!vmm) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    m->impl = vmm;
    vmm->v = vm_make(&m->cfg, err);
    if (!vmm->v) return err ? err->code : TS_ERR_INTERNAL;
    m->dof = vm_dof(vmm->v);
    m->nstate = vm_ny(vmm->v);
    static const ts_channel drive[] = {
        {"sprocket.torque", "N*m", "prescribed torque at each sprocket"},
        {"sprocket.speed", "rad/s", "sprocket speed relative to the hull"},
    };
    rc = vm_channels_declare(m, err);
    return rc == TS_OK ? ts_model_add_channels(m, drive, 2, err) : rc;
}

static void model_fini(ts_model *m)
{
    veh_model *vmm = m->impl;
    if (!vmm) return;
    vm_free(vmm->v);
    free(vmm);
    m->impl = NULL;
}

static void data_fini(const ts_model *m, ts_data *d);

static ts_rc data_init(const ts_model *m, ts_data *d, ts_err *err)
{
    const veh_model *vmm = m->impl;
    veh_data *p = calloc(1, sizeof *p);
    if (!p) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    d->impl = p;
    int ny = vm_ny(vmm->v);
    p->y = calloc((size_t)ny, sizeof(double));
    p->ydot = calloc((size_t)ny, sizeof(double));
    p->w = vm_work_make(vmm->v);
    if (!p->y || !p->ydot || !p->w) {
        data_fini(m, d);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    p->atol = calloc((size_t)ny, sizeof(double));
    if (!p->atol) {
        data_fini(m, d);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    vm_abs_tolerances(vmm->v, m->cfg.run.atol, p->atol);
    ts_ode_opts o = {.rtol = m->cfg.run.rtol,
                     .atol_v = p->atol,
                     .max_step = m->cfg.run.max_step,
                     .max_steps = 500000,
                     .second_order = 1,
                     .max_order = VM_BDF_MAX_ORDER,
                     .jac_eval_frequency = VM_JAC_EVAL_STEPS};
    /* one sample is one CVode call of at most max_steps steps: a cap that
     * cannot reach the next sample fails there, after minutes of work
     * (session-24 probe: 1e-6 s at 1 Hz gave CV_TOO_MUCH_WORK at t = 0.5 s) */
    double period = 1.0 / m->cfg.run.sample_rate;
    if (o.max_step > 0 && period / o.max_step > 0.9 * (double)o.max_steps) {
        data_fini(m, d);
        return ts_err_set(err, TS_ERR_RANGE, "/run/max_step",
                          "/run/max_step: %g s steps reach the next sample (%g s on, "
                          "/run/sample_rate) only in %.3g steps, past the integrator's %ld per "
                          "sample; raise max_step or the sample rate",
                          o.max_step, period, period / o.max_step, (long)o.max_steps);
    }
    p->ode = ts_ode_make(ny, rhs, d, &o, err);
    if (!p->ode) {
        data_fini(m, d);
        return err ? err->code : TS_ERR_SOLVER;
    }
    return TS_OK;
}

static void data_fini(const ts_model *m, ts_data *d)
{
    (void)m;
    veh_data *p = d->impl;
    if (!p) return;
    ts_ode_free(p->ode);
    vm_work_free(p->w);
    free(p->y);
    free(p->ydot);
    free(p->atol);
    free(p);
    d->impl = NULL;
}

static ts_rc reset(const ts_model *m, ts_data *d, ts_err *err)
{
    const veh_model *vmm = m->impl;
    veh_data *p = d->impl;
    memcpy(p->y, vm_equilibrium(vmm->v), (size_t)vm_ny(vmm->v) * sizeof(double));
    return ts_ode_init(p->ode, 0.0, p->y, err);
}

static ts_rc step_to(const ts_model *m, ts_data *d, double t, ts_err *err)
{
    const veh_model *vmm = m->impl;
    veh_data *p = d->impl;
    ts_rc rc = ts_ode_advance(p->ode, t, NULL, NULL, err);
    if (rc == TS_OK) {
        memcpy(p->y, ts_ode_y(p->ode), (size_t)vm_ny(vmm->v) * sizeof(double));
    } else { /* say where: a terrain the wheels cannot ride is the usual cause */
        vm_err_add_state(vmm->v, ts_ode_y(p->ode), err);
    }
    return rc;
}

static ts_rc sample(const ts_model *m, const ts_data *d, double *out, ts_err *err)
{
    const veh_model *vmm = m->impl;
    veh_data *p = d->impl;
    const vm *v = vmm->v;
    vm_diag dg;
    memset(&dg, 0, sizeof dg);
    if (vm_rhs(v, p->w, d->t, p->y, p->ydot, &dg) != 0) return vm_rhs_failed(v, d->t, p->y, err);
    vm_channels_fill(v, p->y, p->ydot, &dg, out + CH_V0);
    out[CH_TORQUE] = dg.drive_torque;
    out[CH_SPR_SPEED] = p->y[vm_nq(v) + 10 + VM_SPROCKET] - p->y[vm_nq(v) + 2];
    return TS_OK;
}

static int integrator_stats(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max)
{
    (void)m, (void)max;
    const veh_data *p = d->impl;
    ts_integrator_stats_of_ode(p->ode, "vehicle",
                               "CVODE BDF (order <= 3), Newton, Schur-complement solves", out);
    return 1;
}

static size_t state_size(const ts_model *m)
{
    const veh_model *vmm = m->impl;
    return sizeof(double) * (size_t)vm_ny(vmm->v);
}

static ts_rc state_save(const ts_model *m, const ts_data *d, void *buf, ts_err *err)
{
    (void)err;
    const veh_data *p = d->impl;
    memcpy(buf, p->y, state_size(m));
    return TS_OK;
}

static ts_rc state_restore(const ts_model *m, ts_data *d, const void *buf, ts_err *err)
{
    veh_data *p = d->impl;
    memcpy(p->y, buf, state_size(m));
    return ts_ode_init(p->ode, d->t, p->y, err);
}

/* Spectrum peak of channel ch over rows, in [f0, f1]. */
/* Peak of the amplitude spectrum of channel ch (less channel minus, if >= 0)
 * in [f0, f1) Hz; its amplitude in *amp. */
static double spectrum_peak(const ts_model *m, const double *rows, long nrows, int ch, int minus,
                            double f0, double f1, double *amp)
{
    int nc = m->nchannel;
    *amp = NAN;
    if (nrows < 64) return NAN;
    double *x = malloc(sizeof(double) * (size_t)nrows);
    int nb = ts_fft_nbins((int)nrows);
    double *fr = malloc(sizeof(double) * (size_t)nb), *am = malloc(sizeof(double) * (size_t)nb);
    double f = NAN;
    if (x && fr && am) {
        for (long i = 0; i < nrows; i++)
            x[i] = rows[i * nc + ch] - (minus >= 0 ? rows[i * nc + minus] : 0);
        if (ts_fft_amplitude(x, (int)nrows, m->cfg.run.sample_rate, TS_FFT_LINEAR, TS_FFT_HANN, fr,
                             am, NULL) == TS_OK)
            f = ts_fft_peak(fr, am, nb, f0, f1, amp);
    }
    free(x);
    free(fr);
    free(am);
    return f;
}

static int metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max)
{
    const veh_model *vmm = m->impl;
    int nc = m->nchannel, n = 0;
    double vmax = 0, tmax = 0, amax = 0, nmax = 0, qsmax = 0, dmax = -INFINITY, d2 = 0;
    for (long i = 0; i < nrows; i++) {
        const double *r = rows + i * nc;
        vmax = fmax(vmax, r[CH_SPEED]);
        tmax = fmax(tmax, r[CH_T_RR]);
        amax = fmax(amax, fabs(r[CH_AX]));
        nmax = fmax(nmax, fabs(r[CH_N_RR]));
        /* the dynamic part of the rear-roller tension: over the quasi-static
         * (massless-track) tension of the same support positions and torque */
        double dyn = r[CH_T_RR] - r[CH_T_QS];
        qsmax = fmax(qsmax, r[CH_T_QS]);
        dmax = fmax(dmax, dyn);
        d2 += dyn * dyn;
    }
    double t0 = vm_static_tension(vmm->v);
    n = ts_metric_add(out, n, max, "dof", "1", m->dof,
                      "mechanical degrees of freedom (paper: 21/26/31)");
    n = ts_metric_add(out, n, max, "top_speed_mph", "mph", vmax / TS_MPH,
                      "highest speed, here the speed at the end of the run (paper II.D: ~25 mph; the "
                      "prescribed torque is calibrated to it [C II.D])");
    n = ts_metric_add(out, n, max, "static_tension", "N", t0,
                      "track tension at the rear roller at rest at t = 0 (the tensioner setting P0 "
                      "on level ground)");
    n = ts_metric_add(
        out, n, max, "peak_tension", "N", tmax,
        "peak rear-roller tension (paper Fig. 12: ~30,000 lb = 133 kN; its level rests on "
        "the static tension P0, inferred from that statement)");
    n = ts_metric_add(out, n, max, "peak_tension_lb", "lbf", tmax / TS_LBF, "the same in lbf");
    n = ts_metric_add(out, n, max, "tension_amplification", "1", t0 > 0 ? tmax / t0 : NAN,
                      "peak over static tension (paper: nearly 2; predicted)");
    n = ts_metric_add(out, n, max, "quasi_static_peak_tension_lb", "lbf", qsmax / TS_LBF,
                      "peak of track.tension.quasi_static: what the suspension travel alone "
                      "(loop-length change, massless track) gives");
    n = ts_metric_add(out, n, max, "dynamic_amplification_max", "1",
                      nrows > 0 && t0 > 0 ? dmax / t0 : NAN,
                      "max(rear-roller tension - quasi-static tension) / static tension: the "
                      "dynamic amplification of Fig. 12 (~0 for the static model)");
    n = ts_metric_add(out, n, max, "dynamic_amplification_rms", "1",
                      nrows > 0 && t0 > 0 ? sqrt(d2 / (double)nrows) / t0 : NAN,
                      "RMS(rear-roller tension - quasi-static tension) / static tension");
    n = ts_metric_add(out, n, max, "peak_abs_accel_x", "m/s^2", amax,
                      "largest |hull.accel_x| (Fig. 11)");
    n = ts_metric_add(out, n, max, "peak_abs_roller_force", "N", nmax,
                      "largest |roller.rear.normal_force|");
    double a;
    double f = spectrum_peak(m, rows, nrows, CH_T_RR, -1, 2.0, 6.0, &a);
    n = ts_metric_add(out, n, max, "tension_peak_2_6hz", "Hz", f,
                      "tension spectrum peak in 2-6 Hz (paper Fig. 13c: 3.7 Hz; the circuit mode's "
                      "frequency follows the roller layout calibrated to Fig. 5)");
    n = ts_metric_add(out, n, max, "tension_peak_2_6hz_amp", "N", a, "its amplitude");
    f = spectrum_peak(m, rows, nrows, CH_T_RR, -1, 13.0, 20.0, &a);
    n = ts_metric_add(
        out, n, max, "tension_peak_13_20hz", "Hz", f,
        "tension spectrum peak in 13-20 Hz (paper Fig. 13b-c: 14.0 Hz; on the bump course "
        "the course's line v / 2 ft, not a calibrated track mode: README)");
    n = ts_metric_add(out, n, max, "tension_peak_13_20hz_amp", "N", a, "its amplitude");
    /* the same on the dynamic part alone (tension less the quasi-static tension
     * of the same support positions): what the track's own vibration adds, free
     * of the suspension travel's loop-length response to the course */
    f = spectrum_peak(m, rows, nrows, CH_T_RR, CH_T_QS, 2.0, 4.6, &a);
    n = ts_metric_add(out, n, max, "dynamic_tension_peak_2_4.6hz", "Hz", f,
                      "spectrum peak of (tension - quasi-static tension) in 2-4.6 Hz "
                      "(paper Fig. 13c: 3.7 Hz, coupled model only)");
    n = ts_metric_add(out, n, max, "dynamic_tension_peak_2_4.6hz_amp", "N", a, "its amplitude");
    f = spectrum_peak(m, rows, nrows, CH_T_RR, CH_T_QS, 13.0, 20.0, &a);
    n = ts_metric_add(out, n, max, "dynamic_tension_peak_13_20hz", "Hz", f,
                      "spectrum peak of (tension - quasi-static tension) in 13-20 Hz "
                      "(paper Fig. 13b-c: 14.0 Hz, both dynamic models)");
    n = ts_metric_add(out, n, max, "dynamic_tension_peak_13_20hz_amp", "N", a, "its amplitude");
    f = spectrum_peak(m, rows, nrows, CH_N_RR, -1, 2.0, 4.6, &a);
    n = ts_metric_add(
        out, n, max, "roller_force_peak_2_4.6hz", "Hz", f,
        "roller-force spectrum peak in 2-4.6 Hz (paper Fig. 14b: 3.7 Hz; mode frequency "
        "from the Fig. 5-calibrated layout)");
    n = ts_metric_add(out, n, max, "roller_force_peak_2_4.6hz_amp", "N", a, "its amplitude");
    f = spectrum_peak(m, rows, nrows, CH_N_RR, -1, 4.6, 7.0, &a);
    n = ts_metric_add(
        out, n, max, "roller_force_peak_4.6_7hz", "Hz", f,
        "roller-force spectrum peak in 4.6-7 Hz (paper Fig. 14b: 5.5 Hz; mode frequency "
        "from the Fig. 5-calibrated layout)");
    n = ts_metric_add(out, n, max, "roller_force_peak_4.6_7hz_amp", "N", a, "its amplitude");
    n = vm_channels_span_metrics(rows, nrows, nc, CH_V0, out, n, max);
    n = vm_channels_traction_metrics(rows, nrows, nc, CH_V0, m->cfg.vehicle.traction_limit, out, n,
                                     max);
    return n;
}

static ts_rc geometry(const ts_model *m, const ts_data *d, ts_geom *out, ts_err *err)
{
    (void)err;
    const veh_model *vmm = m->impl;
    veh_data *p = d->impl;
    vm_geometry(vmm->v, p->w, d->t, p->y, out);
    return TS_OK;
}

const ts_scenario_ops ts_scenario_vehicle = {
    .kind = "vehicle",
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
