/*
 * track_span.c — shallow-sag translating track span, component-mode Galerkin
 * discretisation (paper Section II.A–C, Eqs. 1–9; see track_span.h for the
 * frame, coordinates, sign conventions and which terms of Eqs. 4–8 are in).
 *
 * All span integrals are evaluated once, at construction, by composite
 * Gauss–Legendre quadrature (5 points per sub-interval, enough sub-intervals
 * that products of the highest sine modes are integrated to ~1e-12); the
 * integrands are polynomials of degree <= 2 times sines and cosines, so this
 * is exact to rounding for practical purposes and keeps the code free of
 * hand-derived closed forms.
 *
 * Left out: everything track_span.h lists as left out (second-order rotation
 * terms, P0 U_x^2, the segment's rigid-body Eqs. 6–8 which belong to the caller).
 */
#include "track_span.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#define PI TS_PI

/* 5-point Gauss–Legendre nodes and weights on [-1, 1] (method constants). */
static const double gl_x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
static const double gl_w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};

double ts_span_gravity_normal(double theta, double g)
{
    /* gravity (0, -g) . e_y, e_y = (-sin theta, cos theta) */
    return -g * cos(theta);
}

void ts_span_kinematics(const double P[2][2], const double Vp[2][2], const double Ap[2][2],
                        double g, ts_span_geometry *geom, ts_span_motion *mo, double *ldot)
{
    double dx = P[1][0] - P[0][0], dz = P[1][1] - P[0][1];
    double L = hypot(dx, dz);
    double ex = L > 0 ? dx / L : 1.0, ez = L > 0 ? dz / L : 0.0;
    double yx = -ez, yz = ex;
    geom->p0[0] = P[0][0];
    geom->p0[1] = P[0][1];
    geom->p1[0] = P[1][0];
    geom->p1[1] = P[1][1];
    geom->length = L;
    geom->angle = atan2(ez, ex);
    geom->ex[0] = ex;
    geom->ex[1] = ez;
    geom->ey[0] = yx;
    geom->ey[1] = yz;
    double rvx = Vp[1][0] - Vp[0][0], rvz = Vp[1][1] - Vp[0][1];
    double ld = rvx * ex + rvz * ez;
    double thd = L > 0 ? (rvx * yx + rvz * yz) / L : 0.0;
    double a0[2] = {0, 0}, ra[2] = {0, 0};
    if (Ap) {
        a0[0] = Ap[0][0];
        a0[1] = Ap[0][1];
        ra[0] = Ap[1][0] - Ap[0][0];
        ra[1] = Ap[1][1] - Ap[0][1];
    }
    memset(mo, 0, sizeof *mo);
    mo->theta_d = thd;
    mo->theta_dd = L > 0 ? ((ra[0] * yx + ra[1] * yz) - 2.0 * ld * thd) / L : 0.0;
    mo->a0x = a0[0] * ex + a0[1] * ez;
    mo->a0y = a0[0] * yx + a0[1] * yz;
    mo->g_y = -g * yz; /* (0, -g) . e_y */
    if (ldot) *ldot = ld;
}

ts_rc ts_span_tangent(const ts_span_support *a, const ts_span_support *b, ts_span_geometry *g,
                      ts_err *err)
{
    double dx = b->x - a->x, dz = b->z - a->z;
    double dist = hypot(dx, dz);
    int sa = a->side >= 0 ? 1 : -1, sb = b->side >= 0 ? 1 : -1;
    /* Tangent points p = c - side r l, l = left normal of the travel direction d;
     * (p1 - p0) . l = 0 gives D . l(d) = sb rb - sa ra =: delta. */
    double delta = sb * b->radius - sa * a->radius;
    if (!(dist > fabs(delta)) || a->radius < 0 || b->radius < 0)
        return ts_err_set(err, TS_ERR_RANGE, NULL,
                          "support circles at (%g, %g) r %g and (%g, %g) r %g have no common "
                          "tangent of the requested sides",
                          a->x, a->z, a->radius, b->x, b->z, b->radius);
    double beta = atan2(dz, dx);
    double alpha = beta - asin(delta / dist);
    double ex = cos(alpha), ez = sin(alpha);
    double lx = -ez, lz = ex;
    g->p0[0] = a->x - sa * a->radius * lx;
    g->p0[1] = a->z - sa * a->radius * lz;
    g->p1[0] = b->x - sb * b->radius * lx;
    g->p1[1] = b->z - sb * b->radius * lz;
    g->length = sqrt(dist * dist - delta * delta);
    g->angle = alpha;
    g->ex[0] = ex;
    g->ex[1] = ez;
    g->ey[0] = lx;
    g->ey[1] = lz;
    return TS_OK;
}

