/*
 * test_engine_parts.c — the engine's building blocks against closed forms:
 * slider-crank kinematics, valve lift, Watson burn law, ignition delay, ideal-
 * gas properties, orifice flow, layered-wall conduction, turbomachinery map
 * shapes, the wastegate actuator law and its range check, the open-loop
 * turbine schedule and its table check, Millington-Hartles
 * friction and the fuel law of Eqs. 13-14.
 * Uses the engine's internal header (engine_impl.h) on purpose.
 */
#include "test_util.h"

#include <string.h>

#include "engine_test_util.h"
#include "sim/engine_impl.h"
#include "turbo_fixture.h"

/* The gas properties of the default engine config (engine.json). */
static en_gas default_gas(void)
{
    ts_config c = et_defaults();
    en_gas g;
    en_gas_init(&g, c.engine.cp_air, c.engine.cp_burned, c.engine.r_air, c.engine.r_burned);
    return g;
}

/* EVIDENCE: slider-crank closed form (Heywood Eq. 2.4): V(0) = V_c,
 * V(pi) = V_c + V_d, dV/dtheta and d2x/dtheta2 equal central differences of
 * V and x (relative 1e-6); 12 x V_d = 37.9 L for 0.159 x 0.159 m (paper: 37.7 L
 * with Cummins' 0.15875 m). Closed form, tolerance 1e-6. */
static void slider_crank(void **state)
{
    (void)state;
    en_geom g = {.bore = 0.159, .stroke = 0.159, .crank = 0.0795, .rod = 0.30};
    g.area = ET_PI / 4 * g.bore * g.bore;
    g.vd = g.area * g.stroke;
    g.vc = g.vd / 14.0;
    en_kin k0, k1, kp, km;
    en_kinematics(&g, 0, &k0);
    en_kinematics(&g, ET_PI, &k1);
    assert_close(k0.V, g.vc, 1e-12, 0);
    assert_close(k1.V, g.vc + g.vd, 1e-12, 0);
    assert_close(12 * g.vd, 0.03788, 1e-3, 0);
    for (double th = 0.3; th < 4 * ET_PI; th += 0.7) {
        double h = 1e-5;
        en_kin k;
        en_kinematics(&g, th, &k);
        en_kinematics(&g, th + h, &kp);
        en_kinematics(&g, th - h, &km);
        assert_close(k.dVdth, (kp.V - km.V) / (2 * h), 1e-6, 1e-12);
        assert_close(k.d2xdth2, (kp.dxdth - km.dxdth) / (2 * h), 1e-5, 1e-9);
    }
}

/* EVIDENCE: valve lift profile definition: zero outside [open, close], peak at
 * mid-event, symmetric; area = cd n min(pi D L, 0.9 pi D^2/4). Closed form. */
static void valve_lift_and_area(void **state)
{
    (void)state;
    double o = 340 * ET_PI / 180, c = 575 * ET_PI / 180, l = 0.014;
    assert_true(en_valve_lift(300 * ET_PI / 180, o, c, l) == 0);
    assert_true(en_valve_lift(600 * ET_PI / 180, o, c, l) == 0);
    assert_close(en_valve_lift(0.5 * (o + c), o, c, l), l, 1e-12, 0);
    assert_close(en_valve_lift(o + 0.3, o, c, l), en_valve_lift(c - 0.3, o, c, l), 1e-12, 0);
    assert_close(en_valve_area(0.001, 0.05, 2, 0.7, 0.9), 0.7 * 2 * ET_PI * 0.05 * 0.001, 1e-12, 0);
    assert_close(en_valve_area(0.05, 0.05, 2, 0.7, 0.9), 0.7 * 2 * 0.9 * ET_PI / 4 * 0.0025, 1e-12, 0);
}

/* EVIDENCE: Watson et al. (1980) burn law: X(0) = 0, X(1) = 1, dX/dtau is the
 * derivative of X (trapezoid integral of dX from 0 to tau equals X within
 * 1e-3); premixed fraction beta = 1 - 0.926 phi^0.37 / tau_id^0.26. Ignition
 * delay 3.45 p^-1.02 exp(2100/T) ms: at 50 bar, 900 K, 0.658 ms. Closed form. */
