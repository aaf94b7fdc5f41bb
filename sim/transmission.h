/*
 * transmission.h — four-speed planetary automatic with clutch-to-clutch shifts
 * (paper Section III.B.2): "Operating modes are defined by combinations of
 * locked and unlocked clutches. Shifting is accomplished through simultaneous
 * disengagement and engagement of appropriate clutches during a user-specified
 * interval of time", with the upshift "based on engine speed" (1850 rpm).
 *
 * Model. Each forward gear i has one range clutch between the input shaft
 * (turbine, speed w_in) and the output shaft (w_out) with ratio r_i; its
 * friction torque, referred to the input, is regularised Coulomb friction
 *     T_i = C_i(t) tanh((w_in - r_i w_out) C_max / (w_s C_i(t))),
 * so a clutch is locked up to a creep of w_s (C_i/C_max) atanh(T/C_i), with
 * the same stiffness C_max/w_s near zero slip whatever its capacity, and
 * slips at its capacity beyond. C_max = clutch_capacity (applied). The input
 * shaft loses sum T_i; the output gains sum r_i eta_i^(+-1) T_i (efficiency on
 * the forward power path, its inverse when torque flows back).
 *
 * A shift from gear a to gear b over the interval [t0, t0 + dt]: with
 * tau = (t - t0)/dt the off-going clutch capacity falls as (1 - tau) Cs and the
 * on-coming one rises as tau Cs, Cs = shift_capacity_factor x |input torque at
 * t0| (floored at 5 % of clutch_capacity). The torque is handed over between
 * the clutches during the interval (torque phase, then inertia phase once the
 * off-going clutch breaks away), not by an instant ratio jump. At t0 + dt the
 * shift is over (gear b engaged) but the on-coming clutch is not yet fully
 * applied: its capacity rises linearly from Cs to clutch_capacity over one
 * more interval, [t0 + dt, t0 + 2 dt] [E: the torque and inertia phases of a
 * shift take about the nominal interval each; a clutch still slipping at
 * t0 + dt — the converter's torque grows as the turbine slows — finishes its
 * inertia phase under a rising torque instead of being slammed shut at
 * clutch_capacity]. Map engine, Table 2 run: peak transmission output torque
 * of the 1-2 shift 24 kN*m instead of 74 kN*m, turbine deceleration 5.5
 * instead of 59 rad/s per 5 ms. (A slower variant, the rise continued at
 * Cs/dt, closed the slip ~0.5 s after the interval and left no tension spike
 * in the coupled run's Fig. 29 test; this faster one was chosen after that.)
 *
 * Shift logic: an upshift starts when the engine speed crosses shift_speed
 * upwards [P III.B.2]. The upshift is then disarmed until the engine speed has
 * fallen to shift_speed - shift_hysteresis — during the shift or after it —
 * or, as a fallback, shift_dwell has passed since the shift ended (so a shift
 * that ends with the engine still above shift_speed does not chain straight
 * into the next one, and an engine that dipped during the shift and climbs
 * back to shift_speed shifts again without waiting for the dwell). A downshift starts when the
 * engine speed falls to downshift_speed (gear > 1) while the lower gear would turn its input no
 * faster than downshift_speed at the present output speed (a slow vehicle, not a dropped rack: no
 * downshift-upshift hunting).
 *
 * Events: shift start (engine speed crossings), shift end, dwell end and the
 * end of the post-shift capacity ramp (time; capacity set to 0 = fully
 * applied there, so the clutch law's kink is an integrator restart) are ROOT FUNCTIONS of the
 * caller's ODE (ts_transmission_roots); at a root the caller runs ts_transmission_update (a
 * discrete state machine) and re-initialises its integrator when it returns 1.
 */
#ifndef TS_TRANSMISSION_H
#define TS_TRANSMISSION_H

#include "config.h"
#include "errors.h"

#define TS_TRANSMISSION_NROOTS 4

typedef struct ts_transmission {
    int n;                            /* forward gears */
    double ratio[TS_NGEAR_MAX];       /* input / output speed per gear */
    double efficiency[TS_NGEAR_MAX];  /* per gear */
    double shift_speed;               /* upshift engine speed [rad/s] */
    double downshift_speed;           /* downshift engine speed, 0 = never [rad/s] */
    double shift_time;                /* [s] */
    double shift_dwell;               /* re-arm time after a shift [s] */
    double shift_hysteresis;          /* re-arm below shift_speed by this [rad/s] */
    double clutch_capacity;           /* applied clutch [N*m] */
    double shift_capacity_factor;     /* [1] */
    double shift_capacity_floor;      /* [1] of clutch_capacity */
    double slip_speed;                /* regularisation [rad/s] */
} ts_transmission;

/* Discrete state (part of a saved state). */
typedef struct ts_shift_state {
    int gear;          /* engaged gear 1..n; during a shift the off-going gear */
    int target;        /* on-coming gear during a shift, 0 otherwise */
    double t_start;    /* start of the current shift [s] */
    double capacity;   /* peak shift-clutch capacity Cs of the current (or, while the
                          engaged clutch's capacity still ramps, the last) shift;
                          0: engaged clutch fully applied [N*m] */
    int shifts;        /* completed shifts since reset */
    int armed;         /* an upshift may start */
    double t_end;      /* end of the last completed shift [s] */
} ts_shift_state;

typedef struct ts_tr_point {
    double input_torque;   /* torque the clutches take from the input shaft [N*m] */
    double output_torque;  /* torque delivered to the output shaft [N*m] */
    double offgoing_torque, oncoming_torque; /* clutch torques, input side [N*m] (on-coming 0 outside shifts) */
    double slip;           /* slip of the engaged (off-going) clutch [rad/s] */
    double gear;           /* gear as a number; between a and b during a shift (by tau) [1] */
} ts_tr_point;

TS_MUST_CHECK ts_rc ts_transmission_init(ts_transmission *tr, const ts_driveline_config *c,
                                         ts_err *err);

/* Capacity of the engaged clutch at t outside a shift [N*m] (rising after a
 * shift, see above); 0 during a shift. */
double ts_transmission_applied_capacity(const ts_transmission *tr, const ts_shift_state *st,
                                        double t);

/* Start in gear (1..n), not shifting. */
void ts_transmission_reset(const ts_transmission *tr, ts_shift_state *st, int gear);

/* Torques at time t for input speed w_in and output speed w_out [rad/s]. */
void ts_transmission_eval(const ts_transmission *tr, const ts_shift_state *st, double t,
                          double w_in, double w_out, ts_tr_point *out);

/* TS_TRANSMISSION_NROOTS root functions of (t, engine speed, output speed
 * [rad/s]) for the current discrete state; a sign change marks an event. */
void ts_transmission_roots(const ts_transmission *tr, const ts_shift_state *st, double t,
                           double w_engine, double w_out, double *g);

/* Discrete state machine, run at an event (and once after each re-init): ends a
 * shift whose interval has elapsed, re-arms the upshift (engine below
 * shift_speed - hysteresis, or dwell over), starts an upshift when armed and
 * w_engine >= shift_speed (gear < n) or a downshift when w_engine and the
 * lower gear's input speed at w_out are both <= downshift_speed (gear > 1).
 * input_torque = current input-shaft torque (sets
 * Cs). Returns 1 when the discrete state changed (the caller must
 * re-initialise its integrator: the root functions changed). */
int ts_transmission_update(const ts_transmission *tr, ts_shift_state *st, double t, double w_engine,
                           double w_out, double input_torque);

#endif
