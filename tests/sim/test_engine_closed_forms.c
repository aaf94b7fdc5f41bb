/*
 * test_engine_closed_forms.c — engine building blocks against closed forms
 * that tests/sim/test_engine_parts.c leaves open: subcritical and linearised
 * orifice flow, the Watson burn law term by term, intercooler effectiveness,
 * turbine power off the optimum blade-speed ratio, the turbocharger rotor
 * balance, the layered wall's heat capacity and Crank-Nicolson step, the
 * friction torque of every fidelity, the crankshaft's variable-inertia
 * equation and the V-12 firing order. Each closes a mutant the rest of the
 * suite let through (the commit message lists them).
 * Uses the engine's internal header (engine_impl.h) on purpose.
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "engine_test_util.h"
#include "sim/engine_impl.h"
#include "turbo_fixture.h"

/* Textbook subcritical mass flow (Heywood App. C, Eq. C.8):
 * mdot = A p1 / sqrt(R T1) (p2/p1)^(1/g) sqrt(2 g/(g-1) (1 - (p2/p1)^((g-1)/g))). */
static double heywood_flow(double A, double p1, double T1, double R, double g, double p2)
{
    double pr = p2 / p1;
    return A * p1 / sqrt(R * T1) * pow(pr, 1 / g) *
           sqrt(2 * g / (g - 1) * (1 - pow(pr, (g - 1) / g)));
}

/* EVIDENCE: compressible orifice, Heywood (1988) App. C Eqs. C.8-C.9, written
 * independently of en_psi: subcritical flow at p2/p1 = 0.6, 0.75, 0.9, 0.98
 * (1e-12); choked flow constant below the critical ratio
 * (2/(g+1))^(g/(g-1)) = 0.5283 at g = 1.4 and equal to C.8 just above it
 * (continuous, 1e-6); within 1 % of equal pressures the linearisation
 * documented in engine_impl.h, mdot(0.99) (1 - pr) / 0.01, continuous at
 * pr = 0.99 (1e-9). Closed form, not calibrated. */
static void orifice_subcritical_and_linear(void **state)
{
    (void)state;
    double A = 2e-3, p1 = 2.5e5, T1 = 700, R = 290, g = 1.35;
    const double prs[] = {0.6, 0.75, 0.9, 0.98};
    for (int k = 0; k < 4; k++)
        assert_close(en_orifice(A, p1, T1, R, g, prs[k] * p1, 300, 287, 1.4),
                     heywood_flow(A, p1, T1, R, g, prs[k] * p1), 1e-12, 0);
    double prc = pow(2 / (g + 1), g / (g - 1));
    double choked = A * p1 * sqrt(g / (R * T1)) * pow(2 / (g + 1), (g + 1) / (2 * (g - 1)));
    assert_close(en_orifice(A, p1, T1, R, g, 0.2 * p1, T1, R, g), choked, 1e-12, 0);
    assert_close(en_orifice(A, p1, T1, R, g, (prc - 1e-7) * p1, T1, R, g), choked, 1e-9, 0);
    assert_close(en_orifice(A, p1, T1, R, g, (prc + 1e-7) * p1, T1, R, g),
                 heywood_flow(A, p1, T1, R, g, prc * p1), 1e-6, 0);
    assert_close(heywood_flow(A, p1, T1, R, g, prc * p1), choked, 1e-12, 0);
    double m99 = heywood_flow(A, p1, T1, R, g, 0.99 * p1);
    assert_close(en_orifice(A, p1, T1, R, g, 0.995 * p1, T1, R, g), 0.5 * m99, 1e-9, 0);
    assert_close(en_orifice(A, p1, T1, R, g, (0.99 + 1e-9) * p1, T1, R, g), m99, 1e-6, 0);
}

/* EVIDENCE: Watson, Pilley & Marzouk (SAE 800029) as engine_combustion.c
 * documents it, evaluated by hand: beta = 1 - a phi^b / tau_id^c,
 * f1 = 1 - (1 - tau^C1)^C2, C1 = 2 + c1k (tau_id N)^c1e, f2 = 1 - exp(-C3
 * tau^C4), C3 = c3k phi^-c3e, C4 = c4k C3^0.25; X = beta f1 + (1 - beta) f2
 * at tau = 0.02 ... 0.8 and phi = 0.3, 0.6 (1e-9). The derivative is
 * d/dtau of the same expressions (central difference, 1e-6). Closed form. */
