/*
 * test_track_span.c — the span continuum (track_span.h): geometry of the
 * common tangent, matrix properties, the taut-string and bar limits, Irvine's
 * shallow-sag cable theory, convergence, the axially moving string, the end
 * forces, the no-compression (slack) law, and the paper's Table 1 test span.
 */
#include "test_util.h"

#include <complex.h>
#include <stdlib.h>
#include <string.h>

#include "sim/track_circuit.h"
#include "sim/track_span.h"

#define PI 3.14159265358979323846
#define G0 9.80665

/* Track data of sim/data/defaults/track.json (repeated here so the theory
 * checks do not depend on the data file; any positive values would do). */
#define RHO 165.0
#define EA  3.0e7
#define P0  66700.0

static ts_span_params base(double L, double g_y, int nl, int nt)
{
    ts_span_params p = {
        .length = L, .g_y = g_y, .rho = RHO, .ea = EA, .tension = P0, .n_long = nl, .n_trans = nt};
    return p;
}

/* The span of p, or the test fails with ts_span_make's message. */
static ts_span *span_of(const ts_span_params *p)
{
    ts_err err;
    ts_span *sp = ts_span_make(p, &err);
    if (!sp) fail_msg("ts_span_make: %s %s", err.pointer, err.msg);
    return sp;
}

/* g (ts_span_slack_force at y, n coordinates) is the gradient of
 * ts_span_slack_energy: central differences of 1e-9 on each, 1e-6 relative. */
static void assert_slack_gradient(const ts_span *sp, const double *y, const double *g, int n)
{
    for (int i = 0; i < n; i++) {
        double h = 1e-9, yp[2 + 2 * TS_SPAN_MAX_MODES], ym[2 + 2 * TS_SPAN_MAX_MODES];
        memcpy(yp, y, sizeof(double) * (size_t)n);
        memcpy(ym, y, sizeof(double) * (size_t)n);
        yp[i] += h;
        ym[i] -= h;
        double d = (ts_span_slack_energy(sp, yp) - ts_span_slack_energy(sp, ym)) / (2 * h);
        assert_close(g[i], d, 1e-6, 1e-6 * P0);
    }
}

static ts_modes *modes_of(const ts_span_params *p, int family, int nmax)
{
    ts_err err;
    ts_span *sp = span_of(p);
    ts_modes *m = ts_span_modes(sp, family, nmax, &err);
    if (!m) fail_msg("ts_span_modes: %s", err.msg);
    ts_span_free(sp);
    return m;
}

/* Roots x of Irvine's symmetric-mode equation tan x = x - (4/lambda^2) x^3
 * (x = omega_bar/2), written as sin x - cos x (x - 4x^3/lambda^2) = 0, which
 * has the same roots and no poles. Returns the first nroot positive roots. */
static int irvine_roots(double lam2, double *x, int nroot)
{
    int k = 0;
    double h = 1e-3, a = 0.05;
#define IRV(t) (sin(t) - cos(t) * ((t)-4.0 * (t) * (t) * (t) / lam2))
    double fa = IRV(a);
    while (k < nroot && a < 20.0) {
        double b = a + h, fb = IRV(b);
        if (fa * fb < 0) {
            double lo = a, hi = b, flo = fa;
            for (int it = 0; it < 80; it++) {
                double mid = 0.5 * (lo + hi), fm = IRV(mid);
                if (flo * fm <= 0)
                    hi = mid;
                else {
                    lo = mid;
                    flo = fm;
                }
            }
            x[k++] = 0.5 * (lo + hi);
        }
        a = b;
        fa = fb;
    }
#undef IRV
    return k;
}

/* Is a span mode symmetric about mid-span? (odd sine coefficients dominate) */
static int is_symmetric(const ts_modes *m, int mode, int i_trans, int nt)
{
    double odd = 0, even = 0;
    for (int k = 0; k < nt; k++) {
        double v = m->shape[mode * m->ndof + i_trans + k];
        if (k % 2 == 0)
            odd += v * v; /* sin((k+1) pi s/L), k+1 odd */
        else
            even += v * v;
    }
    return odd > even;
}

static void track_span_tangent_geometry(void **state)
{
    (void)state;
    /* EVIDENCE: plane geometry (not calibrated). Equal circles: the outer
     * common tangent is parallel to the line of centres at distance r, length
     * equal to the centre distance; unequal circles: L = sqrt(D^2 - (r1-r2)^2). */
    ts_err err;
    ts_span_geometry g;
    ts_span_support a = {4.0, 1.0, 0.2, 1}, b = {1.0, 1.0, 0.2, 1};
    assert_int_equal(ts_span_tangent(&a, &b, &g, &err), TS_OK);
    assert_close(g.length, 3.0, 1e-12, 0);
    assert_close(g.p0[0], 4.0, 0, 1e-12);
    assert_close(g.p0[1], 1.2, 0, 1e-12); /* top of the wheel: travel -x, wheels left */
    assert_close(g.p1[1], 1.2, 0, 1e-12);
    assert_close(fabs(g.angle), PI, 1e-12, 0);
    assert_close(g.ey[1], -1.0, 0, 1e-12); /* e_y points into the loop (down) */
    assert_close(ts_span_gravity_normal(g.angle, G0), G0, 1e-12, 0);
    ts_span_support c = {0.0, 0.0, 0.5, 1}, d = {3.0, 4.0, 0.2, 1};
    assert_int_equal(ts_span_tangent(&c, &d, &g, &err), TS_OK);
    assert_close(g.length, sqrt(25.0 - 0.09), 1e-12, 0);
    /* tangent: (p1 - p0) perpendicular to both radii */
    double tx = g.p1[0] - g.p0[0], tz = g.p1[1] - g.p0[1];
    assert_close(tx * (g.p0[0] - c.x) + tz * (g.p0[1] - c.z), 0, 0, 1e-12);
    assert_close(tx * (g.p1[0] - d.x) + tz * (g.p1[1] - d.z), 0, 0, 1e-12);
    assert_close(hypot(g.p0[0] - c.x, g.p0[1] - c.z), 0.5, 1e-12, 0);
    /* crossed tangent (opposite sides) L = sqrt(D^2 - (r1 + r2)^2) */
    d.side = -1;
    assert_int_equal(ts_span_tangent(&c, &d, &g, &err), TS_OK);
    assert_close(g.length, sqrt(25.0 - 0.49), 1e-12, 0);
    /* overlapping circles have no tangent */
    ts_span_support e = {0.1, 0.0, 0.1, -1};
    assert_int_equal(ts_span_tangent(&c, &e, &g, &err), TS_ERR_RANGE);
}

static void track_span_matrices_and_eq9(void **state)
{
    (void)state;
    /* EVIDENCE: Eq. 9 constants m = rho L, n = rho L^2/2, I = rho L^3/3,
     * k1 = EA kappa, k2 = EA kappa^2, kappa = rho g_y/(P0 - rho c^2) (the
     * moving span's sag, c = 5 m/s); M symmetric positive,
     * K symmetric, G skew, total mass of the support shapes = rho L (exact). */
    ts_err err;
    ts_span_params p = base(2.0, G0, 3, 3);
    p.translation_terms = 1;
    p.speed = 5.0;
    ts_span *sp = span_of(&p);
    double kappa = RHO * G0 / (P0 - RHO * 5.0 * 5.0);
    assert_close(sp->kappa, kappa, 1e-14, 0);
    assert_close(sp->m, RHO * 2.0, 1e-14, 0);
    assert_close(sp->n1, 0.5 * RHO * 4.0, 1e-14, 0);
    assert_close(sp->inertia, RHO * 8.0 / 3.0, 1e-14, 0);
    assert_close(sp->k1, EA * kappa, 1e-14, 0);
    assert_close(sp->k2, EA * kappa * kappa, 1e-14, 0);
    assert_close(sp->sag, kappa * 4.0 / 8.0, 1e-14, 0);
    /* EVIDENCE: the shallow cable's parabola (Irvine's cable) Y0(s) = kappa s
     * (L - s) / 2, the Eq. 9 curvature integrated with Y0(0) = Y0(L) = 0: its
     * midspan value is the sag kappa L^2 / 8, at a quarter 3 kappa L^2 / 32. */
    assert_close(ts_span_sag(sp, 1.0), sp->sag, 1e-14, 0);
    assert_close(ts_span_sag(sp, 0.5), 3.0 * kappa * 4.0 / 32.0, 1e-14, 0);
    assert_close(ts_span_sag(sp, 0.0), 0, 0, 0);
    int n = sp->n;
    assert_int_equal(n, 8);
    double mass_b = sp->M[0] + 2 * sp->M[1] + sp->M[n + 1]; /* (N0 + N1)^2 = 1 */
    assert_close(mass_b, RHO * 2.0, 1e-12, 0);
    assert_close(sp->M[0], RHO * 2.0 / 3.0, 1e-12, 0);
    assert_close(sp->M[1], RHO * 2.0 / 6.0, 1e-12, 0);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            assert_close(sp->M[i * n + j], sp->M[j * n + i], 0, 1e-12);
            assert_close(sp->K[i * n + j], sp->K[j * n + i], 0, 1e-6);
            assert_close(sp->G[i * n + j], -sp->G[j * n + i], 0, 1e-9);
            assert_close(sp->W[i * n + j], -sp->W[j * n + i], 0, 1e-12);
        }
    /* rigid transport (u0 = u1, no modes) costs no strain energy */
    double x[8] = {1, 1, 0, 0, 0, 0, 0, 0}, xd[8] = {0}, f[8];
    ts_span_force(sp, NULL, x, xd, f);
    assert_close(f[0], P0, 1e-12, 0);
    assert_close(f[1], -P0, 1e-12, 0);
    for (int i = 2; i < n; i++)
        assert_close(f[i], 0, 0, 1e-9);
    ts_span_free(sp);
    /* parameter errors name the field */
    p.n_trans = 99;
    assert_null(ts_span_make(&p, &err));
    assert_string_equal(err.pointer, "/span/n_trans");
    p = base(2.0, G0, 1, 1);
    p.quasi_static_stretch = 1;
    assert_null(ts_span_make(&p, &err));
    assert_string_equal(err.pointer, "/span/quasi_static_stretch");
}

