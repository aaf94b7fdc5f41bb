/*
 * model.c — the generic model interface (model.h): scenario dispatch, the
 * channel registry, and the sampling loop shared by every scenario kind.
 *
 * Sampling: row k is at t_k = k / run.sample_rate. ts_advance asks the scenario
 * to step_to(t_k) for every row after the current one up to t_end and hands
 * each row to the caller's callback, so output times never depend on the
 * integrator's internal steps.
 */
#include "model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "scenario.h"

/* One row per run kind; NULL where the kind is not built into this library. */
static const ts_scenario_ops *const scenarios[TS_NRUN_KIND] = {
    [TS_RUN_POINTMASS] = &ts_scenario_pointmass,
    [TS_RUN_ENGINE_DYNO] = &ts_scenario_engine_dyno,
    [TS_RUN_VEHICLE] = &ts_scenario_vehicle,
    [TS_RUN_COUPLED] = &ts_scenario_coupled,
};

#define CHANNEL_STRINGS_CAP 65536

double ts_monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *copy_string(ts_model *m, const char *s)
{
    size_t n = strlen(s) + 1;
    if (m->channel_strings_used + n > m->channel_strings_cap) return NULL;
    char *dst = m->channel_strings + m->channel_strings_used;
    memcpy(dst, s, n);
    m->channel_strings_used += n;
    return dst;
}

int ts_model_add_channel(ts_model *m, const char *name, const char *unit,
                         const char *description, ts_err *err)
{
    if (m->nchannel >= TS_MAX_CHANNELS) {
        ts_err_set(err, TS_ERR_LIMIT, NULL, "too many channels (limit %d)", TS_MAX_CHANNELS);
        return -1;
    }
    if (ts_model_channel_index(m, name) >= 0) {
        ts_err_set(err, TS_ERR_INTERNAL, NULL, "channel '%s' declared twice", name);
        return -1;
    }
    ts_channel *c = &m->channel[m->nchannel];
    c->name = copy_string(m, name);
    c->unit = copy_string(m, unit ? unit : "1");
    c->description = copy_string(m, description ? description : "");
    if (!c->name || !c->unit || !c->description) {
        ts_err_set(err, TS_ERR_LIMIT, NULL, "channel name storage exhausted");
        return -1;
    }
    return m->nchannel++;
}

ts_rc ts_model_add_channels(ts_model *m, const ts_channel *rows, int n, ts_err *err)
{
    for (int i = 0; i < n; i++)
        if (ts_model_add_channel(m, rows[i].name, rows[i].unit, rows[i].description, err) < 0)
            return err && err->code != TS_OK ? err->code : TS_ERR_INTERNAL;
    return TS_OK;
}

ts_model *ts_model_make(const ts_config *cfg, ts_err *err)
{
    ts_err_clear(err);
    if (!cfg) {
        ts_err_set(err, TS_ERR_PARAM, NULL, "no config given");
        return NULL;
    }
    if (ts_param_validate(cfg, err) != TS_OK) return NULL;
    /* off the grid the last row falls short of the run's end, which then never comes */
    if (ts_on_sample_grid(cfg->run.duration, 1.0 / cfg->run.sample_rate, "/run/duration", err) !=
        TS_OK)
        return NULL;
    const ts_scenario_ops *ops = scenarios[cfg->run.kind];
    if (!ops) {
        ts_err_set(err, TS_ERR_UNSUPPORTED, "/run/kind",
                   "/run/kind: scenario '%s' is not available in this build",
                   ts_run_kind_names[cfg->run.kind]);
        return NULL;
    }
    ts_model *m = calloc(1, sizeof *m);
    if (!m) goto nomem;
    m->channel_strings = malloc(CHANNEL_STRINGS_CAP);
    if (!m->channel_strings) goto nomem;
    m->channel_strings_cap = CHANNEL_STRINGS_CAP;
    m->cfg = *cfg;
    m->ops = ops;
    if (ts_model_add_channel(m, "t", "s", "simulated time", err) < 0) goto fail;
    if (ops->model_init(m, err) != TS_OK) goto fail;
    return m;
nomem:
    ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory building the model");
fail:
    if (m) {
        if (m->impl && ops->model_fini) ops->model_fini(m);
        free(m->channel_strings);
        free(m);
    }
    return NULL;
}