static void watson_burn_by_hand(void **state)
{
    (void)state;
    en_watson w = {0.926, 0.37, 0.26, 1.25e-8, 2.4, 5000, 14.2, 0.644, 0.79, 2.18};
    double id = 0.8, n = 2100;
    const double phis[] = {0.3, 0.6}, taus[] = {0.02, 0.05, 0.1, 0.3, 0.5, 0.8};
    for (int ip = 0; ip < 2; ip++)
        for (int it = 0; it < 6; it++) {
            double phi = phis[ip], tau = taus[it];
            double beta = 1 - 0.926 * pow(phi, 0.37) / pow(id, 0.26);
            double c1 = 2 + 1.25e-8 * pow(id * n, 2.4);
            double c3 = 14.2 / pow(phi, 0.644), c4 = 0.79 * pow(c3, 0.25);
            double xf = beta * (1 - pow(1 - pow(tau, c1), 5000)) +
                        (1 - beta) * (1 - exp(-c3 * pow(tau, c4)));
            double X, dX, Xp, Xm, d;
            en_watson_burn(&w, tau, id, n, phi, &X, &dX);
            assert_close(X, xf, 1e-9, 1e-12);
            double h = 1e-6 * tau;
            en_watson_burn(&w, tau + h, id, n, phi, &Xp, &d);
            en_watson_burn(&w, tau - h, id, n, phi, &Xm, &d);
            assert_close(dX, (Xp - Xm) / (2 * h), 1e-5, 1e-9);
        }
}

/* EVIDENCE: heat-exchanger effectiveness-NTU with a wall at uniform
 * temperature (Incropera & DeWitt, Eq. 11.35 with C_r = 0): eps = 1 -
 * exp(-NTU), NTU = UA / (mdot cp); Q = eps mdot cp (T_in - T_wall). At NTU = 2:
 * 0.8647 of the maximum; Q -> UA dT as the flow grows (NTU -> 0); a charge
 * below the wall temperature gains heat (Q < 0). 1e-12. */
static void intercooler_effectiveness_ntu(void **state)
{
    (void)state;
    double ua = 2000, cp = 1010, T_in = 420, T_w = 320;
    double mdot = ua / (2 * cp); /* NTU = 2 */
    assert_close(en_intercooler_heat(ua, mdot, cp, T_in, T_w),
                 (1 - exp(-2.0)) * mdot * cp * (T_in - T_w), 1e-12, 0);
    assert_close(en_intercooler_heat(ua, 1e3, cp, T_in, T_w), ua * (T_in - T_w), 1e-3, 0);
    assert_close(en_intercooler_heat(ua, 1e-3, cp, T_in, T_w), 1e-3 * cp * (T_in - T_w), 1e-9, 0);
    /* both ways: a charge cooler than the wall (idle: ~302 K from the
     * compressor, a 325-K wall) is warmed by the same law */
    assert_close(en_intercooler_heat(ua, mdot, cp, 300, T_w),
                 (1 - exp(-2.0)) * mdot * cp * (300 - T_w), 1e-12, 0);
}

/* EVIDENCE: turbine (engine_turbo.c; Watson & Janota 1982 Ch. 4): flow from the
 * nozzle equation (Heywood C.8), isentropic enthalpy drop dh = cp T03 (1 -
 * (p4/p03)^((g-1)/g)), eta = eta_t (2 b - b^2) with b = (U/c_s)/bsr_opt,
 * c_s = sqrt(2 dh), and P_t = mdot eta dh, at b = 0.5 and 1.3 (off the
 * optimum, where the efficiency law matters); unchoked p4/p03 = 0.625.
 * eta_t = 0.75, not the compressor's eta_max = 0.8 (turbo_fixture.h), so
 * the turbine reading eta_max shows. Closed form, 1e-9. */
static void turbine_power_off_optimum(void **state)
{
    (void)state;
    en_turbo t = test_turbo();
    double T3 = 850, cp = 1160, R = 288, p3 = 1.6e5, p4 = 1.0e5, g = cp / (cp - R);
    double dh = cp * T3 * (1 - pow(p4 / p3, (g - 1) / g)), cs = sqrt(2 * dh);
    double mdot = heywood_flow(t.a_t, p3, T3, R, g, p4);
    const double bs[] = {0.5, 1.3};
    for (int k = 0; k < 2; k++) {
        double w = bs[k] * 0.7 * cs / 0.05;
        en_turb_out o;
        en_turbine(&t, t.a_t, w, p3, T3, R, cp, p4, &o);
        double eta = 0.75 * (2 * bs[k] - bs[k] * bs[k]);
        assert_close(o.mdot, mdot, 1e-12, 0);
        assert_close(o.eta, eta, 1e-9, 0);
        assert_close(o.power, mdot * eta * dh, 1e-9, 0);
    }
}