static void watson_and_ignition_delay(void **state)
{
    (void)state;
    en_watson w = {0.926, 0.37, 0.26, 1.25e-8, 2.4, 5000, 14.2, 0.644, 0.79, 2.18};
    double X, dX, Xp, dXp, integral = 0;
    en_watson_burn(&w, 0.0, 0.8, 2100, 0.45, &X, &dX);
    assert_true(X == 0);
    /* just below tau = 1, where the correlation itself is evaluated (at 1
     * a branch returns 1) */
    en_watson_burn(&w, 1.0 - 1e-9, 0.8, 2100, 0.45, &X, &dX);
    assert_close(X, 1.0, 1e-6, 0);
    int n = 20000;
    en_watson_burn(&w, 1e-9, 0.8, 2100, 0.45, &Xp, &dXp);
    for (int i = 1; i <= n; i++) {
        double tau = (double)i / n * 0.6;
        en_watson_burn(&w, tau, 0.8, 2100, 0.45, &X, &dX);
        integral += 0.5 * (dX + dXp) * 0.6 / n;
        dXp = dX;
    }
    assert_close(integral, X, 1e-3, 0);
    double tau_ms = 3.45 * pow(50.0, -1.02) * exp(2100.0 / 900.0);
    assert_close(en_ignition_delay(3.45e-3, 1.02, 2100, 50e5, 900), tau_ms * 1e-3, 1e-12, 0);
    assert_close(tau_ms, 0.658, 0.005, 0);
}

/* EVIDENCE: ideal gas with cp(T): h(T0) = 0; dh/dT = cp (central difference);
 * u = h - R T; cp(air, 300 K) = 1005 +/- 1 %,
 * cp(air, 1000 K) = 1142 +/- 1 % (JANAF). The energy-form temperature rate of
 * the right-hand sides (en_gas_dTdt_s) closes: m cv dT + u dm + m du/dF dF =
 * dE. Closed form. */
static void gas_properties(void **state)
{
    (void)state;
    en_gas g = default_gas();
    assert_close(en_gas_h(&g, EN_T0, 0.3), 0.0, 0, 1e-9);
    assert_close(en_gas_cp(&g, 300, 0), 1005, 0.01, 0);
    assert_close(en_gas_cp(&g, 1000, 0), 1142, 0.01, 0);
    for (double T = 400; T < 2500; T += 300) {
        double d = 1e-3;
        assert_close((en_gas_h(&g, T + d, 0.4) - en_gas_h(&g, T - d, 0.4)) / (2 * d),
                     en_gas_cp(&g, T, 0.4), 1e-6, 0);
    }
    /* dT/dt from an energy rate: check with finite differences of E = m u(T, F) */
    double m = 0.01, T = 1200, F = 0.3, dE = 5e4, dm = 0.2, dF = 3.0;
    en_gas_state s0;
    en_gas_eval(&g, T, F, &s0);
    double dT = en_gas_dTdt_s(&s0, m, dE, dm, dF), h = 1e-7;
    double E0 = m * en_gas_u(&g, T, F);
    double E1 = (m + dm * h) * en_gas_u(&g, T + dT * h, F + dF * h);
    assert_close((E1 - E0) / h, dE, 1e-4, 0);
    /* the right-hand side's one-pass evaluation (polynomials in T, en_gas_eval)
     * equals the separate functions (polynomials in T/1000) to rounding */
    for (double Tk = 200; Tk < 3000; Tk += 137)
        for (double Fk = -0.1; Fk < 1.2; Fk += 0.25) {
            en_gas_state st;
            en_gas_eval(&g, Tk, Fk, &st);
            assert_close(st.cp, en_gas_cp(&g, Tk, Fk), 1e-12, 0);
            assert_close(st.R, en_gas_r(&g, Fk), 1e-12, 0);
            assert_close(st.h, en_gas_h(&g, Tk, Fk), 1e-11, 1e-6);
            assert_close(st.u, en_gas_u(&g, Tk, Fk), 1e-11, 1e-6);
        }
}

/* EVIDENCE: compressible orifice (Heywood App. C): choked flow for
 * p2/p1 < (2/(g+1))^(g/(g-1)) equals cda p1 sqrt(g/(R T1)) (2/(g+1))^((g+1)/(2(g-1)));
 * antisymmetric in the pressures; zero at equal pressures. Closed form 1e-9. */
static void orifice_flow(void **state)
{
    (void)state;
    double g = 1.4, R = 287, A = 1e-3;
    double choked = A * 3e5 * sqrt(g / (R * 600)) * pow(2 / (g + 1), (g + 1) / (2 * (g - 1)));
    assert_close(en_orifice(A, 3e5, 600, R, g, 1e5, 600, R, g), choked, 1e-9, 0);
    assert_close(en_orifice(A, 1e5, 600, R, g, 3e5, 600, R, g), -choked, 1e-9, 0);
    assert_true(en_orifice(A, 2e5, 600, R, g, 2e5, 400, R, g) == 0);
}

/* EVIDENCE: 1-D steady conduction (Fourier): a linear-in-resistance profile
 * from gas side to sink carrying flux q is stationary (all dT/dt = 0 within
 * 1e-9 K/s relative) and passes q to the sink, for the metal and the 1.0 mm
 * zirconia-coated wall. Closed form. */
