/*
 * cfg_run.c — parameter-table rows of the "run" section (see param.h for the columns).
 */
#include <stddef.h>

#include "config.h"

const char *const ts_run_kind_names[] = {"pointmass", "vehicle", "engine_dyno", "coupled", NULL};

#define F(field) offsetof(ts_config, run.field)
static const ts_param rows[] = {
    {"/run/kind", TS_PT_ENUM, F(kind), "", 0, 0, ts_run_kind_names, 0, 0,
     "scenario: pointmass, vehicle, engine_dyno or coupled"},
    {"/run/duration", TS_PT_DOUBLE, F(duration), "s", 1e-3, 3600, NULL, 0, 0,
     "simulated time of a full run"},
    {"/run/sample_rate", TS_PT_DOUBLE, F(sample_rate), "Hz", 1, 20000, NULL, 0, 0,
     "output samples per simulated second"},
    {"/run/rtol", TS_PT_DOUBLE, F(rtol), "1", 1e-10, 1e-2, NULL, 0, 0,
     "integrator relative tolerance"},
    {"/run/atol", TS_PT_DOUBLE, F(atol), "1", 1e-14, 1e-2, NULL, 0, 0,
     "integrator absolute tolerance (states are scaled to order one)"},
    {"/run/max_step", TS_PT_DOUBLE_OFF, F(max_step), "s", 1e-6, 1, NULL, 0, 0,
     "largest integrator step; 0 lets the integrator choose; a cap is at least 1e-6 s (the "
     "models' fastest dynamics, crank-angle steps of ~4e-5 s at 2100 rpm and kHz track modes, "
     "are resolved 40x over at 1 us; below it a cap only multiplies the steps, and near 1e-300 "
     "CVODE fails at t = 0)"},
};
#undef F

const ts_param_section ts_section_run = {"run", "scenario kind, duration, sampling, tolerances",
                                         rows, (int)(sizeof rows / sizeof rows[0])};
