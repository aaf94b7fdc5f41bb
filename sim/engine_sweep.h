/*
 * engine_sweep.h — the engine's full-load curve on a dynamometer (paper
 * Section III.B.3, Fig. 18): steady states at 100-rpm steps from 800 to
 * 2100 rpm at the configured variant, fidelity and rack (/control/rack),
 * ambient air from /driveline/ambient_pressure and ambient_temperature.
 * What `tanksim engine-map --out` writes and what the /engine/map_* tables of
 * engine.json are made from (tools/engine_maps.py).
 */
#ifndef TS_ENGINE_SWEEP_H
#define TS_ENGINE_SWEEP_H

#include "config.h"
#include "engine.h"
#include "errors.h"
#include "model.h"

#define TS_ENGINE_SWEEP_RPM_LO   800  /* lowest speed of the sweep [rpm] */
#define TS_ENGINE_SWEEP_RPM_HI   2100 /* rated speed, where the sweep starts [rpm] */
#define TS_ENGINE_SWEEP_RPM_STEP 100  /* [rpm] */
#define TS_ENGINE_SWEEP_NPOINT   14   /* (RPM_HI - RPM_LO) / RPM_STEP + 1 */

/* rows[k] is the steady state at RPM_LO + k*RPM_STEP (ascending), run as today: a lug-down
 * from rated speed (2100, 2000, ..., 800 rpm), each point started from the previous one's
 * state, the first from ts_engine_init_state with the turbo at a search speed; every point
 * is ts_engine_steady with the crank speed held. progress (may be NULL) is called after each
 * point with (done, TS_ENGINE_SWEEP_NPOINT); as the sweep runs downwards, the point just
 * finished is rows[TS_ENGINE_SWEEP_NPOINT - done]. Errors: cfg's (ts_param_validate), the
 * engine's (ts_engine_make,
 * ts_engine_steady, with their pointer and message), TS_ERR_NOMEM, TS_ERR_CANCELLED when
 * progress returned non-zero; rows are then only partly filled. */
TS_MUST_CHECK ts_rc ts_engine_full_load_sweep(const ts_config *cfg,
                                              ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT],
                                              ts_progress_fn progress, void *ud, ts_err *err);

/* The sweep's refusals of cfg itself, without running it (ts_param_validate,
 * ts_engine_make): what a server answers before queueing the sweep. */
TS_MUST_CHECK ts_rc ts_engine_full_load_sweep_check(const ts_config *cfg, ts_err *err);

#endif