static void wall_steady_conduction(void **state)
{
    (void)state;
    for (int coated = 0; coated < 2; coated++) {
        en_wall w;
        en_wall_build(&w, coated ? 1e-3 : 0, 1.0, 2.6e6, 0.012, 45, 3.7e6, 3000);
        double q = 5e5, Tsink = 360, T[EN_WALL_NODES], dT[EN_WALL_NODES], qb;
        double r = 1.0 / w.cond[EN_WALL_NODES - 1];
        for (int n = EN_WALL_NODES - 1; n >= 0; n--) {
            if (n < EN_WALL_NODES - 1) r += 1.0 / w.cond[n];
            T[n] = Tsink + q * r;
        }
        en_wall_rates(&w, T, q, Tsink, dT, &qb);
        for (int n = 0; n < EN_WALL_NODES; n++)
            assert_true(fabs(dT[n]) < 1e-6);
        assert_close(qb, q, 1e-9, 0);
        assert_close(w.depth[EN_WALL_NODES - 1], 0.012 + (coated ? 1e-3 : 0), 1e-9, 0);
        if (coated) assert_close(T[0] - T[w.coated_nodes], q * 1e-3 / 1.0, 1e-9, 0);
    }
}

/* EVIDENCE: the synthetic turbomachinery maps (engine_turbo.c): compressor
 * flow = rho D^2 phi_ch sqrt(U^2 - dh/psi0), zero at the zero-flow line;
 * efficiency peaks at phi_opt and, above the tip Mach number M_opt, falls by
 * the factor 1 - ((M - M_opt)/M_width)^2 (M = U / sqrt(1.4 R T01)); a stopped
 * wheel passes flow when PR < 1 with no work; the outlet stream carries the
 * shaft's work as enthalpy, h(T02) - h(T01) = P_c / mdot to 1e-12 (energy
 * conservation across the wheel; the map-convention T02 with cp = 1005 gave
 * 2 % more at PR 3); turbine efficiency peaks
 * (eta_t) at the optimum blade-speed ratio. Similarity scaling: flow x1.6
 * and equal efficiency at equal tip speed. Closed form. */
static void turbo_maps(void **state)
{
    (void)state;
    en_turbo t = test_turbo();
    en_gas gas = default_gas();
    en_comp_out o;
    double w = 9000, U = w * 0.05, T1 = 298, p1 = 1e5, pr = 3.0;
    double dh = 1005 * T1 * (pow(pr, 0.4 / 1.4) - 1), rho = p1 / (287 * T1);
    en_compressor(&t, &gas, w, p1, T1, pr * p1, &o);
    assert_true(o.power > 0);
    assert_close(en_gas_h(&gas, o.T_out, 0) - en_gas_h(&gas, T1, 0), o.power / o.mdot, 1e-12, 0);
    assert_close(o.h_out, en_gas_h(&gas, o.T_out, 0), 1e-12, 0); /* what the volume receives */
    assert_close(o.cp_out, en_gas_cp(&gas, o.T_out, 0), 1e-12, 0);
    assert_true(o.T_out > T1 + 0.5 * dh / 1005);
    assert_close(o.mdot, rho * 0.01 * 0.22 * sqrt(U * U - dh / 0.9), 1e-9, 0);
    /* efficiency: island in phi times the tip-Mach fall-off (M = 1.30 here) */
    double phi = o.mdot / (rho * U * 0.01), mach = U / sqrt(1.4 * 287 * T1);
    double xphi = (phi - 0.13) / 0.15, xm = (mach - 1.0) / 1.5;
    assert_true(mach > 1.25 && mach < 1.35);
    assert_close(o.eta, 0.8 * (1 - xphi * xphi) * (1 - xm * xm), 1e-9, 0);
    en_compressor(&t, &gas, 5000, p1, T1, 1.5 * p1, &o); /* M = 0.72: island alone */
    phi = o.mdot / (rho * 250 * 0.01);
    xphi = (phi - 0.13) / 0.15;
    assert_close(o.eta, 0.8 * (1 - xphi * xphi), 1e-9, 0);
    double w0 = sqrt(dh / 0.9) / 0.05;
    en_compressor(&t, &gas, w0 * 0.999, p1, T1, pr * p1, &o);
    assert_true(o.mdot == 0);
    en_compressor(&t, &gas, 0, p1, T1, 0.9 * p1, &o);
    assert_true(o.mdot > 0 && o.power == 0 && o.T_out == T1);
    en_turbo big = t;
    big.d_c *= sqrt(1.6);
    en_comp_out ob;
    en_compressor(&t, &gas, 9000, p1, T1, 2.5 * p1, &o);
    en_compressor(&big, &gas, 9000 / sqrt(1.6), p1, T1, 2.5 * p1, &ob);
    assert_close(ob.mdot, 1.6 * o.mdot, 1e-9, 0);
    assert_close(ob.eta, o.eta, 1e-9, 0);
    /* turbine at the optimum blade-speed ratio */
    double T3 = 800, cp = 1150, R = 287, pr4 = 0.5, g = cp / (cp - R);
    double cs = sqrt(2 * cp * T3 * (1 - pow(pr4, (g - 1) / g)));
    en_turb_out to;
    en_turbine(&t, t.a_t, 0.7 * cs / 0.05, 2e5, T3, R, cp, 1e5, &to);
    assert_close(to.eta, 0.75, 1e-9, 0);
}

