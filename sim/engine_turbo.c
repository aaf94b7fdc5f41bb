/*
 * engine_turbo.c — turbocharger of one bank (paper Section III.B.1): compressor
 * and turbine from maps, and the intercooler heat removal.
 *
 * The paper scales DDC Series 60 truck maps to +60 % mass flow; no public DDC
 * map exists, so the reference map is SYNTHESISED from standard
 * non-dimensional shapes (Watson & Janota 1982):
 *
 *  Compressor, tip speed U = w D/2, flow coefficient phi = mdot/(rho01 U D^2),
 *  isentropic head coefficient psi = dh_is / U^2, dh_is = cp T01 (PR^k - 1):
 *     speed lines   psi = psi0 (1 - (phi/phi_choke)^2)
 *     efficiency    eta = eta_max (1 - ((phi - phi_opt)/phi_width)^2)
 *                       x (1 - ((M - M_opt)/M_width)^2) for tip Mach M = U/a01 > M_opt,
 *                   >= eta_min. The tip-Mach factor (losses on the high speed
 *                   lines) bounds the full-load turbo match: with the
 *                   constant-phi fuel law (Eq. 14) exhaust energy grows with
 *                   the air flow, and with a fixed turbine and a map whose
 *                   efficiency depends on phi alone boost ran away (15 bar).
 *                   It also sets how strongly boost follows exhaust energy
 *                   (the LHR engines' gain, Fig. 18b).
 *  Inverted for the flow at given PR and speed:
 *     mdot = rho01 D^2 phi_choke sqrt(U^2 - dh_is/psi0)   (0 past the surge/zero-flow
 *  line); this stays finite as U -> 0 (a stopped wheel passes flow when PR < 1).
 *  Power P_c = mdot dh_is / eta (PR > 1). The map's convention (constant cp
 *  and gamma) defines dh_is and eta; the outlet state takes the shaft's work
 *  as real enthalpy: h(T02) = h(T01) + dh_is/eta with the engine's air
 *  enthalpy (en_gas), so the compressed stream carries exactly the power the
 *  rotor gives up (with T02 = T01 + dh_is/(eta cp), cp = 1005, the
 *  intercooler received 10.7 kW more than the shafts gave at rated, 2.2 %).
 *
 *  Turbine: nozzle equation mdot = A_eff p03 Psi(p4/p03) / sqrt(R T03) and
 *     eta_t = eta_max [2 (bsr/bsr_opt) - (bsr/bsr_opt)^2], bsr = U_t / c_s,
 *     c_s = sqrt(2 dh_is,t);  P_t = mdot eta_t dh_is,t.
 *
 *  Scaling (engine.c): D x sqrt(s), A_eff x s, J x s^2.5 for s = 1.6, so flow
 *  x 1.6 at equal PR and efficiency and speed x 0.79 (paper: "lower shaft
 *  speeds and higher polar moment of inertia").
 *  Geometry scheduled OPEN LOOP in engine speed (en_turb_schedule,
 *  /engine/turb_sched_*; a full-load feed-forward map as on production VGT
 *  and electronic-wastegate diesels): a variable nozzle (area factor, the
 *  efficiency law unchanged), the authority of the boost-sensing wastegate
 *  actuator, and a bypass held open; used in engine_manifold.c.
 * Leaves out: surge dynamics (no Greitzer model), vane-position effects on
 * turbine efficiency, closed-loop vane control. The boost-sensing wastegate
 * is in engine_manifold.c.
 */
#include <math.h>

#include "constants.h"
#include "engine_impl.h"

#define CP_AIR_TURBO TS_CP_AIR_MAP /* map convention, constants.h */
#define GAMMA_AIR TS_GAMMA_AIR_MAP

/* The outlet air of o whose sensible enthalpy is h(T01) + dh: T_out by Newton
 * on the cp polynomial from the inlet-cp guess (a guess within ~2 K over a
 * 200-K rise, cp changing < 3 %: two steps reach rounding); h_out is the
 * target itself, cp_out cp(T_out). */
