/*
 * engine_mean.c — the mean-value fidelity (cycle-averaged cylinder, manifolds and turbos kept):
 * cycle-averaged cylinders between the SAME intercoolers, manifolds and
 * turbochargers as the crank-angle model (engine_manifold.c, engine_turbo.c).
 *
 * Per bank, from the crank-angle model's own full-load sweep (tables
 * /engine/map_eta_v, map_eta_i, map_q_wall of the variant, vs speed):
 *   air into the cylinders   mdot = eta_v rho_im V_d,bank w / (4 pi)
 *   fuel                      Eq. 14 on the compressor air flow (or commanded)
 *   indicated torque          eta_i mdot_f LHV / w
 *   exhaust enthalpy          mdot h_im + mdot_f LHV (1 - eta_i - q_wall)
 * exhaust temperature from that enthalpy at the products' composition. At
 * part boost eta_v, eta_i and q_wall are the full-load values times the
 * factors /engine/pb_* at (speed, p_im / map_boost): the crank-angle model's
 * own launch spool-ups (`tanksim engine-map --spool`, tools/engine_maps.py),
 * which start from the idle walls, so the factors carry both the part-boost
 * state and the cold-wall heat loss of a launch (walls warm for minutes, the
 * spool-ups cover 6 s: at full boost the factors keep the 2-6-s walls, which
 * is what a 20-s launch sees, not a long run's). Not represented: the walls'
 * own warm-up beyond that (no wall state), the spool-up's dependence on the
 * speed history. No crank-angle variation: crank speed follows
 * J dw/dt = T_brake - T_load with the mean inertia.
 */
#include <math.h>

#include "engine_impl.h"

int en_mean_rhs(const ts_engine *e, double t, const double *x, const ts_engine_inputs *in,
                double *xdot, ts_engine_outputs *out)
{
    (void)t;
    const ts_engine_config *c = &e->c;
    const en_gas *g = &e->gas;
    double w = x[TS_ENGINE_X_SPEED];
    double wp = fmax(w, 0.0);
    en_bank_out bo[EN_NBANK];
    en_comp_out co[EN_NBANK];
    double air = 0;
    for (int b = 0; b < EN_NBANK; b++) {
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        /* compressor flow is needed for Eq. 14 before the bank derivatives
         * (and handed on to en_bank_rhs) */
        en_bank_read(e, xb, &bo[b]);
        en_compressor(&e->turbo, g, xb[BX_TC], in->p_amb, in->T_amb, bo[b].p_ic, &co[b]);
        air += co[b].mdot;
    }
    double mf_cyc = en_fuel_command(e, in, air, wp);
    const ts_engine_map_table *mt = en_map_table(e);
    en_lin at = en_map_at(e, wp);
    double eta_v_fl = en_lin_eval(&at, mt->eta_v);
    double eta_i_fl = en_lin_eval(&at, mt->eta_i);
    double q_w_fl = en_lin_eval(&at, mt->q_wall);
    double p_fl = en_lin_eval(&at, mt->boost);
    double t_ind = 0, fuel_rate = 0, wall = 0, hin = 0, hout = 0, min = 0, mout = 0;
    double *xl = xdot + e->off_ledger;
    for (int b = 0; b < EN_NBANK; b++) {
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        en_bank_out *o = &bo[b];
        double rho = o->p_im / (en_gas_r(g, o->F_im) * o->T_im);
        /* part boost: the crank-angle spool-ups' factors at this bank's
         * intake manifold pressure / full-load boost (see the header) */
        double ratio = o->p_im / p_fl;
        en_bilin pb = en_pb_at(e, wp, ratio);
        double eta_v = eta_v_fl * en_bilin_eval(&pb, mt->pb_eta_v);
        double eta_i = eta_i_fl * en_bilin_eval(&pb, mt->pb_eta_i);
        double q_wb = q_w_fl * en_bilin_eval(&pb, mt->pb_q_wall);
        double m_cyl = eta_v * rho * e->geom.vd * (EN_NCYL / EN_NBANK) * wp / EN_CYCLE;
        double m_f = mf_cyc * (EN_NCYL / EN_NBANK) * wp / EN_CYCLE;
        double q_fuel = m_f * c->lhv;
        double h_in = m_cyl * en_gas_h(g, o->T_im, o->F_im);
        double h_out = h_in + q_fuel * (1.0 - eta_i - q_wb);
        double m_out = m_cyl + m_f;
        double F_out = m_out > 0 ? fmin((m_cyl * o->F_im + m_f * (1 + c->afr_stoich)) / m_out, 1.0) : o->F_em;
        en_bank_flows f = {.m_in = m_cyl, .h_in = h_in, .mf_in = m_cyl * o->F_im,
                           .m_ex = m_out, .h_ex = h_out, .mf_ex = m_out * F_out,
                           .omega = wp, .have_co = 1, .co = co[b]};
        en_bank_rhs(e, xb, &f, in->p_amb, in->T_amb, xdot + e->off_bank + b * EN_BANK_NX, o);
        t_ind += wp > 1 ? eta_i * q_fuel / wp : 0.0;
        fuel_rate += m_f;
        wall += q_fuel * q_wb;
        hin += h_in;
        hout += h_out;
        min += m_cyl;
        mout += m_out;
    }
    double t_fric = en_friction_torque(e, w);
    double t_brake = t_ind - t_fric;
    xdot[TS_ENGINE_X_SPEED] =
        in->hold_speed ? 0.0 : (t_brake - in->load_torque) / (e->mean_inertia + in->load_inertia);
    xdot[TS_ENGINE_X_ANGLE] = w;
    xl[LX_FUEL_E] = fuel_rate * c->lhv;
    xl[LX_WORK] = t_ind * wp;
    xl[LX_WALL] = wall;
    xl[LX_HIN] = hin;
    xl[LX_HOUT] = hout;
    xl[LX_MIN] = min;
    xl[LX_MOUT] = mout;
    xl[LX_MFUEL] = fuel_rate;
    if (out) {
        out->speed = w;
        out->brake_torque = t_brake;
        out->indicated_torque = t_ind;
        out->friction_torque = t_fric;
        en_bank_outputs(bo, out);
        out->fuel_flow = fuel_rate;
        out->fuel_per_cycle = mf_cyc;
        out->phi = min > 0 ? fuel_rate * c->afr_stoich / min : 0.0;
    }
    return 0;
}

en_bilin en_pb_at(const ts_engine *e, double omega, double ratio)
{
    const ts_engine_config *c = &e->c;
    int ns = c->spool_speed_n, nr = c->spool_ratio_n;
    const double *ws = c->spool_speed, *rs = c->spool_ratio;
    int i = 0, j = 0;
    double fw = 0, fr = 0;
    if (ns > 1) {
        i = en_bracket(ws, ns, omega);
        fw = fmin(fmax((omega - ws[i]) / (ws[i + 1] - ws[i]), 0.0), 1.0);
    }
    j = en_bracket(rs, nr, ratio);
    fr = fmin(fmax((ratio - rs[j]) / (rs[j + 1] - rs[j]), 0.0), 1.0);
    return (en_bilin){i * nr, ns > 1 ? (i + 1) * nr : i * nr, j, fw, fr};
}

double en_pb_interp(const ts_engine *e, const double *y, double omega, double ratio)
{
    en_bilin w = en_pb_at(e, omega, ratio);
    return en_bilin_eval(&w, y);
}