/* EVIDENCE: conservation in the exhaust manifold (filling-and-emptying,
 * Watson & Janota 1982) when its pressure falls below ambient (a tip-out at
 * idle): the turbine then draws AMBIENT AIR in, so the burned mass m F does
 * not change (d(mF)/dt = cylinder inflow = 0 here: F falls by dilution, dF/dt
 * = -F dm/dt / m) and the energy brought in is that air's enthalpy h_air(T_amb)
 * (dE/dt = -h_out - q_wall with h_out = m_out h_air(T_amb), m_out < 0). Until
 * session 21 the inflow carried the manifold's own F and enthalpy (burned gas
 * at 800 K appearing from ambient air at 298 K). Closed form, 1e-9. */
static void exhaust_backflow_brings_ambient_air(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE);
    const ts_engine_config *c = &e->c;
    double xb[EN_BANK_NX] = {0}, xd[EN_BANK_NX];
    /* T_amb away from EN_T0 (298.15 K), where every sensible enthalpy is 0 */
    double p_amb = 101325, T_amb = 320, T_em = 700, F_em = 0.5, p_em = 0.9 * p_amb;
    xb[BX_ICM] = p_amb * c->ic_volume / (e->gas.r_a * 300);
    xb[BX_ICT] = 300;
    xb[BX_IMM] = p_amb * c->intake_volume / (e->gas.r_a * 300);
    xb[BX_IMT] = 300;
    xb[BX_EMM] = p_em * c->exhaust_volume / (en_gas_r(&e->gas, F_em) * T_em);
    xb[BX_EMT] = T_em;
    xb[BX_EMF] = F_em;
    xb[BX_TC] = 0; /* rotor at rest: no turbine work, the nozzle as an orifice */
    en_bank_flows f = {.omega = ET_RPM(700)}; /* valves shut: no cylinder flows */
    en_bank_out o;
    en_bank_rhs(e, xb, &f, p_amb, T_amb, xd, &o);
    double m = xb[BX_EMM], dm = xd[BX_EMM];
    /* inflow through the turbine nozzle, an orifice fed by ambient AIR */
    en_gas_state s_em, s_air;
    en_gas_eval(&e->gas, T_em, F_em, &s_em);
    en_gas_eval(&e->gas, T_amb, 0, &s_air);
    double m_t = en_orifice(e->turbo.a_t, p_em, T_em, s_em.R, s_em.cp / s_em.cv, p_amb, T_amb,
                            s_air.R, s_air.cp / s_air.cv);
    assert_true(m_t < 0);
    assert_close(dm, -m_t, 1e-12, 0);
    assert_close(xd[BX_EMF], -F_em * dm / m, 1e-9, 0);
    double dE = dm * s_air.h - c->exhaust_ua * (T_em - T_amb);
    assert_close(xd[BX_EMT], en_gas_dTdt_s(&s_em, m, dE, dm, xd[BX_EMF]), 1e-9, 0);
    assert_true(xd[BX_EMT] < 0); /* cold air cools the manifold */
    ts_engine_free(e);
}

/* Burned mass in the intercooler volume (kg/s): d(m_ic F_ic)/dt = dm F + m dF. */
static double ic_burned_rate(const double *xb, const double *xd)
{
    return xd[BX_ICM] * xb[BX_ICF] + xb[BX_ICM] * xd[BX_ICF];
}

/* EVIDENCE: conservation across the intercooler-outlet orifice
 * (filling-and-emptying, Watson & Janota 1982): the intercooler volume and
 * the intake manifold exchange gas, so over both
 *   mass         d(m_ic)/dt + d(m_im)/dt = m_c - m_in
 *   burned mass  d(m_ic F_ic)/dt + d(m_im F_im)/dt = 0 * m_c - mf_in
 *   energy       d(m_ic u_ic)/dt + d(m_im u_im)/dt = H_c - Q_ic - H_in
 * (compressor: fresh air F = 0, enthalpy H_c; the cylinders take m_in, mf_in,
 * H_in; the stream through the orifice carries the upstream volume's F and h
 * and cancels). Formerly the intercooler volume had no F: a reverse
 * flow (intake manifold above the intercooler) took burned mass m_ici F_im out
 * of the intake manifold that appeared nowhere, and the pressure of a burned
 * intercooler charge used air's R. Both directions, to round-off. */
