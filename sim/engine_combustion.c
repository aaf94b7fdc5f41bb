/*
 * engine_combustion.c — ignition delay and fuel burning rate (paper Section
 * III.B.1: "Arrhenius correlation" for the delay, Watson's premixed +
 * diffusion correlation for the burn).
 *
 * Ignition delay (Watson et al. 1980): tau_id [ms] = a p[bar]^-n exp(ta / T),
 * applied under varying conditions through the Livengood-Wu integral
 * int dt / tau_id = 1 (engine_crank.c integrates it as a state).
 * Watson, Pilley & Marzouk (SAE 800029), tau = (theta - theta_ign)/duration:
 *   X = beta f1 + (1 - beta) f2,  beta = 1 - a phi^b / tau_id^c
 *   f1 = 1 - (1 - tau^C1)^C2,     C1 = 2 + c1k (tau_id N)^c1e, C2
 *   f2 = 1 - exp(-C3 tau^C4),     C3 = c3k / phi^c3e, C4 = c4k C3^0.25
 */
#include <math.h>

#include "engine_impl.h"

double en_ignition_delay(double a, double n, double ta, double p, double T)
{
    double p_bar = en_atleast(p / 1e5, 0.1);
    /* p^-n exp(ta / T) as one exp: exp(ta / T - n log p) */
    return a * exp(ta / en_atleast(T, 200.0) - n * log(p_bar));
}

void en_watson_pre(const en_watson *w, double tau, double tau_id_ms, double n_rpm,
                   en_watson_tau *p)
{
    p->tau = tau;
    if (tau <= 0 || tau >= 1) return;
    tau_id_ms = en_atleast(tau_id_ms, 0.05);
    p->id_c = pow(tau_id_ms, w->c);
    p->ltau = log(tau);
    double c1 = 2.0 + w->c1k * pow(tau_id_ms * n_rpm, w->c1e);
    double c2 = w->c2;
    double tc1 = exp(c1 * p->ltau);
    /* (1 - tc1)^c2 <= exp(-c2 tc1): past c2 tc1 = 50 the premixed burn is over
     * to 2e-22 (f1 = 1 in double precision, df1 below 1e-17), and the power is
     * skipped (c2 ~ 5000: after the first ~20 % of the burn) */
    double g = c2 * tc1 > 50.0 ? 0.0 : pow(1.0 - tc1, c2);
    p->f1 = 1.0 - g;
    p->df1 = c2 * g / (1.0 - tc1) * c1 * tc1 / tau; /* c2 (1 - tc1)^(c2 - 1) c1 tc1 / tau */
}

void en_watson_phi(const en_watson *w, const en_watson_tau *p, double phi, double *X, double *dX)
{
    if (p->tau <= 0) {
        *X = 0;
        *dX = 0;
        return;
    }
    if (p->tau >= 1) {
        *X = 1;
        *dX = 0;
        return;
    }
    double lphi = log(en_atleast(phi, 0.05));
    double beta = 1.0 - w->a * exp(w->b * lphi) / p->id_c;
    beta = beta < 0 ? 0 : beta > 1 ? 1 : beta;
    double c3 = w->c3k * exp(-w->c3e * lphi);
    double c4 = w->c4k * sqrt(sqrt(c3));
    double tc4 = exp(c4 * p->ltau);
    double ex = exp(-c3 * tc4);
    double f2 = 1.0 - ex;
    double df2 = c3 * c4 * tc4 / p->tau * ex;
    *X = beta * p->f1 + (1.0 - beta) * f2;
    *dX = beta * p->df1 + (1.0 - beta) * df2;
}

void en_watson_burn(const en_watson *w, double tau, double tau_id_ms, double n_rpm, double phi,
                    double *X, double *dX)
{
    en_watson_tau p;
    en_watson_pre(w, tau, tau_id_ms, n_rpm, &p);
    en_watson_phi(w, &p, phi, X, dX);
}
