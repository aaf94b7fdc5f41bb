/*
 * cmd_tune.c — "tanksim tune": Ziegler–Nichols open-loop tuning of the IVS
 * speed controller from a simulated step of the rack (paper Section IV.B.1,
 * Eqs. 11-12, Fig. 26), optionally repeated over vehicle masses or grades to
 * give a gain schedule (Fig. 27).
 *
 * Plant: the POINT-MASS vehicle with the powertrain (scenario_pointmass.c,
 * /drive/kind "powertrain") of the given config — engine fidelity, driveline,
 * mass, grade and resistances from it; the multibody vehicle is too slow for
 * the minutes of simulated time the two steady states need. Procedure: settle
 * at /control/tune_rack_low for /control/tune_settle s (steady state 0), save
 * the state, restore it into the same model at full rack and run
 * /control/tune_duration s more; the final speed is the rated steady state b.
 * The speed is normalised by Eq. 11 and ts_zn_reaction_curve builds the
 * tangent (X, Y); K_p = 0.9/|Y| (normalised) and T_I = ti_factor |X| (Eq. 12).
 *
 * Prints one JSON document:
 *   {"plant", "rack_low", "rack_rated", "v0", "vb", "settle_slope", "final_slope",
 *    "t_inflection", "slope", "x", "y", "kp_norm", "kp", "ti", "ti_factor",
 *    "schedule": {"var", "x": [...], "kp": [...], "ti": [...]}}   (SI units)
 * The schedule block is there with --schedule-mass M1,M2,... [kg] or
 * --schedule-grade G1,G2,... [rad]; its arrays fit /control/schedule_*.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/zn_tuning.h"
#include "cli.h"

#define SCHEDULE_MAX 16

typedef struct series {
    double *t, *v;
    long n, cap;
    int ch;
} series;

static int keep(void *ud, long index, double t, const double *values, int n)
{
    (void)index;
    (void)n;
    series *s = ud;
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 4096;
        double *tt = realloc(s->t, (size_t)cap * sizeof *tt);
        if (!tt) return 1;
        s->t = tt;
        double *vv = realloc(s->v, (size_t)cap * sizeof *vv);
        if (!vv) return 1;
        s->v = vv;
        s->cap = cap;
    }
    s->t[s->n] = t;
    s->v[s->n] = values[s->ch];
    s->n++;
    return 0;
}

typedef struct tune_out {
    double v0, vb, settle_slope, final_slope, kp;
    ts_zn_result zn;
} tune_out;

/* Slope of the last second of a series [m/s^2]. */
static double tail_slope(const series *s, double t_from)
{
    long i0 = s->n - 1;
    while (i0 > 0 && s->t[i0] > s->t[s->n - 1] - 1.0 && s->t[i0] > t_from)
        i0--;
    double dt = s->t[s->n - 1] - s->t[i0];
    return dt > 0 ? (s->v[s->n - 1] - s->v[i0]) / dt : NAN;
}

