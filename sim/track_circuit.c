/*
 * track_circuit.c — upper track circuit of Fig. 5 assembled from span
 * elements, and the generalised eigenproblems of spans and circuit (LAPACKE
 * dsygv / dggev). Frame, DOFs and what is left out: track_circuit.h.
 */
#include "track_circuit.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "vehicle_layout.h"

#define TWO_PI  (2.0 * TS_PI) /* the same double as the 2 pi literal: doubling is exact */
#define GRAVITY TS_GRAVITY

const char *const ts_circuit_support_names[TS_CIRCUIT_NSUPPORTS] = {
    "road_wheel_1", "idler", "front_roller", "rear_roller", "sprocket", "road_wheel_7"};
const char *const ts_circuit_span_names[TS_CIRCUIT_NSPANS] = {
    "road_wheel_1-idler", "idler-front_roller", "front_roller-rear_roller", "rear_roller-sprocket",
    "sprocket-road_wheel_7"};

void ts_circuit_free(ts_circuit *c)
{
    if (!c) return;
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++)
        ts_span_free(c->span[i]);
    free(c->M);
    free(c);
}

/* Global index of span i's local coordinate l, -1 when fixed (road wheels 1, 7). */
static int global_index(const ts_circuit *c, int i, int l)
{
    if (l >= 2) return c->span_dof0[i] + (l - 2);
    int sup = i + l; /* support at end l of span i */
    return (sup >= 1 && sup <= TS_CIRCUIT_NSUPPORTS - 2) ? sup - 1 : -1;
}

ts_circuit *ts_circuit_make(const ts_circuit_params *p, ts_err *err)
{
    ts_circuit *c = calloc(1, sizeof *c);
    if (!c) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory building the track circuit");
        return NULL;
    }
    c->p = *p;
    int nwheel = TS_CIRCUIT_NSUPPORTS - 2;
    int ndof = nwheel;
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
        if (ts_span_tangent(&p->support[i], &p->support[i + 1], &c->geom[i], err) != TS_OK) {
            ts_circuit_free(c);
            return NULL;
        }
        ts_span_params sp = {
            .length = c->geom[i].length,
            .g_y = ts_span_gravity_normal(c->geom[i].angle, p->gravity),
            .rho = p->rho,
            .ea = p->ea,
            .tension = p->tension,
            .speed = p->speed,
            .translation_terms = p->translation_terms,
            .quasi_static_stretch = p->quasi_static_stretch,
            .n_long = p->n_long,
            .n_trans = p->n_trans,
            .damping_ratio = 0.0,
        };
        c->span[i] = ts_span_make(&sp, err);
        if (!c->span[i]) {
            ts_span_err_to_config(err, "/vehicle"); /* the circuit's spans: the layout */
            ts_circuit_free(c);
            return NULL;
        }
        c->span_dof0[i] = ndof;
        ndof += c->span[i]->n - 2;
    }
    c->ndof = ndof;
    c->M = calloc((size_t)(3 * ndof * ndof), sizeof(double));
    if (!c->M) {
        ts_circuit_free(c);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory building the track circuit");
        return NULL;
    }
    c->K = c->M + ndof * ndof;
    c->G = c->K + ndof * ndof;
    /* Free wheels: spin inertia and the wrapped track, on u_w = r_w phi_w. */
    for (int w = 1; w <= nwheel; w++) {
        const ts_span_support *s = &p->support[w];
        double in = c->geom[w - 1].angle, out = c->geom[w].angle;
        double a = s->side >= 0 ? out - in : in - out;
        /* principal wrap in [-pi/4, 7pi/4): a slightly negative wrap is a
         * support the straight chords would just clear (the sag still rests
         * the track on it); no wrapped mass then. */
        a = fmod(a + 0.125 * TWO_PI, TWO_PI);
        if (a < 0) a += TWO_PI;
        a -= 0.125 * TWO_PI;
        c->wrap[w] = a;
        if (!(s->radius > 0)) {
            ts_circuit_free(c);
            ts_err_set(err, TS_ERR_RANGE, NULL, "free support %s needs a radius > 0",
                       ts_circuit_support_names[w]);
            return NULL;
        }
        c->M[(w - 1) * ndof + (w - 1)] +=
            p->inertia[w] / (s->radius * s->radius) + p->rho * s->radius * (a > 0 ? a : 0.0);
    }
    /* Span elements. */
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
        const ts_span *sp = c->span[i];
        int n = sp->n;
        for (int a = 0; a < n; a++) {
            int ga = global_index(c, i, a);
            if (ga < 0) continue;
            for (int b = 0; b < n; b++) {
                int gb = global_index(c, i, b);
                if (gb < 0) continue;
                c->M[ga * ndof + gb] += sp->M[a * n + b];
                c->K[ga * ndof + gb] += sp->K[a * n + b];
                c->G[ga * ndof + gb] += sp->G[a * n + b];
                if (sp->G[a * n + b] != 0.0) c->gyroscopic = 1;
            }
        }
    }
    return c;
}

