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
#include <stdio.h>
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
    if (a >= 0.0 && a < EN_CYCLE) return a; /* fmod would return a itself */
    a = fmod(a, EN_CYCLE);
    return a < 0 ? a + EN_CYCLE : a;
}

/* The start's wall temperatures (ts_engine_init_state): a warm engine's,
 * piston crowns above the oil and head and liner above the coolant [K].
 * Starting guesses only: the steady searches and the idle start settle the
 * walls (ts_engine_steady moves them to each cycle's conduction profile). */
#define INIT_PISTON_OVER_OIL   150.0
#define INIT_WALL_OVER_COOLANT 60.0

void en_crank_init(const ts_engine *e, double p, double T, double *x)
{
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
            double tw = s == EN_PISTON ? c->oil_temp + INIT_PISTON_OVER_OIL
                                       : c->coolant_temp + INIT_WALL_OVER_COOLANT;
            for (int n = 0; n < EN_WALL_NODES; n++) xw[n] = tw;
        }
    }
}

int en_crank_rhs(const ts_engine *e, double t, const double *x, const ts_engine_inputs *in,
                 double *xdot, ts_engine_outputs *out)
{
    (void)t;
    return en_crank_eval(e, x, in, xdot, out, NULL);
}

/* Performance notes (issue 6/10 speed-up; the equations are those above):
 * one sincos of the crank angle rotated to every cylinder, one evaluation of
 * the gas polynomials per control volume, the manifold-side properties once
 * per bank (handed on to en_bank_rhs with the compressor), valve flows only
 * while a valve is open, and (q_wall != NULL) the
 * walls frozen over a step of the multirate integrator in engine.c.
 * The evaluation is split in two: gas_part computes everything that does not
 * depend on the wall temperatures or the load (cached in en_crank_part),
 * wall_part the wall heat fluxes, the cylinders' dT/dt, the coolant and oil
 * and the crankshaft. en_crank_refresh re-runs wall_part alone (same
 * operations, same result) after a wall step or a change of load.
 * Later (branch engspeed, bitwise the same results, tests/sim/
 * test_engine_shortcuts.c): the orifice equation, energy cascade and Nusselt
 * coefficient inline (engine_impl.h), fmax/fmin against constant bounds
 * inline, valve areas, gamma and the cascade's in/outflows only while a valve
 * is open, the turbine and wastegate sharing one pressure-ratio function,
 * wall_part's three surfaces written out. */

/* Local angle of cylinder i in [0, 4 pi) at the wrapped crank angle th_w;
 * *nw: wraps added (0 or 1), the phase index of valve_lift. */
static inline double local_angle(const ts_engine *e, int i, double th_w, int *nw)
{
    double thl = th_w - e->cyl_offset[i];
    *nw = thl < 0;
    return thl < 0 ? thl + EN_CYCLE : thl;
}

/* en_valve_lift of valve v (0 intake, 1 exhaust) of cylinder i at local angle
 * thl = th_w - offset + 4 pi nw: the same (1 - cos(k d)) / 2 profile, with
 * cos(k d) = cos(k th_w - phase) = C cos(phase) + S sin(phase) from the
 * evaluation's C, S = cos, sin(k th_w) (one sincos per valve kind instead of
 * one cos per open valve; equal to rounding). */
static double valve_lift(const ts_engine *e, int v, int i, double thl, int nw, double open,
                         double close, double lmax, double C, double S)
{
    double d = thl - open;
    if (d < 0) {
        d += EN_CYCLE;
        nw++;
    }
    if (d > close - open) return 0.0;
    return lmax * 0.5 * (1.0 - (C * e->valve_cos[v][i][nw] + S * e->valve_sin[v][i][nw]));
}

