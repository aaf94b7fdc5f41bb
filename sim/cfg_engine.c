/*
 * cfg_engine.c — parameter-table rows of the "engine" section (columns in
 * param.h). Defaults and sources: sim/data/defaults/engine.json.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_engine_variant_names[] = {"conventional", "lhr05", "lhr10", NULL};
const char *const ts_engine_fidelity_names[] = {"crank_angle", "mean_value", "map", NULL};

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

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_engine = {"engine", "virtual V-12 diesel", engine_rows,
                                            N(engine_rows)};
#undef N