void ts_circuit_span_state(const ts_circuit *c, int i, const double *y, double *x)
{
    for (int l = 0; l < c->span[i]->n; l++) {
        int g = global_index(c, i, l);
        x[l] = g < 0 ? 0.0 : y[g];
    }
}

void ts_modes_free(ts_modes *m)
{
    if (!m) return;
    free(m->freq);
    free(m);
}

static ts_modes *modes_alloc(int nmodes, int ndof, ts_err *err)
{
    ts_modes *m = calloc(1, sizeof *m);
    double *buf = m ? calloc((size_t)nmodes * (size_t)(ndof + 1) + 1, sizeof(double)) : NULL;
    if (!buf) {
        free(m);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory for %d modes", nmodes);
        return NULL;
    }
    m->ndof = ndof;
    m->freq = buf;
    m->shape = buf + nmodes;
    return m;
}

static int any_nonzero(int n, const double *a)
{
    if (!a) return 0;
    for (int i = 0; i < n * n; i++)
        if (a[i] != 0.0) return 1;
    return 0;
}

/* Symmetric definite: K v = w^2 M v. */
static ts_modes *eig_sym(int n, const double *M, const double *K, int nmax, ts_err *err)
{
    double *a = malloc(sizeof(double) * (size_t)(2 * n * n + n));
    if (!a) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory in eigenanalysis (n = %d)", n);
        return NULL;
    }
    double *b = a + n * n, *w = b + n * n;
    memcpy(a, K, sizeof(double) * (size_t)(n * n));
    memcpy(b, M, sizeof(double) * (size_t)(n * n));
    lapack_int info = LAPACKE_dsygv(LAPACK_ROW_MAJOR, 1, 'V', 'U', n, a, n, b, n, w);
    if (info != 0) {
        free(a);
        ts_err_set(err, TS_ERR_SOLVER, NULL, "LAPACKE_dsygv failed (info %d)", (int)info);
        return NULL;
    }
    int nm = n < nmax ? n : nmax;
    ts_modes *m = modes_alloc(nm, n, err);
    if (!m) {
        free(a);
        return NULL;
    }
    int k = 0;
    for (int j = 0; j < n && k < nm; j++) {
        if (!(w[j] > 0)) continue;
        m->freq[k] = sqrt(w[j]) / TWO_PI;
        for (int i = 0; i < n; i++)
            m->shape[k * n + i] = a[i * n + j]; /* column j */
        k++;
    }
    m->n = k;
    free(a);
    return m;
}

typedef struct {
    double f;
    int col;
} fcol;

static int cmp_fcol(const void *x, const void *y)
{
    double a = ((const fcol *)x)->f, b = ((const fcol *)y)->f;
    return (a > b) - (a < b);
}