/* How far off a row a time may be and count as it [periods], per (1 + its
 * row count): floating-point error of t / dt is ~1e-16 of it, and a slack
 * that grows with the count must stay far below one period at the largest
 * counts (the longest run, 3600 s at 20 kHz, has 7.2e7 rows: 0.072 period);
 * 1e-6 had let 72 million rows count 72 periods either way. */
#define GRID_SLACK 1e-9

/* The slack at n sample periods [periods]. */
static double grid_slack(double n)
{
    return GRID_SLACK * (1.0 + fabs(n));
}

long ts_grid_row(double t, double dt)
{
    double n = t / dt;
    return (long)floor(n + grid_slack(n));
}

/* The suggested times carry 15 digits: with %g a 3-Hz run's "nearest
 * 0.333333 s" was itself off the grid. */
ts_rc ts_on_sample_grid(double t, double dt, const char *pointer, ts_err *err)
{
    double n = t / dt, k = floor(n + 0.5);
    if (fabs(n - k) <= grid_slack(n)) return TS_OK;
    return ts_err_set(err, TS_ERR_PARAM, pointer,
                      "%s: a whole number of sample periods expected (samples are %.15g s "
                      "apart, run.sample_rate %g Hz), got %.15g s; nearest %.15g or %.15g s",
                      pointer, dt, 1.0 / dt, t, floor(n) * dt, (floor(n) + 1) * dt);
}

void ts_model_free(ts_model *m)
{
    if (!m) return;
    if (m->ops->model_fini) m->ops->model_fini(m);
    free(m->channel_strings);
    free(m);
}

const ts_config *ts_model_config(const ts_model *m) { return &m->cfg; }
const char *ts_model_kind(const ts_model *m) { return m->ops->kind; }
int ts_model_dof(const ts_model *m) { return m->dof; }
int ts_model_nstate(const ts_model *m) { return m->nstate; }
int ts_model_nchannel(const ts_model *m) { return m->nchannel; }
double ts_model_sample_period(const ts_model *m) { return 1.0 / m->cfg.run.sample_rate; }

const ts_channel *ts_model_channel(const ts_model *m, int i)
{
    return (i >= 0 && i < m->nchannel) ? &m->channel[i] : NULL;
}

int ts_model_channel_index(const ts_model *m, const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < m->nchannel; i++)
        if (strcmp(m->channel[i].name, name) == 0) return i;
    return -1;
}

ts_data *ts_data_make(const ts_model *m, ts_err *err)
{
    ts_err_clear(err);
    ts_data *d = calloc(1, sizeof *d);
    if (!d) goto nomem;
    d->m = m;
    d->latest = calloc((size_t)m->nchannel, sizeof *d->latest);
    if (!d->latest) goto nomem;
    if (m->ops->data_init(m, d, err) != TS_OK) goto fail;
    return d;
nomem:
    ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory making run data");
fail:
    if (d) {
        free(d->latest);
        free(d);
    }
    return NULL;
}

void ts_data_free(ts_data *d)
{
    if (!d) return;
    if (d->m->ops->data_fini) d->m->ops->data_fini(d->m, d);
    free(d->latest);
    free(d);
}

static ts_rc take_sample(const ts_model *m, ts_data *d, ts_err *err)
{
    ts_rc rc = m->ops->sample(m, d, d->latest, err);
    d->latest[0] = d->t;
    return rc;
}

ts_rc ts_reset(const ts_model *m, ts_data *d, ts_err *err)
{
    ts_err_clear(err);
    d->t = 0.0;
    d->index = 0;
    d->ready = 0;
    d->sticky = TS_OK;
    ts_rc rc = m->ops->reset(m, d, err);
    if (rc == TS_OK) rc = take_sample(m, d, err);
    if (rc != TS_OK) return rc;
    d->ready = 1;
    return TS_OK;
}

