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
