/*
 * torque_converter.h — three-element hydrodynamic torque converter from
 * look-up tables (paper Section III.B.2, Fig. 17): "using the pump to turbine
 * speed ratio, the pump's K factor is determined from a look-up table. Then,
 * the pump torque is calculated based on the instantaneous engine speed and the
 * K factor. Subsequently, the turbine torque is determined from a look-up
 * table, using the pump torque value and the pump to turbine speed ratio."
 *
 * Quasi-steady (no fluid inertia); no lock-up clutch (the paper mentions none).
 * Units: speeds rad/s, torques N*m, K in rad/s/sqrt(N*m).
 */
#ifndef TS_TORQUE_CONVERTER_H
#define TS_TORQUE_CONVERTER_H

#include "config.h"
#include "errors.h"

typedef struct ts_torque_converter {
    int n;                                /* table rows */
    double speed_ratio[TS_TC_TABLE_MAX];  /* SR, from 0, increasing, < 1 */
    double torque_ratio[TS_TC_TABLE_MAX]; /* TR at each SR */
    double capacity[TS_TC_TABLE_MAX];     /* 1 / K^2 [N*m/(rad/s)^2] at each SR */
} ts_torque_converter;

/* Operating point. Sign convention: pump_torque is the torque the converter
 * takes from the crankshaft (positive loads the engine); turbine_torque is the
 * torque it gives the transmission input (positive drives forward). */
typedef struct ts_tc_point {
    double pump_torque;    /* [N*m] */
    double turbine_torque; /* [N*m] */
    double speed_ratio;    /* turbine / pump speed (0 when the pump is stopped) [1] */
    double torque_ratio;   /* turbine / pump torque [1] */
    double k_factor;       /* pump (or, over-running, turbine) speed / sqrt(|torque|) [rad/s/sqrt(N*m)]; inf at SR 1 */
    double efficiency;     /* turbine power / pump power = TR * SR when power flows forward [1] */
} ts_tc_point;

/* Build from the driveline config: checks table lengths, SR starts at 0 and
 * increases below 1, TR >= 1 at the last row. TS_ERR_PARAM naming the field. */
TS_MUST_CHECK ts_rc ts_torque_converter_init(ts_torque_converter *tc, const ts_driveline_config *c,
                                             ts_err *err);

/* Torques at pump speed w_pump and turbine speed w_turbine [rad/s].
 *  - forward flow (0 <= w_turbine < w_pump): T_p = (w_p / K(SR))^2, T_t = TR(SR) T_p;
 *    beyond the table's last SR the capacity 1/K^2 falls linearly to 0 at SR 1;
 *  - turbine turning backwards (w_turbine < 0 < w_pump): treated as stall (SR 0);
 *  - over-running (w_turbine > w_pump, engine braking): the turbine drives the
 *    pump as a fluid coupling with the stator freewheeling: TR = 1 and
 *    T_p = T_t = -(w_t / K(w_p / w_t))^2 (the forward capacity curve with the
 *    roles exchanged — an estimate; no reverse-flow data are published);
 *  - both stopped: no torque. */
void ts_torque_converter_eval(const ts_torque_converter *tc, double w_pump, double w_turbine,
                              ts_tc_point *out);

#endif
