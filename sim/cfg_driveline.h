/*
 * cfg_driveline.h — the "driveline" section of a run config: torque converter,
 * automatic transmission, final drive (paper Section III.B.2). Extended by the
 * driveline module.
 */
#ifndef TS_CFG_DRIVELINE_H
#define TS_CFG_DRIVELINE_H

#define TS_NGEAR_MAX 8

typedef struct ts_driveline_config {
    int gear_ratio_n;                 /* number of forward gears */
    double gear_ratio[TS_NGEAR_MAX];  /* transmission ratio per gear [1] */
    double final_ratio;               /* overall final-drive ratio [1] */
    double shift_speed;               /* engine speed that triggers an upshift [rad/s] */
    double shift_time;                /* clutch-to-clutch shift interval [s] */
} ts_driveline_config;

#endif
