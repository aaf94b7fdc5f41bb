/*
 * test_threads.c — many sessions on many threads: the model/data split of
 * model.h (a ts_model built once is read-only and shareable; a ts_data
 * belongs to one thread) and render.h (one tsr_ctx per render thread) hold
 * when runs of every scenario kind advance concurrently.
 *
 * Each case is a short run of a shipped preset (durations cut to keep the
 * suite at a few seconds): the vehicle with the coupled track, the point-mass
 * vehicle with the map and the mean-value engine, the engine dynamometer
 * (crank-angle engine) and the integrated engine-vehicle system. Every case is
 * first run serially; then the same runs go on threads at once — several
 * ts_data from ONE shared ts_model per case, and separately one ts_model made
 * on each thread — and every sample row and the final saved state must equal
 * the serial run's bit for bit. A data race in sim/ (a shared scratch buffer,
 * a lazily filled table, a static in a solver callback) shows up here as a
 * mismatch, and under `make tsan` as a ThreadSanitizer report.
 *
 * cmocka's assertions are not thread-safe: threads only record, the main
 * thread checks after joining.
 */
#include "test_util.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "render/render.h"
#include "sim/tanksim.h"

typedef struct scase {
    const char *name;
    const char *preset;
    const char *overrides; /* JSON sections merged over the preset */
} scase;

static const scase cases[] = {
    {"vehicle coupled track", "bump-prescribed-coupled", "{\"run\": {\"duration\": 0.2}}"},
    {"pointmass + map engine", "accel-pointmass-conventional",
     "{\"run\": {\"duration\": 2.0}, \"engine\": {\"fidelity\": \"map\"}}"},
    {"pointmass + mean-value engine", "accel-pointmass-conventional",
     "{\"run\": {\"duration\": 0.3}, \"engine\": {\"fidelity\": \"mean_value\"}}"},
    {"engine dyno crank-angle", "engine-map-conventional", "{\"run\": {\"duration\": 0.01}}"},
    {"coupled engine-vehicle", "flat-coupled-rack90", "{\"run\": {\"duration\": 0.1}}"},
};
#define NCASE ((int)(sizeof cases / sizeof cases[0]))
#define PER_MODEL 2 /* threads sharing one model in the shared-model test */

/* One run: inputs, then what the thread found. */
typedef struct run {
    const ts_config *cfg;  /* own-model runs: make the model on the thread */
    const ts_model *model; /* shared-model runs: the model to use */
    ts_rows rows;          /* row 0 and every row ts_advance produced */
    unsigned char *state;  /* ts_state_save at the end */
    size_t state_size;
    ts_rc rc;
    char msg[640];
} run;

static ts_config *load(const scase *c)
{
    ts_err err;
    json_t *doc = json_loads(c->overrides, 0, NULL);
    assert_non_null(doc);
    json_object_set_new(doc, "preset", json_string(c->preset));
    ts_config *cfg = malloc(sizeof *cfg);
    assert_non_null(cfg);
    ts_rc rc = tsa_config_load(doc, cfg, NULL, NULL, &err);
    json_decref(doc);
    if (rc != TS_OK) fail_msg("%s: %s %s", c->name, err.pointer, err.msg);
    return cfg;
}

static void *run_thread(void *arg)
{
    run *r = arg;
    ts_err err = {0};
    ts_model *own = NULL;
    const ts_model *m = r->model;
    ts_data *d = NULL;
    r->rc = TS_OK;
    if (!m) m = own = ts_model_make(r->cfg, &err);
    if (!m || !(d = ts_data_make(m, &err))) {
        r->rc = err.code ? err.code : TS_ERR_NOMEM;
        goto out;
    }
    if ((r->rc = ts_reset(m, d, &err)) != TS_OK) goto out;
    ts_rows_append(&r->rows, 0, ts_time(d), ts_latest(d), ts_model_nchannel(m));
    if ((r->rc = ts_advance(m, d, ts_model_config(m)->run.duration, ts_rows_append, &r->rows,
                            &err)) != TS_OK)
        goto out;
    r->state_size = ts_state_size(m);
    r->state = malloc(r->state_size);
    if (!r->state) {
        r->rc = TS_ERR_NOMEM;
        goto out;
    }
    r->rc = ts_state_save(m, d, r->state, r->state_size, &err);
out:
    if (r->rc != TS_OK) snprintf(r->msg, sizeof r->msg, "%s %s", err.pointer, err.msg);
    ts_data_free(d);
    ts_model_free(own);
    return NULL;
}

