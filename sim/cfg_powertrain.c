/*
 * cfg_powertrain.c — parameter-table rows of the "engine", "driveline", "control"
 * and "coupling" sections (columns in param.h). Defaults: sim/data/defaults/.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_engine_variant_names[] = {"conventional", "lhr05", "lhr10", NULL};
const char *const ts_engine_fidelity_names[] = {"crank_angle", "mean_value", "map", NULL};
const char *const ts_control_mode_names[] = {"rack", "ivs", NULL};
const char *const ts_coupling_method_names[] = {"monolithic", "leading_following", NULL};

#define F(field) offsetof(ts_config, engine.field)
static const ts_param engine_rows[] = {
    {"/engine/variant", TS_PT_ENUM, F(variant), "", 0, 0, ts_engine_variant_names, 0, 0,
     "combustion chamber: conventional (all metal), lhr05 or lhr10 (zirconia coating)"},
    {"/engine/fidelity", TS_PT_ENUM, F(fidelity), "", 0, 0, ts_engine_fidelity_names, 0, 0,
     "engine model: crank_angle, mean_value or map"},
    {"/engine/dyno_speed", TS_PT_DOUBLE, F(dyno_speed), "rad/s", 20, 300, NULL, 0, 0,
     "speed held by the dynamometer in engine_dyno runs"},
};
#undef F

#define F(field) offsetof(ts_config, driveline.field)
static const ts_param driveline_rows[] = {
    {"/driveline/gear_ratio", TS_PT_DARRAY, F(gear_ratio), "1", 0.3, 10, NULL, TS_NGEAR_MAX,
     F(gear_ratio_n), "transmission ratio of each forward gear"},
    {"/driveline/final_ratio", TS_PT_DOUBLE, F(final_ratio), "1", 0.5, 20, NULL, 0, 0,
     "overall final-drive ratio, transmission output to sprocket"},
    {"/driveline/shift_speed", TS_PT_DOUBLE, F(shift_speed), "rad/s", 50, 300, NULL, 0, 0,
     "engine speed at which the transmission upshifts"},
    {"/driveline/shift_time", TS_PT_DOUBLE, F(shift_time), "s", 0.01, 5, NULL, 0, 0,
     "clutch-to-clutch shift interval"},
};
#undef F

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
const ts_param_section ts_section_engine = {"engine", "virtual V-12 diesel", engine_rows,
                                            N(engine_rows)};
const ts_param_section ts_section_driveline = {
    "driveline", "torque converter, transmission, final drive", driveline_rows,
    N(driveline_rows)};
const ts_param_section ts_section_control = {"control", "driver: fixed rack or IVS controller",
                                             control_rows, N(control_rows)};
const ts_param_section ts_section_coupling = {
    "coupling", "powertrain-vehicle coupling", coupling_rows, N(coupling_rows)};
#undef N