/* A bank state of the mean-value engine: intercooler and manifolds at the
 * given pressures, rotor at w_tc. */
static void bank_state(const ts_engine *e, double p_ic, double p_im, double p_em, double w_tc,
                       double *xb)
{
    const ts_engine_config *c = &e->c;
    const en_gas *g = &e->gas;
    memset(xb, 0, EN_BANK_NX * sizeof *xb);
    xb[BX_ICM] = p_ic * c->ic_volume / (en_gas_r(g, 0) * 330);
    xb[BX_ICT] = 330;
    xb[BX_IMM] = p_im * c->intake_volume / (en_gas_r(g, 0.02) * 340);
    xb[BX_IMT] = 340;
    xb[BX_IMF] = 0.02;
    xb[BX_EMM] = p_em * c->exhaust_volume / (en_gas_r(g, 0.6) * 850);
    xb[BX_EMT] = 850;
    xb[BX_EMF] = 0.6;
    xb[BX_TC] = w_tc;
}

/* EVIDENCE: turbocharger rotor (paper Section III.B.1, as engine_manifold.c
 * states it): J dw/dt = (eta_m P_t - P_c) / w, with P_t = mdot_t eta_t dh_t of
 * the turbine and P_c = mdot_c dh_is / eta_c of the compressor at the bank's
 * state, both evaluated here from the public part functions; the mechanical
 * efficiency multiplies the turbine's power only (bearing loss on the
 * driving side). 1e-12. */
static void rotor_power_balance(void **state)
{
    (void)state;
    ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE);
    double p_amb = 101325, T_amb = 298.15, w_tc = 8000;
    double xb[EN_BANK_NX], xd[EN_BANK_NX];
    bank_state(e, 2.4e5, 2.3e5, 2.1e5, w_tc, xb);
    en_bank_flows f = {.omega = ET_RPM(1800)};
    en_bank_out o;
    en_bank_rhs(e, xb, &f, p_amb, T_amb, xd, &o);
    en_comp_out co;
    en_compressor(&e->turbo, &e->gas, w_tc, p_amb, T_amb, o.p_ic, &co);
    en_gas_state s_em;
    en_gas_eval(&e->gas, o.T_em, o.F_em, &s_em);
    en_turb_out to;
    double m_wg;
    en_exhaust_outflow(e, ET_RPM(1800), w_tc, &o, &s_em, p_amb, T_amb, &to, &m_wg);
    assert_true(co.power > 0 && to.power > 0);
    double J = e->turbo.inertia * e->turbo_inertia_scale;
    assert_close(xd[BX_TC], (e->turbo.mech_eff * to.power - co.power) / (J * w_tc), 1e-12, 0);
    ts_engine_free(e);
}

/* EVIDENCE: vertex-centred finite volumes of the layered wall
 * (engine_wall.c): the node capacities are half cells at the ends, so their
 * sum is the wall's heat capacity per area, the integral of rho c over the
 * depth = rc_coat x coat + rc_metal x metal (1e-12), and the surface node
 * holds half the first cell. One Crank-Nicolson step of every stack
 * (en_walls_step) keeps the steady conduction profile carrying a held flux q
 * to the sink (Fourier; the profile of test_engine_parts.c) unchanged
 * (1e-9 K), and a step from a uniform wall at the sink temperature with
 * q = 0 stays there. Closed form. */