static void intercooler_backflow_conserves_burned_mass(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE);
    const ts_engine_config *c = &e->c;
    const en_gas *g = &e->gas;
    double p_amb = 101325, T_amb = 298.15;
    double T_ic = 330, T_im = 360, F_im = 0.3, p_ic = 2.0e5;
    /* reverse flow into clean air, reverse and forward with burned gas there */
    const double F_ics[] = {0, 0.1, 0.1}, p_ims[] = {1.05 * p_ic, 1.05 * p_ic, 0.95 * p_ic};
    for (int k = 0; k < 3; k++) {
        double F_ic = F_ics[k], p_im = p_ims[k];
        int reverse = p_im > p_ic;
        double xb[EN_BANK_NX] = {0}, xd[EN_BANK_NX];
        xb[BX_ICM] = p_ic * c->ic_volume / (en_gas_r(g, F_ic) * T_ic);
        xb[BX_ICT] = T_ic;
        xb[BX_ICF] = F_ic;
        xb[BX_IMM] = p_im * c->intake_volume / (en_gas_r(g, F_im) * T_im);
        xb[BX_IMT] = T_im;
        xb[BX_IMF] = F_im;
        xb[BX_EMM] = p_amb * c->exhaust_volume / (en_gas_r(g, 0.5) * 700);
        xb[BX_EMT] = 700;
        xb[BX_EMF] = 0.5;
        xb[BX_TC] = 0;
        en_gas_state s_ic, s_im, s_c;
        en_gas_eval(g, T_ic, F_ic, &s_ic);
        en_gas_eval(g, T_im, F_im, &s_im);
        double T_c = 400; /* the compressor's air, given */
        en_gas_eval(g, T_c, 0, &s_c);
        en_comp_out co = {.mdot = 0.3, .T_out = T_c, .h_out = s_c.h, .cp_out = s_c.cp};
        double m_in = 0.5;
        en_bank_flows f = {.m_in = m_in,
                           .h_in = m_in * s_im.h,
                           .mf_in = m_in * F_im,
                           .omega = ET_RPM(1500),
                           .have_co = 1,
                           .co = co};
        en_bank_out o;
        en_bank_rhs(e, xb, &f, p_amb, T_amb, xd, &o);
        /* the orifice sees the intercooler at the mixture's R */
        double m_ici = en_orifice(c->ic_cda, p_ic, T_ic, s_ic.R, s_ic.cp / s_ic.cv, p_im, T_im,
                                  s_im.R, s_im.cp / s_im.cv);
        assert_true(reverse ? m_ici < 0 : m_ici > 0);
        assert_close(xd[BX_ICM], co.mdot - m_ici, 1e-12, 0);
        double scale = fabs(m_ici) + m_in; /* the largest mass flow [kg/s] */
        assert_close(xd[BX_ICM] + xd[BX_IMM], co.mdot - m_in, 0, 1e-13 * scale);
        /* burned mass: what the cylinders take and nothing else */
        double mf_im = xd[BX_IMM] * F_im + xb[BX_IMM] * xd[BX_IMF];
        assert_close(ic_burned_rate(xb, xd) + mf_im, -f.mf_in, 0, 1e-13 * scale);
        /* and the stream carries the upstream volume's burned fraction (the sum
         * above holds for any F on the stream) */
        assert_close(mf_im, m_ici * (reverse ? F_im : xb[BX_ICF]) - f.mf_in, 0, 1e-13 * scale);
        /* energy: d(m u)/dt = m cv dT/dt + u dm/dt + m du/dF dF/dt of each volume */
        double q_ic = en_intercooler_heat(c->ic_ua, co.mdot, co.cp_out, co.T_out, c->ic_wall_temp);
        double dE_ic =
            xb[BX_ICM] * (s_ic.cv * xd[BX_ICT] + s_ic.dudF * xd[BX_ICF]) + s_ic.u * xd[BX_ICM];
        double dE_im =
            xb[BX_IMM] * (s_im.cv * xd[BX_IMT] + s_im.dudF * xd[BX_IMF]) + s_im.u * xd[BX_IMM];
        double dE = co.mdot * co.h_out - q_ic - f.h_in;
        assert_close(dE_ic + dE_im, dE, 0, 1e-12 * scale * s_c.h);
        /* the stream carries the upstream gas's enthalpy */
        assert_close(dE_im, m_ici * (reverse ? s_im.h : s_ic.h) - f.h_in, 0, 1e-12 * scale * s_c.h);
    }
    ts_engine_free(e);
}

