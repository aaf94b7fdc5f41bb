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
    double Lh = c->V / c->area;
    if (Lh > c->bore / 2) Lh = c->bore / 2;
    double K = c->K > 0.0 ? c->K : 0.0, k = c->k > 1e-9 ? c->k : 1e-9;
    double im = 1.0 / m, iL = 1.0 / Lh, skm = sqrt(k * im); /* sqrt(k / m) */
    double up = sqrt(2.0 / 3.0) * skm;                    /* sqrt(2 k / (3 m)) */
    double P = 0.3307 * cbeta * (K * iL) * skm;
    double eps = up * up * up * iL;
    double out_m = c->mdot_out * im;
    *dK = 0.5 * c->mdot_in * c->v_in * c->v_in - P - K * out_m;
    *dk = P - m * eps - k * out_m + rdt * (2.0 / 3.0) * k * c->drho_rho;
    *L = Lh;
    *u_turb = up;
    *U_mean = sqrt(2.0 * K * im);
}

double en_htc(double a, double b, double rho, double u, double L, double T, double cp)
{
    /* h = a Re^b lambda / L with lambda = mu cp / Pr, mu = 3.3e-7 T^0.7:
     *   h = (a cp / (Pr L)) (rho u L)^b mu^(1 - b), one exp and two logs */
    double lmu = log(3.3e-7) + 0.7 * log(T > 200.0 ? T : 200.0);
    return a * cp / (PRANDTL * L) * exp(b * log(rho * u * L) + (1.0 - b) * lmu);
}