static void wall_capacity_and_cn_steady_state(void **state)
{
    (void)state;
    for (int coated = 0; coated < 2; coated++) {
        double coat = coated ? 1e-3 : 0, metal = 0.012;
        en_wall w;
        en_wall_build(&w, coat, 1.0, 2.6e6, metal, 45, 3.7e6, 3000);
        double sum = 0;
        for (int i = 0; i < EN_WALL_NODES; i++)
            sum += w.cap[i];
        assert_close(sum, 2.6e6 * coat + 3.7e6 * metal, 1e-12, 0);
        double rc0 = coated ? 2.6e6 : 3.7e6;
        assert_close(w.cap[0], 0.5 * rc0 * w.depth[1], 1e-12, 0);
    }
    et_bench b = et_bench_at(TS_ENGINE_LHR10, TS_ENGINE_CRANK_ANGLE, ET_RPM(1800));
    ts_engine *e = b.e;
    double *x = b.x;
    double T_sink[EN_NSURF] = {x[e->off_coolant + 1], x[e->off_coolant], x[e->off_coolant]};
    double q[EN_NCYL * EN_NSURF], want[EN_NCYL * EN_NSURF * EN_WALL_NODES];
    for (int i = 0; i < EN_NCYL; i++)
        for (int s = 0; s < EN_NSURF; s++) {
            const en_wall *w = &e->wall[s];
            double qs = (1 + 0.1 * i) * 2e5 * (s + 1);
            q[i * EN_NSURF + s] = qs;
            double r = 1.0 / w->cond[EN_WALL_NODES - 1];
            double *T = want + (i * EN_NSURF + s) * EN_WALL_NODES;
            for (int n = EN_WALL_NODES - 1; n >= 0; n--) {
                if (n < EN_WALL_NODES - 1) r += 1.0 / w->cond[n];
                T[n] = T_sink[s] + qs * r;
            }
        }
    memcpy(x + e->off_wall, want, sizeof want);
    en_walls_step(e, x, q, 2e-4);
    for (int k = 0; k < EN_NCYL * EN_NSURF * EN_WALL_NODES; k++)
        assert_close(x[e->off_wall + k], want[k], 0, 1e-9 * want[k]);
    for (int i = 0; i < EN_NCYL; i++)
        for (int s = 0; s < EN_NSURF; s++) {
            q[i * EN_NSURF + s] = 0;
            for (int n = 0; n < EN_WALL_NODES; n++)
                x[e->off_wall + (i * EN_NSURF + s) * EN_WALL_NODES + n] = T_sink[s];
        }
    en_walls_step(e, x, q, 2e-4);
    for (int i = 0; i < EN_NCYL; i++)
        for (int s = 0; s < EN_NSURF; s++)
            for (int n = 0; n < EN_WALL_NODES; n++)
                assert_close(x[e->off_wall + (i * EN_NSURF + s) * EN_WALL_NODES + n], T_sink[s],
                             1e-12, 0);
    et_bench_free(&b);
}

/* EVIDENCE: heat continuity at the walls' back faces (engine_crank.c
 * wall_part; the lumped coolant/oil network of the paper's III.A.1): with
 * both thermostats shut (the fluids 10 K below their set points, so nothing
 * leaves to ambient), the oil gains exactly what the twelve pistons' last
 * wall nodes conduct into it, sum g_back (T_last - T_oil) A_piston, and the
 * coolant what the heads and the liners conduct, each over its surface's
 * whole area (the exposed share of the liner limits its gas side only).
 * 1e-12. Closed form. */
static void coolant_and_oil_take_the_walls_back_heat(void **state)
{
    (void)state;
    et_bench b = et_bench_at(TS_ENGINE_LHR05, TS_ENGINE_CRANK_ANGLE, ET_RPM(1800));
    ts_engine *e = b.e;
    const ts_engine_config *c = &e->c;
    double *x = b.x, *xd = b.xd;
    x[e->off_coolant] = c->coolant_temp - 10;
    x[e->off_coolant + 1] = c->oil_temp - 10;
    ts_engine_inputs in = et_full_load();
    ts_engine_outputs out;
    assert_int_equal(en_crank_eval(e, x, &in, xd, &out, NULL), 0);
    const double sink[EN_NSURF] = {x[e->off_coolant + 1], x[e->off_coolant], x[e->off_coolant]};
    double q[EN_NSURF] = {0};
    for (int i = 0; i < EN_NCYL; i++)
        for (int s = 0; s < EN_NSURF; s++) {
            const double *xw = x + e->off_wall + (i * EN_NSURF + s) * EN_WALL_NODES;
            q[s] += e->wall[s].cond[EN_WALL_NODES - 1] * (xw[EN_WALL_NODES - 1] - sink[s]) *
                    e->surf_area[s];
        }
    for (int s = 0; s < EN_NSURF; s++)
        assert_true(q[s] > 1e3); /* every surface gives heat: each term is tested */
    assert_close(xd[e->off_coolant + 1] * c->oil_capacity * e->thermal_scale, q[EN_PISTON], 1e-12,
                 0);
    assert_close(xd[e->off_coolant] * c->coolant_capacity * e->thermal_scale,
                 q[EN_HEAD] + q[EN_LINER], 1e-12, 0);
    et_bench_free(&b);
}