static void track_span_taut_string_and_bar_limits(void **state)
{
    (void)state;
    /* EVIDENCE: closed form, kappa -> 0 (no sag): taut string f_n = n/(2L)
     * sqrt(P0/rho) and fixed-fixed bar f_n = n/(2L) sqrt(EA/rho); first four
     * modes within 0.5 % with 8 modes per family kept; here with a small but
     * non-zero sag (g_y = 0.001 g, lambda^2 ~ 1e-6) so the coupled matrices
     * are exercised. Not calibrated. */
    const double L = 1.7;
    ts_span_params p = base(L, 1e-3 * G0, 8, 8);
    ts_modes *t = modes_of(&p, 2, 4), *l = modes_of(&p, 1, 4), *c = modes_of(&p, 0, 12);
    for (int n = 1; n <= 4; n++) {
        double ft = n / (2 * L) * sqrt(P0 / RHO), fl = n / (2 * L) * sqrt(EA / RHO);
        assert_close(t->freq[n - 1], ft, 0.005, 0);
        assert_close(l->freq[n - 1], fl, 0.005, 0);
        assert_close(c->freq[n - 1], ft, 0.005, 0); /* the lowest coupled modes are transverse */
    }
    print_message("  string f1..4 = %.3f %.3f %.3f %.3f Hz; bar f1..4 = %.1f %.1f %.1f %.1f Hz\n",
                  t->freq[0], t->freq[1], t->freq[2], t->freq[3], l->freq[0], l->freq[1],
                  l->freq[2], l->freq[3]);
    ts_modes_free(t);
    ts_modes_free(l);
    ts_modes_free(c);
}

static void check_irvine(int quasi_static, int nl, int nt, double tol, double tol_anti)
{
    const double L = 1.39;
    const double lam2s[] = {0.1, 0.5, 1, 2, 5, 10, 20, 4 * PI * PI, 100};
    double f0 = sqrt(P0 / RHO) / (2 * L);
    for (size_t q = 0; q < sizeof lam2s / sizeof lam2s[0]; q++) {
        double lam2 = lam2s[q];
        /* lambda^2 = EA kappa^2 L^2 / P0 (= k2 L^2 / P0): choose kappa via g_y */
        double kappa = sqrt(lam2 * P0 / EA) / L;
        ts_span_params p = base(L, kappa * P0 / RHO, quasi_static ? 0 : nl, nt);
        p.quasi_static_stretch = quasi_static;
        ts_modes *m = modes_of(&p, 0, 12);
        int i_trans = 2 + p.n_long - 2; /* shape index within the modal block */
        double xr[3];
        int nr = irvine_roots(lam2, xr, 2);
        assert_int_equal(nr, 2);
        int nsym = 0, nanti = 0;
        for (int i = 0; i < m->n && (nsym < 2 || nanti < 2); i++) {
            if (m->freq[i] > 6 * f0) break;
            double share = 0; /* skip longitudinal-dominated modes (none this low) */
            for (int k = 0; k < nt; k++)
                share += pow(m->shape[i * m->ndof + i_trans + k], 2);
            if (share == 0) continue;
            if (is_symmetric(m, i, i_trans, nt)) {
                if (nsym < 2) {
                    double want = f0 * (2 * xr[nsym]) / PI; /* f/f0 = omega_bar / pi */
                    assert_close(m->freq[i], want, tol, 0);
                    if (nsym == 0 && !quasi_static)
                        print_message("  lambda^2 %6.2f: 1st sym f/f0 = %.4f (Irvine %.4f)\n", lam2,
                                      m->freq[i] / f0, want / f0);
                }
                nsym++;
            } else {
                /* antisymmetric modes: unchanged by sag, f = n f0, n = 2, 4 */
                if (nanti < 2) assert_close(m->freq[i], (2 * nanti + 2) * f0, tol_anti, 0);
                nanti++;
            }
        }
        assert_true(nsym >= 2 && nanti >= 2);
        ts_modes_free(m);
    }
}

static void track_span_irvine_quasi_static(void **state)
{
    (void)state;
    /* EVIDENCE: Irvine & Caughey 1974 / Irvine 1981 shallow-sag cable theory,
     * symmetric in-plane modes tan(w/2) = w/2 - (4/lambda^2)(w/2)^3, w = f/f0 pi,
     * solved numerically here; antisymmetric modes n f0 unchanged by sag.
     * Quasi-static stretch (Irvine's own assumption): first two symmetric
     * modes within 1 % for lambda^2 = 0.1 ... 100. Not calibrated. */
    check_irvine(1, 0, 16, 0.01, 0.002);
}

static void track_span_irvine_dynamic_stretch(void **state)
{
    (void)state;
    /* EVIDENCE: as above, but with the longitudinal field carried by 16
     * dynamic sine modes (the "coupled" fidelity) instead of uniform tension:
     * the continuum converges to Irvine because longitudinal waves (426 m/s)
     * are 20x faster than transverse ones. Within 1 %, antisymmetric modes
     * too (their longitudinal inertia, which Irvine neglects, lowers them by
     * up to ~0.3 % at lambda^2 = 100). Not calibrated. */
    check_irvine(0, 16, 16, 0.01, 0.01);
}

static void track_span_irvine_crossover(void **state)
{
    (void)state;
    /* EVIDENCE: Irvine 1981: at lambda^2 = 4 pi^2 the first symmetric mode
     * equals the first antisymmetric one (2 f0); below it is lower, above it
     * higher. Tolerance 0.5 %. Not calibrated. */
    const double L = 1.39;
    double f0 = sqrt(P0 / RHO) / (2 * L);
    const double lam2s[] = {4 * PI * PI * 0.8, 4 * PI * PI, 4 * PI * PI * 1.2};
    double first_sym[3];
    for (int q = 0; q < 3; q++) {
        double kappa = sqrt(lam2s[q] * P0 / EA) / L;
        ts_span_params p = base(L, kappa * P0 / RHO, 0, 16);
        p.quasi_static_stretch = 1;
        ts_modes *m = modes_of(&p, 0, 6);
        for (int i = 0; i < m->n; i++)
            if (is_symmetric(m, i, 0, 16)) {
                first_sym[q] = m->freq[i] / f0;
                break;
            }
        ts_modes_free(m);
    }
    assert_true(first_sym[0] < 2.0 && first_sym[2] > 2.0);
    /* the root finder against independently computed roots of Irvine's
     * transcendental equation (Irvine 1981): 1st symmetric f/f0 at lambda^2 = 5 and 100, 2nd at 100 */
    double xr[2];
    assert_int_equal(irvine_roots(5.0, xr, 2), 2);
    assert_close(2 * xr[0] / PI, 1.187, 0, 6e-4);
    assert_int_equal(irvine_roots(100.0, xr, 2), 2);
    assert_close(2 * xr[0] / PI, 2.597, 0, 6e-4);
    assert_close(2 * xr[1] / PI, 3.480, 0, 6e-4);
    assert_close(first_sym[1], 2.0, 0.005, 0);
}

