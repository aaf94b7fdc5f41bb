/*
 * engine_heat.c — in-cylinder heat transfer (paper Section III.B.1; Assanis &
 * Heywood 1986, Poulos & Heywood 1983): a 0-D energy cascade gives the mean
 * (K = m U^2 / 2) and turbulent (k = 3 m u'^2 / 2) kinetic energies,
 *   dK/dt = 1/2 mdot_in v_in^2 - P - K mdot_out / m
 *   dk/dt = P - m eps - k mdot_out / m + c_rdt (2/3) k (1/rho) drho/dt
 *   P = 0.3307 c_beta (K / L) sqrt(k / m),  eps = u'^3 / L,
 *   L = instantaneous chamber height V / A_bore, at most B / 2;
 * the convective coefficient follows a turbulent pipe-flow Nusselt law
 *   Nu = h L / lambda = a Re^b,  Re = rho u L / mu,  u = sqrt(U^2 + u'^2 + (s S_p)^2)
 * (s = /engine/htc_piston_speed_share, 1/2, an estimate). Radiation during
 * combustion is added in engine_crank.c. Gas viscosity mu = c T^n
 * (/engine/gas_mu_coeff 3.3e-7 Pa s, gas_mu_exp 0.7: Heywood's air law, within
 * ~5 % over 300-2500 K), lambda = mu cp / Pr (/engine/gas_prandtl 0.7).
 */
#include <math.h>

#include "engine_impl.h"

/* en_cascade and en_htc, the crank-angle right-hand side's hot path (twelve
 * calls each per evaluation), are static inline in engine_impl.h; their
 * equations are the ones above. This file keeps the description. */