/* Everything but the wall- and load-dependent derivatives; fills pc. */
static int gas_part(const ts_engine *e, const double *x, const ts_engine_inputs *in, double *xdot,
                    ts_engine_outputs *out, en_crank_part *pc)
{
    const ts_engine_config *c = &e->c;
    const en_gas *g = &e->gas;
    const en_geom *geo = &e->geom;
    double w = x[TS_ENGINE_X_SPEED], th = x[TS_ENGINE_X_ANGLE];
    double wp = en_atleast(w, 1.0);
    double n_rpm = wp * EN_RPM;
    /* the piston-speed term of the heat-transfer velocity: a share of the mean
     * piston speed S_p = 2 stroke N */
    double sp_term = c->stroke * wp / EN_PI * c->htc_piston_speed_share;
    en_bank_out bo[EN_NBANK];
    /* the manifolds' gas (handed on to en_bank_rhs with the compressor) */
    en_bank_flows bf[EN_NBANK]; /* every field set below (no memset: a rep stos per call) */
    double g_im[EN_NBANK], g_em[EN_NBANK], rho_im[EN_NBANK];
    double air = 0;
    for (int b = 0; b < EN_NBANK; b++) {
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        if (!(xb[BX_IMM] > 0 && xb[BX_EMM] > 0 && xb[BX_ICM] > 0 && xb[BX_IMT] > EN_T_DOMAIN_MIN &&
              xb[BX_EMT] > EN_T_DOMAIN_MIN && xb[BX_ICT] > EN_T_DOMAIN_MIN))
            return 1;
        en_bank_read(e, xb, &bo[b]);
        bf[b].m_in = bf[b].h_in = bf[b].mf_in = 0.0; /* the cylinders' sums */
        bf[b].m_ex = bf[b].h_ex = bf[b].mf_ex = 0.0;
        bf[b].omega = w;
        bf[b].have_co = 1;
        en_compressor(&e->turbo, g, xb[BX_TC], in->p_amb, in->T_amb, bo[b].p_ic, &bf[b].co);
        air += bf[b].co.mdot;
        bf[b].have_gas = 1;
        const en_gas_state *si = &bf[b].s_im, *se = &bf[b].s_em;
        en_gas_eval(g, bo[b].T_im, bo[b].F_im, &bf[b].s_im);
        en_gas_eval(g, bo[b].T_em, bo[b].F_em, &bf[b].s_em);
        g_im[b] = si->cp / si->cv;
        rho_im[b] = bo[b].p_im / (si->R * bo[b].T_im);
        g_em[b] = se->cp / se->cv;
    }
    double mf_cyc = en_fuel_command(e, in, air, wp);
    double t_ind = 0, J = c->inertia + in->load_inertia, dJ = 0;
    double led[EN_LEDGER_NX] = {0};
    double s_th = sin(th), c_th = cos(th);
    double th_w = wrap(th);
    double vC[2], vS[2]; /* cos, sin of k th_w for the valve lifts */
    for (int v = 0; v < 2; v++) {
        vS[v] = sin(e->valve_k[v] * th_w);
        vC[v] = cos(e->valve_k[v] * th_w);
    }
    for (int i = 0; i < EN_NCYL; i++) {
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        double *dc = xdot + e->off_cyl + i * EN_CYL_NX;
        en_cyl_part *cp_ = &pc->cyl[i];
        int b = e->cyl_bank[i];
        int nw;
        double thl = local_angle(e, i, th_w, &nw);
        en_kin kin; /* sin, cos of th - offset by rotation */
        en_kinematics_sc(geo, s_th * e->cyl_cos[i] - c_th * e->cyl_sin[i],
                         c_th * e->cyl_cos[i] + s_th * e->cyl_sin[i], &kin);
        double m = xc[CX_M], T = xc[CX_T], mb = xc[CX_MB];
        if (!(m > 0 && T > EN_T_DOMAIN_MIN && T < EN_T_DOMAIN_MAX)) return 1;
        double im = 1.0 / m, iV = 1.0 / kin.V; /* the divisions by m and V */
        double F = mb * im;
        F = F < 0.0 ? 0.0 : F > 1.0 ? 1.0 : F;
        en_gas_state gs;
        en_gas_eval(g, T, F, &gs);
        double R = gs.R, cp = gs.cp;
        double p = m * R * T * iV;
        double rho = m * iV;
        /* valves */
        /* areas of open valves only (a shut valve's lift is 0: area 0, no flow) */
        double l_iv =
            valve_lift(e, 0, i, thl, nw, c->ivo, c->ivc, c->intake_max_lift, vC[0], vS[0]);
        double l_ev =
            valve_lift(e, 1, i, thl, nw, c->evo, c->evc, c->exhaust_max_lift, vC[1], vS[1]);
        double a_iv = l_iv > 0 ? en_valve_area(l_iv, c->intake_valve_diameter, c->n_intake_valves,
                                               c->valve_cd, c->valve_throat_factor)
                               : 0.0;
        double a_ev = l_ev > 0 ? en_valve_area(l_ev, c->exhaust_valve_diameter,
                                               c->n_exhaust_valves, c->valve_cd,
                                               c->valve_throat_factor)
                               : 0.0;
        int valves_open = a_iv > 0 || a_ev > 0;
        const en_bank_out *o = &bo[b];
        const en_gas_state *si = &bf[b].s_im, *se = &bf[b].s_em;
        double mi = 0, me = 0, hi = 0, fi = 0, he = 0, fe = 0;
        double gam = valves_open ? cp / gs.cv : 0.0; /* a division: valves open only */
        if (a_iv > 0) {
            mi = en_orifice(a_iv, o->p_im, o->T_im, si->R, g_im[b], p, T, R, gam);
            hi = mi >= 0 ? mi * si->h : mi * gs.h;
            fi = mi >= 0 ? mi * o->F_im : mi * F;
        }
        if (a_ev > 0) {
            me = en_orifice(a_ev, p, T, R, gam, o->p_em, o->T_em, se->R, g_em[b]);
            he = me >= 0 ? me * gs.h : me * se->h;
            fe = me >= 0 ? me * F : me * o->F_em;
        }
        /* ignition delay and burning */
        double I = xc[CX_IGN], s = xc[CX_BURN];
        double a_soi = thl + c->soi; /* wrap: thl in [0, 4 pi), 0 < soi < 4 pi */
        if (a_soi >= EN_CYCLE) a_soi -= EN_CYCLE;
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
                double tau_id_ms = 1e3 * en_atleast(a_soi - s, 0.0) / wp;
                double X, dX, phi = mf_cyc * c->afr_stoich / en_atleast(m - mb, 1e-9);
                en_watson_tau wt;
                en_watson_pre(&e->watson, tau, tau_id_ms, n_rpm, &wt);
                en_watson_phi(&e->watson, &wt, phi, &X, &dX);
                /* overall phi of the cycle: air trapped before burning began */
                phi =
                    mf_cyc * c->afr_stoich / en_atleast(m - mb + mf_cyc * X * c->afr_stoich, 1e-9);
                en_watson_phi(&e->watson, &wt, phi, &X, &dX);
                mfb = mf_cyc * dX / c->burn_duration * wp;
                burning = 1;
            }
        }
        double q_comb = mfb * c->lhv;
        /* turbulence */
        double dm = mi - me + mfb;
        double min_ = 0.0, mout = 0.0, v_in = 0.0; /* valves shut: mi = me = 0 */
        if (valves_open) {
            min_ = (mi > 0 ? mi : 0) + (me < 0 ? -me : 0);
            mout = (me > 0 ? me : 0) + (mi < 0 ? -mi : 0);
            v_in = mi > 0 && a_iv > 0 ? mi / (rho_im[b] * a_iv) : 0.0;
        }
        en_cascade_in ci = {.m = m, .V = kin.V, .bore = c->bore, .area = geo->area,
                            .mdot_in = min_, .v_in = v_in, .mdot_out = mout,
                            .drho_rho = dm * im - kin.dVdth * w * iV, .K = xc[CX_KMEAN],
                            .k = xc[CX_KTURB] > K_FLOOR ? xc[CX_KTURB] : K_FLOOR};
        double dK, dk, Lh, up, Um;
        en_cascade(&ci, c->cascade_cbeta, c->cascade_rdt, &dK, &dk, &Lh, &up, &Um);
        double uch = sqrt(Um * Um + up * up + sp_term * sp_term);
        /* what the walls need (wall_part) */
        cp_->T = T;
        cp_->h = en_htc(&e->htc, rho, uch, Lh, T, cp);
        cp_->burning = burning;
        cp_->T4 = burning ? T * T * T * T : 0.0;
        cp_->liner_area = geo->circ * (kin.xp + geo->clear_h); /* exposed liner */
        cp_->liner_share = cp_->liner_area / e->surf_area[EN_LINER];
        cp_->m = m;
        cp_->dm = dm;
        cp_->u = gs.u;
        cp_->cv = gs.cv;
        cp_->dudF = gs.dudF;
        cp_->q_comb = q_comb;
        /* first law but the wall heat */
        double pdv = p * kin.dVdth * w;
        cp_->pdv = pdv;
        cp_->hi = hi;
        cp_->he = he;
        double dmb = fi - fe + mfb * (1.0 + c->afr_stoich);
        cp_->dF = (dmb - F * dm) * im;
        dc[CX_M] = dm;
        dc[CX_MB] = dmb;
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
        led[LX_HIN] += hi;
        led[LX_HOUT] += he;
        led[LX_MIN] += mi;
        led[LX_MOUT] += me;
        led[LX_MFUEL] += mfb;
        if (i == 0 && out) {
            out->cyl_pressure = p;
            out->cyl_temp = T;
            out->heat_release = q_comb;
        }
    }
    for (int b = 0; b < EN_NBANK; b++)
        en_bank_rhs(e, x + e->off_bank + b * EN_BANK_NX, &bf[b], in->p_amb, in->T_amb,
                    xdot + e->off_bank + b * EN_BANK_NX, &bo[b]);
    memcpy(xdot + e->off_ledger, led, sizeof led); /* LX_WALL: wall_part */
    double t_fric = en_friction_torque(e, w);
    pc->t_brake = t_ind - t_fric;
    pc->J = J;
    pc->dJ = dJ;
    xdot[TS_ENGINE_X_ANGLE] = w;
    if (out) {
        out->speed = w;
        out->brake_torque = pc->t_brake;
        out->indicated_torque = t_ind;
        out->friction_torque = t_fric;
        en_bank_outputs(bo, out);
        out->fuel_per_cycle = mf_cyc;
        out->fuel_flow = mf_cyc * EN_NCYL * wp / EN_CYCLE;
        out->phi = out->air_flow > 0 ? out->fuel_flow * c->afr_stoich / out->air_flow : 0.0;
    }
    return 0;
}

