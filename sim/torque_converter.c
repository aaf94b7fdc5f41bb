/*
 * torque_converter.c — table-driven torque converter (torque_converter.h),
 * paper Section III.B.2. The K-factor table is interpolated as the capacity
 * 1/K^2 (linear in SR), which is smooth through the coupling range and lets the
 * capacity reach zero at SR = 1, where a real converter transmits no torque.
 * Leaves out: fluid inertia, lock-up clutch, temperature effects.
 */
#include "torque_converter.h"

#include <math.h>

ts_rc ts_torque_converter_init(ts_torque_converter *tc, const ts_driveline_config *c,
                               ts_err *err)
{
    int n = c->tc_speed_ratio_n;
    if (n < 2)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_speed_ratio",
                          "/driveline/tc_speed_ratio: need at least 2 rows");
    if (c->tc_torque_ratio_n != n)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_torque_ratio",
                          "/driveline/tc_torque_ratio: %d values for %d speed ratios",
                          c->tc_torque_ratio_n, n);
    if (c->tc_k_factor_n != n)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_k_factor",
                          "/driveline/tc_k_factor: %d values for %d speed ratios",
                          c->tc_k_factor_n, n);
    if (c->tc_speed_ratio[0] != 0.0)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_speed_ratio/0",
                          "/driveline/tc_speed_ratio: the table must start at SR 0 (stall)");
    for (int i = 1; i < n; i++)
        if (!(c->tc_speed_ratio[i] > c->tc_speed_ratio[i - 1]) || c->tc_speed_ratio[i] >= 1.0)
            return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_speed_ratio",
                              "/driveline/tc_speed_ratio: must increase and stay below 1 "
                              "(row %d)", i);
    /* the coupling range: TR holds its last value up to SR 1, where it must
     * be 1 (below, the coupling would lose torque; above, create power) */
    if (c->tc_torque_ratio[n - 1] != 1.0)
        return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_torque_ratio",
                          "/driveline/tc_torque_ratio: the last row must be 1 (coupling range), "
                          "got %g",
                          c->tc_torque_ratio[n - 1]);
    /* no more power out than in: TR * SR <= 1 at every row and at the top of
     * each segment's parabola (TR linear in SR between rows) */
    const double *sr = c->tc_speed_ratio, *tr = c->tc_torque_ratio;
    for (int i = 0; i < n; i++) {
        double e = tr[i] * sr[i], e_seg = 0;
        if (i + 1 < n) {
            double b = (tr[i + 1] - tr[i]) / (sr[i + 1] - sr[i]), a = tr[i] - b * sr[i];
            double s_top = b < 0 ? -a / (2 * b) : -1;
            if (s_top > sr[i] && s_top < sr[i + 1]) e_seg = (a + b * s_top) * s_top;
        }
        if (e > 1.0 + 1e-12 || e_seg > 1.0 + 1e-12)
            return ts_err_set(err, TS_ERR_PARAM, "/driveline/tc_torque_ratio",
                              "/driveline/tc_torque_ratio: efficiency TR*SR reaches %.4f at or "
                              "after row %d (SR %g); the converter would give more power than "
                              "it takes",
                              e > e_seg ? e : e_seg, i, sr[i]);
    }
    tc->n = n;
    for (int i = 0; i < n; i++) {
        tc->speed_ratio[i] = c->tc_speed_ratio[i];
        tc->torque_ratio[i] = c->tc_torque_ratio[i];
        tc->capacity[i] = 1.0 / (c->tc_k_factor[i] * c->tc_k_factor[i]);
    }
    return TS_OK;
}

/* Capacity 1/K^2 and TR at speed ratio sr in [0, 1]. */
static void lookup(const ts_torque_converter *tc, double sr, double *cap, double *tr)
{
    int n = tc->n;
    if (sr <= 0.0) {
        *cap = tc->capacity[0];
        *tr = tc->torque_ratio[0];
        return;
    }
    double last = tc->speed_ratio[n - 1];
    if (sr >= last) { /* falls linearly to zero capacity at SR 1; TR stays at its last value */
        double s = sr >= 1.0 ? 1.0 : (sr - last) / (1.0 - last);
        *cap = tc->capacity[n - 1] * (1.0 - s);
        *tr = tc->torque_ratio[n - 1];
        return;
    }
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (tc->speed_ratio[mid] <= sr) lo = mid;
        else hi = mid;
    }
    double s = (sr - tc->speed_ratio[lo]) / (tc->speed_ratio[hi] - tc->speed_ratio[lo]);
    *cap = tc->capacity[lo] + s * (tc->capacity[hi] - tc->capacity[lo]);
    *tr = tc->torque_ratio[lo] + s * (tc->torque_ratio[hi] - tc->torque_ratio[lo]);
}

void ts_torque_converter_eval(const ts_torque_converter *tc, double w_pump, double w_turbine,
                              ts_tc_point *out)
{
    double cap, tr;
    if (w_pump <= 0.0 && w_turbine <= 0.0) {
        *out = (ts_tc_point){0.0, 0.0, 0.0, tc->torque_ratio[0], INFINITY, 0.0};
        return;
    }
    if (w_turbine <= w_pump) { /* forward flow; a backwards turbine counts as stall */
        double sr = w_turbine > 0.0 ? w_turbine / w_pump : 0.0;
        lookup(tc, sr, &cap, &tr);
        out->pump_torque = cap * w_pump * w_pump;
        out->turbine_torque = tr * out->pump_torque;
        out->speed_ratio = w_turbine / w_pump;
        out->torque_ratio = tr;
        out->k_factor = cap > 0.0 ? 1.0 / sqrt(cap) : INFINITY;
        out->efficiency = tr * out->speed_ratio;
        return;
    }
    /* over-running: the turbine drives the pump (engine braking) */
    double sr_rev = w_pump > 0.0 ? w_pump / w_turbine : 0.0;
    lookup(tc, sr_rev, &cap, &tr);
    double t = -cap * w_turbine * w_turbine;
    out->pump_torque = t;
    out->turbine_torque = t;
    out->speed_ratio = w_pump > 0.0 ? w_turbine / w_pump : INFINITY;
    out->torque_ratio = 1.0;
    out->k_factor = cap > 0.0 ? 1.0 / sqrt(cap) : INFINITY;
    out->efficiency = sr_rev; /* pump power / turbine power, power flowing backwards */
}
