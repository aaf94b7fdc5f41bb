/*
 * governor.h — the two-speed governor of the fuel actuator (paper Section
 * IV.B.2): "prevents the engine from overspeeding and stalling at low speeds.
 * The amount of fuel is corrected proportionally to the speed difference."
 *
 * Between the low-idle and high-idle speeds the governor passes the driver/IVS
 * rack through unchanged. Below low idle it adds fuel in proportion to the
 * speed deficit, reaching full rack `low_band` below low idle; above high idle
 * it removes fuel in proportion to the excess, reaching zero `high_band` above
 * high idle. Speeds in rad/s; the result is a rack in [0, 1].
 */
#ifndef TS_GOVERNOR_H
#define TS_GOVERNOR_H

#include "cfg_control.h"
#include "errors.h"

typedef struct ts_governor {
    double low_idle;  /* speed below which fuel is added [rad/s] */
    double low_band;  /* speed deficit that calls for full rack [rad/s] */
    double high_idle; /* speed above which fuel is cut [rad/s] */
    double high_band; /* speed excess that cuts fuel to zero [rad/s] */
    int on;           /* 0: the rack passes as demanded (/control/governor off) */
} ts_governor;

/* Governed rack for a demanded rack in [0, 1] at engine speed w [rad/s]
 * (the demand itself when the governor is off). */
double ts_governor_rack(const ts_governor *g, double rack, double w);

/* The governor /control describes (its four speeds into *g), for every run
 * kind that fuels an engine. TS_ERR_PARAM naming /control/governor_high_idle
 * when /control/governor is on and high idle does not exceed low idle. */
TS_MUST_CHECK ts_rc ts_governor_of_config(const ts_control_config *cc, ts_governor *g, ts_err *err);

#endif
