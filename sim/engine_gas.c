/*
 * engine_gas.c — ideal-gas properties of the cylinder and manifold contents
 * (Section III.B.1: "ideal-gas properties varying with temperature and
 * composition"). Two species: air and stoichiometric burned gas (diesel
 * products); a mixture is fixed by F, the burned-gas mass fraction.
 * cp of each is a cubic in t = T/1000 K (engine.json: fitted to JANAF species
 * data, 300-2500 K, within 1 %). Enthalpies are sensible, zero at 298.15 K;
 * the chemical energy enters the cylinder as the fuel's LHV when it burns.
 * Leaves out dissociation (small below ~2500 K at the lean mixtures here).
 * en_gas_eval, the right-hand sides' hot path, is static inline in engine_impl.h.
 */
#include "engine_impl.h"

static double cp1(const double *c, double T)
{
    double t = T / 1000.0;
    return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}

/* integral of cp from EN_T0 to T [J/kg] */
static double h1(const double *c, double T)
{
    double t = T / 1000.0, t0 = EN_T0 / 1000.0;
    double a = t * (c[0] + t * (c[1] / 2 + t * (c[2] / 3 + t * (c[3] / 4))));
    double b = t0 * (c[0] + t0 * (c[1] / 2 + t0 * (c[2] / 3 + t0 * (c[3] / 4))));
    return 1000.0 * (a - b);
}

double en_gas_r(const en_gas *g, double F)
{
    F = en_gas_clamp_F(F);
    return (1 - F) * g->r_a + F * g->r_b;
}

double en_gas_cp(const en_gas *g, double T, double F)
{
    F = en_gas_clamp_F(F);
    T = en_gas_clamp_T(T);
    return (1 - F) * cp1(g->cp_a, T) + F * cp1(g->cp_b, T);
}

double en_gas_h(const en_gas *g, double T, double F)
{
    F = en_gas_clamp_F(F);
    return (1 - F) * h1(g->cp_a, T) + F * h1(g->cp_b, T);
}

double en_gas_u(const en_gas *g, double T, double F) { return en_gas_h(g, T, F) - en_gas_r(g, F) * T; }

static void derive(const double *c, double *cpT, double *hT)
{
    double sc = 1.0;
    for (int j = 0; j < 4; j++, sc *= 1e-3) cpT[j] = c[j] * sc; /* t^j = T^j 1e-3^j */
    hT[0] = 0.0;
    for (int j = 0; j < 4; j++) hT[j + 1] = cpT[j] / (j + 1); /* integral in T */
    double T0 = EN_T0;
    hT[0] = -T0 * (hT[1] + T0 * (hT[2] + T0 * (hT[3] + T0 * hT[4]))); /* h(EN_T0) = 0 */
}

void en_gas_init(en_gas *g, const double *cp_air, const double *cp_burned, double r_air,
                 double r_burned)
{
    for (int j = 0; j < 4; j++) {
        g->cp_a[j] = cp_air[j];
        g->cp_b[j] = cp_burned[j];
    }
    g->r_a = r_air;
    g->r_b = r_burned;
    derive(g->cp_a, g->cpT_a, g->hT_a);
    derive(g->cp_b, g->cpT_b, g->hT_b);
}