/* Longitudinal shape function i of n_long+2 (0: 1 - s/L, 1: s/L, 2+j-1: sin(j pi s/L))
 * and its derivative; transverse shape k (1-based) sin(k pi s/L). */
static void long_shape(int i, double s, double L, double *N, double *dN)
{
    if (i == 0) {
        *N = 1.0 - s / L;
        *dN = -1.0 / L;
    } else if (i == 1) {
        *N = s / L;
        *dN = 1.0 / L;
    } else {
        double w = (i - 1) * PI / L;
        *N = sin(w * s);
        *dN = w * cos(w * s);
    }
}

static void trans_shape(int k, double s, double L, double *N, double *dN)
{
    double w = k * PI / L;
    *N = sin(w * s);
    *dN = w * cos(w * s);
}

/* Equilibrium curvature: P0 Y0'' = -rho g_y at rest; a span translating at c
 * along its chord carries the momentum flux rho c^2 as well,
 * (P0 - rho c^2) Y0'' = -rho g_y, so kappa = rho g_y / (P0 - rho c^2) with
 * translation_terms (then V = 0 is the moving span's equilibrium). */
static double span_transport_speed(const ts_span_params *p)
{
    return p->translation_terms ? p->speed : 0.0;
}

static double span_curvature(const ts_span_params *p, double c)
{
    return p->rho * p->g_y / (p->tension - p->rho * c * c);
}

static ts_rc check_params(const ts_span_params *p, ts_err *err)
{
#define REQ(cond, field, ...)                                                                      \
    if (!(cond)) return ts_err_set(err, TS_ERR_RANGE, "/span/" field, __VA_ARGS__)
    REQ(isfinite(p->length) && p->length > 0, "length", "span length must be > 0, got %g",
        p->length);
    REQ(isfinite(p->rho) && p->rho > 0, "rho", "mass per length must be > 0, got %g", p->rho);
    REQ(isfinite(p->ea) && p->ea > 0, "ea", "EA must be > 0, got %g", p->ea);
    REQ(isfinite(p->tension) && p->tension > 0, "tension", "tension must be > 0, got %g",
        p->tension);
    REQ(isfinite(p->g_y), "g_y", "g_y must be finite");
    REQ(isfinite(p->speed), "speed", "speed must be finite");
    REQ(p->n_long >= 0 && p->n_long <= TS_SPAN_MAX_MODES, "n_long",
        "n_long must be in [0, %d], got %d", TS_SPAN_MAX_MODES, p->n_long);
    REQ(p->n_trans >= 0 && p->n_trans <= TS_SPAN_MAX_MODES, "n_trans",
        "n_trans must be in [0, %d], got %d", TS_SPAN_MAX_MODES, p->n_trans);
    REQ(!(p->quasi_static_stretch && p->n_long > 0), "quasi_static_stretch",
        "quasi-static stretch replaces the longitudinal modes: n_long must be 0, got %d",
        p->n_long);
    REQ(isfinite(p->damping_ratio) && p->damping_ratio >= 0, "damping_ratio",
        "damping ratio must be >= 0, got %g", p->damping_ratio);
    if (p->translation_terms) {
        REQ(p->rho * p->speed * p->speed < p->tension, "speed",
            "track speed %g m/s reaches the transverse wave speed", p->speed);
    }
    double kappa = span_curvature(p, span_transport_speed(p));
    REQ(fabs(kappa * p->length) < 1.0, "tension",
        "shallow-sag condition |kappa L| < 1 violated (kappa L = %g)", kappa * p->length);
#undef REQ
    return TS_OK;
}

