/*
 * engine_sweep.c — the full-load dynamometer sweep (engine_sweep.h, Fig. 18).
 * Moved here from cli/cmd_engine_map.c unchanged in numerics (same start
 * state, order, cycle limit and tolerance), so that `tanksim engine-map` and
 * the daemon compute the curve with the same code.
 */
#include "engine_sweep.h"

#include <stdlib.h>

#include "constants.h"
#include "param.h"

_Static_assert(TS_ENGINE_SWEEP_NPOINT ==
                   (TS_ENGINE_SWEEP_RPM_HI - TS_ENGINE_SWEEP_RPM_LO) / TS_ENGINE_SWEEP_RPM_STEP + 1,
               "TS_ENGINE_SWEEP_NPOINT does not match the speed range");

/* The sweep's engine; NULL with err filled when cfg is refused. ts_engine_make
 * indexes its tables by the enum fields: validate as ts_model_make does. */
static ts_engine *sweep_engine(const ts_config *cfg, ts_err *err)
{
    if (ts_param_validate(cfg, err) != TS_OK) return NULL;
    return ts_engine_make(cfg, err);
}

ts_rc ts_engine_full_load_sweep_check(const ts_config *cfg, ts_err *err)
{
    ts_engine *e = sweep_engine(cfg, err);
    if (!e) return err ? err->code : TS_ERR_PARAM;
    ts_engine_free(e);
    return TS_OK;
}

ts_rc ts_engine_full_load_sweep(const ts_config *cfg, ts_engine_cycle rows[TS_ENGINE_SWEEP_NPOINT],
                                ts_progress_fn progress, void *ud, ts_err *err)
{
    ts_engine *e = sweep_engine(cfg, err);
    if (!e) return err ? err->code : TS_ERR_PARAM;
    double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x);
    if (!x) {
        ts_engine_free(e);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "engine sweep: out of memory");
    }
    ts_engine_inputs in = {.rack = cfg->control.rack,
                           .fuel_per_cycle = -1,
                           .p_amb = cfg->driveline.ambient_pressure,
                           .T_amb = cfg->driveline.ambient_temperature,
                           .hold_speed = 1};
    ts_engine_init_state(e, TS_ENGINE_SWEEP_RPM_HI * TS_PI / 30, in.p_amb, in.T_amb, x);
    ts_engine_set_turbo_speed(e, x, TS_ENGINE_SEARCH_TURBO);
    ts_rc rc = TS_OK;
    for (int k = TS_ENGINE_SWEEP_NPOINT - 1; k >= 0; k--) {
        double w = (TS_ENGINE_SWEEP_RPM_LO + k * TS_ENGINE_SWEEP_RPM_STEP) * TS_PI / 30;
        rc = ts_engine_steady(e, x, w, &in, TS_ENGINE_STEADY_CYCLES, TS_ENGINE_STEADY_TOL, &rows[k],
                              err);
        if (rc != TS_OK) break;
        int done = TS_ENGINE_SWEEP_NPOINT - k;
        if (progress && progress(ud, done, TS_ENGINE_SWEEP_NPOINT) != 0) {
            rc = ts_err_set(err, TS_ERR_CANCELLED, NULL,
                            "engine sweep: cancelled after %d of %d speeds", done,
                            TS_ENGINE_SWEEP_NPOINT);
            break;
        }
    }
    free(x);
    ts_engine_free(e);
    return rc;
}