/* Gyroscopic: [0 I; -K -G] z = lambda [I 0; 0 M] z, frequencies Im(lambda)/2pi. */
static ts_modes *eig_gyro(int n, const double *M, const double *K, const double *G, int nmax,
                          ts_err *err)
{
    int N = 2 * n;
    size_t nn = (size_t)N * (size_t)N;
    double *a = calloc(3 * nn + 3 * (size_t)N, sizeof(double));
    fcol *fc = calloc((size_t)N, sizeof *fc);
    if (!a || !fc) {
        free(a);
        free(fc);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory in eigenanalysis (n = %d)", n);
        return NULL;
    }
    double *b = a + nn, *vr = b + nn, *ar = vr + nn, *ai = ar + N, *be = ai + N;
    for (int i = 0; i < n; i++) {
        a[i * N + (n + i)] = 1.0;
        b[i * N + i] = 1.0;
        for (int j = 0; j < n; j++) {
            a[(n + i) * N + j] = -K[i * n + j];
            a[(n + i) * N + (n + j)] = -G[i * n + j];
            b[(n + i) * N + (n + j)] = M[i * n + j];
        }
    }
    double vl_dummy[1];
    lapack_int info =
        LAPACKE_dggev(LAPACK_ROW_MAJOR, 'N', 'V', N, a, N, b, N, ar, ai, be, vl_dummy, 1, vr, N);
    if (info != 0) {
        free(a);
        free(fc);
        ts_err_set(err, TS_ERR_SOLVER, NULL, "LAPACKE_dggev failed (info %d)", (int)info);
        return NULL;
    }
    int k = 0;
    for (int j = 0; j < N; j++) {
        if (be[j] == 0.0 || !(ai[j] / be[j] > 0)) continue; /* one of each conjugate pair */
        fc[k].f = ai[j] / be[j] / TWO_PI;
        fc[k].col = j;
        k++;
    }
    qsort(fc, (size_t)k, sizeof *fc, cmp_fcol);
    int nm = k < nmax ? k : nmax;
    ts_modes *m = modes_alloc(nm > 0 ? nm : 1, n, err);
    if (!m) {
        free(a);
        free(fc);
        return NULL;
    }
    for (int q = 0; q < nm; q++) {
        m->freq[q] = fc[q].f;
        /* complex pair: columns col (real) and col+1 (imaginary) of vr */
        int col = fc[q].col;
        double amax = 0;
        for (int i = 0; i < n; i++) {
            double re = vr[i * N + col], im = vr[i * N + col + 1];
            double mag = hypot(re, im);
            m->shape[q * n + i] = re;
            if (mag > amax) amax = mag;
        }
        if (amax > 0)
            for (int i = 0; i < n; i++)
                m->shape[q * n + i] /= amax;
    }
    m->n = nm;
    free(a);
    free(fc);
    return m;
}

ts_modes *ts_eig(int n, const double *M, const double *K, const double *G, int nmax, ts_err *err)
{
    if (n <= 0) {
        ts_err_set(err, TS_ERR_PARAM, NULL, "eigenproblem of size %d", n);
        return NULL;
    }
    if (any_nonzero(n, G)) return eig_gyro(n, M, K, G, nmax, err);
    return eig_sym(n, M, K, nmax, err);
}

ts_modes *ts_span_modes(const ts_span *sp, int family, int nmax, ts_err *err)
{
    int n = sp->n, lo = 2, hi = n; /* all modal coordinates */
    if (family == 1) hi = sp->i_trans;
    if (family == 2) lo = sp->i_trans;
    int m = hi - lo;
    if (m <= 0) {
        ts_modes *r = modes_alloc(1, 0, err);
        return r; /* n = 0: no modes of that family */
    }
    double *buf = malloc(sizeof(double) * (size_t)(3 * m * m));
    if (!buf) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory in span eigenanalysis");
        return NULL;
    }
    double *Ms = buf, *Ks = buf + m * m, *Gs = buf + 2 * m * m;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++) {
            Ms[i * m + j] = sp->M[(lo + i) * n + (lo + j)];
            Ks[i * m + j] = sp->K[(lo + i) * n + (lo + j)];
            Gs[i * m + j] = sp->G[(lo + i) * n + (lo + j)];
        }
    ts_modes *r = ts_eig(m, Ms, Ks, Gs, nmax, err);
    free(buf);
    return r;
}

ts_modes *ts_circuit_modes(const ts_circuit *c, int nmax, ts_err *err)
{
    return ts_eig(c->ndof, c->M, c->K, c->gyroscopic ? c->G : NULL, nmax, err);
}