/* EVIDENCE: friction torque of a four-stroke engine from its mean effective
 * pressure (Heywood 1988 Eq. 2.19: T = mep V_d,total / (4 pi) for n_R = 2),
 * V_d,total = 12 pi/4 B^2 S, with Millington-Hartles fmep = a (r_c - 4) + b N
 * + c (2 S N / 60)^2 evaluated here by hand, times the documented fade
 * tanh(w / 5 rad/s); the same torque in every fidelity's friction channel
 * (map, mean value, crank angle), at 600, 1400 and 2200 rpm, and inside the
 * fade at 2.5 rad/s. 1e-9. */
static void friction_torque_four_stroke(void **state)
{
    (void)state;
    const int fids[3] = {TS_ENGINE_MAP, TS_ENGINE_MEAN_VALUE, TS_ENGINE_CRANK_ANGLE};
    for (int f = 0; f < 3; f++) {
        ts_engine *e = et_make(TS_ENGINE_CONVENTIONAL, fids[f]);
        const ts_engine_config *c = &e->c;
        double *x = calloc((size_t)ts_engine_nstate(e), sizeof *x),
               *xd = calloc((size_t)ts_engine_nstate(e), sizeof *xd);
        assert_non_null(x);
        assert_non_null(xd);
        for (int rpm = 600; rpm <= 2200; rpm += 800) {
            double w = ET_RPM(rpm), sp = 2 * c->stroke * rpm / 60.0;
            double fmep =
                c->fmep_a * (c->compression_ratio - 4) + c->fmep_b * w + c->fmep_c * sp * sp;
            double vd = 12 * ET_PI / 4 * c->bore * c->bore * c->stroke;
            double want = fmep * vd / (4 * ET_PI) * tanh(w / 5.0);
            assert_close(en_friction_torque(e, w), want, 1e-9, 0);
            ts_engine_init_state(e, w, 101325, 298.15, x);
            ts_engine_inputs in = et_full_load();
            ts_engine_outputs out;
            assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &out), 0);
            assert_close(out.friction_torque, want, 1e-9, 0);
        }
        /* in the fade, 2.5 rad/s: tanh(0.5) = 0.46 of the torque */
        double w = 2.5, sp = c->stroke * w / ET_PI;
        double fmep = c->fmep_a * (c->compression_ratio - 4) + c->fmep_b * w + c->fmep_c * sp * sp;
        assert_close(en_friction_torque(e, w),
                     fmep * 12 * ET_PI / 4 * c->bore * c->bore * c->stroke / (4 * ET_PI) *
                         tanh(0.5),
                     1e-9, 0);
        free(x);
        free(xd);
        ts_engine_free(e);
    }
}

/* Crankshaft inertia of the crank-angle engine at crank angle th, by hand:
 * J0 + load + m_rec sum over the cylinders of (dx_p/dth)^2 at th - 60 deg k. */
static double inertia_at(const ts_engine *e, double load, double th)
{
    double J = e->c.inertia + load;
    for (int i = 0; i < 12; i++) {
        en_kin k;
        en_kinematics(&e->geom, th - i * ET_PI / 3, &k);
        J += e->c.recip_mass * k.dxdth * k.dxdth;
    }
    return J;
}

/* EVIDENCE: crankshaft with crank-angle-varying inertia (engine_crank.c;
 * Lagrange, kinetic energy J(th) w^2 / 2): J dw/dt = T_brake - T_load -
 * 1/2 dJ/dth w^2, with J(th) = J0 + J_load + m_rec sum (dx_p/dth)^2 computed
 * here from the kinematics and dJ/dth by a central difference of it (1e-6), at
 * six crank angles where dJ/dth w^2 is a large fraction of the torque. Also
 * the firing order the header documents: even 60-degree intervals (cylinder
 * k fires k x 60 deg after cylinder 1) and banks alternating. Closed form. */
static void crankshaft_variable_inertia(void **state)
{
    (void)state;
    double w = ET_RPM(2000), load = 1500, J_load = 3.0;
    et_bench b = et_bench_at(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE, w);
    ts_engine *e = b.e;
    double *x = b.x, *xd = b.xd;
    for (int i = 0; i < EN_NCYL; i++) {
        assert_close(e->cyl_offset[i], i * ET_PI / 3, 1e-12, 1e-15);
        assert_int_equal(e->cyl_bank[i], i % 2);
    }
    ts_engine_inputs in = et_full_load();
    in.hold_speed = 0;
    in.load_torque = load;
    in.load_inertia = J_load;
    for (int k = 0; k < 6; k++) {
        double th = 0.13 + k * 0.37;
        x[TS_ENGINE_X_ANGLE] = th;
        ts_engine_outputs out;
        assert_int_equal(en_crank_eval(e, x, &in, xd, &out, NULL), 0);
        double J = inertia_at(e, J_load, th), h = 1e-5;
        double dJ = (inertia_at(e, J_load, th + h) - inertia_at(e, J_load, th - h)) / (2 * h);
        double want = (out.brake_torque - load - 0.5 * dJ * w * w) / J;
        assert_close(xd[TS_ENGINE_X_SPEED], want, 1e-6, 1e-9);
    }
    et_bench_free(&b);
}

