/*
 * fuel_actuator.c — constant-phi fuel law, Eqs. 13-14 (see fuel_actuator.h).
 */
#include "fuel_actuator.h"

#include <math.h>

#include "constants.h"
#define RPM_PER_RAD_S (30.0 / TS_PI)
#define OMEGA_MIN 10.0 /* guard against N -> 0 in Eq. 14 [rad/s] */
#define N_REV_PER_CYCLE 2.0 /* n_R: four-stroke */

ts_fuel_law ts_fuel_law_from_config(const ts_engine_config *c)
{
    ts_fuel_law f = {c->phi_rated, c->phi_curvature, c->phi_speed,
                     c->phi_max,   c->afr_stoich,    TS_ENGINE_NCYL};
    return f;
}

double ts_fuel_phi_target(const ts_fuel_law *f, double omega)
{
    double dw = omega - f->speed_rated;
    double phi = f->phi_rated + f->phi_curvature * dw * dw; /* Eq. 13 */
    return phi < f->phi_max ? phi : f->phi_max;
}

double ts_fuel_per_cycle(const ts_fuel_law *f, double air_flow, double omega, double rack)
{
    if (rack < 0) rack = 0;
    if (rack > 1) rack = 1;
    if (air_flow < 0) air_flow = 0;
    double n_rpm = fmax(omega, OMEGA_MIN) * RPM_PER_RAD_S;
    /* Eq. 14: m_f = m_air phi_tgt / (A/F)_s Rack 60 n_R / (N n_cyl) */
    return air_flow * ts_fuel_phi_target(f, omega) / f->afr_stoich * rack * 60.0 *
           N_REV_PER_CYCLE / (n_rpm * f->n_cyl);
}