void ts_span_err_to_config(ts_err *err, const char *layout)
{
    static const char *const map[][2] = {
        {"/span/rho", "/track/mass_per_length"},
        {"/span/ea", "/track/ea"},
        {"/span/tension", "/track/tension"},
        {"/span/speed", "/track/modes_speed"},
        {"/span/n_long", "/track/n_long"},
        {"/span/n_trans", "/track/n_trans"},
        {"/span/quasi_static_stretch", "/track/n_long"},
        {"/span/damping_ratio", "/track/damping_ratio"},
    };
    if (!err || strncmp(err->pointer, "/span/", 6) != 0) return;
    const char *to = layout; /* /span/length, /span/g_y */
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (strcmp(err->pointer, map[i][0]) == 0) to = map[i][1];
    snprintf(err->pointer, sizeof err->pointer, "%s", to);
}

void ts_span_free(ts_span *sp)
{
    if (!sp) return;
    free(sp->M);
    free(sp);
}

/* The slack law's rule (ts_span_slack_force): 2-point Gauss-Legendre on
 * TS_SPAN_SLACK_POINTS / 2 equal sub-intervals, equal weights; at each point
 * the strain basis de/dx_i of e = U_x + kappa V, or of the uniform Irvine
 * stretch (u1 - u0 + kappa \int V) / L with quasi_static_stretch; and the
 * largest |de/dx_i| over the points. */
static void slack_rule(ts_span *sp)
{
    static const double g2 = 0.5773502691896258; /* 1/sqrt(3), a method constant */
    int n = sp->n, nl = sp->p.n_long, nt = sp->p.n_trans;
    double L = sp->p.length, h = L / (TS_SPAN_SLACK_POINTS / 2);
    sp->slack_w = 0.5 * h;
    for (int q = 0; q < TS_SPAN_SLACK_POINTS; q++) {
        double s = h * ((q / 2) + 0.5 + 0.5 * (q % 2 ? g2 : -g2)), N;
        double *b = sp->slack_b + q * n;
        for (int i = 0; i < 2 + nl; i++)
            long_shape(i, s, L, &N, &b[i]);
        for (int k = 0; k < nt; k++) {
            double dN;
            trans_shape(k + 1, s, L, &N, &dN);
            b[sp->i_trans + k] =
                sp->p.quasi_static_stretch
                    ? sp->kappa * (1.0 - cos((k + 1) * PI)) / ((k + 1) * PI)
                    : sp->kappa * N;
        }
        for (int i = 0; i < n; i++)
            sp->slack_bmax[i] = fmax(sp->slack_bmax[i], fabs(b[i]));
    }
}