void ts_circuit_mode_character(const ts_circuit *c, const double *shape, ts_mode_character *ch)
{
    memset(ch, 0, sizeof *ch);
    int nd = c->ndof;
    double total = 0;
    for (int g = 0; g < nd; g++)
        total += c->M[g * nd + g] * shape[g] * shape[g];
    if (!(total > 0)) total = 1;
    for (int g = 0; g < TS_CIRCUIT_NSUPPORTS - 2; g++)
        ch->wheels += c->M[g * nd + g] * shape[g] * shape[g] / total;
    double best = -1, trans = 0, lon = ch->wheels;
    for (int i = 0; i < TS_CIRCUIT_NSPANS; i++) {
        const ts_span *sp = c->span[i];
        for (int l = 2; l < sp->n; l++) {
            int g = c->span_dof0[i] + l - 2;
            double e = c->M[g * nd + g] * shape[g] * shape[g] / total;
            if (l >= sp->i_trans)
                ch->trans[i] += e;
            else
                ch->lon[i] += e;
        }
        trans += ch->trans[i];
        lon += ch->lon[i];
        if (ch->trans[i] + ch->lon[i] > best) {
            best = ch->trans[i] + ch->lon[i];
            ch->dominant_span = i;
        }
    }
    ch->transverse = trans > lon;
}

ts_rc ts_circuit_params_from_config(const ts_config *cfg, ts_circuit_params *p, ts_err *err)
{
    const ts_vehicle_config *v = &cfg->vehicle;
    const ts_track_config *t = &cfg->track;
    memset(p, 0, sizeof *p);
    if (v->road_wheel_n < 2)
        return ts_err_set(err, TS_ERR_PARAM, "/vehicle/road_wheel_x",
                          "the upper circuit needs at least two road wheels, got %d",
                          v->road_wheel_n);
    ts_rc lrc = ts_vehicle_layout_check(v, err); /* the order this circuit assumes */
    if (lrc != TS_OK) return lrc;
    double off = v->track_pitch_offset; /* one layout for the vehicle and its Fig. 5 circuit */
    double rw = v->road_wheel_radius + off;
    const ts_span_support sup[TS_CIRCUIT_NSUPPORTS] = {
        {v->road_wheel_x[0], v->road_wheel_z, rw, 1},
        {v->idler_x, v->idler_z, v->idler_radius + off, 1},
        {v->front_roller_x, v->front_roller_z, v->roller_radius + off, 1},
        {v->rear_roller_x, v->rear_roller_z, v->roller_radius + off, 1},
        {v->sprocket_x, v->sprocket_z, v->sprocket_radius, 1},
        {v->road_wheel_x[v->road_wheel_n - 1], v->road_wheel_z, rw, 1},
    };
    memcpy(p->support, sup, sizeof sup);
    p->inertia[1] = v->idler_inertia;
    p->inertia[2] = v->roller_inertia;
    p->inertia[3] = v->roller_inertia;
    p->inertia[4] = v->sprocket_inertia;
    p->rho = t->mass_per_length;
    p->ea = t->ea;
    p->tension = t->tension;
    p->gravity = GRAVITY;
    p->speed = t->modes_speed;
    p->translation_terms = t->translation_terms;
    p->n_long = t->n_long;
    p->n_trans = t->n_trans;
    p->quasi_static_stretch = t->n_long == 0;
    return TS_OK;
}

ts_rc ts_span_params_from_config(const ts_config *cfg, int i, ts_span_params *p, ts_err *err)
{
    const ts_track_config *t = &cfg->track;
    if (t->span_inclination_n != t->span_n)
        return ts_err_set(err, TS_ERR_PARAM, "/track/span_inclination",
                          "needs one angle per /track/span_length entry (%d), got %d", t->span_n,
                          t->span_inclination_n);
    if (i < 0 || i >= t->span_n)
        return ts_err_set(err, TS_ERR_PARAM, "/track/span_length", "no span %d (have %d)", i,
                          t->span_n);
    memset(p, 0, sizeof *p);
    p->length = t->span_length[i];
    p->g_y = GRAVITY * cos(t->span_inclination[i]); /* chord run in +x: e_y up-ish; sag sign only */
    p->rho = t->mass_per_length;
    p->ea = t->ea;
    p->tension = t->tension;
    p->speed = t->modes_speed;
    p->translation_terms = t->translation_terms;
    p->n_long = t->n_long;
    p->n_trans = t->n_trans;
    p->quasi_static_stretch = t->n_long == 0;
    p->damping_ratio = t->damping_ratio;
    return TS_OK;
}