static void track_span_convergence_monotone(void **state)
{
    (void)state;
    /* EVIDENCE: Rayleigh–Ritz with nested bases (Galerkin, Section II.C):
     * each frequency decreases monotonically toward the continuum value as
     * modes are added (n = 1..12 per family); the change from 8 to 12 modes
     * is below 0.5 %. Span of the Fig. 5 circuit's longest span (2.72 m). */
    const double L = 2.72;
    double prev[3] = {INFINITY, INFINITY, INFINITY}, at8[3] = {0};
    for (int n = 1; n <= 12; n++) {
        ts_span_params p = base(L, G0, n, n);
        ts_modes *m = modes_of(&p, 0, 3);
        for (int i = 0; i < 3 && i < m->n; i++) {
            assert_true(m->freq[i] <= prev[i] * (1 + 1e-12));
            prev[i] = m->freq[i];
            if (n == 8) at8[i] = m->freq[i];
        }
        ts_modes_free(m);
    }
    for (int i = 0; i < 3; i++)
        assert_close(at8[i], prev[i], 0.005, 0);
}

static void track_span_moving_string(void **state)
{
    (void)state;
    /* EVIDENCE: axially moving string (Wickert & Mote 1990): f_n = n c_w
     * (1 - v^2/c_w^2) / (2L), c_w = sqrt(P0/rho), from the gyroscopic
     * matrices with translation_terms on (dggev). v = 0.5 c_w (a strong test:
     * factor 0.75). Within 0.5 % for n = 1..3. Not calibrated. */
    const double L = 1.5;
    double cw = sqrt(P0 / RHO), v = 0.5 * cw;
    ts_span_params p = base(L, 0.0, 0, 12);
    p.translation_terms = 1;
    p.speed = v;
    ts_modes *m = modes_of(&p, 2, 3);
    for (int n = 1; n <= 3; n++)
        assert_close(m->freq[n - 1], n * cw * (1 - v * v / (cw * cw)) / (2 * L), 0.005, 0);
    ts_modes_free(m);
}

static void track_span_end_forces_static(void **state)
{
    (void)state;
    /* EVIDENCE: statics of the sagged span (Eq. 9 curvature): each support
     * carries half the span weight normal to the chord (rho g_y L / 2) and P0
     * along it; a uniform stretch e gives tension P0 + EA e at both ends and
     * the generalised end forces -+(P0 + EA e). Exact. */
    const double L = 2.0;
    ts_span_params p = base(L, G0, 4, 4);
    ts_span *sp = span_of(&p);
    double x[10] = {0}, xd[10] = {0}, f[10];
    ts_span_end_forces ef;
    ts_span_end_forces_eval(sp, x, &ef);
    assert_close(ef.f0x, P0, 1e-12, 0);
    assert_close(ef.f1x, -P0, 1e-12, 0);
    assert_close(ef.f0y, RHO * G0 * L / 2, 1e-12, 0);
    assert_close(ef.f1y, RHO * G0 * L / 2, 1e-12, 0);
    x[1] = 1e-3 * L; /* strain 1e-3 */
    ts_span_end_forces_eval(sp, x, &ef);
    assert_close(ef.tension0, P0 + EA * 1e-3, 1e-12, 0);
    assert_close(ef.tension1, P0 + EA * 1e-3, 1e-12, 0);
    ts_span_force(sp, NULL, x, xd, f);
    assert_close(f[0], P0 + EA * 1e-3, 1e-12, 0);
    assert_close(f[1], -(P0 + EA * 1e-3), 1e-12, 0);
    /* the stretch also pulls the sagged span straight: force on the symmetric
     * transverse modes -EA kappa e \int sin = -k1 e 2L/(k pi) for odd k */
    assert_close(f[sp->i_trans], -sp->k1 * 1e-3 * 2 * L / PI, 1e-9, 0);
    assert_close(f[sp->i_trans + 1], 0, 0, 1e-6);
    /* uniform-tension variant: tau = EA/L (u1 - u0 + kappa \int V), same end
     * tension for the stretch, and the sag term for a first-mode deflection */
    ts_span_params pq = base(L, G0, 0, 4);
    pq.quasi_static_stretch = 1;
    ts_span *sq = span_of(&pq);
    double xq[6] = {0, 1e-3 * L, 0.01, 0, 0, 0}, tq;
    ts_span_eval(sq, xq, 0.3, NULL, NULL, &tq);
    assert_close(tq, EA / L * (1e-3 * L + sq->kappa * 0.01 * 2 * L / PI), 1e-12, 0);
    ts_span_free(sq);
    /* uniform acceleration of the supports a0y loads the modes by -rho a \int phi */
    ts_span_motion mo = {.a0y = 2.0, .g_y = G0};
    memset(x, 0, sizeof x);
    ts_span_force(sp, &mo, x, xd, f);
    assert_close(f[sp->i_trans], -RHO * 2.0 * 2 * L / PI, 1e-9, 0);
    ts_span_free(sp);
}

static void track_span_slack_law(void **state)
{
    (void)state;
    const double L = 1.5;
    /* EVIDENCE: closed form. A straight span (g_y = 0, kappa = 0) with one
     * longitudinal mode: sigma(s) = a + c cos(pi s / L), a = P0 + EA x1 / L,
     * c = EA q pi / L. Where sigma < 0 (cos < -a/c, s > L th0 / pi, th0 =
     * acos(-a/c)) the law adds int min(sigma, 0) de/dx1 ds with de/dx1 = 1/L:
     *   (a (pi - th0) - c sin th0) / pi.
     * The 48-point rule integrates across the kink; tolerance 2e-4 of P0. */
    ts_span_params p = base(L, 0.0, 1, 1);
    ts_span *sp = span_of(&p);
    double x[4] = {0, -0.5 * P0 / EA * L, 0.9 * P0 / EA * L / PI, 0}, f[4] = {0};
    double a = P0 + EA * x[1] / L, c = EA * x[2] * PI / L, th0 = acos(-a / c);
    assert_int_equal(ts_span_slack_force(sp, x, NULL, 0, f), 1);
    double want = (a * (PI - th0) - c * sin(th0)) / PI;
    printf("# half-slack span: end-1 force correction %.2f N, closed form %.2f N\n", f[1], want);
    assert_close(f[1], want, 0, 2e-4 * P0);
    assert_close(f[0], -want, 0, 2e-4 * P0); /* de/dx0 = -1/L */
    /* the force is the gradient of ts_span_slack_energy (same points): central
     * differences on every coordinate, kinked field included; 1e-6 relative */
    ts_span_params pc = base(L, G0, 2, 2);
    ts_span *sc = span_of(&pc);
    double y[6] = {0, -0.3 * P0 / EA * L, 0.8 * P0 / EA * L / PI, -0.1 * P0 / EA * L / PI, 0.02,
                   -0.01};
    double g[6] = {0};
    assert_int_equal(ts_span_slack_force(sc, y, NULL, 0, g), 1);
    assert_slack_gradient(sc, y, g, 6);
    /* the whole span slack (uniform compression): with the linear forces the end
     * rows carry no force at all; a taut span is left alone */
    double z[4] = {0, -2.0 * P0 / EA * L, 0, 0}, fl[4], zd[4] = {0};
    ts_span_force(sp, NULL, z, zd, fl);
    assert_int_equal(ts_span_slack_force(sp, z, NULL, 0, fl), 1);
    assert_close(fl[0], 0, 0, 1e-9 * P0);
    assert_close(fl[1], 0, 0, 1e-9 * P0);
    assert_close(ts_span_slack_energy(sp, z), L * (P0 - 2.0 * P0) * (P0 - 2.0 * P0) / (2 * EA),
                 1e-12, 0);
    double t[4] = {0, 0.1 * P0 / EA * L, 0.2 * P0 / EA * L / PI, 0}, ft[4] = {1, 2, 3, 4};
    assert_int_equal(ts_span_slack_force(sp, t, NULL, 0, ft), 0);
    assert_true(ft[0] == 1 && ft[1] == 2 && ft[2] == 3 && ft[3] == 4);
    assert_true(ts_span_slack_energy(sp, t) == 0);
    /* a Kelvin-Voigt rate unloading the span fast makes it slack too */
    double r[4] = {0, -0.5 * L / 0.002, 0, 0};
    memset(ft, 0, sizeof ft);
    assert_int_equal(ts_span_slack_force(sp, t, r, 0.002, ft), 1);
    /* the uniform-tension (Irvine) variant: one stress for the whole span */
    ts_span_params pq = base(L, G0, 0, 2);
    pq.quasi_static_stretch = 1;
    ts_span *sq = span_of(&pq);
    double u[4] = {0, -2.0 * P0 / EA * L, 0, 0}, fu[4], ud[4] = {0};
    assert_close(ts_span_slack_energy(sq, u), L * P0 * P0 / (2 * EA), 1e-12, 0);
    ts_span_force(sq, NULL, u, ud, fu);
    assert_int_equal(ts_span_slack_force(sq, u, NULL, 0, fu), 1);
    assert_close(fu[0], 0, 0, 1e-9 * P0);
    assert_close(fu[1], 0, 0, 1e-9 * P0);
    ts_span_free(sq);
    ts_span_free(sc);
    ts_span_free(sp);
}

