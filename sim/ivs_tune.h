/*
 * ivs_tune.h — the plant step behind the Ziegler–Nichols tuning of the IVS
 * speed controller (paper Section IV.B.1, Eqs. 11-12, Fig. 26): a simulated
 * rack step of the vehicle with its powertrain, reduced by zn_tuning.h to
 * K_p and T_I. What `tanksim tune` runs once per config (and once per point
 * of a Fig. 27 gain schedule).
 *
 * Plant: the POINT-MASS vehicle with the powertrain (scenario_pointmass.c,
 * /drive/kind "powertrain") of the given config — engine fidelity,
 * driveline, mass, grade and resistances from it; the multibody vehicle is
 * too slow for the minutes of simulated time the two steady states need.
 * Procedure: settle at /control/tune_rack_low for /control/tune_settle s
 * (steady state 0), save the state, restore it into a second model at full
 * rack and run /control/tune_duration s more; the final speed is the rated
 * steady state b. The speed is normalised by Eq. 11 and ts_zn_reaction_curve
 * builds the tangent (X, Y) over /control/tune_window samples;
 * K_p = /control/kp_factor / |Y| (normalised) and T_I = /control/ti_factor |X| (Eq. 12).
 */
#ifndef TS_IVS_TUNE_H
#define TS_IVS_TUNE_H

#include "config.h"
#include "errors.h"
#include "model.h"
#include "zn_tuning.h"

typedef struct ts_ivs_tune_result {
    double v0, vb, settle_slope, final_slope, kp; /* m/s, m/s, m/s^2, m/s^2, rack/(m/s) */
    ts_zn_result zn;                              /* sim/zn_tuning.h */
} ts_ivs_tune_result;

/* Run the step on cfg (its run, drive and control mode are overridden as above)
 * and fill out: v0 and vb the speeds at the end of the settle and of the step,
 * settle_slope / final_slope the speed slopes over the last second of each
 * (how steady they are), zn the reaction curve (t_inflection measured from the
 * start of the settle), kp = zn.kp_norm in rack per m/s (Eq. 11 scalings).
 * Errors: the model's (config pointer and message); TS_ERR_PARAM at
 * /control/tune_window when it is even; TS_ERR_RANGE (a value in its range
 * that does not work for this plant) at /control/tune_rack_low when the low
 * rack rolls the vehicle backwards or full rack is not faster, at
 * /control/tune_settle when the settle gives fewer than two samples, and at
 * /control/tune_settle or tune_duration when either speed is not steady;
 * ts_zn_reaction_curve's when the response is not S-shaped; TS_ERR_NOMEM. */
TS_MUST_CHECK ts_rc ts_ivs_tune(const ts_config *cfg, ts_ivs_tune_result *out, ts_err *err);

/* ts_ivs_tune that also calls poll(ud, done, total) every few samples of its
 * runs (done and total passed through unchanged: the caller's own count of
 * parts) and stops with TS_ERR_CANCELLED when it returns non-zero, so that a
 * long step response can be cancelled while it runs. poll may be NULL. */
TS_MUST_CHECK ts_rc ts_ivs_tune_polled(const ts_config *cfg, ts_ivs_tune_result *out,
                                       ts_progress_fn poll, void *ud, int done, int total,
                                       ts_err *err);

/* ts_ivs_tune's refusals of cfg itself, without its runs (the fields checked
 * before them, the point-mass plant's ts_model_make): what a server answers
 * before queueing a tune. */
TS_MUST_CHECK ts_rc ts_ivs_tune_check(const ts_config *cfg, ts_err *err);

#endif
