/*
 * ivs_controller.h — the intelligent vehicle speed (IVS) controller of paper
 * Section IV.B.1: a PI law on the speed error (Eq. 10, Fig. 25) followed by a
 * saturation to the fuel-rack range [0, 1], with anti-windup, and a gain
 * schedule (Fig. 27) that tabulates K_p and T_I against a scheduling variable
 * (vehicle mass, road grade, ...).
 *
 *   U(t) = K_p [ e(t) + (1/T_I) ∫ e dτ ],  e = V_r − V_a           (Eq. 10)
 *   rack = clamp(U, 0, 1)                                           (Fig. 25)
 *
 * The integral is a state of the caller's ODE: ts_ivs_rack() gives the rack
 * for (e, integral) and ts_ivs_integral_rate() the integral's derivative. Anti-
 * windup is back-calculation (Åström & Hägglund): while the output saturates
 * the integral is driven towards the value that would just reach the limit,
 * with tracking time constant T_t = T_I (0 disables it: plain integration).
 * The paper says only "saturation"; anti-windup is our addition and can be
 * switched off to reproduce the plain form.
 */
#ifndef TS_IVS_CONTROLLER_H
#define TS_IVS_CONTROLLER_H

#include "errors.h"

#define TS_IVS_SCHEDULE_MAX 16

typedef struct ts_ivs_gains {
    double kp; /* proportional gain [rack per (m/s)] */
    double ti; /* integral time [s] */
} ts_ivs_gains;

typedef struct ts_ivs {
    int nschedule;                          /* 0: fixed gains; else table rows */
    double sched_x[TS_IVS_SCHEDULE_MAX];    /* scheduling variable, increasing */
    ts_ivs_gains sched[TS_IVS_SCHEDULE_MAX];
    ts_ivs_gains fixed;                     /* used when nschedule == 0 */
    int anti_windup;                        /* back-calculation on/off */
} ts_ivs;

/* Gains at scheduling value x: linear interpolation in the table, held at the
 * ends (Fig. 27); the fixed gains when there is no table. */
ts_ivs_gains ts_ivs_gains_at(const ts_ivs *c, double x);

/* Unsaturated PI output U of Eq. 10 for error e [m/s] and integral I [m]. */
double ts_ivs_output(ts_ivs_gains g, double e, double integral);

/* Rack position in [0, 1] (the saturation block of Fig. 25). */
double ts_ivs_rack(ts_ivs_gains g, double e, double integral);

/* d(integral)/dt: e, plus the back-calculation term when anti-windup is on. */
double ts_ivs_integral_rate(const ts_ivs *c, ts_ivs_gains g, double e, double integral);

/* Check a controller description (positive gains, increasing table). */
TS_MUST_CHECK ts_rc ts_ivs_check(const ts_ivs *c, ts_err *err);

#endif