/* Gas-side heat flux [W/m^2] into a wall at surface temperature Ts:
 * convection, and radiation eps sigma (T^4 - Ts^4) while fuel burns. */
static inline double gas_flux(const en_cyl_part *cp_, double eps_sigma, double Ts)
{
    double flux = cp_->h * (cp_->T - Ts);
    if (cp_->burning) flux += eps_sigma * (cp_->T4 - Ts * Ts * Ts * Ts);
    return flux;
}

/* The wall heat fluxes and what depends on them (cylinder temperatures, wall
 * ledger, coolant and oil, walls unless frozen) and the crankshaft (load). */
static void wall_part(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                      const en_crank_part *pc, double *xdot, ts_engine_outputs *out,
                      double *q_wall)
{
    const ts_engine_config *c = &e->c;
    double w = x[TS_ENGINE_X_SPEED];
    double T_cool = x[e->off_coolant], T_oil = x[e->off_coolant + 1];
    double q_cool = 0, q_oil = 0, led_wall = 0;
    const double eps_sigma = c->emissivity * EN_SIGMA;
    const double g_back[EN_NSURF] = {e->wall[EN_PISTON].cond[EN_WALL_NODES - 1],
                                     e->wall[EN_HEAD].cond[EN_WALL_NODES - 1],
                                     e->wall[EN_LINER].cond[EN_WALL_NODES - 1]};
    for (int i = 0; i < EN_NCYL; i++) {
        const en_cyl_part *cp_ = &pc->cyl[i];
        /* the three surfaces written out (the operations of a loop over them):
         * piston (sink: oil), head and exposed liner (sink: coolant) */
        int ow = i * EN_NSURF * EN_WALL_NODES;
        const double *xp = x + e->off_wall + ow, *xh = xp + EN_WALL_NODES,
                     *xl = xp + 2 * EN_WALL_NODES;
        double fp = gas_flux(cp_, eps_sigma, xp[0]);
        double fh = gas_flux(cp_, eps_sigma, xh[0]);
        double fl = gas_flux(cp_, eps_sigma, xl[0]);
        double q_w = 0;
        q_w += fp * e->surf_area[EN_PISTON];
        q_w += fh * e->surf_area[EN_HEAD];
        q_w += fl * cp_->liner_area;
        double qbp, qbh, qbl; /* back-side fluxes [W/m^2] */
        if (q_wall) {         /* frozen walls: their back sides only */
            double *qw = q_wall + i * EN_NSURF;
            qw[EN_PISTON] = fp;
            qw[EN_HEAD] = fh;
            qw[EN_LINER] = fl * cp_->liner_share;
            qbp = g_back[EN_PISTON] * (xp[EN_WALL_NODES - 1] - T_oil);
            qbh = g_back[EN_HEAD] * (xh[EN_WALL_NODES - 1] - T_cool);
            qbl = g_back[EN_LINER] * (xl[EN_WALL_NODES - 1] - T_cool);
        } else {
            double *dw = xdot + e->off_wall + ow;
            en_wall_rates(&e->wall[EN_PISTON], xp, fp, T_oil, dw, &qbp);
            en_wall_rates(&e->wall[EN_HEAD], xh, fh, T_cool, dw + EN_WALL_NODES, &qbh);
            en_wall_rates(&e->wall[EN_LINER], xl, fl * cp_->liner_share, T_cool,
                          dw + 2 * EN_WALL_NODES, &qbl);
        }
        q_oil += qbp * e->surf_area[EN_PISTON];
        q_cool += qbh * e->surf_area[EN_HEAD];
        q_cool += qbl * e->surf_area[EN_LINER];
        /* first law */
        double dE = cp_->q_comb - q_w - cp_->pdv + cp_->hi - cp_->he;
        en_gas_state gs = {.u = cp_->u, .cv = cp_->cv, .dudF = cp_->dudF};
        xdot[e->off_cyl + i * EN_CYL_NX + CX_T] = en_gas_dTdt_s(&gs, cp_->m, dE, cp_->dm, cp_->dF);
        led_wall += q_w;
    }
    if (out) out->piston_surface_temp = x[e->off_wall + EN_PISTON * EN_WALL_NODES];
    xdot[e->off_ledger + LX_WALL] = led_wall;
    /* coolant and oil: each thermostat opens over /engine/thermostat_band
     * centred on its set point */
    const double band = c->thermostat_band, half = 0.5 * band;
    double open_c = en_atmost(en_atleast((T_cool - c->coolant_temp + half) / band, 0.0), 1.0);
    double open_o = en_atmost(en_atleast((T_oil - c->oil_temp + half) / band, 0.0), 1.0);
    xdot[e->off_coolant] = (q_cool - open_c * c->coolant_ua * (T_cool - in->T_amb)) /
                           (c->coolant_capacity * e->thermal_scale);
    xdot[e->off_coolant + 1] = (q_oil - open_o * c->oil_ua * (T_oil - in->T_amb)) /
                               (c->oil_capacity * e->thermal_scale);
    /* crankshaft */
    xdot[TS_ENGINE_X_SPEED] =
        in->hold_speed ? 0.0 : (pc->t_brake - in->load_torque - 0.5 * pc->dJ * w * w) / pc->J;
}

