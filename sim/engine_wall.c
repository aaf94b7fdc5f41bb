/*
 * engine_wall.c — layered wall of one combustion-chamber surface (paper
 * Section III.B.1 "wall-structure model", III.B.3 zirconia LHR variants):
 * 1-D transient conduction through an optional plasma-sprayed zirconia coat
 * on metal, back side to coolant or oil through a film coefficient.
 *
 * Vertex-centred finite volumes, EN_WALL_NODES nodes, node 0 ON the gas-side
 * surface (half-cell capacity), cells graded geometrically from the surface so
 * the cyclic temperature swing (penetration ~0.08 mm in zirconia, ~0.5 mm in
 * metal at 2100 rpm) is resolved: coated walls get 7 coating cells (ratio 1.6,
 * first cell 2.3 % of the coat) and 3 metal cells (ratio 3); all-metal walls 10
 * metal cells (ratio 1.5). Leaves out contact resistance at the bond coat and
 * lateral conduction.
 */
#include <math.h>

#include "engine_impl.h"

static void grade(double *h, int n, double total, double ratio)
{
    double h0 = total * (ratio - 1.0) / (pow(ratio, n) - 1.0);
    for (int i = 0; i < n; i++) h[i] = h0 * pow(ratio, i);
}

void en_wall_build(en_wall *w, double coating, double k_coat, double rc_coat, double metal,
                   double k_metal, double rc_metal, double h_back)
{
    enum { NC = EN_WALL_NODES - 1 };
    double h[NC], k[NC], rc[NC];
    int nc = coating > 0 ? 7 : 0;
    if (nc) grade(h, nc, coating, 1.6);
    grade(h + nc, NC - nc, metal, nc ? 3.0 : 1.5);
    for (int i = 0; i < NC; i++) {
        k[i] = i < nc ? k_coat : k_metal;
        rc[i] = i < nc ? rc_coat : rc_metal;
    }
    double depth = 0;
    for (int i = 0; i < EN_WALL_NODES; i++) {
        double left = i > 0 ? rc[i - 1] * h[i - 1] : 0.0;
        double right = i < NC ? rc[i] * h[i] : 0.0;
        w->cap[i] = 0.5 * (left + right);
        w->cond[i] = i < NC ? k[i] / h[i] : h_back;
        w->depth[i] = depth;
        if (i < NC) depth += h[i];
    }
    w->coated_nodes = nc;
}

void en_wall_rates(const en_wall *w, const double *T, double q, double T_sink, double *dT,
                   double *q_back)
{
    int n = EN_WALL_NODES;
    double in = q;
    for (int i = 0; i < n; i++) {
        double out = i < n - 1 ? w->cond[i] * (T[i] - T[i + 1]) : w->cond[i] * (T[i] - T_sink);
        dT[i] = (in - out) / w->cap[i];
        in = out;
    }
    *q_back = in;
}

/* Crank-Nicolson over h for every stack: (C/h + K/2) T' = (C/h - K/2) T + q e_0 +
 * g_n T_sink e_n, K the (tridiagonal) conduction matrix. The matrix depends on
 * the surface and h only, so it is factored once per surface (Thomas
 * algorithm) and the twelve cylinders' stacks are solved with it, node by node
 * across the cylinders (twelve independent recurrences in flight instead of
 * one; the same operations per stack). */
void en_walls_step(const ts_engine *e, double *x, const double *q, double h)
{
    enum { N = EN_WALL_NODES, S = EN_NSURF * N /* stride between cylinders */ };
    double T_cool = x[e->off_coolant], T_oil = x[e->off_coolant + 1];
    double *T0 = x + e->off_wall;
    for (int sf = 0; sf < EN_NSURF; sf++) {
        const en_wall *w = &e->wall[sf];
        const double *g = w->cond;
        double ch[N], gl[N], up[N], f[N], inv[N];
        for (int i = 0; i < N; i++) {
            gl[i] = i > 0 ? w->cond[i - 1] : 0.0;
            ch[i] = w->cap[i] / h;
            up[i] = -0.5 * w->cond[i];
        }
        double d = ch[0] + 0.5 * (gl[0] + w->cond[0]);
        inv[0] = 1.0 / d;
        f[0] = 0.0;
        for (int i = 1; i < N; i++) {
            f[i] = -0.5 * gl[i] * inv[i - 1];
            d = ch[i] + 0.5 * (gl[i] + w->cond[i]) - f[i] * up[i - 1];
            inv[i] = 1.0 / d;
        }
        double T_sink = sf == EN_PISTON ? T_oil : T_cool;
        double r[N][EN_NCYL];
        double *Ts = T0 + sf * N; /* stack of cylinder c: Ts + c * S */
        /* right-hand sides down each stack (no recurrence: the node loop runs
         * inside, the stack's temperatures read once each) */
        for (int c = 0; c < EN_NCYL; c++) {
            const double *T = Ts + c * S;
            double Tl = T[0], Tc = T[1];
            r[0][c] = ch[0] * Tl + 0.5 * g[0] * (Tc - Tl) + q[c * EN_NSURF + sf];
            for (int i = 1; i < N - 1; i++) { /* C/h T + 1/2 (g_l (T_l - T) + g_r (T_r - T)) */
                double Tr = T[i + 1];
                r[i][c] = ch[i] * Tc + 0.5 * (gl[i] * (Tl - Tc) + g[i] * (Tr - Tc));
                Tl = Tc;
                Tc = Tr;
            }
            r[N - 1][c] = ch[N - 1] * Tc + 0.5 * (gl[N - 1] * (Tl - Tc) + g[N - 1] * (T_sink - Tc));
            r[N - 1][c] += 0.5 * w->cond[N - 1] * T_sink; /* sink half of the implicit side */
        }
        for (int i = 1; i < N; i++)
            for (int c = 0; c < EN_NCYL; c++) r[i][c] -= f[i] * r[i - 1][c];
        for (int c = 0; c < EN_NCYL; c++) Ts[c * S + N - 1] = r[N - 1][c] * inv[N - 1];
        for (int i = N - 2; i >= 0; i--)
            for (int c = 0; c < EN_NCYL; c++)
                Ts[c * S + i] = (r[i][c] - up[i] * Ts[c * S + i + 1]) * inv[i];
    }
}
