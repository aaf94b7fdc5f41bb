/*
 * governor.c — two-speed governor (governor.h, paper §IV.B.2).
 */
#include "governor.h"

static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

double ts_governor_rack(const ts_governor *g, double rack, double w)
{
    if (!g->on) return rack;
    rack = clamp01(rack);
    if (w < g->low_idle) { /* stall protection: add fuel in proportion to the deficit */
        double add = (g->low_idle - w) / g->low_band;
        return clamp01(rack + (1.0 - rack) * clamp01(add));
    }
    if (w > g->high_idle) { /* overspeed protection: cut fuel in proportion to the excess */
        double cut = (w - g->high_idle) / g->high_band;
        return clamp01(rack * (1.0 - clamp01(cut)));
    }
    return rack;
}

ts_rc ts_governor_of_config(const ts_control_config *cc, ts_governor *g, ts_err *err)
{
    *g = (ts_governor){cc->governor_low_idle, cc->governor_low_band, cc->governor_high_idle,
                       cc->governor_high_band, cc->governor};
    if (cc->governor && !(cc->governor_high_idle > cc->governor_low_idle))
        return ts_err_set(err, TS_ERR_PARAM, "/control/governor_high_idle",
                          "/control/governor_high_idle: must exceed governor_low_idle");
    return TS_OK;
}