int en_crank_eval_part(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                       double *xdot, ts_engine_outputs *out, double *q_wall, en_crank_part *pc)
{
    en_crank_part local;
    if (!pc) pc = &local;
    if (gas_part(e, x, in, xdot, out, pc)) return 1;
    wall_part(e, x, in, pc, xdot, out, q_wall);
    return 0;
}

/* "what value unit (must be bound)", or "what is not a number"; returns 1. */
static int domain_fault(char *out, size_t n, const char *what, double value, const char *unit,
                        const char *bound)
{
    if (isnan(value))
        snprintf(out, n, "%s is not a number", what);
    else
        snprintf(out, n, "%s %.4g %s (must be %s)", what, value, unit, bound);
    return 1;
}

int en_domain_fault(const ts_engine *e, const double *x, char *out, size_t n)
{
    static const char *const vol[] = {"intercooler", "intake manifold", "exhaust manifold"};
    static const int mass[] = {BX_ICM, BX_IMM, BX_EMM}, temp[] = {BX_ICT, BX_IMT, BX_EMT};
    char what[64], tmin[32], trange[48];
    snprintf(tmin, sizeof tmin, "> %g K", EN_T_DOMAIN_MIN);
    snprintf(trange, sizeof trange, "%g-%g K", EN_T_DOMAIN_MIN, EN_T_DOMAIN_MAX);
    if (n) out[0] = '\0';
    for (int b = 0; e->off_bank >= 0 && b < EN_NBANK; b++) {
        const double *xb = x + e->off_bank + b * EN_BANK_NX;
        for (int k = 0; k < 3; k++) {
            snprintf(what, sizeof what, "bank %d %s gas mass", b + 1, vol[k]);
            if (!(xb[mass[k]] > 0)) return domain_fault(out, n, what, xb[mass[k]], "kg", "> 0");
            snprintf(what, sizeof what, "bank %d %s temperature", b + 1, vol[k]);
            if (!(xb[temp[k]] > EN_T_DOMAIN_MIN))
                return domain_fault(out, n, what, xb[temp[k]], "K", tmin);
        }
    }
    for (int i = 0; e->off_cyl >= 0 && i < EN_NCYL; i++) {
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        snprintf(what, sizeof what, "cylinder %d gas mass", i + 1);
        if (!(xc[CX_M] > 0)) return domain_fault(out, n, what, xc[CX_M], "kg", "> 0");
        snprintf(what, sizeof what, "cylinder %d temperature", i + 1);
        if (!(xc[CX_T] > EN_T_DOMAIN_MIN && xc[CX_T] < EN_T_DOMAIN_MAX))
            return domain_fault(out, n, what, xc[CX_T], "K", trange);
    }
    for (int i = 0; i < e->nx; i++)
        if (!isfinite(x[i])) return snprintf(out, n, "state %d is not finite", i), 1;
    return 0;
}