/* Static response of the fixed-end span to the loads of a motion: solve
 * K_qq q = f_q (q = modal block), return the state x (u0 = u1 = 0). */
static void static_response(const ts_span *sp, const ts_span_motion *mo, double *x)
{
    int n = sp->n, m = n - 2;
    double xd[2 + 2 * TS_SPAN_MAX_MODES] = {0}, f[2 + 2 * TS_SPAN_MAX_MODES];
    double A[(2 * TS_SPAN_MAX_MODES) * (2 * TS_SPAN_MAX_MODES)];
    memset(x, 0, sizeof(double) * (size_t)n);
    ts_span_force(sp, mo, x, xd, f);
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++)
            A[i * m + j] = sp->K[(i + 2) * n + (j + 2)];
    double *b = f + 2;
    /* Gaussian elimination with partial pivoting (m <= 32) */
    for (int k = 0; k < m; k++) {
        int piv = k;
        for (int i = k + 1; i < m; i++)
            if (fabs(A[i * m + k]) > fabs(A[piv * m + k])) piv = i;
        for (int j = 0; j < m; j++) {
            double t = A[k * m + j];
            A[k * m + j] = A[piv * m + j];
            A[piv * m + j] = t;
        }
        double t = b[k];
        b[k] = b[piv];
        b[piv] = t;
        for (int i = k + 1; i < m; i++) {
            double r = A[i * m + k] / A[k * m + k];
            for (int j = k; j < m; j++)
                A[i * m + j] -= r * A[k * m + j];
            b[i] -= r * b[k];
        }
    }
    for (int i = m - 1; i >= 0; i--) {
        double acc = b[i];
        for (int j = i + 1; j < m; j++)
            acc -= A[i * m + j] * x[2 + j];
        x[2 + i] = acc / A[i * m + i];
    }
}

static void track_span_support_motion_loads(void **state)
{
    (void)state;
    /* EVIDENCE: Eqs. 4-5 right-hand sides, checked by their static responses
     * against closed-form string/bar solutions (no sag, fixed ends):
     *  - support acceleration y0_dd = a: P0 V'' = rho a -> V(L/2) = -rho a L^2/(8 P0)
     *  - chord angular acceleration theta_dd: P0 V'' = rho s theta_dd ->
     *    V(L/2) = -rho theta_dd L^3/(16 P0)
     *  - chord spin theta_d: EA U'' = -rho s theta_d^2 -> U(L/2) = rho theta_d^2 L^3/(16 EA)
     *  - a change of gravity along e_y acts like -a (equivalence principle).
     * 12 modes per family; within 0.5 %. Not calibrated. */
    const double L = 1.8, a = 3.0, thdd = 2.0, thd = 4.0;
    ts_span_params p = base(L, 0.0, 12, 12);
    ts_span *sp = span_of(&p);
    double x[2 + 2 * TS_SPAN_MAX_MODES], U, V, tau;
    ts_span_motion mo = {.a0y = a};
    static_response(sp, &mo, x);
    ts_span_eval(sp, x, L / 2, &U, &V, &tau);
    assert_close(V, -RHO * a * L * L / (8 * P0), 0.005, 0);
    assert_close(U, 0, 0, 1e-12);
    ts_span_motion mg = {.g_y = -a};
    static_response(sp, &mg, x);
    ts_span_eval(sp, x, L / 2, NULL, &V, NULL);
    assert_close(V, -RHO * a * L * L / (8 * P0), 0.005, 0);
    ts_span_motion mt = {.theta_dd = thdd};
    static_response(sp, &mt, x);
    ts_span_eval(sp, x, L / 2, NULL, &V, NULL);
    assert_close(V, -RHO * thdd * L * L * L / (16 * P0), 0.005, 0);
    ts_span_motion mw = {.theta_d = thd};
    static_response(sp, &mw, x);
    ts_span_eval(sp, x, L / 2, &U, &V, NULL);
    assert_close(U, RHO * thd * thd * L * L * L / (16 * EA), 0.005, 0);
    /* Coriolis: a transverse velocity field in a spinning chord frame pushes
     * the longitudinal modes by 2 theta_d rho \int N V_t, and does no work */
    double xd[2 + 2 * TS_SPAN_MAX_MODES] = {0}, f[2 + 2 * TS_SPAN_MAX_MODES];
    memset(x, 0, sizeof x);
    xd[sp->i_trans] = 1.0; /* V_t = sin(pi s/L) */
    ts_span_force(sp, &mw, x, xd, f);
    double rate = 0;
    for (int i = 0; i < sp->n; i++)
        rate += f[i] * xd[i];
    assert_close(rate, 0, 0, 1e-9); /* Coriolis is workless (W skew) */
    /* end-1 row: -P0 + centripetal theta_d^2 rho \int s (s/L) + Coriolis
     * 2 theta_d rho \int (s/L) sin(pi s/L) = 2 theta_d rho L/pi */
    assert_close(f[1], -P0 + thd * thd * RHO * L * L / 3 + 2 * thd * RHO * L / PI, 1e-9, 0);
    /* the same, not vacuous: velocities on EVERY coordinate (support feeds,
     * longitudinal and transverse modes), so the T-L and L-T entries of W both
     * act; the Coriolis part cor = f(theta_d, x_d) - f(theta_d, 0) - (f(-, x_d)
     * - f(-, 0)) must do no work, cor . x_d = 0 (W skew: -2 theta_d V_t on U
     * balances +2 theta_d U_t on V), while each family's share |cor_i x_d,i|
     * is large. Measured: power 3.5e-12 W against shares 3.45e3 (U) and
     * 2.81e3 W (V). With the load on V from U_t dropped (ts_span_force
     * summing W x_d over the transverse velocities only) the assertion above
     * still passes (x_d there is on one transverse mode, whose W entries with
     * the transverse family are zero); this one fails: power 2.81e3 W,
     * transverse share 0. */
    double xd2[2 + 2 * TS_SPAN_MAX_MODES], f0[2 + 2 * TS_SPAN_MAX_MODES],
        fn[2 + 2 * TS_SPAN_MAX_MODES], fn0[2 + 2 * TS_SPAN_MAX_MODES],
        zero[2 + 2 * TS_SPAN_MAX_MODES] = {0};
    for (int i = 0; i < sp->n; i++)
        xd2[i] = 0.3 + 0.1 * ((i * 7) % 5) - (i % 3 == 0 ? 0.8 : 0);
    ts_span_force(sp, &mw, x, xd2, f);
    ts_span_force(sp, &mw, x, zero, f0);
    ts_span_force(sp, NULL, x, xd2, fn);
    ts_span_force(sp, NULL, x, zero, fn0);
    double work = 0, share_l = 0, share_t = 0;
    for (int i = 0; i < sp->n; i++) {
        double cor = (f[i] - f0[i]) - (fn[i] - fn0[i]);
        work += cor * xd2[i];
        if (i < sp->i_trans)
            share_l += fabs(cor * xd2[i]);
        else
            share_t += fabs(cor * xd2[i]);
    }
    printf("# Coriolis power %.3g W; |shares| longitudinal %.3g, transverse %.3g W\n", work,
           share_l, share_t);
    assert_true(share_l > 10 && share_t > 10); /* both families carry it */
    assert_close(work, 0, 0, 1e-9 * (share_l + share_t));
    ts_span_free(sp);
}

static void track_span_chord_kinematics(void **state)
{
    (void)state;
    /* EVIDENCE: rigid-body kinematics (exact). Tangent points of a chord
     * spinning at w about end 0 while end 0 accelerates with A and the chord
     * grows at rate Ld: theta_d = w, L_d = Ld, theta_dd = -2 Ld w / L for a
     * constant w (the Coriolis part of d^2(L e_x)/dt^2), a0 in chord axes. */
    const double L = 2.0, th = 0.3, w = 1.5, Ld = 0.2;
    double ex[2] = {cos(th), sin(th)}, ey[2] = {-sin(th), cos(th)};
    double P[2][2] = {{1.0, 0.5}, {1.0 + L * ex[0], 0.5 + L * ex[1]}};
    double Vp[2][2] = {{0, 0}, {Ld * ex[0] + L * w * ey[0], Ld * ex[1] + L * w * ey[1]}};
    /* d'' = (L'' - L w^2) e_x + (2 L' w + L w') e_y with L'' = 0, w' = 0 */
    double A[2][2] = {{0.3, -0.7},
                      {0.3 - L * w * w * ex[0] + 2 * Ld * w * ey[0],
                       -0.7 - L * w * w * ex[1] + 2 * Ld * w * ey[1]}};
    ts_span_geometry g;
    ts_span_motion mo;
    double ld;
    ts_span_kinematics(P, Vp, A, G0, &g, &mo, &ld);
    assert_close(g.length, L, 1e-12, 0);
    assert_close(g.angle, th, 1e-12, 0);
    assert_close(ld, Ld, 1e-12, 0);
    assert_close(mo.theta_d, w, 1e-12, 0);
    assert_close(mo.theta_dd, 0.0, 0, 1e-12);
    assert_close(mo.a0x, 0.3 * ex[0] - 0.7 * ex[1], 0, 1e-12);
    assert_close(mo.a0y, 0.3 * ey[0] - 0.7 * ey[1], 0, 1e-12);
    assert_close(mo.g_y, ts_span_gravity_normal(th, G0), 1e-12, 0);
}