ts_span *ts_span_make(const ts_span_params *p, ts_err *err)
{
    if (check_params(p, err) != TS_OK) return NULL;
    ts_span *sp = calloc(1, sizeof *sp);
    int nl = p->n_long, nt = p->n_trans;
    int n = 2 + nl + nt;
    double *block = sp ? calloc((size_t)(5 * n * n + 5 * n + TS_SPAN_SLACK_POINTS * n),
                                sizeof(double))
                       : NULL;
    if (!block) {
        free(sp);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory building a span (n = %d)", n);
        return NULL;
    }
    sp->p = *p;
    sp->n = n;
    sp->i_long = 2;
    sp->i_trans = 2 + nl;
    sp->M = block;
    sp->K = block + n * n;
    sp->G = block + 2 * n * n;
    sp->C = block + 3 * n * n;
    sp->W = block + 4 * n * n;
    sp->ax = block + 5 * n * n;
    sp->ay = sp->ax + n;
    sp->sx = sp->ay + n;
    sp->sy = sp->sx + n;
    sp->slack_bmax = sp->sy + n;
    sp->slack_b = sp->slack_bmax + n;

    double L = p->length, rho = p->rho, EA = p->ea, P0 = p->tension;
    double c = span_transport_speed(p);
    double kappa = span_curvature(p, c);
    sp->kappa = kappa;
    sp->k = kappa * L;
    sp->m = rho * L;
    sp->n1 = 0.5 * rho * L * L;
    sp->inertia = rho * L * L * L / 3.0;
    sp->k1 = EA * kappa; /* Eq. 9 */
    sp->k2 = EA * kappa * kappa;
    sp->sag = kappa * L * L / 8.0;

    int nlong = 2 + nl; /* longitudinal shapes incl. the two support shapes */
    double *M = sp->M, *K = sp->K, *A = sp->G, *W = sp->W;
    double *at = calloc((size_t)(nt > 0 ? nt : 1), sizeof(double)); /* \int phi_k */
    if (!at) {
        ts_span_free(sp);
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory building a span");
        return NULL;
    }
    int nmax = (nl > nt ? nl : nt) + 2;
    int nsub = 8 * nmax;
    double h = L / nsub;
    double Nl[2 + TS_SPAN_MAX_MODES], dNl[2 + TS_SPAN_MAX_MODES];
    double Nt[TS_SPAN_MAX_MODES], dNt[TS_SPAN_MAX_MODES];
    for (int e = 0; e < nsub; e++) {
        for (int g = 0; g < 5; g++) {
            double s = (e + 0.5) * h + 0.5 * h * gl_x[g];
            double w = 0.5 * h * gl_w[g];
            for (int i = 0; i < nlong; i++)
                long_shape(i, s, L, &Nl[i], &dNl[i]);
            for (int k = 0; k < nt; k++)
                trans_shape(k + 1, s, L, &Nt[k], &dNt[k]);
            for (int i = 0; i < nlong; i++) {
                sp->ax[i] += w * rho * Nl[i];
                sp->sx[i] += w * rho * s * Nl[i];
                for (int j = 0; j < nlong; j++) {
                    M[i * n + j] += w * rho * Nl[i] * Nl[j];
                    if (!p->quasi_static_stretch)
                        K[i * n + j] += w * (EA - rho * c * c) * dNl[i] * dNl[j];
                    A[i * n + j] += w * rho * c * Nl[i] * dNl[j];
                }
                for (int k = 0; k < nt; k++) {
                    int jk = 2 + nl + k;
                    if (!p->quasi_static_stretch) {
                        K[i * n + jk] += w * EA * kappa * dNl[i] * Nt[k]; /* k1 coupling */
                        K[jk * n + i] += w * EA * kappa * dNl[i] * Nt[k];
                    }
                    W[i * n + jk] += w * rho * Nl[i] * Nt[k];
                    W[jk * n + i] -= w * rho * Nl[i] * Nt[k];
                }
            }
            for (int k = 0; k < nt; k++) {
                int ik = 2 + nl + k;
                at[k] += w * Nt[k];
                sp->ay[ik] += w * rho * Nt[k];
                sp->sy[ik] += w * rho * s * Nt[k];
                for (int l = 0; l < nt; l++) {
                    int il = 2 + nl + l;
                    M[ik * n + il] += w * rho * Nt[k] * Nt[l];
                    K[ik * n + il] += w * (P0 - rho * c * c) * dNt[k] * dNt[l];
                    if (!p->quasi_static_stretch)
                        K[ik * n + il] += w * EA * kappa * kappa * Nt[k] * Nt[l]; /* k2 */
                    A[ik * n + il] += w * rho * c * Nt[k] * dNt[l];
                }
            }
        }
    }
    if (p->quasi_static_stretch) {
        /* Uniform tension tau = EA/L (u1 - u0 + kappa \int V) (Irvine's assumption):
         * W = EA/(2L) (u1 - u0 + kappa sum_k a_k q_k)^2; the longitudinal field
         * reduced to the constraint mode, with -rho c^2 on it when moving. */
        double b[2 + TS_SPAN_MAX_MODES * 2];
        memset(b, 0, sizeof b);
        b[0] = -1.0;
        b[1] = 1.0;
        for (int k = 0; k < nt; k++)
            b[2 + k] = kappa * at[k];
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                K[i * n + j] += EA / L * b[i] * b[j];
        K[0] -= rho * c * c / L;
        K[1] += rho * c * c / L;
        K[n] += rho * c * c / L;
        K[n + 1] -= rho * c * c / L;
    }
    free(at);
    /* G = A - A^T (skew), from the cross term rho c \int W_t W_s of T. */
    for (int i = 0; i < n; i++)
        for (int j = i; j < n; j++) {
            double gij = A[i * n + j] - A[j * n + i];
            A[i * n + j] = gij;
            A[j * n + i] = -gij;
        }
    /* Modal damping on the sine modes: 2 zeta omega_j M_jj from the diagonal. */
    for (int i = 2; i < n; i++) {
        double mi = M[i * n + i], ki = K[i * n + i];
        sp->C[i * n + i] = (mi > 0 && ki > 0) ? 2.0 * p->damping_ratio * sqrt(ki * mi) : 0.0;
    }
    /* Symmetrise K and M against rounding. */
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double km = 0.5 * (K[i * n + j] + K[j * n + i]);
            K[i * n + j] = K[j * n + i] = km;
            double mm = 0.5 * (M[i * n + j] + M[j * n + i]);
            M[i * n + j] = M[j * n + i] = mm;
        }
    slack_rule(sp);
    return sp;
}

