/*
 * ivs_tune.c — the Ziegler–Nichols plant step of the IVS speed controller
 * (ivs_tune.h, Eqs. 11-12, Fig. 26). Moved here from cli/cmd_tune.c
 * unchanged in numerics and messages, so that `tanksim tune` and the daemon
 * tune with the same code. New over the CLI version: a settle too short to
 * give two samples is an error at /control/tune_settle (it used to crash),
 * and a failed allocation of the speed series is TS_ERR_NOMEM (it used to
 * surface as a cancelled run).
 */
#include "ivs_tune.h"

#include <math.h>
#include <stdlib.h>

#include "model.h"

/* The vehicle speed of a run, sample by sample (a ts_sample_fn's ud). */
typedef struct series {
    double *t, *v;
    long n, cap;
    int ch;  /* channel index of vehicle.speed */
    int oom; /* set when growing the arrays failed */
    ts_progress_fn poll; /* asked every POLL_SAMPLES samples whether to stop (may be NULL) */
    void *poll_ud;
    int done, total; /* handed to poll unchanged */
    int stopped;     /* set when poll said stop */
} series;

#define POLL_SAMPLES 16 /* samples between two polls: ~0.03 s of the 500-Hz runs */

/* ts_sample_fn: append values[ch] at t; non-zero (and oom set) when out of memory. */
static int keep(void *ud, long index, double t, const double *values, int n)
{
    (void)index;
    (void)n;
    series *s = ud;
    if (s->poll && s->n % POLL_SAMPLES == 0 && s->poll(s->poll_ud, s->done, s->total))
        return s->stopped = 1;
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 4096;
        double *tt = realloc(s->t, (size_t)cap * sizeof *tt);
        if (!tt) return s->oom = 1;
        s->t = tt;
        double *vv = realloc(s->v, (size_t)cap * sizeof *vv);
        if (!vv) return s->oom = 1;
        s->v = vv;
        s->cap = cap;
    }
    s->t[s->n] = t;
    s->v[s->n] = values[s->ch];
    s->n++;
    return 0;
}

/* Slope of the last second of a series [m/s^2] (n >= 2, times increasing),
 * not reaching back before t_from. */
static double tail_slope(const series *s, double t_from)
{
    long i0 = s->n - 1;
    while (i0 > 0 && s->t[i0] > s->t[s->n - 1] - 1.0 && s->t[i0] > t_from)
        i0--;
    double dt = s->t[s->n - 1] - s->t[i0];
    return dt > 0 ? (s->v[s->n - 1] - s->v[i0]) / dt : NAN;
}

/* ts_advance with the series as sink; an allocation failure inside is TS_ERR_NOMEM. */
static ts_rc advance(const ts_model *m, ts_data *d, double t_end, series *s, ts_err *err)
{
    ts_rc rc = ts_advance(m, d, t_end, keep, s, err);
    if (s->oom) return ts_err_set(err, TS_ERR_NOMEM, NULL, "tune: out of memory (speed series)");
    if (s->stopped)
        return ts_err_set(err, TS_ERR_CANCELLED, NULL,
                          "tune: cancelled at t = %.3g s of a step response",
                          s->n ? s->t[s->n - 1] : 0.0);
    return rc;
}

/* TS_OK when a speed slope [m/s^2] is steady for Eq. 11: below 1e-3/s of the
 * step's span [m/s]; else TS_ERR_RANGE naming field (whose length, seconds,
 * to raise). */
static ts_rc steady(double slope, double span, const char *field, const char *which,
                    const char *when, double seconds, ts_err *err)
{
    double tol = 1e-3 * span;
    if (fabs(slope) < tol) return TS_OK;
    return ts_err_set(err, TS_ERR_RANGE, field,
                      "%s: the %s speed is still changing %s (%.3g m/s^2, steady means below "
                      "%.3g: 1e-3/s of the step's %.4g m/s); lengthen it (%g s)",
                      field, which, when, slope, tol, span, seconds);
}

ts_rc ts_ivs_tune(const ts_config *cfg, ts_ivs_tune_result *out, ts_err *err)
{
    return ts_ivs_tune_polled(cfg, out, NULL, NULL, 0, 0, err);
}

/* The refusals made before any run, and the plant's config (*plant: the point
 * mass at the low rack over cfg's settle + duration). */
static ts_rc plant_config(const ts_config *cfg, ts_config *plant, ts_err *err)
{
    ts_config c = *cfg;
    const ts_control_config *cc = &cfg->control;
    if (!ts_zn_window_centred(cc->tune_window)) /* before the runs, naming the field */
        return ts_err_set(err, TS_ERR_PARAM, "/control/tune_window",
                          "/control/tune_window: the slope window is centred on a sample, so an "
                          "odd number of samples; got %d",
                          cc->tune_window);
    /* the step response is one run: its length is bounded like any run's,
     * and the fields that set it are the ones to name */
    const ts_param *dur = ts_param_find("/run/duration");
    if (dur && cc->tune_settle + cc->tune_duration > dur->max)
        return ts_err_set(err, TS_ERR_RANGE, "/control/tune_duration",
                          "/control/tune_duration: with /control/tune_settle the step response "
                          "runs %g + %g s, past a run's longest (%g s, /run/duration)",
                          cc->tune_settle, cc->tune_duration, dur->max);
    c.run.kind = TS_RUN_POINTMASS;
    c.terrain.kind = TS_TERRAIN_FLAT; /* the point-mass plant: level ground or /vehicle/grade */
    c.drive.kind = TS_DRIVE_POWERTRAIN;
    c.control.mode = TS_CONTROL_RACK;
    c.control.rack = cc->tune_rack_low;
    c.run.duration = cc->tune_settle + cc->tune_duration;
    *plant = c;
    return TS_OK;
}

