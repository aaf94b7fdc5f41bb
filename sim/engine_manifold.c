/*
 * engine_manifold.c — filling-and-emptying control volumes (paper Section
 * III.B.1, Fig. 15): per bank, the compressor outlet + intercooler volume, the
 * intake manifold and the exhaust manifold, each a well-mixed ideal-gas volume
 * with states (m, T, F); and the quasi-steady compressible orifice equation
 * used for every restriction (valves, intercooler outlet).
 *
 * Per bank: ambient -> compressor -> [intercooler volume, heat to its wall]
 * -> orifice -> [intake manifold] -> intake valves -> cylinders -> exhaust
 * valves -> [exhaust manifold, small heat loss] -> turbine (|| wastegate,
 * /engine/wg_area; 0 = none) -> ambient. The wastegate's pneumatic actuator
 * (en_wastegate_open) opens it linearly in boost between /engine/wg_crack
 * and /engine/wg_full (diaphragm force against a preloaded linear spring);
 * the open-loop schedule in engine speed (en_turb_schedule) scales that
 * opening and the nozzle and adds a bypass held open.
 * Leaves out pipe wave dynamics (0-D volumes) and the air filter / exhaust
 * back pressure (turbine exhausts to ambient).
 */
#include <math.h>

#include "engine_impl.h"

/* The orifice equation (psi, en_orifice and their parts) is static inline in
 * engine_impl.h: the crank-angle right-hand side calls it for every open
 * valve. */

void en_orifice_pair(double cda_a, double cda_b, double p1, double T1, double R1, double g1,
                     double p2, double T2, double R2, double g2, double *m_a, double *m_b)
{
    if (p1 < p2 || cda_a <= 0 || cda_b <= 0) { /* reverse or one shut */
        *m_a = en_orifice(cda_a, p1, T1, R1, g1, p2, T2, R2, g2);
        *m_b = en_orifice(cda_b, p1, T1, R1, g1, p2, T2, R2, g2);
        return;
    }
    en_flow_ratio r = en_ratio_of(p1, g1, p2);
    double sRT = sqrt(R1 * T1);
    *m_a = en_flow_area(&r, cda_a, p1, sRT);
    *m_b = en_flow_area(&r, cda_b, p1, sRT);
}

/* Pneumatic actuator: boost on the diaphragm against the spring preload
 * (wg_crack) and rate (full lift at wg_full): lift, and so the poppet's
 * curtain area, LINEAR in boost between the two, with C1 rounding over
 * WG_ROUND of the spring range at each end (the integrators want a continuous
 * slope). Fraction of /engine/wg_area open, in [0, 1]. */
#define WG_ROUND 0.02
double en_wastegate_open(const ts_engine_config *c, double p_boost)
{
    double t = (p_boost - c->wg_crack) / en_atleast(c->wg_full - c->wg_crack, 1.0);
    const double d = WG_ROUND;
    if (t <= -d) return 0.0;
    if (t < d) return (t + d) * (t + d) / (4.0 * d);
    if (t <= 1.0 - d) return t;
    if (t < 1.0 + d) return 1.0 - (1.0 + d - t) * (1.0 + d - t) / (4.0 * d);
    return 1.0;
}

void en_bank_read(const ts_engine *e, const double *xb, en_bank_out *o)
{
    const en_gas *g = &e->gas;
    o->T_ic = xb[BX_ICT];
    o->F_ic = en_atmost(en_atleast(xb[BX_ICF], 0), 1);
    o->p_ic = xb[BX_ICM] * en_gas_r(g, o->F_ic) * o->T_ic / e->c.ic_volume;
    o->T_im = xb[BX_IMT];
    o->F_im = en_atmost(en_atleast(xb[BX_IMF], 0), 1);
    o->p_im = xb[BX_IMM] * en_gas_r(g, o->F_im) * o->T_im / e->c.intake_volume;
    o->T_em = xb[BX_EMT];
    o->F_em = en_atmost(en_atleast(xb[BX_EMF], 0), 1);
    o->p_em = xb[BX_EMM] * en_gas_r(g, o->F_em) * o->T_em / e->c.exhaust_volume;
    o->turbo_speed = xb[BX_TC];
    o->air_flow = 0;
}

void en_bank_outputs(const en_bank_out *bo, ts_engine_outputs *out)
{
    out->boost = 0.5 * (bo[0].p_im + bo[1].p_im);
    out->intake_temp = 0.5 * (bo[0].T_im + bo[1].T_im);
    out->exhaust_temp = 0.5 * (bo[0].T_em + bo[1].T_em);
    out->air_flow = bo[0].air_flow + bo[1].air_flow;
    out->turbo_speed = 0.5 * (bo[0].turbo_speed + bo[1].turbo_speed);
}

/* Outflows of the exhaust manifold: the turbine (nozzle as scheduled), and
 * the bypass around it: the boost-sensing wastegate (its opening x the
 * scheduled authority) + the scheduled open bypass, one orifice (a check
 * valve: no reverse flow). */