static void track_span_table1_test_span(void **state)
{
    (void)state;
    /* EVIDENCE: paper Table 1 (single test span): predicted 7.2, 14.6, 23.2,
     * 29.7 Hz; measured 7.2, 14.7, 25.3, 37.0 Hz. CALIBRATED: the span length
     * 1.39 m (track.json /track/span_length) and P0, rho were inferred from
     * f1 = 7.2 Hz itself (table1-span preset), so f1, f2 within 5 % shows
     * consistency, not prediction. Modes 3-4 are printed beside the paper. */
    const double L = 1.39;
    ts_span_params p = base(L, G0, 8, 8);
    ts_modes *m = modes_of(&p, 0, 4);
    const double pred[4] = {7.2, 14.6, 23.2, 29.7}, meas[4] = {7.2, 14.7, 25.3, 37.0};
    for (int i = 0; i < 4; i++)
        print_message("  Table 1 f%d: model %.2f Hz, paper predicted %.1f, measured %.1f\n", i + 1,
                      m->freq[i], pred[i], meas[i]);
    assert_close(m->freq[0], 7.2, 0.05, 0);
    assert_close(m->freq[1], 14.6, 0.05, 0);
    ts_modes_free(m);
}

/* Composite 5-point Gauss-Legendre rule on [0, L] (64 sub-intervals): the
 * test's own quadrature, independent of the span's construction rule. */
#define QN 64
static void quad_point(double L, int q, double *s, double *w)
{
    static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
    static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                 0.4786286704993665, 0.2369268850561891};
    double h = L / QN;
    *s = (q / 5 + 0.5) * h + 0.5 * h * x5[q % 5];
    *w = 0.5 * h * w5[q % 5];
}

/* V_x(s) of the transverse sine basis V = sum_k q_Tk sin(k pi s/L) (track_span.h). */
static double span_vx(const ts_span *sp, const double *x, double s)
{
    double L = sp->p.length, vx = 0;
    for (int k = 1; k <= sp->p.n_trans; k++)
        vx += x[sp->i_trans + k - 1] * (k * PI / L) * cos(k * PI * s / L);
    return vx;
}

static void check_energy_and_end_force(int nl, int quasi_static)
{
    const double L = 1.7;
    ts_span_params p = base(L, G0, nl, 6);
    p.quasi_static_stretch = quasi_static;
    ts_span *sp = span_of(&p);
    assert_true(sp->kappa > 0); /* a sagging span: the kappa terms are live */
    int n = sp->n;
    double x[2 + 2 * TS_SPAN_MAX_MODES], xd[2 + 2 * TS_SPAN_MAX_MODES] = {0};
    double f[2 + 2 * TS_SPAN_MAX_MODES];
    unsigned st = 20260u + (unsigned)(nl * 7 + quasi_static);
    x[0] = 1e-3 * test_urand(&st);
    x[1] = 2e-3 + 1e-3 * test_urand(&st); /* net stretch u1 - u0 != 0 */
    for (int i = 2; i < sp->i_trans; i++)
        x[i] = 2e-4 * test_urand(&st);
    for (int i = sp->i_trans; i < n; i++)
        x[i] = 2e-2 * test_urand(&st);
    x[sp->i_trans] = 3e-2; /* a first-mode sag change: \int V != 0 */
    double xkx = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            xkx += x[i] * sp->K[i * n + j] * x[j];
    double w_field = 0, mean_tau = 0;
    for (int q = 0; q < 5 * QN; q++) {
        double s, w, tau, vx;
        quad_point(L, q, &s, &w);
        ts_span_eval(sp, x, s, NULL, NULL, &tau);
        vx = span_vx(sp, x, s);
        w_field += w * 0.5 * (tau * tau / EA + P0 * vx * vx);
        mean_tau += w * tau / L;
    }
    print_message("  n_long %d%s: 1/2 x'Kx = %.9g J, 1/2 int(tau^2/EA + P0 V_x^2) = %.9g J\n", nl,
                  quasi_static ? " uniform tension" : "", 0.5 * xkx, w_field);
    assert_close(0.5 * xkx, w_field, 1e-9, 0);
    ts_span_force(sp, NULL, x, xd, f);
    print_message("    f[0] = %.6f N, f[1] = %.6f N, P0 + mean tau = %.6f N\n", f[0], f[1],
                  P0 + mean_tau);
    assert_close(f[1], -(P0 + mean_tau), 1e-10, 0);
    assert_close(f[0], P0 + mean_tau, 1e-10, 0);
    ts_span_free(sp);
}

static void track_span_energy_tension_consistency(void **state)
{
    (void)state;
    /* EVIDENCE: Eqs. 1-2 and the span's strain energy (track_span.h):
     *   W = 1/2 x^T K x = 1/2 \int_0^L (tau^2/EA + P0 V_x^2) ds,
     *   tau = EA (U_x + kappa V)  (dynamic stretch), or
     *   tau = EA/L (u1 - u0 + kappa \int V)  (uniform tension, Irvine),
     * with tau from ts_span_eval and the integral by the test's own 320-point
     * Gauss rule; and the end-1 generalised force of the stretched span
     *   f[1] = -P0 - dW/du1 = -(P0 + (1/L) \int tau ds) = -(P0 + mean tau)
     * (dU_x/du1 = 1/L), f[0] = P0 + mean tau. A sagging span (g_y = g,
     * kappa L = 0.041) in a random modal state, n_long = 0 (both the uniform-
     * tension and the linear-U variant) and n_long = 4: the sign of kappa in
     * tau, in K's sag coupling and in the uniform-tension b vector must all
     * agree. Exact up to quadrature: 1e-9 (energy), 1e-10 (force). Not
     * calibrated. */
    check_energy_and_end_force(4, 0);
    check_energy_and_end_force(0, 0);
    check_energy_and_end_force(0, 1);
}

/* A slack state of a sagging span: compressed (x[1] = -2 P0 L/EA) with
 * transverse and longitudinal modes small enough that sigma < 0 everywhere. */
static void check_slack_sagging(int nl, int quasi_static)
{
    const double L = 1.5;
    ts_span_params p = base(L, G0, nl, 4);
    p.quasi_static_stretch = quasi_static;
    ts_span *sp = span_of(&p);
    int n = sp->n;
    double x[2 + 2 * TS_SPAN_MAX_MODES] = {0}, xd[2 + 2 * TS_SPAN_MAX_MODES] = {0};
    double f[2 + 2 * TS_SPAN_MAX_MODES];
    x[0] = 1e-4;
    x[1] = x[0] - 2.0 * P0 / EA * L;
    for (int i = 2; i < sp->i_trans; i++)
        x[i] = 1e-4 / (i - 1);
    x[sp->i_trans] = 0.03; /* EA kappa V ~ 2e4 N < P0: still all slack */
    x[sp->i_trans + 1] = -0.01;
    x[sp->i_trans + 2] = 0.005;
    /* slack energy = \int (P0 + tau)^2/(2 EA) with tau from ts_span_eval */
    double want = 0, smax = -INFINITY;
    for (int q = 0; q < 5 * QN; q++) {
        double s, w, tau;
        quad_point(L, q, &s, &w);
        ts_span_eval(sp, x, s, NULL, NULL, &tau);
        want += w * (P0 + tau) * (P0 + tau) / (2 * EA);
        smax = fmax(smax, P0 + tau);
    }
    assert_true(smax < 0); /* the whole span is slack */
    double got = ts_span_slack_energy(sp, x);
    print_message("  slack energy n_long %d%s: %.9g J, \\int sigma^2/(2EA) = %.9g J\n", nl,
                  quasi_static ? " uniform tension" : "", got, want);
    assert_close(got, want, 1e-5, 0); /* the 48-point rule against 320 points */
    /* linear + slack forces of the fully slack span: the axial field is gone,
     * end rows carry nothing; each transverse row k keeps the string stiffness
     * and the sag's P0 load: P0 kappa a_k - P0 (k pi/L)^2 (L/2) q_k,
     * a_k = \int sin(k pi s/L) ds = L (1 - cos k pi)/(k pi). */
    ts_span_force(sp, NULL, x, xd, f);
    assert_int_equal(ts_span_slack_force(sp, x, NULL, 0, f), 1);
    double rmax = 0;
    for (int i = 0; i < sp->i_trans; i++)
        rmax = fmax(rmax, fabs(f[i]));
    print_message("    linear + slack force: largest axial row %.3g N\n", rmax);
    for (int i = 0; i < sp->i_trans; i++)
        assert_close(f[i], 0, 0, 1e-5 * P0);
    for (int k = 1; k <= 4; k++) {
        double ak = L * (1 - cos(k * PI)) / (k * PI);
        double fk =
            P0 * sp->kappa * ak - P0 * pow(k * PI / L, 2) * (L / 2) * x[sp->i_trans + k - 1];
        assert_close(f[sp->i_trans + k - 1], fk, 0, 1e-5 * P0);
    }
    /* gradient pair with g_y != 0 on a slack state (partly slack with n_long > 0) */
    double y[2 + 2 * TS_SPAN_MAX_MODES] = {0}, g[2 + 2 * TS_SPAN_MAX_MODES] = {0};
    y[1] = (quasi_static ? -1.3 : -0.6) * P0 / EA * L; /* uniform tension: slack all over */
    if (nl > 0) y[2] = 0.7 * P0 / EA * L / PI;
    y[sp->i_trans] = quasi_static ? 0.02 : 0.05;
    y[sp->i_trans + 1] = -0.04;
    assert_int_equal(ts_span_slack_force(sp, y, NULL, 0, g), 1);
    assert_slack_gradient(sp, y, g, n);
    ts_span_free(sp);
}

