/*
 * engine_map.c — the map fidelity: a full-load torque-speed map with a
 * first-order boost lag (paper Section III; the map fidelity of README's engine fidelities).
 *
 * The tables (/engine/map_*_<variant>) are the crank-angle model's own
 * dynamometer sweep (`tanksim engine-map`, provenance in engine.json).
 * States: crank speed, crank angle, boost-lag state z in [0, 1]:
 *   dz/dt = (rack - z) / tau_boost(speed)   (/engine/spool_lag: the
 *           crank-angle spool-ups' 63 % time at each held speed,
 *           tools/engine_maps.py; linear in speed between them)
 *   boost p = p_amb + z (p_fl - p_amb), ratio r = p / p_fl
 *   available fraction a = pb_torque(speed, r): the crank-angle spool-ups'
 *           indicated torque / full-load indicated torque at that boost ratio
 *           (smoke-limited fuel, part-boost efficiency and the launch's cold
 *           walls; tools/engine_maps.py)
 *   fuel fraction f = min(rack, a) of the full-load fuel at this speed
 *   (or the commanded fuel_per_cycle, also capped by a)
 *   indicated torque = f (T_fl + T_fric), brake = indicated - T_fric (Willans line)
 * The spool-ups are full-rack: at part rack (z settling at the rack) a is
 * about r >= rack, so the cap does not bind in part-load steady states.
 *   J domega/dt = brake - load
 * The default fuel law of Eq. 14 needs the air flow, which a map does not
 * have: with rack input the map scales its full-load fuel (which already
 * follows Eq. 13-14 on the sweep) by the rack. Exhaust temperature and the
 * cylinder channels are not modelled (0).
 */
#include <math.h>

#include "engine_impl.h"

int en_map_rhs(const ts_engine *e, double t, const double *x, const ts_engine_inputs *in,
               double *xdot, ts_engine_outputs *out)
{
    (void)t;
    const ts_engine_config *c = &e->c;
    double w = x[TS_ENGINE_X_SPEED];
    double z = fmin(fmax(x[e->off_lag], 0.0), 1.0);
    double rack = fmin(fmax(in->rack, 0.0), 1.0);
    const ts_engine_map_table *mt = en_map_table(e);
    en_lin at = en_map_at(e, w);
    double tq_fl = en_lin_eval(&at, mt->torque);
    double fuel_fl = en_lin_eval(&at, mt->fuel);
    double boost_fl = en_lin_eval(&at, mt->boost);
    /* en_friction_torque with fmep x (12 V_d): the other association moves the
     * map runs by rounding, which clutch and shift events amplify to 1e-5 */
    double vd_total = e->geom.vd * EN_NCYL;
    double t_fric = en_fmep(c, w) * vd_total / EN_CYCLE * tanh(w / EN_FRICTION_FADE);
    double boost = in->p_amb + z * (boost_fl - in->p_amb);
    double avail = en_pb_interp(e, mt->pb_torque, w, boost / boost_fl);
    double f;
    double cycles_per_s = fmax(w, 0.0) / EN_CYCLE;
    if (in->fuel_per_cycle >= 0) {
        double rate = in->fuel_per_cycle * EN_NCYL * cycles_per_s;
        f = fuel_fl > 0 ? rate / fuel_fl : 0.0;
    } else {
        f = rack;
    }
    double target = fmin(fmax(f, 0.0), 1.0); /* boost follows the demanded fuel */
    if (f > avail) f = avail;
    if (f < 0) f = 0;
    double t_ind = f * (tq_fl + t_fric);
    double t_brake = t_ind - t_fric;
    double lag = en_spool_lag(e, w) * e->turbo_inertia_scale; /* shrunk in ts_engine_steady */
    xdot[TS_ENGINE_X_SPEED] =
        in->hold_speed ? 0.0 : (t_brake - in->load_torque) / (e->mean_inertia + in->load_inertia);
    xdot[TS_ENGINE_X_ANGLE] = w;
    xdot[e->off_lag] = (target - x[e->off_lag]) / lag;
    if (out) {
        double fuel = f * fuel_fl;
        double phi = ts_fuel_phi_target(&e->fuel, w);
        out->speed = w;
        out->brake_torque = t_brake;
        out->indicated_torque = t_ind;
        out->friction_torque = t_fric;
        out->boost = boost;
        /* no manifolds or turbochargers: not modelled (ts_engine_models) */
        out->intake_temp = out->exhaust_temp = out->turbo_speed = NAN;
        out->fuel_flow = fuel;
        out->air_flow = fuel_fl * c->afr_stoich / phi * (out->boost / boost_fl);
        out->fuel_per_cycle = cycles_per_s > 0 ? fuel / (EN_NCYL * cycles_per_s) : 0.0;
        out->phi = out->air_flow > 0 ? fuel * c->afr_stoich / out->air_flow : 0.0;
    }
    return 0;
}

double en_spool_lag(const ts_engine *e, double omega)
{
    en_lin l = en_lin_at(e->c.spool_speed, e->c.spool_speed_n, omega);
    return en_lin_eval(&l, e->c.spool_lag);
}
