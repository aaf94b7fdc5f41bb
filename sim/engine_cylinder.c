/*
 * engine_cylinder.c — slider-crank kinematics and valve lift/flow areas of one
 * cylinder (paper Section III.B.1). Angles are local crank angles from the
 * cylinder's firing TDC, 0..4 pi. The valve flow itself is the quasi-steady
 * orifice of engine_manifold.c applied to the areas returned here.
 */
#include <math.h>

#include "engine_impl.h"

void en_kinematics(const en_geom *g, double th, en_kin *k)
{
    en_kinematics_sc(g, sin(th), cos(th), k);
}

void en_kinematics_sc(const en_geom *g, double s, double c, en_kin *k)
{
    double a = g->crank, l = g->rod;
    double r = sqrt(l * l - a * a * s * s), ir = 1.0 / r; /* one division */
    k->xp = a + l - (a * c + r);
    k->dxdth = a * s + a * a * s * c * ir;
    k->d2xdth2 = a * c + a * a * (c * c - s * s) * ir + a * a * a * a * s * s * c * c * (ir * ir * ir);
    k->V = g->vc + g->area * k->xp;
    k->dVdth = g->area * k->dxdth;
}

double en_valve_lift(double th, double open, double close, double lmax)
{
    double span = close - open;
    double d = th - open;
    if (d < 0) d += 4.0 * EN_PI;
    if (d > span) return 0.0;
    return lmax * 0.5 * (1.0 - cos(2.0 * EN_PI * d / span));
}

double en_valve_area(double lift, double diameter, int n, double cd)
{
    double curtain = EN_PI * diameter * lift;
    double seat = 0.9 * EN_PI / 4.0 * diameter * diameter;
    return cd * n * (curtain < seat ? curtain : seat);
}