void ts_span_force(const ts_span *sp, const ts_span_motion *mo, const double *x, const double *xd,
                   double *f)
{
    int n = sp->n;
    double P0 = sp->p.tension;
    for (int i = 0; i < n; i++) {
        double acc = 0.0;
        for (int j = 0; j < n; j++)
            acc -= sp->K[i * n + j] * x[j] + (sp->C[i * n + j] + sp->G[i * n + j]) * xd[j];
        f[i] = acc;
    }
    f[0] += P0; /* static tension pulls end 0 toward end 1 */
    f[1] -= P0;
    if (!mo) return;
    double dg = mo->g_y - sp->p.g_y;
    for (int i = 0; i < n; i++) {
        double cor = 0.0;
        if (mo->theta_d != 0.0) /* the vehicle passes no chord rotation: skip the product */
            for (int j = 0; j < n; j++)
                cor += sp->W[i * n + j] * xd[j];
        /* Eqs. 4-5 Coriolis; with translation_terms also that of the transport
         * c along the chord, -2 theta_d rho c \int phi on V (as a rigid feed
         * u0_d = u1_d = c would give through W) */
        if (sp->p.translation_terms) cor -= sp->p.speed * sp->ay[i];
        f[i] += 2.0 * mo->theta_d * cor                     /* Coriolis */
                - mo->a0x * sp->ax[i] - mo->a0y * sp->ay[i] /* x0_dd, y0_dd */
                + mo->theta_d * mo->theta_d * sp->sx[i]     /* -x theta_d^2 */
                - mo->theta_dd * sp->sy[i]                  /* x theta_dd */
                + dg * sp->ay[i];                           /* weight change */
    }
}

void ts_span_eval(const ts_span *sp, const double *x, double s, double *U, double *V, double *tau)
{
    double L = sp->p.length;
    int nl = sp->p.n_long, nt = sp->p.n_trans;
    double u = 0, du = 0, v = 0, iv = 0;
    for (int i = 0; i < 2 + nl; i++) {
        double N, dN;
        long_shape(i, s, L, &N, &dN);
        u += N * x[i];
        du += dN * x[i];
    }
    for (int k = 0; k < nt; k++) {
        double N, dN;
        trans_shape(k + 1, s, L, &N, &dN);
        v += N * x[sp->i_trans + k];
        /* \int_0^L sin(k pi s/L) ds for the uniform-tension variant */
        iv += x[sp->i_trans + k] * L * (1.0 - cos((k + 1) * PI)) / ((k + 1) * PI);
    }
    if (U) *U = u;
    if (V) *V = v;
    if (tau) {
        if (sp->p.quasi_static_stretch)
            *tau = sp->p.ea / L * (x[1] - x[0] + sp->kappa * iv); /* uniform */
        else
            *tau = sp->p.ea * (du + sp->kappa * v); /* Eqs. 1-2: tau = EA(U_x + kappa V) */
    }
}

