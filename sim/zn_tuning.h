/*
 * zn_tuning.h — Ziegler–Nichols open-loop (reaction-curve) tuning of the IVS
 * PI controller from a simulated unit step of rack -> vehicle speed (paper
 * Section IV.B.1, Eqs. 11–12, Fig. 26).
 *
 * The response is normalised (Eq. 11):
 *   U_r = (R − R_0)/(R_b − R_0),   V_ar = (V_a − V_a0)/(V_ab − V_a0)
 * (0 = steady state before the step, b = rated: engine at rated power, full
 * rack). The tangent at the point of steepest slope (the inflection of the
 * S-shaped V_ar(t)) meets the time axis at X (measured from the step) and the
 * speed axis at Y = −slope·X. Gains (Eq. 12; Ziegler & Nichols 1942 PI rule):
 *   K_p = e/|Y|  (normalised units),   T_I = f·|X|
 * with e = 0.9 (paper and classical rule alike) and f printed 3 by the paper
 * against the classical 3.33 (= 1/0.3): both are parameters (/control/kp_factor,
 * /control/ti_factor). K_p converts to rack per m/s through the normalisation.
 */
#ifndef TS_ZN_TUNING_H
#define TS_ZN_TUNING_H

#include "errors.h"

typedef struct ts_zn_result {
    double t_inflection; /* time of steepest slope [s] */
    double slope;        /* steepest slope of V_ar [1/s] */
    double x;            /* X: dead time, tangent's time-axis intercept after the step [s] */
    double y;            /* Y: tangent's speed-axis intercept at the step time [1], negative */
    double kp_norm;      /* e/|Y| [1] */
    double ti;           /* f |X| [s] */
} ts_zn_result;

/* Reaction-curve construction on a sampled normalised response v[i] at
 * increasing times t[i] (n >= 5 samples, uniform or not), step applied at
 * t_step. The slope is a least-squares line over `window` samples (odd, >= 3)
 * to ride over track-vibration ripple. kp_factor is e and ti_factor f above. */
TS_MUST_CHECK ts_rc ts_zn_reaction_curve(const double *t, const double *v, int n, double t_step,
                                         int window, double kp_factor, double ti_factor,
                                         ts_zn_result *out, ts_err *err);

/* 1 when a slope window of `window` samples is centred on one (odd): the
 * rule ts_zn_reaction_curve applies, and ts_ivs_tune before its runs. */
int ts_zn_window_centred(int window);

/* Normalised K_p to physical gain [rack per (m/s)], Eq. 11 scalings. */
double ts_zn_kp_physical(double kp_norm, double rack0, double rack_b, double v0, double v_b);

#endif