static void track_span_slack_law_sagging(void **state)
{
    (void)state;
    /* EVIDENCE: the slack law's strain e = U_x + kappa V (or the uniform
     * (u1 - u0 + kappa \int V)/L) must be the strain of tau = EA e in
     * ts_span_eval and of K (track_span.h). A sagging span (g_y = g)
     * compressed to sigma < 0 everywhere:
     *  - removed energy = \int (P0 + tau)^2/(2EA) ds (tau from ts_span_eval,
     *    the test's own 320-point rule): 1e-5 (the 48-point rule's own
     *    quadrature error, 3e-7 measured);
     *  - linear + slack forces: no axial force left on the end and
     *    longitudinal rows, and P0 kappa a_k - P0 (k pi/L)^2 (L/2) q_k on
     *    transverse row k (the string stiffness and the sag's P0 load):
     *    1e-5 P0 (0.19 N measured);
     *  - on a slack state (partly slack with n_long > 0) ts_span_slack_force
     *    is the gradient of ts_span_slack_energy (central differences, 1e-6).
     * n_long = 3 and uniform tension. Exact; not calibrated. */
    check_slack_sagging(3, 0);
    check_slack_sagging(0, 1);
}

static void track_span_end_force_shear(void **state)
{
    (void)state;
    /* EVIDENCE: statics, force of the track on each support = (P0 + tau) times
     * the unit tangent leaving that support into the span, linearised
     * (ts_span_end_forces_eval): with Y0' = kappa (L/2 - s) and V = q_T1
     * sin(pi s/L) + q_T2 sin(2 pi s/L) (q_T1 = a, q_T2 = b) and a stretch e,
     * tau(0) = tau(L) = EA e (V = 0 at the ends):
     *   f0y = P0 (kappa L/2 + a pi/L + b 2pi/L) + EA e kappa L/2
     *   f1y = P0 (kappa L/2 + a pi/L - b 2pi/L) + EA e kappa L/2
     * (end 1: tangent into the span is -(1, Y0'(L) + V_x(L)), Y0'(L) =
     * -kappa L/2, V_x(L) = -a pi/L + b 2pi/L). The symmetric mode a loads
     * both supports alike, the antisymmetric b oppositely. Uniform tension:
     * tau = EA (e + kappa a 2/pi) at both ends. Exact (1e-12). */
    const double L = 2.0, a = 0.01, b = 0.004, e = 1e-3;
    ts_span_params p = base(L, G0, 2, 3);
    ts_span *sp = span_of(&p);
    double kap = sp->kappa, x[7] = {0};
    x[1] = e * L;
    x[sp->i_trans] = a;
    x[sp->i_trans + 1] = b;
    ts_span_end_forces ef;
    ts_span_end_forces_eval(sp, x, &ef);
    double f0y = P0 * (kap * L / 2 + a * PI / L + b * 2 * PI / L) + EA * e * kap * L / 2;
    double f1y = P0 * (kap * L / 2 + a * PI / L - b * 2 * PI / L) + EA * e * kap * L / 2;
    print_message("  q_T1 %.3g, q_T2 %.3g, e %.0e: f0y %.3f N (closed form %.3f), f1y %.3f N "
                  "(%.3f)\n",
                  a, b, e, ef.f0y, f0y, ef.f1y, f1y);
    assert_close(ef.f0y, f0y, 1e-12, 0);
    assert_close(ef.f1y, f1y, 1e-12, 0);
    assert_close(ef.f0x, P0 + EA * e, 1e-12, 0);
    assert_close(ef.f1x, -(P0 + EA * e), 1e-12, 0);
    /* EVIDENCE: Eqs. 1-2, tau = EA (U_x + kappa V), at each end: a first
     * longitudinal mode U = c sin(pi s/L) stretches end 0 by c pi/L and
     * shortens end 1 by as much (V = 0 at both ends), so the two end
     * tensions differ by 2 EA c pi/L. Exact (1e-12). */
    const double cl = 1e-4;
    x[sp->i_long] = cl;
    ts_span_end_forces_eval(sp, x, &ef);
    assert_close(ef.tension0, P0 + EA * (e + cl * PI / L), 1e-12, 0);
    assert_close(ef.tension1, P0 + EA * (e - cl * PI / L), 1e-12, 0);
    assert_close(ef.f1x, -(P0 + EA * (e - cl * PI / L)), 1e-12, 0);
    ts_span_free(sp);
    /* uniform tension: tau = EA (e + kappa a (2L/pi)/L) at both ends */
    ts_span_params pq = base(L, G0, 0, 3);
    pq.quasi_static_stretch = 1;
    ts_span *sq = span_of(&pq);
    double xq[5] = {0, e * L, a, b, 0};
    ts_span_end_forces_eval(sq, xq, &ef);
    double tq = EA * (e + kap * a * 2 / PI);
    assert_close(ef.f0y, P0 * (kap * L / 2 + a * PI / L + b * 2 * PI / L) + tq * kap * L / 2, 1e-12,
                 0);
    assert_close(ef.f1y, P0 * (kap * L / 2 + a * PI / L - b * 2 * PI / L) + tq * kap * L / 2, 1e-12,
                 0);
    assert_close(ef.tension0, P0 + tq, 1e-12, 0);
    assert_close(ef.tension1, P0 + tq, 1e-12, 0);
    ts_span_free(sq);
}

static void track_span_rotation_loads_profile(void **state)
{
    (void)state;
    /* EVIDENCE: closed forms of the static responses to the chord rotation
     * loads of Eqs. 4-5, lever arm s measured from end 0 (fixed ends, no sag):
     *  - theta_dd: P0 V'' = rho theta_dd s -> V(s) = rho theta_dd/(6 P0)
     *    (s^3 - L^2 s): V(L/4) = -15 rho theta_dd L^3/(384 P0),
     *    V(3L/4) = -21 rho theta_dd L^3/(384 P0)
     *  - theta_d^2: EA U'' = -rho theta_d^2 s -> U(s) = rho theta_d^2/(6 EA)
     *    (L^2 s - s^3): U(L/4) = 15 rho theta_d^2 L^3/(384 EA),
     *    U(3L/4) = 21 rho theta_d^2 L^3/(384 EA)
     * (at L/2 both give the mid-span values of
     * track_span_support_motion_loads). A lever arm from end 1 (L - s) swaps
     * the quarter-point values (40 % apart). 12 modes per family; sine
     * coefficients of the cubic fall as 1/k^3, within 0.2 %. Not calibrated. */
    const double L = 1.8, thdd = 2.0, thd = 4.0;
    ts_span_params p = base(L, 0.0, 12, 12);
    ts_span *sp = span_of(&p);
    double x[2 + 2 * TS_SPAN_MAX_MODES], U, V;
    double l3 = L * L * L;
    ts_span_motion mt = {.theta_dd = thdd};
    static_response(sp, &mt, x);
    ts_span_eval(sp, x, L / 4, NULL, &V, NULL);
    print_message("  theta_dd: V(L/4) = %.6e m (closed form %.6e)", V,
                  -15 * RHO * thdd * l3 / (384 * P0));
    assert_close(V, -15 * RHO * thdd * l3 / (384 * P0), 0.002, 0);
    ts_span_eval(sp, x, 3 * L / 4, NULL, &V, NULL);
    print_message(", V(3L/4) = %.6e m (%.6e)\n", V, -21 * RHO * thdd * l3 / (384 * P0));
    assert_close(V, -21 * RHO * thdd * l3 / (384 * P0), 0.002, 0);
    ts_span_motion mw = {.theta_d = thd};
    static_response(sp, &mw, x);
    ts_span_eval(sp, x, L / 4, &U, NULL, NULL);
    print_message("  theta_d^2: U(L/4) = %.6e m (closed form %.6e)", U,
                  15 * RHO * thd * thd * l3 / (384 * EA));
    assert_close(U, 15 * RHO * thd * thd * l3 / (384 * EA), 0.002, 0);
    ts_span_eval(sp, x, 3 * L / 4, &U, NULL, NULL);
    print_message(", U(3L/4) = %.6e m (%.6e)\n", U, 21 * RHO * thd * thd * l3 / (384 * EA));
    assert_close(U, 21 * RHO * thd * thd * l3 / (384 * EA), 0.002, 0);
    ts_span_free(sp);
}