/* Lower bound of the axial stress P0 + EA (e + t_kv e_d) over the rule's points
 * (the triangle inequality on the tabulated basis; de/dx0, de/dx1 = -+1/L). */
static double stress_lower_bound(const ts_span *sp, const double *x, const double *xd, double t_kv)
{
    const double *bmax = sp->slack_bmax;
    double L = sp->p.length, r = 0, rd = 0;
    for (int i = 2; i < sp->n; i++)
        r += bmax[i] * fabs(x[i]);
    if (xd && t_kv > 0) {
        rd = fabs(xd[1] - xd[0]) / L;
        for (int i = 2; i < sp->n; i++)
            rd += bmax[i] * fabs(xd[i]);
    }
    return sp->p.tension + sp->p.ea * ((x[1] - x[0]) / L - r - t_kv * rd);
}

/* Axial stress P0 + EA (e + t_kv e_d) at the rule's point q (xd may be NULL). */
static double point_stress(const ts_span *sp, int q, const double *x, const double *xd,
                           double t_kv)
{
    const double *b = sp->slack_b + q * sp->n;
    double e = 0, ed = 0;
    for (int i = 0; i < sp->n; i++) {
        e += b[i] * x[i];
        if (xd) ed += b[i] * xd[i];
    }
    return sp->p.tension + sp->p.ea * (e + t_kv * ed);
}

int ts_span_slack_force(const ts_span *sp, const double *x, const double *xd, double t_kv,
                        double *f)
{
    if (!(t_kv > 0)) xd = NULL;
    if (stress_lower_bound(sp, x, xd, t_kv) >= 0) return 0;
    int slack = 0;
    for (int q = 0; q < TS_SPAN_SLACK_POINTS; q++) {
        double sigma = point_stress(sp, q, x, xd, t_kv);
        if (sigma >= 0) continue;
        slack = 1;
        const double *b = sp->slack_b + q * sp->n;
        for (int i = 0; i < sp->n; i++)
            f[i] += sp->slack_w * sigma * b[i];
    }
    return slack;
}

double ts_span_slack_energy(const ts_span *sp, const double *x)
{
    if (stress_lower_bound(sp, x, NULL, 0) >= 0) return 0;
    double energy = 0;
    for (int q = 0; q < TS_SPAN_SLACK_POINTS; q++) {
        double sigma = point_stress(sp, q, x, NULL, 0);
        if (sigma < 0) energy += sp->slack_w * sigma * sigma / (2.0 * sp->p.ea);
    }
    return energy;
}

double ts_span_sag(const ts_span *sp, double s)
{
    return 0.5 * sp->kappa * s * (sp->p.length - s);
}

void ts_span_end_forces_eval(const ts_span *sp, const double *x, ts_span_end_forces *ef)
{
    double L = sp->p.length, P0 = sp->p.tension;
    int nt = sp->p.n_trans;
    double vx0 = 0, vx1 = 0;
    for (int k = 0; k < nt; k++) {
        double N, dN;
        trans_shape(k + 1, 0.0, L, &N, &dN);
        vx0 += dN * x[sp->i_trans + k];
        trans_shape(k + 1, L, L, &N, &dN);
        vx1 += dN * x[sp->i_trans + k];
    }
    double tau0, tau1;
    ts_span_eval(sp, x, 0.0, NULL, NULL, &tau0);
    ts_span_eval(sp, x, L, NULL, NULL, &tau1);
    double y0p0 = 0.5 * sp->kappa * L, y0p1 = -0.5 * sp->kappa * L; /* Y0'(0), Y0'(L) */
    ef->tension0 = P0 + tau0;
    ef->tension1 = P0 + tau1;
    /* Force of the track on a support = tension times the track's unit tangent
     * leaving the support into the span (linearised). */
    ef->f0x = P0 + tau0;
    ef->f0y = P0 * (y0p0 + vx0) + tau0 * y0p0;
    ef->f1x = -(P0 + tau1);
    ef->f1y = -(P0 * (y0p1 + vx1) + tau1 * y0p1);
}
