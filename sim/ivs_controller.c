/*
 * ivs_controller.c — PI speed controller with saturation, back-calculation
 * anti-windup and gain scheduling (ivs_controller.h; paper Eq. 10, Figs. 25, 27).
 */
#include "ivs_controller.h"

ts_ivs_gains ts_ivs_gains_at(const ts_ivs *c, double x)
{
    int n = c->nschedule;
    if (n <= 0) return c->fixed;
    if (x <= c->sched_x[0]) return c->sched[0];
    if (x >= c->sched_x[n - 1]) return c->sched[n - 1];
    int i = 0;
    while (i < n - 2 && x > c->sched_x[i + 1]) i++;
    double s = (x - c->sched_x[i]) / (c->sched_x[i + 1] - c->sched_x[i]);
    ts_ivs_gains g = {c->sched[i].kp + s * (c->sched[i + 1].kp - c->sched[i].kp),
                      c->sched[i].ti + s * (c->sched[i + 1].ti - c->sched[i].ti)};
    return g;
}

double ts_ivs_output(ts_ivs_gains g, double e, double integral)
{
    return g.kp * (e + integral / g.ti); /* Eq. 10 */
}

double ts_ivs_rack(ts_ivs_gains g, double e, double integral)
{
    double u = ts_ivs_output(g, e, integral);
    return u < 0 ? 0 : u > 1 ? 1 : u; /* Fig. 25 saturation */
}

double ts_ivs_integral_rate(const ts_ivs *c, ts_ivs_gains g, double e, double integral)
{
    if (!c->anti_windup) return e;
    double u = ts_ivs_output(g, e, integral);
    double us = u < 0 ? 0 : u > 1 ? 1 : u;
    /* Back-calculation with tracking time T_t = T_I: dI/dt = e + (T_I/(K_p T_t)) (u_s - u). */
    return e + (us - u) / g.kp;
}

ts_rc ts_ivs_check(const ts_ivs *c, ts_err *err)
{
    if (c->nschedule < 0 || c->nschedule > TS_IVS_SCHEDULE_MAX)
        return ts_err_set(err, TS_ERR_RANGE, "/control/schedule_x",
                          "/control/schedule_x: at most %d rows", TS_IVS_SCHEDULE_MAX);
    if (c->nschedule == 0 && (!(c->fixed.kp > 0) || !(c->fixed.ti > 0)))
        return ts_err_set(err, TS_ERR_RANGE, "/control/kp", "/control/kp, /control/ti: positive");
    for (int i = 0; i < c->nschedule; i++) {
        if (!(c->sched[i].kp > 0) || !(c->sched[i].ti > 0))
            return ts_err_set(err, TS_ERR_RANGE, "/control/schedule_kp",
                              "/control/schedule_kp, schedule_ti: positive (row %d)", i);
        if (i > 0 && !(c->sched_x[i] > c->sched_x[i - 1]))
            return ts_err_set(err, TS_ERR_RANGE, "/control/schedule_x",
                              "/control/schedule_x: must increase (row %d)", i);
    }
    return TS_OK;
}