/* EVIDENCE: first law and species balance of the mean-value cylinders
 * (engine_mean.c, steady-flow open system over the cycle-averaged
 * cylinders): fuel energy = indicated work + wall heat + (exhaust - intake
 * enthalpy flow) (ledger rates, 1e-12 of the fuel energy); exhaust mass flow
 * = air + fuel; and the burned mass entering each exhaust manifold is the
 * intake's burned mass plus the stoichiometric products of the fuel,
 * m_f (1 + (A/F)_s) (Heywood 1988 Sec. 4.2), read from the manifold's
 * d(m F)/dt plus what leaves through the turbine and wastegate (1e-9). At
 * a commanded fuel per cycle (no fuel law), 1400 rpm, the manifolds of
 * ts_engine_init_state with an intake burned fraction of 0.05. The phi
 * channel is the charge's equivalence ratio, m_f (A/F)_s / m_in (1e-12). */
static void mean_value_first_law_and_burned_mass(void **state)
{
    (void)state;
    double w = ET_RPM(1400);
    et_bench b = et_bench_at(TS_ENGINE_CONVENTIONAL, TS_ENGINE_MEAN_VALUE, w);
    ts_engine *e = b.e;
    const ts_engine_config *c = &e->c;
    double *x = b.x, *xd = b.xd;
    ts_engine_inputs in = et_full_load();
    in.fuel_per_cycle = 1.2e-4;
    for (int b = 0; b < EN_NBANK; b++)
        x[e->off_bank + b * EN_BANK_NX + BX_IMF] = 0.05;
    ts_engine_outputs out;
    assert_int_equal(ts_engine_rhs(e, 0, x, &in, xd, &out), 0);
    const double *l = xd + e->off_ledger;
    assert_true(l[LX_FUEL_E] > 0 && l[LX_WALL] > 0 && l[LX_WORK] > 0);
    assert_close(l[LX_FUEL_E], 1.2e-4 * 12 * w / (4 * ET_PI) * c->lhv, 1e-12, 0);
    assert_close(l[LX_FUEL_E] - l[LX_WORK] - l[LX_WALL], l[LX_HOUT] - l[LX_HIN], 0,
                 1e-12 * l[LX_FUEL_E]);
    assert_close(l[LX_MOUT], l[LX_MIN] + l[LX_MFUEL], 1e-12, 0);
    /* the equivalence ratio reported: (fuel / charge) / (fuel / air)_s */
    assert_close(out.phi, l[LX_MFUEL] * c->afr_stoich / l[LX_MIN], 1e-12, 0);
    for (int b = 0; b < EN_NBANK; b++) { /* the banks are alike: half of each flow */
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        const double *db = xd + e->off_bank + b * EN_BANK_NX;
        en_bank_out o;
        en_bank_read(e, xb, &o);
        en_gas_state s_em;
        en_gas_eval(&e->gas, o.T_em, o.F_em, &s_em);
        en_turb_out to;
        double m_wg;
        en_exhaust_outflow(e, w, xb[BX_TC], &o, &s_em, in.p_amb, in.T_amb, &to, &m_wg);
        double m_out = to.mdot + m_wg;
        assert_true(m_out > 0);
        double dmF = db[BX_EMM] * o.F_em + xb[BX_EMM] * db[BX_EMF];
        assert_close(db[BX_EMM], 0.5 * l[LX_MOUT] - m_out, 1e-9, 1e-15);
        double mf_ex = 0.5 * (l[LX_MIN] * 0.05 + l[LX_MFUEL] * (1 + c->afr_stoich));
        assert_close(dmF + m_out * o.F_em, mf_ex, 1e-9, 0);
    }
    et_bench_free(&b);
}