ts_rc ts_ivs_tune_check(const ts_config *cfg, ts_err *err)
{
    ts_config c;
    ts_rc rc = plant_config(cfg, &c, err);
    if (rc != TS_OK) return rc;
    ts_model *m = ts_model_make(&c, err); /* the plant's own refusals (engine, driveline) */
    if (!m) return err ? err->code : TS_ERR_PARAM;
    ts_model_free(m);
    return TS_OK;
}

ts_rc ts_ivs_tune_polled(const ts_config *cfg, ts_ivs_tune_result *out, ts_progress_fn poll,
                         void *ud, int done, int total, ts_err *err)
{
    const ts_control_config *cc = &cfg->control;
    ts_config c;
    ts_rc rc = plant_config(cfg, &c, err);
    if (rc != TS_OK) return rc;
    ts_model *m1 = NULL;
    ts_data *d0 = NULL, *d1 = NULL;
    series s = {NULL, NULL, 0, 0, -1, 0, poll, ud, done, total, 0};
    void *buf = NULL;
    ts_model *m0 = ts_model_make(&c, err);
    if (m0) {
        c.control.rack = 1.0;
        m1 = ts_model_make(&c, err);
    }
    if (m1) d0 = ts_data_make(m0, err);
    if (d0) d1 = ts_data_make(m1, err);
    if (!d1) {
        rc = err ? err->code : TS_ERR_INTERNAL;
        goto done;
    }
    s.ch = ts_model_channel_index(m0, "vehicle.speed");
    if (s.ch < 0) {
        rc = ts_err_set(err, TS_ERR_INTERNAL, NULL, "tune: the plant has no vehicle.speed channel");
        goto done;
    }
    size_t nbuf = ts_state_size(m0);
    buf = nbuf ? malloc(nbuf) : NULL;
    if (!buf) {
        rc = ts_err_set(err, TS_ERR_NOMEM, NULL, "tune: out of memory (state buffer)");
        goto done;
    }
    rc = ts_reset(m0, d0, err);
    if (rc == TS_OK) rc = advance(m0, d0, cc->tune_settle, &s, err);
    if (rc != TS_OK) goto done;
    if (s.n < 2) {
        rc = ts_err_set(err, TS_ERR_RANGE, "/control/tune_settle",
                        "/control/tune_settle: the settle must span at least two sample periods "
                        "(2/run.sample_rate = %g s), got %g s",
                        2.0 / c.run.sample_rate, cc->tune_settle);
        goto done;
    }
    out->v0 = s.v[s.n - 1];
    out->settle_slope = tail_slope(&s, 0.0);
    if (out->v0 < 0) { /* known before the step: no full-rack run for nothing */
        rc = ts_err_set(err, TS_ERR_RANGE, "/control/tune_rack_low",
                        "/control/tune_rack_low: at rack %g the vehicle rolls backwards (v0 = %g "
                        "m/s on grade %g): the driveline model is for forward driving; raise the "
                        "low rack or lower /vehicle/grade",
                        cc->tune_rack_low, out->v0, c.vehicle.grade);
        goto done;
    }
    s.n = 0;
    rc = ts_state_save(m0, d0, buf, nbuf, err);
    if (rc == TS_OK) rc = ts_state_restore(m1, d1, buf, nbuf, err); /* same layout: rack differs */
    if (rc == TS_OK) {
        if (keep(&s, 0, ts_time(d1), ts_latest(d1), 0) != 0)
            rc = ts_err_set(err, TS_ERR_NOMEM, NULL, "tune: out of memory (speed series)");
        else
            rc = advance(m1, d1, c.run.duration, &s, err);
    }
    if (rc != TS_OK) goto done;
    out->vb = s.v[s.n - 1];
    out->final_slope = tail_slope(&s, cc->tune_settle);
    if (!(out->vb - out->v0 > 0)) {
        rc = ts_err_set(err, TS_ERR_RANGE, "/control/tune_rack_low",
                        "/control/tune_rack_low: full rack is not faster than the low rack "
                        "(v0 = %g, vb = %g m/s)",
                        out->v0, out->vb);
        goto done;
    }
    /* Eq. 11 normalises between two STEADY states (and a forward v0, above):
     * a plant still moving at either end (a settle or step too short, a
     * vehicle rolling back down a grade) gave gains with nothing to do with the plant (review,
     * session 20: v0 = -138 m/s on a 0.6 grade, or kp 49x too large with a 1-s step). Steady: the
     * speed moves by less than 1e-3 of the step's span per second. */
    double span = out->vb - out->v0;
    rc = steady(out->settle_slope, span, "/control/tune_settle", "low-rack", "at the step",
                cc->tune_settle, err);
    if (rc == TS_OK)
        rc = steady(out->final_slope, span, "/control/tune_duration", "full-rack", "at the end",
                    cc->tune_duration, err);
    if (rc != TS_OK) goto done;
    for (long i = 0; i < s.n; i++)
        s.v[i] = (s.v[i] - out->v0) / span; /* Eq. 11 */
    rc = ts_zn_reaction_curve(s.t, s.v, (int)s.n, cc->tune_settle, cc->tune_window, cc->kp_factor,
                              cc->ti_factor, &out->zn, err);
    if (rc == TS_OK)
        out->kp = ts_zn_kp_physical(out->zn.kp_norm, cc->tune_rack_low, 1.0, out->v0, out->vb);
done:
    free(buf);
    free(s.t);
    free(s.v);
    ts_data_free(d0);
    ts_data_free(d1);
    ts_model_free(m0);
    ts_model_free(m1);
    return rc;
}
