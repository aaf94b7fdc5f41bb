/*
 * engine_crank.c — the crank-angle fidelity's right-hand side (paper Section
 * III.B.1, Fig. 15): twelve 0-D single-zone cylinders on an even 60-degree
 * V-12 firing order, two banks, each bank with its turbocharger, intercooler,
 * intake and exhaust manifolds (engine_manifold.c); crankshaft dynamics with
 * the load torque and the crank-angle-varying inertia.
 *
 * Cylinder states (EN_CYL_NX): mass m, temperature T, burned-gas mass m_b,
 * Livengood-Wu ignition integral I, burn clock s (crank angle since ignition),
 * mean and turbulent kinetic energies K, k. Energy (first law, open system):
 *   d(m u)/dt = mdot_b LHV - Q_w - p dV/dt + sum mdot_v h_v
 * with fuel added to the charge as it burns (mdot_b from Watson, Eq. in
 * engine_combustion.c) and converted with (A/F)_s of air into burned gas.
 * Injection starts at /engine/soi before firing TDC with the fuel per cycle of
 * the fuel law (Eq. 14 on the compressor air flow, or commanded); I grows by
 * dt / tau_id(p, T) until 1 (ignition); s then grows with the crank; beta of
 * Watson uses the delay in ms = (angle from SOI to ignition) / w. In the intake
 * stroke (local 400-460 deg) I and s relax to 0 (e-folding over 4 deg), which
 * re-arms the cylinder without discrete resets, so the whole model is an ODE a
 * caller can integrate.
 * Heat transfer: energy cascade + Nusselt (engine_heat.c) on piston, head and
 * the exposed liner, each with its layered wall (engine_wall.c); radiation
 * eps sigma (T^4 - T_w^4) while fuel burns. Coolant and oil temperatures are
 * lumped thermostat-controlled capacities receiving the walls' back-side heat.
 * Crankshaft: d/dt(J(th) w^2 / 2) = (T_ind - T_f - T_load) w, so
 *   J dw/dt = T_ind - T_f - T_load - 1/2 dJ/dth w^2,
 *   J(th) = J_0 + sum m_rec (dx_p/dth)^2; friction from Millington-Hartles at
 *   the instantaneous speed (engine_friction.c).
 * Leaves out: spray/evaporation (fuel is accounted as it burns), blow-by,
 * crevices, multi-zone NOx/soot, valve dynamics.
 */
#include <math.h>
#include <string.h>

#include "engine_impl.h"

#define DEG (EN_PI / 180.0)
#define RESET_START (400.0 * DEG) /* re-arm window (intake stroke) [rad local] */
#define RESET_END (460.0 * DEG)
#define RESET_RATE (1.0 / (4.0 * DEG)) /* e-folding per 4 deg CA [1/rad] */
#define LW_WINDOW (180.0 * DEG)        /* ignition must occur within this after SOI */
#define K_FLOOR 1e-6                   /* turbulence floor [J] */

static double wrap(double a)
{
    a = fmod(a, EN_CYCLE);
    return a < 0 ? a + EN_CYCLE : a;
}

static double gamma_of(const en_gas *g, double T, double F)
{
    double cp = en_gas_cp(g, T, F);
    return cp / (cp - en_gas_r(g, F));
}

void en_crank_init(const ts_engine *e, double omega, double p, double T, double *x)
{
    (void)omega;
    const ts_engine_config *c = &e->c;
    x[e->off_coolant] = c->coolant_temp;
    x[e->off_coolant + 1] = c->oil_temp;
    for (int i = 0; i < EN_NCYL; i++) {
        double *xc = x + e->off_cyl + i * EN_CYL_NX;
        en_kin k;
        en_kinematics(&e->geom, wrap(-e->cyl_offset[i]), &k);
        xc[CX_T] = T;
        xc[CX_M] = p * k.V / (e->gas.r_a * T);
        xc[CX_MB] = 0.0;
        xc[CX_IGN] = 0.0;
        xc[CX_BURN] = 0.0;
        xc[CX_KMEAN] = 1e-3;
        xc[CX_KTURB] = 1e-3;
        for (int s = 0; s < EN_NSURF; s++) {
            double *xw = x + e->off_wall + (i * EN_NSURF + s) * EN_WALL_NODES;
            double tw = s == EN_PISTON ? c->oil_temp + 150 : c->coolant_temp + 60;
            for (int n = 0; n < EN_WALL_NODES; n++) xw[n] = tw;
        }
    }
}