static void run_free(run *r)
{
    ts_rows_free(&r->rows);
    free(r->state);
    memset(r, 0, sizeof *r);
}

/* Every row and the final state of got equal want's, bit for bit. */
static void same_run(const char *what, const scase *c, const run *got, const run *want, int nch)
{
    if (got->rc != TS_OK) fail_msg("%s %s: rc %d %s", what, c->name, got->rc, got->msg);
    if (got->rows.n != want->rows.n)
        fail_msg("%s %s: %ld rows, serial %ld", what, c->name, got->rows.n, want->rows.n);
    for (long i = 0; i < got->rows.n; i++)
        for (int k = 0; k < nch; k++) {
            double g = got->rows.v[i * nch + k], w = want->rows.v[i * nch + k];
            if (memcmp(&g, &w, sizeof g) != 0)
                fail_msg("%s %s: row %ld channel %d = %.17g, serial %.17g", what, c->name, i, k,
                         g, w);
        }
    if (got->state_size != want->state_size ||
        memcmp(got->state, want->state, want->state_size) != 0)
        fail_msg("%s %s: final state differs from the serial run", what, c->name);
}

/* Serial reference runs, one per case, each with its own model. */
typedef struct fixture {
    ts_config *cfg[NCASE];
    ts_model *model[NCASE];
    run serial[NCASE];
} fixture;

static int setup(void **st)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    ts_err err;
    for (int i = 0; i < NCASE; i++) {
        f->cfg[i] = load(&cases[i]);
        f->model[i] = ts_model_make(f->cfg[i], &err);
        if (!f->model[i]) fail_msg("%s: %s", cases[i].name, err.msg);
        f->serial[i].model = f->model[i];
        run_thread(&f->serial[i]);
        if (f->serial[i].rc != TS_OK)
            fail_msg("serial %s: %d %s", cases[i].name, f->serial[i].rc, f->serial[i].msg);
        assert_true(f->serial[i].rows.n >= 2);
    }
    *st = f;
    return 0;
}

static int teardown(void **st)
{
    fixture *f = *st;
    for (int i = 0; i < NCASE; i++) {
        run_free(&f->serial[i]);
        ts_model_free(f->model[i]);
        free(f->cfg[i]);
    }
    free(f);
    return 0;
}

/* EVIDENCE: model.h — "a ts_model is built once from a ts_config and is then
 * read-only ... and may be shared by many threads; a ts_data ... belongs to one
 * thread at a time". Quantity: every sample row and the saved end state of
 * PER_MODEL x NCASE concurrent runs, PER_MODEL of them on each shared model.
 * Tolerance: bit-for-bit equality with the serial runs (nothing is
 * calibrated; the same operations on the same inputs must give the same
 * doubles whatever other threads do). */
static void test_shared_models_match_serial(void **st)
{
    fixture *f = *st;
    enum { N = NCASE * PER_MODEL };
    run runs[N];
    pthread_t th[N];
    memset(runs, 0, sizeof runs);
    for (int i = 0; i < N; i++) {
        runs[i].model = f->model[i % NCASE];
        assert_int_equal(pthread_create(&th[i], NULL, run_thread, &runs[i]), 0);
    }
    for (int i = 0; i < N; i++)
        pthread_join(th[i], NULL);
    for (int i = 0; i < N; i++) {
        int c = i % NCASE;
        same_run("shared model", &cases[c], &runs[i], &f->serial[c],
                 ts_model_nchannel(f->model[c]));
        run_free(&runs[i]);
    }
}