ts_rc ts_advance(const ts_model *m, ts_data *d, double t_end, ts_sample_fn fn, void *ud,
                 ts_err *err)
{
    ts_err_clear(err);
    if (!d->ready) return ts_err_set(err, TS_ERR_STATE, NULL, "ts_reset has not been called");
    if (d->sticky != TS_OK)
        return ts_err_set(err, TS_ERR_STATE, NULL,
                          "an earlier advance failed (%s); reset or restore first",
                          ts_rc_name(d->sticky));
    if (t_end > m->cfg.run.duration) t_end = m->cfg.run.duration;
    const double dt = 1.0 / m->cfg.run.sample_rate;
    const long last = ts_grid_row(t_end, dt);
    double t0 = ts_monotonic_seconds();
    ts_rc rc = TS_OK;
    while (d->index < last) {
        long k = d->index + 1;
        double tk = (double)k * dt;
        rc = m->ops->step_to(m, d, tk, err);
        if (rc != TS_OK) {
            d->sticky = rc;
            break;
        }
        d->t = tk;
        d->index = k;
        rc = take_sample(m, d, err);
        if (rc != TS_OK) {
            d->sticky = rc;
            break;
        }
        for (int i = 0; i < m->nchannel; i++) {
            if (!isfinite(d->latest[i])) {
                rc = ts_err_set(err, TS_ERR_DIVERGED, NULL,
                                "channel '%s' became %g at t = %.6g s", m->channel[i].name,
                                d->latest[i], tk);
                d->sticky = rc;
                break;
            }
        }
        if (rc != TS_OK) break;
        if (fn && fn(ud, k, tk, d->latest, m->nchannel) != 0) {
            rc = ts_err_set(err, TS_ERR_CANCELLED, NULL, "stopped by the caller at t = %.6g s",
                            tk);
            break;
        }
    }
    d->wall += ts_monotonic_seconds() - t0;
    return rc;
}

double ts_time(const ts_data *d) { return d->t; }
long ts_sample_index(const ts_data *d) { return d->index; }
const double *ts_latest(const ts_data *d) { return d->latest; }
double ts_wall_seconds(const ts_data *d) { return d->wall; }

void ts_integrator_stats_of_ode(ts_ode *o, const char *name, const char *method,
                                ts_integrator_stats *out)
{
    ts_ode_stats s;
    ts_ode_get_stats(o, &s);
    *out = (ts_integrator_stats){.name = name,
                                 .method = method,
                                 .steps = s.steps,
                                 .rhs_evals = s.rhs_evals,
                                 .jac_evals = s.jac_evals,
                                 .lin_setups = s.lin_setups,
                                 .err_test_fails = s.err_test_fails,
                                 .newton_iters = s.nonlin_iters,
                                 .newton_fails = s.nonlin_fails};
}

int ts_integrator_stats_get(const ts_model *m, const ts_data *d, ts_integrator_stats *out,
                            int max)
{
    if (!m->ops->integrator_stats || !d->impl || max <= 0) return 0;
    int n = m->ops->integrator_stats(m, d, out, max);
    return n < max ? n : max;
}

int ts_rows_append(void *ud, long index, double t, const double *values, int n)
{
    (void)index, (void)t;
    ts_rows *r = ud;
    if (r->n == r->cap) {
        long cap = r->cap ? 2 * r->cap : 4096;
        double *p = realloc(r->v, (size_t)cap * (size_t)n * sizeof *p);
        if (!p) return 1;
        r->v = p;
        r->cap = cap;
    }
    memcpy(r->v + (size_t)r->n * (size_t)n, values, (size_t)n * sizeof *values);
    r->n++;
    return 0;
}

void ts_rows_free(ts_rows *r)
{
    free(r->v);
    *r = (ts_rows){0};
}

int ts_model_metrics(const ts_model *m, const double *rows, long nrows, ts_metric *out, int max)
{
    if (!m->ops->metrics || !rows || nrows <= 0) return 0;
    return m->ops->metrics(m, rows, nrows, out, max > 0 && out ? max : 0);
}

