/*
 * zn_tuning.c — reaction-curve (Ziegler–Nichols open-loop) tuning (zn_tuning.h).
 */
#include "zn_tuning.h"

#include <math.h>

int ts_zn_window_centred(int window)
{
    return window % 2 != 0;
}

ts_rc ts_zn_reaction_curve(const double *t, const double *v, int n, double t_step, int window,
                           double kp_factor, double ti_factor, ts_zn_result *out, ts_err *err)
{
    if (n < 5) return ts_err_set(err, TS_ERR_PARAM, NULL, "step response: need >= 5 samples");
    if (window < 3 || !ts_zn_window_centred(window) || window > n)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "step response: window must be odd, 3..n");
    if (!(kp_factor > 0)) return ts_err_set(err, TS_ERR_PARAM, NULL, "kp_factor must be > 0");
    if (!(ti_factor > 0)) return ts_err_set(err, TS_ERR_PARAM, NULL, "ti_factor must be > 0");
    int h = window / 2;
    double best = -INFINITY, tb = 0, vb = 0;
    for (int i = h; i < n - h; i++) {
        if (t[i] < t_step) continue;
        /* least-squares slope and value over t[i-h .. i+h] */
        double st = 0, sv = 0;
        for (int k = i - h; k <= i + h; k++) {
            st += t[k];
            sv += v[k];
        }
        double tm = st / window, vm = sv / window, num = 0, den = 0;
        for (int k = i - h; k <= i + h; k++) {
            num += (t[k] - tm) * (v[k] - vm);
            den += (t[k] - tm) * (t[k] - tm);
        }
        if (den <= 0) continue;
        double s = num / den;
        if (s > best) {
            best = s;
            tb = tm;
            vb = vm;
        }
    }
    if (!(best > 0) || !isfinite(best))
        return ts_err_set(err, TS_ERR_STATE, NULL,
                          "step response never rises: no reaction curve to tune on");
    /* Fig. 26: tangent v = vb + s (t − tb). */
    double x = (tb - vb / best) - t_step;
    double y = vb + best * (t_step - tb);
    if (!(x > 0))
        return ts_err_set(err, TS_ERR_STATE, NULL,
                          "step response has no dead time (X = %g s): not an S-shaped curve", x);
    out->t_inflection = tb;
    out->slope = best;
    out->x = x;
    out->y = y;
    out->kp_norm = kp_factor / fabs(y); /* Eq. 12a */
    out->ti = ti_factor * fabs(x);     /* Eq. 12b */
    return TS_OK;
}

double ts_zn_kp_physical(double kp_norm, double rack0, double rack_b, double v0, double v_b)
{
    /* U = K_n V: (R − R0)/(Rb − R0) = K_n (V − V0)/(Vb − V0)  => dR/dV = K_n (Rb − R0)/(Vb − V0) */
    return kp_norm * (rack_b - rack0) / (v_b - v0);
}