/* EVIDENCE: closed form of the wastegate actuator (engine_manifold.c; a
 * pneumatic diaphragm against a preloaded linear spring, Watson & Janota
 * 1982 [R11]): the open fraction is (p - crack) / (full - crack), exactly, away
 * from the 2 % rounding bands at the ends; 0 below crack - 2 %, 1 above
 * full + 2 %; continuous with a continuous slope across the bands; a boost
 * rise of 0.1 bar at the rated point's ~0.24 opens it by 0.1/5.2 (linear),
 * not by the ~13 % (relative) of the former smoothstep law. Not calibrated. */
static void wastegate_actuator_linear(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_engine_config *e = &c.engine;
    e->wg_crack = 2.8e5;
    e->wg_full = 8.0e5;
    assert_true(en_wastegate_open(e, 2.6e5) == 0.0);
    assert_true(en_wastegate_open(e, 8.2e5) == 1.0);
    for (double p = 3.0e5; p <= 7.8e5; p += 0.4e5)
        assert_close(en_wastegate_open(e, p), (p - 2.8e5) / 5.2e5, 1e-12, 1e-12);
    assert_close(en_wastegate_open(e, 4.16e5) - en_wastegate_open(e, 4.06e5), 0.1 / 5.2, 1e-9, 0);
    const double ends[2] = {2.8e5, 8.0e5}, band = 0.02 * 5.2e5;
    for (int k = 0; k < 2; k++)
        for (int s = -1; s <= 1; s++) { /* value and slope continuous at the ends and band edges */
            double pe = ends[k] + s * band, h = 1.0;
            double below = en_wastegate_open(e, pe - h), at = en_wastegate_open(e, pe);
            double above = en_wastegate_open(e, pe + h);
            assert_close(at - below, above - at, 0, 1e-9);
        }
    double prev = 0;
    for (double p = 2.0e5; p <= 9.0e5; p += 1e3) { /* monotone */
        double o = en_wastegate_open(e, p);
        assert_true(o >= prev && o >= 0 && o <= 1);
        prev = o;
    }
}

/* A wastegate whose full-open pressure is not above its crack pressure is a
 * configuration error naming /engine/wg_full (not a step in the opening). */
static void wastegate_range_is_checked(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    c.engine.wg_full = c.engine.wg_crack;
    ts_err err;
    ts_engine *e = ts_engine_make(&c, &err);
    assert_null(e);
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/engine/wg_full");
}

/* EVIDENCE: closed form of the open-loop turbine schedule (engine_turbo.c
 * en_turb_schedule): with no schedule the nozzle is turb_area_ref x
 * turbo_flow_scale, the gate authority 1 and the open bypass 0 at every
 * speed; with one, each is interpolated linearly in engine speed between
 * the nodes and held beyond the ends. Not calibrated. */
static void turbine_schedule_interpolates(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    c.engine.turb_sched_speed_n = c.engine.turb_sched_nozzle_n = 0;
    c.engine.turb_sched_gate_n = c.engine.turb_sched_bypass_n = 0;
    ts_err err;
    ts_engine *e = ts_engine_make(&c, &err);
    assert_non_null(e);
    double a0 = c.engine.turb_area_ref * c.engine.turbo_flow_scale;
    for (int rpm = 800; rpm <= 2200; rpm += 700) {
        en_turb_geometry g = en_turb_schedule(e, ET_RPM(rpm));
        assert_close(g.a_t, a0, 1e-12, 0);
        assert_true(g.gate == 1.0 && g.bypass == 0.0);
    }
    ts_engine_free(e);
    const double w[3] = {ET_RPM(1300), ET_RPM(1800), ET_RPM(2100)}, f[3] = {1.0, 1.2, 1.6};
    const double gate[3] = {1.0, 1.0, 0.0}, by[3] = {0.0, 1e-4, 3e-4};
    memcpy(c.engine.turb_sched_speed, w, sizeof w);
    memcpy(c.engine.turb_sched_nozzle, f, sizeof f);
    memcpy(c.engine.turb_sched_gate, gate, sizeof gate);
    memcpy(c.engine.turb_sched_bypass, by, sizeof by);
    c.engine.turb_sched_speed_n = c.engine.turb_sched_nozzle_n = 3;
    c.engine.turb_sched_gate_n = c.engine.turb_sched_bypass_n = 3;
    e = ts_engine_make(&c, &err);
    assert_non_null(e);
    en_turb_geometry lo = en_turb_schedule(e, ET_RPM(800)), mid = en_turb_schedule(e, ET_RPM(1550));
    en_turb_geometry hi = en_turb_schedule(e, ET_RPM(1950)), top = en_turb_schedule(e, ET_RPM(2500));
    assert_close(lo.a_t, a0, 1e-12, 0);
    assert_true(lo.gate == 1.0 && lo.bypass == 0.0);
    assert_close(mid.a_t, 1.1 * a0, 1e-12, 0);
    assert_close(mid.bypass, 0.5e-4, 1e-12, 0);
    assert_close(hi.a_t, 1.4 * a0, 1e-12, 0);
    assert_close(hi.gate, 0.5, 1e-12, 0);
    assert_close(hi.bypass, 2e-4, 1e-12, 0);
    assert_close(top.a_t, 1.6 * a0, 1e-12, 0);
    assert_true(top.gate == 0.0);
    assert_close(top.bypass, 3e-4, 1e-12, 0);
    ts_engine_free(e);
}