static void outlet_air(const en_gas *g, double T01, double h01, double cp01, double dh,
                       en_comp_out *o)
{
    double target = h01 + dh, T = T01 + dh / cp01, h, cp;
    for (int i = 0; i < 2; i++) {
        en_air_eval(g, T, &h, &cp);
        T -= (h - target) / cp;
    }
    en_air_eval(g, T, &h, &cp);
    o->T_out = T;
    o->h_out = target;
    o->cp_out = cp;
}

void en_compressor(const en_turbo *t, const en_gas *g, double w, double p01, double T01, double p02,
                   en_comp_out *o)
{
    double k = (GAMMA_AIR - 1.0) / GAMMA_AIR;
    double pr = p02 / p01;
    double dh = CP_AIR_TURBO * T01 * (pow(pr, k) - 1.0);
    double U = en_atleast(w, 0.0) * t->d_c / 2.0;
    double rho = p01 / (t->r_air * T01);
    double arg = U * U - dh / t->psi0;
    double mdot = arg > 0 ? rho * t->d_c * t->d_c * t->phi_ch * sqrt(arg) : 0.0;
    double phi = U > 1.0 ? mdot / (rho * U * t->d_c * t->d_c) : t->phi_opt;
    double x = (phi - t->phi_opt) / t->phi_w;
    double eta = t->eta_max * (1.0 - x * x);
    /* high tip speed: efficiency falls with the tip Mach number U/a01 above
     * mach_opt (shock and tip-clearance losses on the high speed lines) */
    double mach = U / sqrt(GAMMA_AIR * t->r_air * T01);
    if (mach > t->mach_opt) {
        double y = (mach - t->mach_opt) / t->mach_w;
        eta *= 1.0 - y * y;
    }
    if (eta < t->eta_min) eta = t->eta_min;
    o->mdot = mdot;
    o->eta = eta;
    double h01, cp01;
    en_air_eval(g, T01, &h01, &cp01);
    if (dh > 0) {
        outlet_air(g, T01, h01, cp01, dh / eta, o);
        o->power = mdot * dh / eta;
    } else { /* throttling through the wheel: no work, isenthalpic */
        o->T_out = T01;
        o->h_out = h01;
        o->cp_out = cp01;
        o->power = 0.0;
    }
}

void en_turbine(const en_turbo *t, double a_t, double w, double p03, double T03, double R,
                double cp, double p4, en_turb_out *o)
{
    double g = cp / (cp - R);
    en_turbine_flow(t, en_orifice(a_t, p03, T03, R, g, p4, T03, R, g), w, p03, T03, R, cp, p4, o);
}

void en_turbine_flow(const en_turbo *t, double mdot, double w, double p03, double T03, double R,
                     double cp, double p4, en_turb_out *o)
{
    double g = cp / (cp - R);
    double pr = p4 / p03; /* <= 1 for forward flow */
    o->mdot = mdot;
    if (pr >= 1.0 || o->mdot <= 0) {
        o->power = 0.0;
        o->eta = 0.0;
        return;
    }
    double dh = cp * T03 * (1.0 - pow(pr, (g - 1.0) / g));
    double cs = sqrt(2.0 * dh);
    double bsr = en_atleast(w, 0.0) * t->d_t / 2.0 / en_atleast(cs, 1e-6) / t->bsr_opt;
    double eta = t->eta_t * (2.0 * bsr - bsr * bsr);
    if (eta < 0) eta = 0;
    o->eta = eta;
    o->power = o->mdot * eta * dh;
}

en_turb_geometry en_turb_schedule(const ts_engine *e, double omega)
{
    const ts_engine_config *c = &e->c;
    if (c->turb_sched_speed_n < 2) return (en_turb_geometry){e->turbo.a_t, 1.0, 0.0};
    en_lin l = en_lin_at(c->turb_sched_speed, c->turb_sched_speed_n, omega);
    return (en_turb_geometry){e->turbo.a_t * en_lin_eval(&l, c->turb_sched_nozzle),
                              en_lin_eval(&l, c->turb_sched_gate),
                              en_lin_eval(&l, c->turb_sched_bypass)};
}

double en_intercooler_heat(double ua, double mdot, double cp, double T_in, double T_wall)
{
    if (mdot <= 1e-9) return 0.0;
    double eps = 1.0 - exp(-ua / (mdot * cp));
    return eps * mdot * cp * (T_in - T_wall);
}