/* EVIDENCE: one burning cylinder of the crank-angle engine by hand
 * (engine_crank.c, engine_heat.c): cylinder 1 at 10 deg after firing TDC,
 * valves shut, ignited (Livengood-Wu integral 1) 5 deg ago.
 *  - exposed liner = bore circumference x (V / piston area) = 4 V / B
 *    (slider-crank; 1e-12);
 *  - Nusselt law h = a Re^b lambda / L, Re = rho u L / mu, mu = 3.3e-7
 *    T^0.7, lambda = mu cp / 0.7, L = min(V / A, B / 2), u^2 = U^2 + u'^2 +
 *    (S_p / 2)^2 with U^2 = 2 K / m, u'^2 = 2 k / (3 m) and S_p = 2 S N / 60
 *    (Poulos & Heywood 1983 as engine_heat.c documents it; 1e-9);
 *  - heat release = m_f LHV dX/dtheta w with Watson's X (SAE 800029, whose
 *    ignition delay is in ms and speed in rpm): tau = (5 deg)/duration,
 *    tau_id = (angle from SOI to ignition) / w in ms, phi the cycle's overall
 *    equivalence ratio m_f (A/F)_s / (air trapped before burning) (1e-9);
 *  - mass: dm/dt = the fuel burned (q / LHV), d(m_burned)/dt = (1 + (A/F)_s)
 *    q / LHV, the products of the fuel and its stoichiometric air (1e-12).
 * Closed forms, not calibrated. */
static void crank_cylinder_by_hand(void **state)
{
    (void)state;
    double w = ET_RPM(1800), deg = ET_PI / 180, thl = 10 * deg, s = 5 * deg, mf = 1.5e-4;
    et_bench b = et_bench_at(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE, w);
    ts_engine *e = b.e;
    const ts_engine_config *c = &e->c;
    double *x = b.x, *xd = b.xd;
    x[TS_ENGINE_X_ANGLE] = thl;
    en_kin k;
    en_kinematics(&e->geom, thl, &k);
    double T = 1500, F = 0.1, p = 90e5, R = en_gas_r(&e->gas, F);
    double m = p * k.V / (R * T), K = 0.4, kt = 0.25;
    double *xc = x + e->off_cyl; /* cylinder 1 */
    xc[CX_M] = m;
    xc[CX_T] = T;
    xc[CX_MB] = F * m;
    xc[CX_IGN] = 1.0;
    xc[CX_BURN] = s;
    xc[CX_KMEAN] = K;
    xc[CX_KTURB] = kt;
    ts_engine_inputs in = et_full_load();
    in.fuel_per_cycle = mf;
    ts_engine_outputs out;
    en_crank_part pc;
    assert_int_equal(en_crank_eval_part(e, x, &in, xd, &out, NULL, &pc), 0);
    assert_close(out.cyl_pressure, p, 1e-12, 0);
    /* exposed liner */
    assert_close(pc.cyl[0].liner_area, 4 * k.V / c->bore, 1e-12, 0);
    /* Nusselt coefficient */
    double A = ET_PI / 4 * c->bore * c->bore, L = fmin(k.V / A, c->bore / 2);
    double sp = 2 * c->stroke * (w * 30 / ET_PI) / 60;
    double u = sqrt(2 * K / m + 2 * kt / (3 * m) + 0.25 * sp * sp);
    double mu = 3.3e-7 * pow(T, 0.7), cp = en_gas_cp(&e->gas, T, F), rho = m / k.V;
    double h = c->nu_coeff * pow(rho * u * L / mu, c->nu_exp) * (mu * cp / 0.7) / L;
    assert_close(pc.cyl[0].h, h, 1e-9, 0);
    /* heat release */
    double tau = s / c->burn_duration, id_ms = 1e3 * (thl + c->soi - s) / w;
    double n_rpm = w * 30 / ET_PI, X, dX;
    double air = m - F * m;
    en_watson_burn(&e->watson, tau, id_ms, n_rpm, mf * c->afr_stoich / air, &X, &dX);
    en_watson_burn(&e->watson, tau, id_ms, n_rpm,
                   mf * c->afr_stoich / (air + mf * X * c->afr_stoich), &X, &dX);
    double q = mf * c->lhv * dX / c->burn_duration * w;
    assert_true(q > 0);
    assert_close(out.heat_release, q, 1e-9, 0);
    /* mass, valves shut: the fuel burned is the only gain, and it joins the
     * burned gas with its stoichiometric air (products = fuel + AFR_s fuel) */
    double mfb = q / c->lhv;
    assert_close(xd[e->off_cyl + CX_M], mfb, 1e-12, 0);
    assert_close(xd[e->off_cyl + CX_MB], (1 + c->afr_stoich) * mfb, 1e-12, 0);
    et_bench_free(&b);
}