int en_crank_eval(const ts_engine *e, const double *x, const ts_engine_inputs *in, double *xdot,
                  ts_engine_outputs *out, double *q_wall)
{
    return en_crank_eval_part(e, x, in, xdot, out, q_wall, NULL);
}

void en_crank_refresh(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                      const en_crank_part *pc, double *xdot, double *q_wall)
{
    wall_part(e, x, in, pc, xdot, NULL, q_wall);
}

double en_crank_valve_lift(const ts_engine *e, int v, int i, double th)
{
    const ts_engine_config *c = &e->c;
    double th_w = wrap(th);
    int nw;
    double thl = local_angle(e, i, th_w, &nw);
    double k = e->valve_k[v];
    return v ? valve_lift(e, 1, i, thl, nw, c->evo, c->evc, c->exhaust_max_lift, cos(k * th_w),
                          sin(k * th_w))
             : valve_lift(e, 0, i, thl, nw, c->ivo, c->ivc, c->intake_max_lift, cos(k * th_w),
                          sin(k * th_w));
}

double en_crank_next_switch(const ts_engine *e, const double *x, const double *xdot,
                            double *ign)
{
    const ts_engine_config *c = &e->c;
    double th = wrap(x[TS_ENGINE_X_ANGLE]), w = en_atleast(x[TS_ENGINE_X_SPEED], 1.0);
    /* local angles where the clocks' right-hand sides switch */
    const double sw[4] = {wrap(EN_CYCLE - c->soi), wrap(LW_WINDOW - c->soi), RESET_START,
                          RESET_END};
    double d_known = INFINITY, d_ign = INFINITY;
    for (int i = 0; i < EN_NCYL; i++) {
        double thl = th - e->cyl_offset[i];
        if (thl < 0) thl += EN_CYCLE;
        for (int k = 0; k < 4; k++) {
            double d = sw[k] - thl;
            if (d <= 1e-9) d += EN_CYCLE;
            if (d < d_known) d_known = d;
        }
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        double dI = xdot[e->off_cyl + i * EN_CYL_NX + CX_IGN];
        if (xc[CX_IGN] < 1.0 && dI > 0) {
            double d = (1.0 - xc[CX_IGN]) / dI * w;
            if (d < d_ign) d_ign = d;
        }
    }
    *ign = d_ign;
    return d_known;
}
