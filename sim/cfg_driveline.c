/*
 * cfg_driveline.c — parameter-table rows of the "driveline" section (columns in
 * param.h). Defaults and sources: sim/data/defaults/driveline.json.
 */
#include <stddef.h>

#include "config.h"

#define F(field) offsetof(ts_config, driveline.field)
static const ts_param driveline_rows[] = {
    {"/driveline/tc_speed_ratio", TS_PT_DARRAY, F(tc_speed_ratio), "1", 0, 0.999, NULL,
     TS_TC_TABLE_MAX, F(tc_speed_ratio_n),
     "torque-converter table abscissa: turbine/pump speed ratio, increasing from 0"},
    {"/driveline/tc_torque_ratio", TS_PT_DARRAY, F(tc_torque_ratio), "1", 0.5, 10, NULL,
     TS_TC_TABLE_MAX, F(tc_torque_ratio_n),
     "torque-converter turbine/pump torque ratio at each table speed ratio"},
    {"/driveline/tc_k_factor", TS_PT_DARRAY, F(tc_k_factor), "rad/s/(N*m)^0.5", 0.1, 100, NULL,
     TS_TC_TABLE_MAX, F(tc_k_factor_n),
     "torque-converter capacity (K) factor, pump speed / sqrt(pump torque), at each speed ratio"},
    {"/driveline/pump_inertia", TS_PT_DOUBLE, F(pump_inertia), "kg*m^2", 0, 100, NULL, 0, 0,
     "converter pump inertia, turning with the crankshaft"},
    {"/driveline/turbine_inertia", TS_PT_DOUBLE, F(turbine_inertia), "kg*m^2", 0.01, 100, NULL, 0,
     0, "converter turbine plus transmission input inertia"},
    {"/driveline/gear_ratio", TS_PT_DARRAY, F(gear_ratio), "1", 0.3, 10, NULL, TS_NGEAR_MAX,
     F(gear_ratio_n), "transmission ratio of each forward gear"},
    {"/driveline/gear_efficiency", TS_PT_DARRAY, F(gear_efficiency), "1", 0.5, 1, NULL,
     TS_NGEAR_MAX, F(gear_efficiency_n), "transmission mechanical efficiency of each gear"},
    {"/driveline/shift_speed", TS_PT_DOUBLE, F(shift_speed), "rad/s", 50, 300, NULL, 0, 0,
     "engine speed at which the transmission upshifts"},
    {"/driveline/downshift_speed", TS_PT_DOUBLE, F(downshift_speed), "rad/s", 0, 250, NULL, 0, 0,
     "engine speed below which the transmission downshifts, when the lower gear's input "
     "would also turn below it (0: never)"},
    {"/driveline/shift_time", TS_PT_DOUBLE, F(shift_time), "s", 0.01, 5, NULL, 0, 0,
     "clutch-to-clutch shift interval"},
    {"/driveline/shift_dwell", TS_PT_DOUBLE, F(shift_dwell), "s", 0, 60, NULL, 0, 0,
     "after a shift, the next upshift is re-armed at the latest after this time in gear"},
    {"/driveline/shift_hysteresis", TS_PT_DOUBLE, F(shift_hysteresis), "rad/s", 0, 100, NULL, 0, 0,
     "after a shift, the next upshift is re-armed when the engine falls this far below "
     "shift_speed"},
    {"/driveline/clutch_capacity", TS_PT_DOUBLE, F(clutch_capacity), "N*m", 100, 1e6, NULL, 0, 0,
     "torque capacity of an applied range clutch, referred to the transmission input"},
    {"/driveline/shift_capacity_factor", TS_PT_DOUBLE, F(shift_capacity_factor), "1", 1.0, 5, NULL,
     0, 0,
     "peak shift-clutch capacity as a multiple of the input torque at the start of the shift"},
    {"/driveline/shift_capacity_floor", TS_PT_DOUBLE, F(shift_capacity_floor), "1", 0, 1, NULL, 0,
     0, "least peak shift-clutch capacity, as a fraction of clutch_capacity"},
    {"/driveline/clutch_slip_speed", TS_PT_DOUBLE, F(clutch_slip_speed), "rad/s", 1e-3, 10, NULL, 0,
     0, "slip speed of the regularised (tanh) clutch friction law; numerical"},
    {"/driveline/final_ratio", TS_PT_DOUBLE, F(final_ratio), "1", 0.5, 20, NULL, 0, 0,
     "overall final-drive ratio, transmission output to sprocket"},
    {"/driveline/final_efficiency", TS_PT_DOUBLE, F(final_efficiency), "1", 0.5, 1, NULL, 0, 0,
     "efficiency of propshaft, differential and final drive together"},
    {"/driveline/output_inertia", TS_PT_DOUBLE, F(output_inertia), "kg*m^2", 0, 1e4, NULL, 0, 0,
     "transmission output, propshaft, final drives and both sprockets, referred to the sprocket"},
    {"/driveline/launch_engine_speed", TS_PT_DOUBLE, F(launch_engine_speed), "rad/s", 10, 300, NULL,
     0, 0, "engine speed at the start of a powertrain run (vehicle at rest, 1st gear)"},
    {"/driveline/ambient_pressure", TS_PT_DOUBLE, F(ambient_pressure), "Pa", 5e4, 1.1e5, NULL, 0, 0,
     "ambient pressure at the engine's air intake and exhaust"},
    {"/driveline/ambient_temperature", TS_PT_DOUBLE, F(ambient_temperature), "K", 240, 330, NULL, 0,
     0,
     "ambient air temperature at the engine's air intake; from 240 K: the gas properties are "
     "fitted to 300-2500 K (engine_gas.c) and extrapolated below, and at 222 K the crank-angle "
     "engine's launch left its domain"},
    {"/driveline/engine_macro_step", TS_PT_DOUBLE_OFF, F(engine_macro_step), "s", 1e-5, 0.01, NULL,
     0, 0,
     "crank-angle engine: macro step of its co-simulation with the driveline "
     "(ts_engine_advance_load); 0 integrates its states in the driveline's RK4; a macro step is "
     "at least 1e-5 s (a fraction of one crank-angle step, ~4e-5 s at 2100 rpm: below it the "
     "exchanges only multiply, and near 1e-16 s they no longer advance the time)"},
};
#undef F

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_driveline = {
    "driveline", "torque converter, transmission, final drive", driveline_rows,
    N(driveline_rows)};
#undef N
