/*
 * cfg_control.c — parameter-table rows of the "control" and "coupling" sections
 * (columns in param.h). Defaults: sim/data/defaults/control.json, coupling.json.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_control_mode_names[] = {"rack", "ivs", NULL};
const char *const ts_coupling_method_names[] = {"monolithic", "leading_following", NULL};

#define F(field) offsetof(ts_config, control.field)
static const ts_param control_rows[] = {
    {"/control/mode", TS_PT_ENUM, F(mode), "", 0, 0, ts_control_mode_names, 0, 0,
     "driver: fixed rack or the IVS speed controller"},
    {"/control/rack", TS_PT_DOUBLE, F(rack), "1", 0, 1, NULL, 0, 0,
     "fixed fuel rack position (driver demand)"},
    {"/control/target_speed", TS_PT_DOUBLE, F(target_speed), "m/s", 0, 40, NULL, 0, 0,
     "IVS set speed"},
};
#undef F

#define F(field) offsetof(ts_config, coupling.field)
static const ts_param coupling_rows[] = {
    {"/coupling/method", TS_PT_ENUM, F(method), "", 0, 0, ts_coupling_method_names, 0, 0,
     "monolithic (one integrator) or leading_following (Section IV.A)"},
    {"/coupling/lead", TS_PT_DOUBLE, F(lead), "s", 1e-5, 0.1, NULL, 0, 0,
     "how far the powertrain may run ahead of the vehicle"},
    {"/coupling/predictor_order", TS_PT_INT, F(predictor_order), "1", 0, 1, NULL, 0, 0,
     "sprocket-speed predictor: 0 hold, 1 linear from (omega, alpha)"},
};
#undef F

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_control = {"control", "driver: fixed rack or IVS controller",
                                             control_rows, N(control_rows)};
const ts_param_section ts_section_coupling = {
    "coupling", "powertrain-vehicle coupling", coupling_rows, N(coupling_rows)};
#undef N