static void track_span_modal_damping(void **state)
{
    (void)state;
    /* EVIDENCE: modal damping c_j = 2 zeta omega_j m_j (track_span.h). Without
     * sag the sine modes are the exact modes of the string and bar:
     * m_j = rho L/2, omega_j = j pi/L sqrt(P0/rho) (transverse) or
     * j pi/L sqrt(EA/rho) (longitudinal), so C_jj = zeta j pi sqrt(P0 rho)
     * resp. zeta j pi sqrt(EA rho), C zero off the diagonal and on the support
     * rows, and the force carries -C x_d. zeta = 0.05; 1e-9. Not calibrated. */
    const double L = 1.6, zeta = 0.05;
    ts_span_params p = base(L, 0.0, 3, 4);
    p.damping_ratio = zeta;
    ts_span *sp = span_of(&p);
    int n = sp->n;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double want = 0;
            if (i == j && i >= sp->i_trans)
                want = zeta * (i - sp->i_trans + 1) * PI * sqrt(P0 * RHO);
            else if (i == j && i >= 2)
                want = zeta * (i - 1) * PI * sqrt(EA * RHO);
            assert_close(sp->C[i * n + j], want, 1e-9, 1e-12);
        }
    print_message("  C of transverse mode 1: %.4f N s/m (zeta pi sqrt(P0 rho) = %.4f)\n",
                  sp->C[sp->i_trans * n + sp->i_trans], zeta * PI * sqrt(P0 * RHO));
    /* the damping force on a modal velocity */
    double x[9] = {0}, xd[9] = {0}, f[9];
    xd[sp->i_trans + 1] = 0.3;
    ts_span_force(sp, NULL, x, xd, f);
    assert_close(f[sp->i_trans + 1], -0.3 * zeta * 2 * PI * sqrt(P0 * RHO), 1e-9, 0);
    ts_span_free(sp);
}

static void track_span_moving_uniform_tension(void **state)
{
    (void)state;
    /* EVIDENCE: axially moving bar in the uniform-tension (Irvine) reduction:
     * W = (EA - rho c^2)/(2L) (u1 - u0)^2 on the constraint mode (no sag), so
     * K_00 = K_11 = (EA - rho c^2)/L, K_01 = -(EA - rho c^2)/L; the -rho c^2
     * softening of translation_terms (track_span.h). c = 11.2 m/s: 0.07 %
     * below EA/L; 1e-12. Not calibrated. */
    const double L = 1.5, c = 11.2;
    ts_span_params p = base(L, 0.0, 0, 2);
    p.quasi_static_stretch = 1;
    p.translation_terms = 1;
    p.speed = c;
    ts_span *sp = span_of(&p);
    int n = sp->n;
    double k = (EA - RHO * c * c) / L;
    assert_close(sp->K[0], k, 1e-12, 0);
    assert_close(sp->K[1], -k, 1e-12, 0);
    assert_close(sp->K[n], -k, 1e-12, 0);
    assert_close(sp->K[n + 1], k, 1e-12, 0);
    ts_span_free(sp);
}

/* Characteristic function of the translating shallow-sag cable with uniform
 * (quasi-static, Irvine) dynamic tension, fixed ends, at omega [rad/s]:
 *   T_c v'' + rho w^2 v - 2 i rho c w v' = Lam \int_0^L v,   Lam = EA kappa^2 / L,
 * T_c = P0 - rho c^2, kappa = rho g / T_c (the moving span's sag). With
 * v = e^{i a s} W, a = rho c w / T_c, the first-derivative term drops out and
 * T_c (W'' + b^2 W) = Lam I e^{-i a s}, b^2 = rho P0 w^2 / T_c^2 (the
 * substitution of Wickert & Mote 1990 for the travelling string); W(0) =
 * W(L) = 0 and I = \int e^{i a s} W give
 *   rho w^2 sin bL = Lam (L sin bL - A_c sin bL - (e^{-i a L} - cos bL) A_s),
 * A_c, A_s = \int_0^L e^{i a s} (cos, sin)(b s) ds. Returned times e^{i a L/2},
 * which makes it real on the real axis; c = 0 gives Irvine & Caughey's
 * equations (symmetric: tan x = x - 4 x^3 / lambda^2; antisymmetric:
 * sin bL = 0). The translating-cable equations are Perkins & Mote (1987),
 * "Three-dimensional vibration of travelling elastic cables", JSV 114. */
static double complex moving_cable_char(double w, double L, double c, double g)
{
    double tc = P0 - RHO * c * c, kap = RHO * g / tc, lam = EA * kap * kap / L;
    double a = RHO * c * w / tc, b = sqrt(RHO * P0) * w / tc;
    double complex ep = (cexp(I * (a + b) * L) - 1) / (I * (a + b));
    double complex em = (cexp(I * (a - b) * L) - 1) / (I * (a - b));
    double complex ac = 0.5 * (ep + em), as = (ep - em) / (2 * I);
    double sb = sin(b * L), cb = cos(b * L);
    double complex f = RHO * w * w * sb - lam * (L * sb - ac * sb - (cexp(-I * a * L) - cb) * as);
    return f * cexp(I * a * L / 2);
}

static void track_span_moving_irvine_cable(void **state)
{
    (void)state;
    /* EVIDENCE: closed form (moving_cable_char above: Perkins & Mote 1987's
     * translating cable with Irvine's uniform dynamic tension, solved by the
     * Wickert-Mote substitution): the first four natural frequencies of the
     * 2.72-m layout span (lambda^2 = 5.97 with the moving sag) translating at
     * c = 11.2 m/s (25 mph), uniform-tension variant, 16 sine modes, against
     * the roots of the characteristic equation (sign changes of its real part
     * where its imaginary part vanishes, bisected). Tolerance 0.2 %: measured
     * 0.006 / 0.015 / 0.03 / 0.07 % (the gyroscopic Galerkin converges slower
     * than the symmetric one). With the sag curvature left at rho g / P0 while
     * the stiffness has -rho c^2 (V = 0 then not the moving span's
     * equilibrium): f1 2.783 Hz against 2.997 (-7.1 %). At c = 0 the same
     * equation gives Irvine's 3.981 / 7.392 Hz (checked). Not calibrated. */
    const double L = 2.72, c = 11.2;
    for (int run = 0; run < 2; run++) {
        double cc = run ? c : 0.0, root[4];
        int nr = 0;
        double prev = creal(moving_cable_char(2 * PI * 0.5, L, cc, G0));
        for (double f = 0.5 + 1e-3; f < 40 && nr < 4; f += 1e-3) {
            double cur = creal(moving_cable_char(2 * PI * f, L, cc, G0));
            if ((cur > 0) != (prev > 0)) {
                double lo = f - 1e-3, hi = f;
                for (int it = 0; it < 60; it++) {
                    double mid = 0.5 * (lo + hi);
                    double vm = creal(moving_cable_char(2 * PI * mid, L, cc, G0));
                    double vl = creal(moving_cable_char(2 * PI * lo, L, cc, G0));
                    if ((vm > 0) == (vl > 0))
                        lo = mid;
                    else
                        hi = mid;
                }
                double complex z = moving_cable_char(2 * PI * lo, L, cc, G0);
                double scale = cabs(moving_cable_char(2 * PI * (lo + 0.3), L, cc, G0));
                if (fabs(cimag(z)) < 1e-9 * scale) root[nr++] = lo; /* not a phase jump */
            }
            prev = cur;
        }
        assert_int_equal(nr, 4);
        ts_span_params p = base(L, G0, 0, 16);
        p.quasi_static_stretch = 1;
        p.translation_terms = 1;
        p.speed = cc;
        ts_modes *m = modes_of(&p, 2, 4);
        for (int i = 0; i < 4; i++) {
            printf("# moving Irvine cable, c = %.1f m/s, mode %d: %.4f Hz, closed form %.4f Hz\n",
                   cc, i + 1, m->freq[i], root[i]);
            assert_close(m->freq[i], root[i], 0.002, 0);
        }
        ts_modes_free(m);
    }
}