/* EVIDENCE: as above (model.h: no global mutable state in sim/, so models
 * made at once on different threads are independent). Quantity: rows and end
 * state of NCASE concurrent runs, each thread making its own ts_model from the
 * config. Tolerance: bit for bit with the serial runs; nothing calibrated. */
static void test_own_models_match_serial(void **st)
{
    fixture *f = *st;
    run runs[NCASE];
    pthread_t th[NCASE];
    memset(runs, 0, sizeof runs);
    for (int i = 0; i < NCASE; i++) {
        runs[i].cfg = f->cfg[i];
        assert_int_equal(pthread_create(&th[i], NULL, run_thread, &runs[i]), 0);
    }
    for (int i = 0; i < NCASE; i++)
        pthread_join(th[i], NULL);
    for (int i = 0; i < NCASE; i++) {
        same_run("own model", &cases[i], &runs[i], &f->serial[i],
                 ts_model_nchannel(f->model[i]));
        run_free(&runs[i]);
    }
}

/* ---- render: one tsr_ctx per thread ---------------------------------------- */

#define NRENDER 3
typedef struct frame {
    const ts_geom *g;
    unsigned char *png;
    size_t len;
    ts_rc rc;
    char msg[640];
} frame;

static void *render_thread(void *arg)
{
    frame *fr = arg;
    ts_err err = {0};
    tsr_view v;
    tsr_view_default(&v);
    tsr_ctx *c = tsr_ctx_make(&err);
    fr->rc = c ? tsr_render_png(c, fr->g, &v, NULL, &fr->png, &fr->len, &err) : err.code;
    if (fr->rc != TS_OK) snprintf(fr->msg, sizeof fr->msg, "%s", err.msg);
    tsr_ctx_free(c);
    return NULL;
}

/* EVIDENCE: render.h — "context: OpenGL + buffers, one per render thread".
 * Quantity: the PNG of the vehicle case's geometry at t = 0 (ts_geometry of
 * the coupled-track model), drawn on NRENDER threads at once, each with its
 * own context, then alone on the main thread. Tolerance: every PNG
 * byte-identical to the one drawn alone. */
static void test_render_contexts_on_threads(void **st)
{
    fixture *f = *st;
    ts_err err;
    ts_data *d = ts_data_make(f->model[0], &err);
    assert_non_null(d);
    assert_int_equal(ts_reset(f->model[0], d, &err), TS_OK);
    ts_geom *g = malloc(sizeof *g);
    assert_non_null(g);
    assert_int_equal(ts_geometry(f->model[0], d, g, &err), TS_OK);
    ts_data_free(d);

    /* Threads first: the first contexts of the process are made at once, as
     * on the daemon's workers (Mesa and LLVM initialise their statics then). */
    frame fr[NRENDER];
    pthread_t th[NRENDER];
    memset(fr, 0, sizeof fr);
    for (int i = 0; i < NRENDER; i++) {
        fr[i].g = g;
        assert_int_equal(pthread_create(&th[i], NULL, render_thread, &fr[i]), 0);
    }
    for (int i = 0; i < NRENDER; i++)
        pthread_join(th[i], NULL);
    frame alone = {.g = g};
    render_thread(&alone);
    if (alone.rc == TS_ERR_UNSUPPORTED) {
        for (int i = 0; i < NRENDER; i++)
            free(fr[i].png);
        free(g);
        skip(); /* no OSMesa 3.3 core context on this machine */
    }
    if (alone.rc != TS_OK) fail_msg("serial frame: %s", alone.msg);
    for (int i = 0; i < NRENDER; i++) {
        if (fr[i].rc != TS_OK) fail_msg("thread %d: %s", i, fr[i].msg);
        assert_int_equal(fr[i].len, alone.len);
        assert_memory_equal(fr[i].png, alone.png, alone.len);
        free(fr[i].png);
    }
    free(alone.png);
    free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shared_models_match_serial),
        cmocka_unit_test(test_own_models_match_serial),
        cmocka_unit_test(test_render_contexts_on_threads),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
