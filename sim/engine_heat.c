/*
 * engine_heat.c — in-cylinder heat transfer (paper Section III.B.1; Assanis &
 * Heywood 1986, Poulos & Heywood 1983): a 0-D energy cascade gives the mean
 * (K = m U^2 / 2) and turbulent (k = 3 m u'^2 / 2) kinetic energies,
 *   dK/dt = 1/2 mdot_in v_in^2 - P - K mdot_out / m
 *   dk/dt = P - m eps - k mdot_out / m + c_rdt (2/3) k (1/rho) drho/dt
 *   P = 0.3307 c_beta (K / L) sqrt(k / m),  eps = u'^3 / L,
 *   L = instantaneous chamber height V / A_bore, at most B / 2;
 * the convective coefficient follows a turbulent pipe-flow Nusselt law
 *   Nu = h L / lambda = a Re^b,  Re = rho u L / mu,  u = sqrt(U^2 + u'^2 + (S_p/2)^2)
 * (the piston-speed term is an estimate, parameters.md 3.4). Radiation during
 * combustion is added in engine_crank.c. Gas viscosity mu = 3.3e-7 T^0.7 Pa s
 * (air, within ~5 % 300-2500 K), Prandtl number 0.7.
 */
#include <math.h>

#include "engine_impl.h"

#define PRANDTL 0.7

void en_cascade(const en_cascade_in *c, double cbeta, double rdt, double *dK, double *dk,
                double *L, double *u_turb, double *U_mean)
{
    double m = c->m;
    double Lh = c->V / (EN_PI / 4.0 * c->bore * c->bore);
    if (Lh > c->bore / 2) Lh = c->bore / 2;
    double K = fmax(c->K, 0.0), k = fmax(c->k, 1e-9);
    double up = sqrt(2.0 * k / (3.0 * m));
    double P = 0.3307 * cbeta * (K / Lh) * sqrt(k / m);
    double eps = up * up * up / Lh;
    *dK = 0.5 * c->mdot_in * c->v_in * c->v_in - P - K * c->mdot_out / m;
    *dk = P - m * eps - k * c->mdot_out / m + rdt * (2.0 / 3.0) * k * c->drho_rho;
    *L = Lh;
    *u_turb = up;
    *U_mean = sqrt(2.0 * K / m);
}

double en_htc(double a, double b, double rho, double u, double L, double T, double cp)
{
    double mu = 3.3e-7 * pow(fmax(T, 200.0), 0.7);
    double lambda = mu * cp / PRANDTL;
    double re = rho * u * L / mu;
    return a * pow(re, b) * lambda / L;
}