/* Turbine schedules with one node, a table of another length than
 * turb_sched_speed, or speeds that do not increase are configuration errors
 * naming the array. */
static void turbine_schedule_is_checked(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_err err;
    const double w[2] = {ET_RPM(1000), ET_RPM(2000)}, one[2] = {1.0, 1.0}, zero[2] = {0, 0};
    memcpy(c.engine.turb_sched_speed, w, sizeof w);
    memcpy(c.engine.turb_sched_nozzle, one, sizeof one);
    memcpy(c.engine.turb_sched_gate, one, sizeof one);
    memcpy(c.engine.turb_sched_bypass, zero, sizeof zero);
    c.engine.turb_sched_speed_n = c.engine.turb_sched_nozzle_n = 2;
    c.engine.turb_sched_gate_n = 2;
    c.engine.turb_sched_bypass_n = 1;
    assert_null(ts_engine_make(&c, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_string_equal(err.pointer, "/engine/turb_sched_bypass");
    c.engine.turb_sched_bypass_n = 2;
    c.engine.turb_sched_speed_n = 1;
    assert_null(ts_engine_make(&c, &err));
    assert_string_equal(err.pointer, "/engine/turb_sched_speed");
    c.engine.turb_sched_speed_n = 2;
    c.engine.turb_sched_speed[1] = ET_RPM(900);
    assert_null(ts_engine_make(&c, &err));
    assert_string_equal(err.pointer, "/engine/turb_sched_speed");
    c.engine.turb_sched_speed[1] = ET_RPM(2000);
    ts_engine *e = ts_engine_make(&c, &err);
    assert_non_null(e);
    ts_engine_free(e);
}

/* EVIDENCE: Millington & Hartles (SAE 680590) with the provisional constants:
 * fmep = 6895 (15 - 4) + 33.1 N[rpm] + 107 S_p^2 Pa = 1.59 bar at 2100 rpm (b = 33.1 Pa/rpm
 * = 316.08 Pa s/rad in engine.json)
 * (1.5-2.5 bar expected for this engine; engine.json's fmep notes). Eq. 13: phi_tgt = 0.45 at 2100
 * rpm, 0.65 at 600 rpm; Eq. 14: m_f = m_air phi/(A/F)s Rack 120/(N 12). */
static void friction_and_fuel_law(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    assert_close(en_fmep(&c.engine, ET_RPM(2100)), 1.586e5, 0.005, 0);
    ts_fuel_law f = ts_fuel_law_from_config(&c.engine);
    assert_close(ts_fuel_phi_target(&f, ET_RPM(2100)), 0.45, 1e-9, 0);
    assert_close(ts_fuel_phi_target(&f, ET_RPM(600)), 0.65, 1e-3, 0);
    double mf = ts_fuel_per_cycle(&f, 2.0, ET_RPM(2100), 0.8);
    assert_close(mf, 2.0 * 0.45 / 14.5 * 0.8 * 60 * 2 / (2100 * 12.0), 1e-9, 0);
    assert_true(ts_fuel_per_cycle(&f, 2.0, ET_RPM(2100), 1.5) ==
                ts_fuel_per_cycle(&f, 2.0, ET_RPM(2100), 1.0));
}

/* EVIDENCE: Eq. 13 with its cap (fuel_actuator.h: phi_max, "cap on phi_tgt";
 * engine.json: a smoke-limit guard): phi_tgt = min(phi_rated + c (N -
 * N_rated)^2, phi_max). With phi_max lowered to 0.5 the 650-rpm idle, where
 * the parabola gives 0.64, is held at exactly 0.5, and Eq. 14's fuel follows
 * the capped value; at 2100 rpm (0.45, below the cap) nothing changes.
 * Closed form, tolerance 1e-12. */
static void fuel_law_phi_max_caps_eq13(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_fuel_law f = ts_fuel_law_from_config(&c.engine);
    f.phi_max = 0.5;
    double dw = ET_RPM(650) - f.speed_rated;
    assert_true(f.phi_rated + f.phi_curvature * dw * dw > 0.6); /* the cap binds */
    assert_true(ts_fuel_phi_target(&f, ET_RPM(650)) == 0.5);
    assert_close(ts_fuel_phi_target(&f, ET_RPM(2100)), 0.45, 1e-9, 0);
    double mf = ts_fuel_per_cycle(&f, 1.0, ET_RPM(650), 1.0);
    assert_close(mf, 1.0 * 0.5 / f.afr_stoich * 60 * 2 / (650 * 12.0), 1e-12, 0);
}

/* EVIDENCE: Eq. 14 m_f = m_air phi_tgt / (A/F)_s Rack 60 n_R / (N n_cyl) has N
 * in the denominator; fuel_actuator.h clamps N below at 10 rad/s (the guard
 * against N -> 0). A stopped crank (omega 0) therefore gets the finite fuel
 * of Eq. 14 at N = 10 rad/s with phi_tgt(0), 12 cylinders,
 * n_R = 2; and, phi_tgt being at its cap (0.8) at both speeds with the
 * defaults, exactly the fuel at 10 rad/s itself. Closed form, 1e-12. */
static void fuel_law_speed_floor_eq14(void **state)
{
    (void)state;
    ts_config c = et_defaults();
    ts_fuel_law f = ts_fuel_law_from_config(&c.engine);
    double n_min = 10.0 * 30.0 / ET_PI; /* rpm */
    double mf0 = ts_fuel_per_cycle(&f, 2.0, 0.0, 1.0);
    assert_true(isfinite(mf0) && mf0 > 0);
    assert_close(mf0, 2.0 * ts_fuel_phi_target(&f, 0.0) / f.afr_stoich * 60 * 2 / (n_min * 12.0),
                 1e-12, 0);
    assert_true(ts_fuel_phi_target(&f, 0.0) == f.phi_max);
    assert_true(ts_fuel_phi_target(&f, 10.0) == f.phi_max);
    assert_close(mf0, ts_fuel_per_cycle(&f, 2.0, 10.0, 1.0), 1e-12, 0);
    assert_close(ts_fuel_per_cycle(&f, 2.0, 4.0, 1.0), mf0, 1e-12, 0);
}

/* EVIDENCE: the compressor map's efficiency floor (engine_turbo.c: eta =
 * eta_max (1 - ((phi - phi_opt)/phi_width)^2) ... ">= eta_min"): near the
 * zero-flow line (flow coefficient phi = 0.01, below the ~0.031 where the
 * island reaches eta_min 0.45 of the fixture) eta = eta_min exactly (the
 * island alone would give 0.8 (1 - (0.12/0.15)^2) = 0.288), and the power is
 * P_c = mdot dh_is / eta_min (Watson & Janota 1982). Tip Mach 0.72, below
 * M_opt: the island alone. Closed form, tolerance 1e-9. */
static void compressor_efficiency_floor(void **state)
{
    (void)state;
    en_turbo t = test_turbo();
    en_gas gas = default_gas();
    double w = 5000, U = w * 0.05, T1 = 298, p1 = 1e5, rho = p1 / (287 * T1);
    /* phi = phi_ch sqrt(1 - dh/(psi0 U^2)) = 0.01: the head that gives it */
    double s = 0.01 / t.phi_ch, dh = t.psi0 * U * U * (1 - s * s);
    double pr = pow(1 + dh / (1005 * T1), 1.4 / 0.4);
    en_comp_out o;
    en_compressor(&t, &gas, w, p1, T1, pr * p1, &o);
    double phi = o.mdot / (rho * U * 0.01);
    assert_close(phi, 0.01, 1e-6, 0);
    assert_true(o.mdot > 0);
    double x = (phi - t.phi_opt) / t.phi_w;
    assert_true(t.eta_max * (1 - x * x) < t.eta_min); /* the island is below the floor here */
    assert_true(o.eta == t.eta_min);
    assert_close(o.power, o.mdot * dh / t.eta_min, 1e-9, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(slider_crank),
        cmocka_unit_test(valve_lift_and_area),
        cmocka_unit_test(watson_and_ignition_delay),
        cmocka_unit_test(gas_properties),
        cmocka_unit_test(orifice_flow),
        cmocka_unit_test(wall_steady_conduction),
        cmocka_unit_test(turbo_maps),
        cmocka_unit_test(friction_and_fuel_law),
        cmocka_unit_test(fuel_law_phi_max_caps_eq13),
        cmocka_unit_test(fuel_law_speed_floor_eq14),
        cmocka_unit_test(compressor_efficiency_floor),
        cmocka_unit_test(exhaust_backflow_brings_ambient_air),
        cmocka_unit_test(intercooler_backflow_conserves_burned_mass),
        cmocka_unit_test(wastegate_actuator_linear),
        cmocka_unit_test(wastegate_range_is_checked),
        cmocka_unit_test(turbine_schedule_interpolates),
        cmocka_unit_test(turbine_schedule_is_checked),
    };
    return cmocka_run_group_tests_name("engine_parts", tests, NULL, NULL);
}