static ts_rc tune_one(const ts_config *base, tune_out *out, ts_err *err)
{
    ts_config c = *base;
    const ts_control_config *cc = &base->control;
    c.run.kind = TS_RUN_POINTMASS;
    c.drive.kind = TS_DRIVE_POWERTRAIN;
    c.control.mode = TS_CONTROL_RACK;
    c.control.rack = cc->tune_rack_low;
    c.run.duration = cc->tune_settle + cc->tune_duration;
    ts_rc rc = TS_OK;
    ts_model *m0 = ts_model_make(&c, err);
    c.control.rack = 1.0;
    ts_model *m1 = m0 ? ts_model_make(&c, err) : NULL;
    ts_data *d0 = m1 ? ts_data_make(m0, err) : NULL;
    ts_data *d1 = d0 ? ts_data_make(m1, err) : NULL;
    series s = {NULL, NULL, 0, 0, m0 ? ts_model_channel_index(m0, "vehicle.speed") : -1};
    size_t nbuf = m0 ? ts_state_size(m0) : 0;
    void *buf = nbuf ? malloc(nbuf) : NULL;
    if (!d1 || !buf || s.ch < 0) {
        rc = (err && err->code != TS_OK) ? err->code : TS_ERR_NOMEM;
        goto done;
    }
    rc = ts_reset(m0, d0, err);
    if (rc == TS_OK) rc = ts_advance(m0, d0, cc->tune_settle, keep, &s, err);
    if (rc != TS_OK) goto done;
    out->v0 = s.v[s.n - 1];
    out->settle_slope = tail_slope(&s, 0.0);
    s.n = 0;
    rc = ts_state_save(m0, d0, buf, nbuf, err);
    if (rc == TS_OK) rc = ts_state_restore(m1, d1, buf, nbuf, err); /* same layout: rack differs */
    if (rc == TS_OK) {
        keep(&s, 0, ts_time(d1), ts_latest(d1), 0);
        rc = ts_advance(m1, d1, c.run.duration, keep, &s, err);
    }
    if (rc != TS_OK) goto done;
    out->vb = s.v[s.n - 1];
    out->final_slope = tail_slope(&s, cc->tune_settle);
    if (!(out->vb - out->v0 > 0)) {
        rc = ts_err_set(err, TS_ERR_PARAM, "/control/tune_rack_low",
                        "/control/tune_rack_low: full rack is not faster than the low rack "
                        "(v0 = %g, vb = %g m/s)",
                        out->v0, out->vb);
        goto done;
    }
    for (long i = 0; i < s.n; i++)
        s.v[i] = (s.v[i] - out->v0) / (out->vb - out->v0); /* Eq. 11 */
    rc = ts_zn_reaction_curve(s.t, s.v, (int)s.n, cc->tune_settle, cc->tune_window, cc->ti_factor,
                              &out->zn, err);
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

static int parse_list(const char *text, double *x, int max)
{
    int n = 0;
    const char *p = text;
    while (*p && n < max) {
        char *end;
        double v = strtod(p, &end);
        if (end == p) return -1;
        x[n++] = v;
        p = end;
        if (*p == ',')
            p++;
        else if (*p)
            return -1;
    }
    return n;
}

int tsc_cmd_tune(int argc, char **argv)
{
    const char *smass = tsc_option(argc, argv, "--schedule-mass");
    const char *sgrade = tsc_option(argc, argv, "--schedule-grade");
    ts_config cfg;
    int st = tsc_load_config(argc, argv, &cfg, NULL);
    if (st != TSC_EXIT_OK) return st;
    double xs[SCHEDULE_MAX];
    int nx = 0;
    const char *var = NULL;
    if (smass && sgrade) {
        fprintf(stderr, "tanksim: tune: give --schedule-mass or --schedule-grade, not both\n");
        return TSC_EXIT_USAGE;
    }
    if (smass || sgrade) {
        var = smass ? "mass" : "grade";
        nx = parse_list(smass ? smass : sgrade, xs, SCHEDULE_MAX);
        if (nx < 1) {
            fprintf(stderr, "tanksim: tune: --schedule-%s: comma-separated numbers (at most %d)\n",
                    var, SCHEDULE_MAX);
            return TSC_EXIT_USAGE;
        }
    }
    ts_err err = {0};
    tune_out o;
    if (tune_one(&cfg, &o, &err) != TS_OK) {
        tsc_print_err("tune", &err);
        return TSC_EXIT_FAIL;
    }
    json_t *doc = json_pack(
        "{s:s, s:s, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f}", "plant",
        "pointmass+powertrain", "engine_fidelity",
        ts_param_find("/engine/fidelity")->enum_names[cfg.engine.fidelity], "rack_low",
        cfg.control.tune_rack_low, "rack_rated", 1.0, "v0", o.v0, "vb", o.vb, "settle_slope",
        o.settle_slope, "final_slope", o.final_slope, "t_inflection",
        o.zn.t_inflection - cfg.control.tune_settle, "slope", o.zn.slope, "x", o.zn.x, "y", o.zn.y,
        "kp_norm", o.zn.kp_norm, "kp", o.kp, "ti", o.zn.ti, "ti_factor", cfg.control.ti_factor);
    json_object_set_new(doc, "units",
                        json_pack("{s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s,s:s}",
                                  "rack_low", "1", "rack_rated", "1", "v0", "m/s", "vb", "m/s",
                                  "settle_slope", "m/s^2", "final_slope", "m/s^2", "t_inflection",
                                  "s", "slope", "1/s", "x", "s", "y", "1", "kp_norm", "1", "kp",
                                  "1/(m/s)", "ti", "s"));
    if (nx > 0) {
        json_t *jx = json_array(), *jk = json_array(), *jt = json_array();
        for (int i = 0; i < nx; i++) {
            ts_config c = cfg;
            if (smass)
                c.vehicle.mass = xs[i];
            else
                c.vehicle.grade = xs[i];
            tune_out oi;
            if (tune_one(&c, &oi, &err) != TS_OK) {
                tsc_print_err("tune", &err);
                json_decref(jx);
                json_decref(jk);
                json_decref(jt);
                json_decref(doc);
                return TSC_EXIT_FAIL;
            }
            json_array_append_new(jx, json_real(xs[i]));
            json_array_append_new(jk, json_real(oi.kp));
            json_array_append_new(jt, json_real(oi.zn.ti));
        }
        json_object_set_new(
            doc, "schedule",
            json_pack("{s:s, s:o, s:o, s:o}", "var", var, "x", jx, "kp", jk, "ti", jt));
    }
    json_dumpf(doc, stdout, JSON_INDENT(2) | JSON_REAL_PRECISION(6));
    printf("\n");
    json_decref(doc);
    return TSC_EXIT_OK;
}