int en_crank_rhs(const ts_engine *e, double t, const double *x, const ts_engine_inputs *in,
                 double *xdot, ts_engine_outputs *out)
{
    (void)t;
    const ts_engine_config *c = &e->c;
    const en_gas *g = &e->gas;
    const en_geom *geo = &e->geom;
    double w = x[TS_ENGINE_X_SPEED], th = x[TS_ENGINE_X_ANGLE];
    double wp = fmax(w, 1.0);
    double n_rpm = wp * EN_RPM;
    double sp_half = c->stroke * wp / EN_PI / 2.0; /* half the mean piston speed */
    en_bank_out bo[EN_NBANK];
    double R_im[EN_NBANK], g_im[EN_NBANK], R_em[EN_NBANK], g_em[EN_NBANK];
    double air = 0;
    for (int b = 0; b < EN_NBANK; b++) {
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        if (!(xb[BX_IMM] > 0 && xb[BX_EMM] > 0 && xb[BX_ICM] > 0 && xb[BX_IMT] > 100 &&
              xb[BX_EMT] > 100 && xb[BX_ICT] > 100))
            return 1;
        double p_ic = xb[BX_ICM] * g->r_a * xb[BX_ICT] / c->ic_volume;
        en_comp_out co;
        en_compressor(&e->turbo, xb[BX_TC], in->p_amb, in->T_amb, p_ic, &co);
        air += co.mdot;
        en_bank_read(e, xb, &bo[b]);
        R_im[b] = en_gas_r(g, bo[b].F_im);
        g_im[b] = gamma_of(g, bo[b].T_im, bo[b].F_im);
        R_em[b] = en_gas_r(g, bo[b].F_em);
        g_em[b] = gamma_of(g, bo[b].T_em, bo[b].F_em);
    }
    double mf_cyc = en_fuel_command(e, in, air, wp);
    en_bank_flows bf[EN_NBANK];
    memset(bf, 0, sizeof bf);
    double t_ind = 0, J = c->inertia, dJ = 0;
    double q_cool = 0, q_oil = 0;
    double led[EN_LEDGER_NX] = {0};
    double T_cool = x[e->off_coolant], T_oil = x[e->off_coolant + 1];
    for (int i = 0; i < EN_NCYL; i++) {
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        double *dc = xdot + e->off_cyl + i * EN_CYL_NX;
        int b = e->cyl_bank[i];
        double thl = wrap(th - e->cyl_offset[i]);
        en_kin kin;
        en_kinematics(geo, thl, &kin);
        double m = xc[CX_M], T = xc[CX_T], mb = xc[CX_MB];
        if (!(m > 0 && T > 100 && T < 5000)) return 1;
        double F = fmin(fmax(mb / m, 0.0), 1.0);
        double R = en_gas_r(g, F), cp = en_gas_cp(g, T, F), gam = cp / (cp - R);
        double p = m * R * T / kin.V;
        double rho = m / kin.V;
        /* valves */
        double a_iv = en_valve_area(en_valve_lift(thl, c->ivo, c->ivc, c->intake_max_lift),
                                    c->intake_valve_diameter, c->n_intake_valves, c->valve_cd);
        double a_ev = en_valve_area(en_valve_lift(thl, c->evo, c->evc, c->exhaust_max_lift),
                                    c->exhaust_valve_diameter, c->n_exhaust_valves, c->valve_cd);
        const en_bank_out *o = &bo[b];
        double mi = en_orifice(a_iv, o->p_im, o->T_im, R_im[b], g_im[b], p, T, R, gam);
        double me = en_orifice(a_ev, p, T, R, gam, o->p_em, o->T_em, R_em[b], g_em[b]);
        double h_cyl = en_gas_h(g, T, F);
        double hi = mi >= 0 ? mi * en_gas_h(g, o->T_im, o->F_im) : mi * h_cyl;
        double fi = mi >= 0 ? mi * o->F_im : mi * F;
        double he = me >= 0 ? me * h_cyl : me * en_gas_h(g, o->T_em, o->F_em);
        double fe = me >= 0 ? me * F : me * o->F_em;
        /* ignition delay and burning */
        double I = xc[CX_IGN], s = xc[CX_BURN];
        double a_soi = wrap(thl + c->soi);
        double dI = 0, ds = 0, mfb = 0;
        int burning = 0;
        if (thl >= RESET_START && thl <= RESET_END) {
            dI = -I * wp * RESET_RATE;
            ds = -s * wp * RESET_RATE;
        } else if (I < 1.0) {
            if (a_soi < LW_WINDOW && mf_cyc > 0)
                dI = 1.0 / en_ignition_delay(c->id_a, c->id_n, c->id_ta, p, T); /* Livengood-Wu */
        } else {
            ds = w;
            if (s < c->burn_duration && mf_cyc > 0) {
                double tau = s / c->burn_duration;
                double tau_id_ms = 1e3 * fmax(a_soi - s, 0.0) / wp;
                double X, dX, phi = mf_cyc * c->afr_stoich / fmax(m - mb, 1e-9);
                en_watson_burn(&e->watson, tau, tau_id_ms, n_rpm, phi, &X, &dX);
                /* overall phi of the cycle: air trapped before burning began */
                phi = mf_cyc * c->afr_stoich / fmax(m - mb + mf_cyc * X * c->afr_stoich, 1e-9);
                en_watson_burn(&e->watson, tau, tau_id_ms, n_rpm, phi, &X, &dX);
                mfb = mf_cyc * dX / c->burn_duration * wp;
                burning = 1;
            }
        }
        double q_comb = mfb * c->lhv;
        /* turbulence */
        double dm = mi - me + mfb;
        double min_ = (mi > 0 ? mi : 0) + (me < 0 ? -me : 0);
        double mout = (me > 0 ? me : 0) + (mi < 0 ? -mi : 0);
        double rho_up = o->p_im / (R_im[b] * o->T_im);
        double v_in = mi > 0 && a_iv > 0 ? mi / (rho_up * a_iv) : 0.0;
        en_cascade_in ci = {m, kin.V, rho, T, p, c->bore, min_, v_in, mout,
                            dm / m - kin.dVdth * w / kin.V, xc[CX_KMEAN], fmax(xc[CX_KTURB], K_FLOOR)};
        double dK, dk, Lh, up, Um;
        en_cascade(&ci, c->cascade_cbeta, c->cascade_rdt, &dK, &dk, &Lh, &up, &Um);
        double uch = sqrt(Um * Um + up * up + sp_half * sp_half);
        double h = en_htc(c->nu_coeff, c->nu_exp, rho, uch, Lh, T, cp);
        /* walls */
        double q_w = 0;
        for (int sf = 0; sf < EN_NSURF; sf++) {
            const double *xw = x + e->off_wall + (i * EN_NSURF + sf) * EN_WALL_NODES;
            double *dw = xdot + e->off_wall + (i * EN_NSURF + sf) * EN_WALL_NODES;
            double Ts = xw[0];
            double flux = h * (T - Ts);
            if (burning) flux += c->emissivity * EN_SIGMA * (T * T * T * T - Ts * Ts * Ts * Ts);
            double area = e->surf_area[sf], share = 1.0;
            if (sf == EN_LINER) {
                double exposed = EN_PI * c->bore * (kin.xp + geo->vc / geo->area);
                share = exposed / area;
                area = exposed;
            }
            q_w += flux * area;
            double qb;
            const en_wall *wl = &e->wall[sf];
            en_wall_rates(wl, xw, flux * share, sf == EN_PISTON ? T_oil : T_cool, dw, &qb);
            if (sf == EN_PISTON)
                q_oil += qb * e->surf_area[sf];
            else
                q_cool += qb * e->surf_area[sf];
        }
        /* first law */
        double pdv = p * kin.dVdth * w;
        double dE = q_comb - q_w - pdv + hi - he;
        double dmb = fi - fe + mfb * (1.0 + c->afr_stoich);
        double dF = (dmb - F * dm) / m;
        dc[CX_M] = dm;
        dc[CX_MB] = dmb;
        dc[CX_T] = en_gas_dTdt(g, m, T, F, dE, dm, dF);
        dc[CX_IGN] = dI;
        dc[CX_BURN] = ds;
        dc[CX_KMEAN] = dK;
        dc[CX_KTURB] = xc[CX_KTURB] < K_FLOOR && dk < 0 ? 0.0 : dk;
        /* crank */
        t_ind += p * kin.dVdth;
        J += c->recip_mass * kin.dxdth * kin.dxdth;
        dJ += 2.0 * c->recip_mass * kin.dxdth * kin.d2xdth2;
        /* bank and ledger */
        bf[b].m_in += mi;
        bf[b].h_in += hi;
        bf[b].mf_in += fi;
        bf[b].m_ex += me;
        bf[b].h_ex += he;
        bf[b].mf_ex += fe;
        led[LX_FUEL_E] += q_comb;
        led[LX_WORK] += pdv;
        led[LX_WALL] += q_w;
        led[LX_HIN] += hi;
        led[LX_HOUT] += he;
        led[LX_MIN] += mi;
        led[LX_MOUT] += me;
        led[LX_MFUEL] += mfb;
        if (i == 0 && out) {
            out->cyl_pressure = p;
            out->cyl_temp = T;
            out->heat_release = q_comb;
            out->piston_surface_temp = x[e->off_wall + EN_PISTON * EN_WALL_NODES];
        }
    }
    for (int b = 0; b < EN_NBANK; b++)
        en_bank_rhs(e, x + e->off_bank + b * EN_BANK_NX, &bf[b], in->p_amb, in->T_amb,
                    xdot + e->off_bank + b * EN_BANK_NX, &bo[b]);
    memcpy(xdot + e->off_ledger, led, sizeof led);
    /* coolant and oil: thermostat opens over 4 K around the set point */
    double open_c = fmin(fmax((T_cool - c->coolant_temp + 2.0) / 4.0, 0.0), 1.0);
    double open_o = fmin(fmax((T_oil - c->oil_temp + 2.0) / 4.0, 0.0), 1.0);
    xdot[e->off_coolant] = (q_cool - open_c * c->coolant_ua * (T_cool - in->T_amb)) /
                           (c->coolant_capacity * e->thermal_scale);
    xdot[e->off_coolant + 1] = (q_oil - open_o * c->oil_ua * (T_oil - in->T_amb)) /
                               (c->oil_capacity * e->thermal_scale);
    /* crankshaft */
    double t_fric = en_fmep(c, w) * geo->vd * EN_NCYL / EN_CYCLE * tanh(w / 5.0);
    double t_brake = t_ind - t_fric;
    xdot[TS_ENGINE_X_SPEED] =
        in->hold_speed ? 0.0 : (t_brake - in->load_torque - 0.5 * dJ * w * w) / J;
    xdot[TS_ENGINE_X_ANGLE] = w;
    if (out) {
        out->speed = w;
        out->brake_torque = t_brake;
        out->indicated_torque = t_ind;
        out->friction_torque = t_fric;
        out->boost = 0.5 * (bo[0].p_im + bo[1].p_im);
        out->intake_temp = 0.5 * (bo[0].T_im + bo[1].T_im);
        out->exhaust_temp = 0.5 * (bo[0].T_em + bo[1].T_em);
        out->air_flow = bo[0].air_flow + bo[1].air_flow;
        out->fuel_per_cycle = mf_cyc;
        out->fuel_flow = mf_cyc * EN_NCYL * wp / EN_CYCLE;
        out->phi = out->air_flow > 0 ? out->fuel_flow * c->afr_stoich / out->air_flow : 0.0;
        out->turbo_speed = 0.5 * (bo[0].turbo_speed + bo[1].turbo_speed);
    }
    return 0;
}
