/*
 * engine_friction.c — Millington & Hartles (1968) motored friction (paper
 * Section III.B.1, ref. 28), evaluated at the INSTANTANEOUS crank speed:
 *   fmep = a (r_c - 4) + b N + c S_p^2,   N [rpm], S_p = 2 stroke N / 60 [m/s].
 * Constants in engine.json (a from Millington & Hartles 1968; b, c provisional, chosen for 1.5-2.5 bar fmep at 2100 rpm: engine.json's notes).
 * The friction torque fmep V_d / (4 pi) fades to zero below a few rad/s
 * (tanh(w / EN_FRICTION_FADE), 5 rad/s, a numerical smoothing so the engine does not drive
 * itself backwards at rest). The crank-angle-varying inertia is in
 * engine_crank.c (it needs the piston kinematics of every cylinder).
 */
#include <math.h>

#include "engine_impl.h"

double en_fmep(const ts_engine_config *c, double omega)
{
    double w = omega > 0 ? omega : 0;
    double sp = c->stroke * w / EN_PI; /* mean piston speed 2 S N / 60 [m/s] */
    return c->fmep_a * (c->compression_ratio - 4.0) + c->fmep_b * w + c->fmep_c * sp * sp;
}

double en_friction_torque(const ts_engine *e, double omega)
{
    return en_fmep(&e->c, omega) * e->geom.vd * EN_NCYL / EN_CYCLE * tanh(omega / EN_FRICTION_FADE);
}
