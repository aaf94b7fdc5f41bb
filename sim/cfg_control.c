/*
 * cfg_control.c — parameter-table rows of the "control" and "coupling" sections
 * (columns in param.h). Defaults: sim/data/defaults/control.json, coupling.json.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_control_mode_names[] = {"rack", "ivs", NULL};
const char *const ts_schedule_var_names[] = {"mass", "grade", NULL};
const char *const ts_coupling_method_names[] = {"monolithic", "leading_following", NULL};

#define F(field) offsetof(ts_config, control.field)
static const ts_param control_rows[] = {
    {"/control/mode", TS_PT_ENUM, F(mode), "", 0, 0, ts_control_mode_names, 0, 0,
     "driver: fixed rack or the IVS speed controller"},
    {"/control/rack", TS_PT_DOUBLE, F(rack), "1", 0, 1, NULL, 0, 0,
     "fixed fuel rack position (driver demand)"},
    {"/control/target_speed", TS_PT_DOUBLE, F(target_speed), "m/s", 0, 40, NULL, 0, 0,
     "IVS set speed"},
    {"/control/kp", TS_PT_DOUBLE, F(kp), "1/(m/s)", 1e-6, 1e3, NULL, 0, 0,
     "IVS proportional gain K_p (Eq. 10), rack per m/s of speed error"},
    {"/control/ti", TS_PT_DOUBLE, F(ti), "s", 1e-3, 1e4, NULL, 0, 0,
     "IVS integral time T_I (Eq. 10)"},
    {"/control/anti_windup", TS_PT_BOOL, F(anti_windup), "", 0, 1, NULL, 0, 0,
     "back-calculation anti-windup of the IVS integral while the rack saturates"},
    {"/control/schedule_var", TS_PT_ENUM, F(schedule_var), "", 0, 0, ts_schedule_var_names, 0, 0,
     "gain-schedule variable (Fig. 27): vehicle mass or road grade"},
    {"/control/schedule_x", TS_PT_DARRAY, F(schedule_x), "kg or rad", -1e6, 1e6, NULL,
     TS_CONTROL_SCHEDULE_MAX, F(schedule_n),
     "gain-schedule rows: vehicle mass [kg] or grade [rad], increasing (empty: fixed kp, ti)"},
    {"/control/schedule_kp", TS_PT_DARRAY, F(schedule_kp), "1/(m/s)", 1e-6, 1e3, NULL,
     TS_CONTROL_SCHEDULE_MAX, F(schedule_kp_n), "K_p per gain-schedule row"},
    {"/control/schedule_ti", TS_PT_DARRAY, F(schedule_ti), "s", 1e-3, 1e4, NULL,
     TS_CONTROL_SCHEDULE_MAX, F(schedule_ti_n), "T_I per gain-schedule row"},
    {"/control/governor", TS_PT_BOOL, F(governor), "", 0, 1, NULL, 0, 0,
     "two-speed governor of the fuel actuator on/off"},
    {"/control/governor_low_idle", TS_PT_DOUBLE, F(governor_low_idle), "rad/s", 0, 500, NULL, 0, 0,
     "governor: engine speed below which fuel is added"},
    {"/control/governor_low_band", TS_PT_DOUBLE, F(governor_low_band), "rad/s", 1e-3, 500, NULL, 0,
     0, "governor: speed deficit below low idle that calls for full rack"},
    {"/control/governor_high_idle", TS_PT_DOUBLE, F(governor_high_idle), "rad/s", 0, 1000, NULL, 0,
     0, "governor: engine speed above which fuel is cut"},
    {"/control/governor_high_band", TS_PT_DOUBLE, F(governor_high_band), "rad/s", 1e-3, 500, NULL,
     0, 0, "governor: speed excess above high idle that cuts fuel to zero"},
    {"/control/tune_rack_low", TS_PT_DOUBLE, F(tune_rack_low), "1", 0, 1, NULL, 0, 0,
     "tune: rack of the steady state before the step to full rack (Eq. 11 R_0)"},
    {"/control/tune_settle", TS_PT_DOUBLE, F(tune_settle), "s", 0, 1e4, NULL, 0, 0,
     "tune: simulated time to settle at the low rack before the step"},
    {"/control/tune_duration", TS_PT_DOUBLE, F(tune_duration), "s", 1, 1e4, NULL, 0, 0,
     "tune: simulated time after the step (to the full-rack steady state)"},
    {"/control/kp_factor", TS_PT_DOUBLE, F(kp_factor), "1", 0.01, 100, NULL, 0, 0,
     "tune: K_p = kp_factor / |Y| in normalised units (Eq. 12a: 0.9)"},
    {"/control/ti_factor", TS_PT_DOUBLE, F(ti_factor), "1", 0.1, 100, NULL, 0, 0,
     "tune: T_I = ti_factor |X| (Eq. 12b; paper prints 3, classical rule 3.33)"},
    {"/control/tune_window", TS_PT_INT, F(tune_window), "1", 3, 1001, NULL, 0, 0,
     "tune: samples in the least-squares slope fit of the reaction curve (odd)"},
};
#undef F

#define F(field) offsetof(ts_config, coupling.field)
static const ts_param coupling_rows[] = {
    {"/coupling/method", TS_PT_ENUM, F(method), "", 0, 0, ts_coupling_method_names, 0, 0,
     "monolithic (one integrator) or leading_following (Section IV.A)"},
    {"/coupling/lead", TS_PT_DOUBLE, F(lead), "s", 1e-5, 0.1, NULL, 0, 0,
     "how far the powertrain may run ahead of the vehicle; at least leader_step and "
     "follower_step"},
    {"/coupling/predictor_order", TS_PT_INT, F(predictor_order), "1", 0, 1, NULL, 0, 0,
     "sprocket-speed predictor: 0 hold, 1 linear from (omega, alpha)"},
    {"/coupling/leader_step", TS_PT_DOUBLE, F(leader_step), "s", 1e-6, 0.1, NULL, 0, 0,
     "powertrain (leader) macro step: one published torque sample per step"},
    {"/coupling/follower_step", TS_PT_DOUBLE, F(follower_step), "s", 1e-6, 0.1, NULL, 0, 0,
     "vehicle (follower) macro step: one (omega, alpha) report per step"},
    {"/coupling/interface_inertia", TS_PT_DOUBLE, F(interface_inertia), "1", 0, 10, NULL, 0, 0,
     "leading_following: factor on the turbine inertia reflected through the applied range "
     "clutch that moves from the published torque (+ J_a alpha_k) onto the vehicle's sprocket; "
     "0 = plain torque exchange (unstable: explicit added mass)"},
};
#undef F

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_control = {"control", "driver: fixed rack or IVS controller",
                                             control_rows, N(control_rows)};
const ts_param_section ts_section_coupling = {"coupling", "powertrain-vehicle coupling",
                                              coupling_rows, N(coupling_rows)};
#undef N