/* EVIDENCE: energy cascade of Poulos & Heywood (1983) as engine_heat.c
 * writes it, by hand, for cylinder 1 in its intake stroke (480 deg after
 * firing TDC: intake valves open, exhaust shut) drawing from the intake
 * manifold at 0.8 of its pressure: inflow mdot = quasi-steady orifice at the
 * valves' effective area A_v (Heywood C.8), jet velocity v = mdot /
 * (rho_im A_v) (continuity at the valve), dK/dt = 1/2 mdot v^2 - P with
 * P = 0.3307 c_beta (K / L) sqrt(k / m), L = min(V / A, B / 2) (no outflow).
 * 1e-9. Also the boost channel is the intake manifold pressure (the mean of
 * the banks), not the compressor outlet's. Closed form. */
static void intake_jet_feeds_mean_flow(void **state)
{
    (void)state;
    double w = ET_RPM(1800), thl = 480 * ET_PI / 180;
    et_bench b = et_bench_at(TS_ENGINE_CONVENTIONAL, TS_ENGINE_CRANK_ANGLE, w);
    ts_engine *e = b.e;
    const ts_engine_config *c = &e->c;
    double *x = b.x, *xd = b.xd;
    double *xb = x + e->off_bank; /* cylinder 1 is on bank 0 */
    xb[BX_ICM] *= 1.3;            /* compressor outlet above the intake manifold */
    x[TS_ENGINE_X_ANGLE] = thl;
    en_bank_out o;
    en_bank_read(e, xb, &o);
    en_kin k;
    en_kinematics(&e->geom, thl, &k);
    double T = 350, F = 0.05, R = en_gas_r(&e->gas, F), p = 0.8 * o.p_im;
    double m = p * k.V / (R * T), K = 0.02, kt = 0.01;
    double *xc = x + e->off_cyl;
    xc[CX_M] = m;
    xc[CX_T] = T;
    xc[CX_MB] = F * m;
    xc[CX_KMEAN] = K;
    xc[CX_KTURB] = kt;
    ts_engine_inputs in = et_full_load();
    in.fuel_per_cycle = 0;
    ts_engine_outputs out;
    assert_int_equal(en_crank_eval(e, x, &in, xd, &out, NULL), 0);
    assert_true(en_valve_lift(thl, c->evo, c->evc, c->exhaust_max_lift) == 0);
    double lift = en_valve_lift(thl, c->ivo, c->ivc, c->intake_max_lift);
    double av = en_valve_area(lift, c->intake_valve_diameter, c->n_intake_valves, c->valve_cd,
                              c->valve_throat_factor);
    assert_true(av > 0);
    double R_im = en_gas_r(&e->gas, o.F_im), cp_im = en_gas_cp(&e->gas, o.T_im, o.F_im);
    double cp = en_gas_cp(&e->gas, T, F);
    double mi =
        en_orifice(av, o.p_im, o.T_im, R_im, cp_im / (cp_im - R_im), p, T, R, cp / (cp - R));
    assert_true(mi > 0);
    assert_close(xd[e->off_cyl + CX_M], mi, 1e-12, 0);
    double v = mi / (o.p_im / (R_im * o.T_im) * av);
    double A = ET_PI / 4 * c->bore * c->bore, L = fmin(k.V / A, c->bore / 2);
    double P = 0.3307 * c->cascade_cbeta * K / L * sqrt(kt / m);
    assert_close(xd[e->off_cyl + CX_KMEAN], 0.5 * mi * v * v - P, 1e-9, 0);
    en_bank_out o1;
    en_bank_read(e, x + e->off_bank + EN_BANK_NX, &o1);
    assert_close(out.boost, 0.5 * (o.p_im + o1.p_im), 1e-12, 0);
    et_bench_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(orifice_subcritical_and_linear),
        cmocka_unit_test(watson_burn_by_hand),
        cmocka_unit_test(intercooler_effectiveness_ntu),
        cmocka_unit_test(turbine_power_off_optimum),
        cmocka_unit_test(rotor_power_balance),
        cmocka_unit_test(wall_capacity_and_cn_steady_state),
        cmocka_unit_test(coolant_and_oil_take_the_walls_back_heat),
        cmocka_unit_test(friction_torque_four_stroke),
        cmocka_unit_test(crankshaft_variable_inertia),
        cmocka_unit_test(mean_value_first_law_and_burned_mass),
        cmocka_unit_test(crank_cylinder_by_hand),
        cmocka_unit_test(intake_jet_feeds_mean_flow),
    };
    return cmocka_run_group_tests_name("engine_closed_forms", tests, NULL, NULL);
}