void en_exhaust_outflow(const ts_engine *e, double omega, double w_tc, const en_bank_out *o,
                        const en_gas_state *s_em, double p_amb, double T_amb, en_turb_out *to,
                        double *m_wg)
{
    const ts_engine_config *c = &e->c;
    double R_em = s_em->R, cp_em = s_em->cp;
    en_turb_geometry tg = en_turb_schedule(e, omega);
    double area = tg.gate * en_wastegate_open(c, o->p_im) * c->wg_area + tg.bypass;
    double g_em = cp_em / (cp_em - R_em); /* en_turbine's gamma (the same operations) */
    /* turbine nozzle and bypass see the same upstream gas and pressure ratio:
     * one psi for both (the values en_orifice gives each). Below ambient
     * pressure the turbine draws ambient air back into the manifold (the
     * bypass is a check valve: its reverse value is dropped below) */
    double R2 = R_em, g2 = g_em;
    if (o->p_em < p_amb) {
        en_gas_state s_amb;
        en_gas_eval(&e->gas, T_amb, 0, &s_amb);
        R2 = s_amb.R;
        g2 = s_amb.cp / s_amb.cv;
    }
    double m_t, m;
    en_orifice_pair(tg.a_t, area, o->p_em, o->T_em, R_em, g_em, p_amb, T_amb, R2, g2, &m_t, &m);
    en_turbine_flow(&e->turbo, m_t, w_tc, o->p_em, o->T_em, R_em, cp_em, p_amb, to);
    *m_wg = m > 0 ? m : 0;
}

void en_bank_rhs(const ts_engine *e, const double *xb, const en_bank_flows *f, double p_amb,
                 double T_amb, double *xd, en_bank_out *o)
{
    const en_gas *g = &e->gas;
    const ts_engine_config *c = &e->c;
    if (!f->have_gas) en_bank_read(e, xb, o); /* else the caller read o at this state */
    double m_ic = xb[BX_ICM], T_ic = o->T_ic, F_ic = o->F_ic, p_ic = o->p_ic;
    /* compressor: ambient -> intercooler volume */
    en_comp_out co;
    if (f->have_co)
        co = f->co;
    else
        en_compressor(&e->turbo, g, xb[BX_TC], p_amb, T_amb, p_ic, &co);
    en_gas_state s_ic, s_im, s_em;
    en_gas_eval(g, T_ic, F_ic, &s_ic);
    if (f->have_gas) { /* the caller's evaluation at this state (same values) */
        s_im = f->s_im;
        s_em = f->s_em;
    } else {
        en_gas_eval(g, o->T_im, o->F_im, &s_im);
        en_gas_eval(g, o->T_em, o->F_em, &s_em);
    }
    /* intercooler outlet orifice -> intake manifold: each direction carries
     * the upstream volume's gas (h and F), so burned mass the intake manifold
     * pushes back stays in the intercooler volume */
    double g_ic = s_ic.cp / s_ic.cv, g_im = s_im.cp / s_im.cv;
    double m_ici = en_orifice(c->ic_cda, p_ic, T_ic, s_ic.R, g_ic, o->p_im, o->T_im, s_im.R, g_im);
    double h_ici = m_ici >= 0 ? m_ici * s_ic.h : m_ici * s_im.h;
    double F_ici = m_ici >= 0 ? m_ici * F_ic : m_ici * o->F_im;
    /* intercooler volume: fresh air from the compressor (F = 0), heat to the
     * wall from the compressed stream */
    double q_ic = en_intercooler_heat(c->ic_ua, co.mdot, co.cp_out, co.T_out, c->ic_wall_temp);
    double h_c = co.mdot * co.h_out; /* the compressor passes no reverse flow (engine_turbo.c) */
    double dm_ic = co.mdot - m_ici;
    double dF_ic = (-F_ici - F_ic * dm_ic) / m_ic;
    xd[BX_ICM] = dm_ic;
    xd[BX_ICF] = dF_ic;
    xd[BX_ICT] = en_gas_dTdt_s(&s_ic, m_ic, h_c - h_ici - q_ic, dm_ic, dF_ic);
    /* intake manifold */
    double m_im = xb[BX_IMM];
    double dm_im = m_ici - f->m_in;
    double dmF_im = F_ici - f->mf_in;
    double dF_im = (dmF_im - o->F_im * dm_im) / m_im;
    xd[BX_IMM] = dm_im;
    xd[BX_IMF] = dF_im;
    xd[BX_IMT] = en_gas_dTdt_s(&s_im, m_im, h_ici - f->h_in, dm_im, dF_im);
    /* exhaust manifold -> turbine -> ambient */
    en_turb_out to;
    double m_wg;
    en_exhaust_outflow(e, f->omega, xb[BX_TC], o, &s_em, p_amb, T_amb, &to, &m_wg);
    double m_out = to.mdot + m_wg;
    double m_em = xb[BX_EMM];
    double dm_em = f->m_ex - m_out;
    /* outflow leaves with the manifold's gas; a reverse flow brings ambient air */
    double mF_out = m_out >= 0 ? m_out * o->F_em : 0.0;
    double h_t = m_out >= 0 ? m_out * s_em.h : m_out * en_gas_h(g, T_amb, 0);
    double dmF_em = f->mf_ex - mF_out;
    double dF_em = (dmF_em - o->F_em * dm_em) / m_em;
    double q_em = c->exhaust_ua * (o->T_em - T_amb);
    xd[BX_EMM] = dm_em;
    xd[BX_EMF] = dF_em;
    xd[BX_EMT] = en_gas_dTdt_s(&s_em, m_em, f->h_ex - h_t - q_em, dm_em, dF_em);
    /* rotor: J dw/dt = (eta_m P_t - P_c) / w (Section III.B.1) */
    double w = xb[BX_TC];
    double J = e->turbo.inertia * e->turbo_inertia_scale;
    xd[BX_TC] = (e->turbo.mech_eff * to.power - co.power) / (J * en_atleast(w, 200.0));
    if (w <= 0 && xd[BX_TC] < 0) xd[BX_TC] = 0;
    o->air_flow = co.mdot;
}
