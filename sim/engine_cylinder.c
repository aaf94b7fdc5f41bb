/*
 * engine_cylinder.c — slider-crank kinematics and valve lift/flow areas of one
 * cylinder (paper Section III.B.1). Angles are local crank angles from the
 * cylinder's firing TDC, 0..4 pi. The valve flow itself is the quasi-steady
 * orifice of engine_manifold.c applied to the areas returned here.
 * en_kinematics_sc, en_valve_lift and en_valve_area are static inline in
 * engine_impl.h (hot path of the crank-angle right-hand side); this file keeps
 * the angle-based entry point.
 */
#include <math.h>

#include "engine_impl.h"

void en_kinematics(const en_geom *g, double th, en_kin *k)
{
    en_kinematics_sc(g, sin(th), cos(th), k);
}

