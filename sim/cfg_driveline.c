/*
 * cfg_driveline.c — parameter-table rows of the "driveline" section (columns in
 * param.h). Defaults and sources: sim/data/defaults/driveline.json.
 */
#include <stddef.h>

#include "config.h"

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

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_driveline = {
    "driveline", "torque converter, transmission, final drive", driveline_rows,
    N(driveline_rows)};
#undef N
