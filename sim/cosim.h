/*
 * cosim.h — the leading–following coupling of paper Section IV.A: an explicit
 * predictor–corrector co-simulation of two subsystems that meet at the drive
 * sprocket (Fig. 22).
 *
 *   leader (powertrain)   predicts sprocket speed from the follower's last
 *                         report: ω(t) = ω_k + α_k (t − t_k) (order 1) or ω_k
 *                         (order 0); integrates ahead with its own solver and
 *                         step, at most `lead` seconds ahead of the follower;
 *                         publishes (t, torque) samples at its step ends.
 *   follower (vehicle)    integrates with its own solver and step, never past
 *                         the leader's last sample, taking torque at its own
 *                         (internal) times by linear interpolation between the
 *                         published samples; reports converged (t, ω, α).
 *
 * The two sides see each other only through the two message types below, so
 * either could live in another process (a socket or HTTP transport would carry
 * exactly these). ts_cosim runs them in lock-step in one thread; nothing here
 * knows what a powertrain or a vehicle is.
 *
 * Ownership: ts_cosim_make / ts_cosim_free; participants are borrowed.
 */
#ifndef TS_COSIM_H
#define TS_COSIM_H

#include "errors.h"

typedef struct ts_cosim_report { /* follower -> leader */
    double t;     /* time of the converged follower state [s] */
    double omega; /* sprocket angular velocity [rad/s] */
    double alpha; /* sprocket angular acceleration [rad/s^2] */
} ts_cosim_report;

typedef struct ts_cosim_sample { /* leader -> follower */
    double t;       /* [s] */
    double torque;  /* sprocket torque [N*m] */
    double inertia; /* interface inertia the follower carries at t [kg*m^2] (0: plain
                       torque exchange); see coupled_system.h */
} ts_cosim_sample;

/* Torque seen by the follower at time t: linear interpolation of the
 * published samples (held flat outside them). The follower calls it from its
 * right-hand side through the pointer it gets in advance(). */
typedef struct ts_cosim_torque ts_cosim_torque;
double ts_cosim_torque_at(const ts_cosim_torque *src, double t);
/* The same for the samples' interface inertia. */
double ts_cosim_inertia_at(const ts_cosim_torque *src, double t);
/* Time of the last published sample: the torque beyond it is not known yet,
 * so the follower's integrator must not step past it (one that steps beyond
 * its output time and interpolates back would carry the held torque into its
 * history). */
double ts_cosim_torque_end(const ts_cosim_torque *src);

/* Sprocket speed predicted for the leader at time t from a report. */
double ts_cosim_predict(const ts_cosim_report *last, int order, double t);

typedef struct ts_cosim_leader {
    void *ud;
    /* Integrate from the leader's current time to t_to with the sprocket speed
     * given by ts_cosim_predict(last, order, .), and return the torque at t_to. */
    ts_rc (*advance)(void *ud, double t_to, const ts_cosim_report *last, int order,
                     ts_cosim_sample *out, ts_err *err);
} ts_cosim_leader;

typedef struct ts_cosim_follower {
    void *ud;
    /* Integrate from the follower's current time to t_to taking torque from
     * src, and report the converged sprocket state at t_to. */
    ts_rc (*advance)(void *ud, double t_to, const ts_cosim_torque *src, ts_cosim_report *out,
                     ts_err *err);
} ts_cosim_follower;

typedef struct ts_cosim_opts {
    double leader_step;   /* leader macro step h_L [s] */
    double follower_step; /* follower macro step h_F [s] */
    double lead;          /* largest lead of the leader over the follower [s] (>= h_L) */
    int predictor_order;  /* 0 or 1 */
} ts_cosim_opts;

typedef struct ts_cosim ts_cosim;

/* TS_OK when o can be kept: steps > 0, the lead at least both steps,
 * predictor order 0 or 1; else TS_ERR_PARAM naming the /coupling field. */
TS_MUST_CHECK ts_rc ts_cosim_check(const ts_cosim_opts *o, ts_err *err);

/* initial: the follower's state at t0 (ω, α) and the leader's torque at t0. */
ts_cosim *ts_cosim_make(const ts_cosim_opts *o, ts_cosim_leader leader, ts_cosim_follower follower,
                        double t0, ts_cosim_report initial, double torque0, ts_err *err);
/* The same with the full initial sample (its t is replaced by t0). */
ts_cosim *ts_cosim_make_sample(const ts_cosim_opts *o, ts_cosim_leader leader,
                               ts_cosim_follower follower, double t0, ts_cosim_report initial,
                               ts_cosim_sample sample0, ts_err *err);
void ts_cosim_free(ts_cosim *c);

/* Run both sides until the follower reaches t_end. */
TS_MUST_CHECK ts_rc ts_cosim_advance(ts_cosim *c, double t_end, ts_err *err);

double ts_cosim_follower_time(const ts_cosim *c);
double ts_cosim_leader_time(const ts_cosim *c);
const ts_cosim_report *ts_cosim_last_report(const ts_cosim *c);
long ts_cosim_exchanges(const ts_cosim *c); /* messages exchanged (both directions) */

#endif