int ts_metric_add(ts_metric *out, int n, int max, const char *name, const char *unit, double value,
                  const char *desc)
{
    if (n >= max) return n + 1; /* counted, not written: the caller's out is full */
    ts_metric *mt = &out[n];
    snprintf(mt->name, sizeof mt->name, "%s", name);
    snprintf(mt->unit, sizeof mt->unit, "%s", unit);
    mt->value = value;
    snprintf(mt->description, sizeof mt->description, "%s", desc);
    return n + 1;
}

double ts_rows_first_crossing(const double *rows, long nrows, int nc, int col, double level)
{
    for (long i = 1; i < nrows; i++) {
        double a = rows[(i - 1) * nc + col], b = rows[i * nc + col];
        if (a < level && b >= level) {
            double ta = rows[(i - 1) * nc], tb = rows[i * nc];
            return ta + (tb - ta) * (level - a) / (b - a);
        }
    }
    return NAN;
}

int ts_metric_add_upshifts(const double *rows, long nrows, int nc, int gear_col, ts_metric *out,
                           int n, int max)
{
    char name[48], desc[96];
    for (int g = 1; g <= 3; g++) {
        snprintf(name, sizeof name, "shift_%d_%d_began_s", g, g + 1);
        snprintf(desc, sizeof desc, "time the %d-%d upshift began (gear leaves %d)", g, g + 1, g);
        n = ts_metric_add(out, n, max, name, "s",
                          ts_rows_first_crossing(rows, nrows, nc, gear_col, g + 1e-6), desc);
        snprintf(name, sizeof name, "shift_%d_%d_half_s", g, g + 1);
        snprintf(desc, sizeof desc, "time the %d-%d upshift is half done (gear passes %d.5)", g,
                 g + 1, g);
        n = ts_metric_add(out, n, max, name, "s",
                          ts_rows_first_crossing(rows, nrows, nc, gear_col, g + 0.5), desc);
    }
    return n;
}

/* Saved state = header (t, index) + the scenario's own bytes. */
typedef struct {
    double t;
    long index;
} state_header;

size_t ts_state_size(const ts_model *m) { return sizeof(state_header) + m->ops->state_size(m); }

ts_rc ts_state_save(const ts_model *m, const ts_data *d, void *buf, size_t n, ts_err *err)
{
    if (n < ts_state_size(m))
        return ts_err_set(err, TS_ERR_PARAM, NULL, "state buffer too small (%zu < %zu)", n,
                          ts_state_size(m));
    if (!d->ready) return ts_err_set(err, TS_ERR_STATE, NULL, "nothing to save before ts_reset");
    state_header h = {d->t, d->index};
    memcpy(buf, &h, sizeof h);
    return m->ops->state_save(m, d, (char *)buf + sizeof h, err);
}

ts_rc ts_state_restore(const ts_model *m, ts_data *d, const void *buf, size_t n, ts_err *err)
{
    if (n != ts_state_size(m))
        return ts_err_set(err, TS_ERR_PARAM, NULL, "state size %zu does not match model (%zu)", n,
                          ts_state_size(m));
    state_header h;
    memcpy(&h, buf, sizeof h);
    d->t = h.t;
    d->index = h.index;
    d->sticky = TS_OK;
    ts_rc rc = m->ops->state_restore(m, d, (const char *)buf + sizeof h, err);
    if (rc == TS_OK) rc = take_sample(m, d, err);
    if (rc != TS_OK) {
        d->ready = 0;
        return rc;
    }
    d->ready = 1;
    return TS_OK;
}

ts_rc ts_geometry(const ts_model *m, const ts_data *d, ts_geom *out, ts_err *err)
{
    if (!m->ops->geometry)
        return ts_err_set(err, TS_ERR_UNSUPPORTED, NULL, "scenario '%s' has no geometry",
                          m->ops->kind);
    if (!d->ready) return ts_err_set(err, TS_ERR_STATE, NULL, "no state before ts_reset");
    return m->ops->geometry(m, d, out, err);
}