static void track_span_transport_coriolis(void **state)
{
    (void)state;
    /* EVIDENCE: closed form (Coriolis acceleration 2 w x v_rel of the
     * material's transport c along a chord turning at theta_d): the load on
     * transverse mode k is -2 theta_d c rho \int phi_k = -4 theta_d c rho L
     * / (k pi) for odd k, 0 for even k; the same as the W coupling gives a
     * rigid feed u0_d = u1_d = c of a span at rest. Exact (1e-9). Missing
     * before: 0 on every row. Not calibrated. */
    const double L = 1.8, c = 7.0, thd = 0.6;
    ts_span_params p = base(L, G0, 2, 4);
    p.translation_terms = 1;
    p.speed = c;
    ts_span *sp = span_of(&p);
    double x[8] = {0}, xd[8] = {0}, f[8], fr[8];
    ts_span_motion mo = {.theta_d = thd, .g_y = G0};
    ts_span_force(sp, &mo, x, xd, f);
    for (int k = 1; k <= 4; k++) {
        double want = k % 2 ? -4 * thd * c * RHO * L / (k * PI) : 0;
        assert_close(f[sp->i_trans + k - 1], want, 1e-9, 1e-9);
    }
    ts_span_params q = base(L, G0, 2, 4);
    ts_span *sr = span_of(&q);
    xd[0] = xd[1] = c;
    ts_span_force(sr, &mo, x, xd, fr);
    for (int k = 0; k < 4; k++)
        assert_close(f[sp->i_trans + k], fr[sr->i_trans + k], 1e-9, 1e-9);
    ts_span_free(sr);
    ts_span_free(sp);
}

static void track_span_moving_bar_longitudinal(void **state)
{
    (void)state;
    /* EVIDENCE: closed form, the axially moving bar (the longitudinal
     * equation rho (U_tt + 2 c U_st + c^2 U_ss) = EA U_ss of Eqs. 1-2 with
     * translation_terms is the travelling string's, Wickert & Mote 1990):
     * omega_n = n pi (a^2 - c^2) / (a L), a = sqrt(EA / rho), fixed ends. EA
     * is set to 4 rho c^2 so c = a / 2 (factor 0.75, a strong test; the
     * transverse limit rho c^2 < P0 keeps c below 20 m/s with the track's
     * data). Longitudinal block, 16 sine modes; within 0.5 % for n = 1..3
     * (measured 0.003 / 0.011 / 0.03 %). Without G on the longitudinal
     * shapes the frequencies are n pi sqrt(a^2 - c^2) / L: f1 8.660 Hz
     * against 7.500 (+15 %); with their -rho c^2 tripled 3.536 Hz (-53 %).
     * Not calibrated. */
    const double L = 1.5, c = 15.0, ea = 4 * RHO * c * c, a = sqrt(ea / RHO);
    ts_span_params p = base(L, 0.0, 16, 0);
    p.ea = ea;
    p.translation_terms = 1;
    p.speed = c;
    ts_modes *m = modes_of(&p, 1, 3);
    for (int n = 1; n <= 3; n++) {
        double want = n * PI * (a * a - c * c) / (a * L) / (2 * PI);
        printf("# moving bar, mode %d: %.5f Hz, closed form %.5f Hz\n", n, m->freq[n - 1], want);
        assert_close(m->freq[n - 1], want, 0.005, 0);
    }
    ts_modes_free(m);
}

static void track_span_moving_string_travelling_wave(void **state)
{
    (void)state;
    /* EVIDENCE: closed form (d'Alembert in the moving medium: V = F(s - v t)
     * solves rho (V_tt + 2 c V_st + c^2 V_ss) = P0 V_ss when (v - c)^2 = c_w^2,
     * c_w = sqrt(P0 / rho): waves travel at c + c_w and c - c_w; Wickert &
     * Mote 1990, whose travelling-string modes are travelling waves, phase
     * e^{i rho c w s / (P0 - rho c^2)}, whose direction is the sign of c).
     * String (no sag), c = c_w / 2, a Gaussian pulse (width L/10) at
     * s = 0.65 L launched as the slow wave F(s - (c - c_w) t), i.e. V_t =
     * -(c - c_w) F', which runs UPSTREAM at c_w / 2; after t = 0.6 L / c_w its
     * centre (V^2-weighted) must be at 0.65 L - 0.3 L = 0.35 L, before it
     * reaches the end. 16 sine modes, fixed-step RK4 on ts_span_force
     * (M diagonal). Tolerance 0.03 L: measured 0.0001 L off. With G's sign
     * flipped (waves at -c +- c_w) the launched pulse splits and its centre
     * ends at 0.205 L (the frequencies of track_span_moving_string do not
     * see the sign: they are even in c). Not calibrated. */
    const double L = 1.5, cw = sqrt(P0 / RHO), c = 0.5 * cw, s0 = 0.65 * L, w = 0.1 * L;
    ts_span_params p = base(L, 0.0, 0, 16);
    p.translation_terms = 1;
    p.speed = c;
    ts_span *sp = span_of(&p);
    int n = sp->n, it = sp->i_trans, nt = 16;
    double y[2 * 18] = {0}, k[4][2 * 18], tmp[2 * 18], f[18];
    /* projections of F and -(c - cw) F' on the sine modes (M = rho L/2 I) */
    const int nq = 2000;
    for (int j = 0; j < nq; j++) {
        double s = (j + 0.5) * L / nq, e = exp(-((s - s0) * (s - s0)) / (w * w));
        double dF = -2 * (s - s0) / (w * w) * e;
        for (int kk = 0; kk < nt; kk++) {
            double phi = sin((kk + 1) * PI * s / L) * 2.0 / nq;
            y[it + kk] += e * phi;
            y[n + it + kk] += -(c - cw) * dF * phi;
        }
    }
    const double T = 0.6 * L / cw, dt = 2e-5;
    int steps = (int)lround(T / dt);
    for (int st = 0; st < steps; st++) {
        for (int r = 0; r < 4; r++) {
            const double *yy = y;
            if (r > 0) {
                double h = r == 3 ? dt : 0.5 * dt;
                for (int i = 0; i < 2 * n; i++)
                    tmp[i] = y[i] + h * k[r - 1][i];
                yy = tmp;
            }
            ts_span_force(sp, NULL, yy, yy + n, f);
            for (int i = 0; i < n; i++) {
                k[r][i] = i >= it ? yy[n + i] : 0;
                k[r][n + i] = i >= it ? f[i] / sp->M[i * n + i] : 0;
            }
        }
        for (int i = 0; i < 2 * n; i++)
            y[i] += dt / 6 * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]);
    }
    double num = 0, den = 0;
    for (int j = 0; j < 400; j++) {
        double s = (j + 0.5) * L / 400, V;
        ts_span_eval(sp, y, s, NULL, &V, NULL);
        num += s * V * V, den += V * V;
    }
    double centre = num / den;
    printf("# travelling string: slow wave's centre %.4f L, closed form %.4f L\n", centre / L,
           (s0 + (c - cw) * T) / L);
    assert_close(centre, s0 + (c - cw) * T, 0, 0.03 * L);
    ts_span_free(sp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(track_span_tangent_geometry),
        cmocka_unit_test(track_span_matrices_and_eq9),
        cmocka_unit_test(track_span_taut_string_and_bar_limits),
        cmocka_unit_test(track_span_irvine_quasi_static),
        cmocka_unit_test(track_span_irvine_dynamic_stretch),
        cmocka_unit_test(track_span_irvine_crossover),
        cmocka_unit_test(track_span_convergence_monotone),
        cmocka_unit_test(track_span_moving_string),
        cmocka_unit_test(track_span_end_forces_static),
        cmocka_unit_test(track_span_slack_law),
        cmocka_unit_test(track_span_support_motion_loads),
        cmocka_unit_test(track_span_chord_kinematics),
        cmocka_unit_test(track_span_table1_test_span),
        cmocka_unit_test(track_span_energy_tension_consistency),
        cmocka_unit_test(track_span_slack_law_sagging),
        cmocka_unit_test(track_span_end_force_shear),
        cmocka_unit_test(track_span_rotation_loads_profile),
        cmocka_unit_test(track_span_modal_damping),
        cmocka_unit_test(track_span_moving_uniform_tension),
        cmocka_unit_test(track_span_moving_irvine_cable),
        cmocka_unit_test(track_span_transport_coriolis),
        cmocka_unit_test(track_span_moving_bar_longitudinal),
        cmocka_unit_test(track_span_moving_string_travelling_wave),
    };
    return cmocka_run_group_tests_name("sim/track_span", tests, NULL, NULL);
}
