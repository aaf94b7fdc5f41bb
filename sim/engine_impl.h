/*
 * engine_impl.h — internals shared by the engine's source files (engine*.c).
 * NOT public API: callers use engine.h. One concept per file:
 *   engine.c            model construction, state layout, dispatch, fixed-step
 *                       integration, cycle means and the steady-state search
 *   engine_gas.c        ideal-gas properties vs temperature and composition
 *   engine_cylinder.c   slider-crank kinematics by angle (the sin/cos form
 *                       and the valve lift and areas are inline below)
 *   engine_manifold.c   quasi-steady compressible orifice flow, control volumes
 *   engine_combustion.c ignition delay (Livengood-Wu) and Watson burning
 *   engine_heat.c       K-k energy cascade, Nusselt convection, radiation
 *   engine_wall.c       layered wall conduction (metal / zirconia)
 *   engine_turbo.c      compressor and turbine maps, rotor, intercooler
 *   engine_friction.c   Millington-Hartles friction (the crank-angle-varying
 *                       inertia is in engine_crank.c)
 *   engine_crank.c      the crank-angle fidelity's right-hand side
 *   engine_mean.c       the mean-value fidelity's right-hand side
 *   engine_map.c        the map fidelity's right-hand side
 */
#ifndef TS_ENGINE_IMPL_H
#define TS_ENGINE_IMPL_H

#include <math.h>

#include "constants.h"
#include "engine.h"
#include "fuel_actuator.h"

#define EN_PI    TS_PI
#define EN_NCYL          TS_ENGINE_NCYL
#define EN_NBANK 2
#define EN_CYCLE (4.0 * EN_PI)  /* crank angle of one four-stroke cycle [rad] */
#define EN_RPM   (30.0 / EN_PI) /* rpm per rad/s */
#define EN_T0    298.15         /* reference temperature of sensible enthalpy [K] */
#define EN_SIGMA 5.670374e-8    /* Stefan-Boltzmann [W/m^2/K^4] */
#define EN_FRICTION_FADE 5.0  /* friction torque x tanh(w / this) [rad/s]: smoothing at rest */

/* fmax(x, lo) and fmin(x, hi) for a bound lo, hi that is never NaN, inline
 * (libm's are calls; the right-hand sides take ~15 per evaluation): the same
 * value, x when it passes the bound, else the bound (also for NaN x). */
static inline double en_atleast(double x, double lo) { return x > lo ? x : lo; }
static inline double en_atmost(double x, double hi) { return x < hi ? x : hi; }

/* ---- gas (engine_gas.c) --------------------------------------------------- */
typedef struct en_gas {
    double cp_a[4], cp_b[4]; /* cp polynomials in t = T/1000 [J/kg/K] */
    double r_a, r_b;         /* gas constants [J/kg/K] */
    /* derived by en_gas_init (en_gas_eval only): cp and h - h(EN_T0) as
     * polynomials in T itself, air and burned gas */
    double cpT_a[4], cpT_b[4], hT_a[5], hT_b[5];
} en_gas;
/* Fill g from the cubic cp fits (in t = T/1000) and the gas constants. */
void en_gas_init(en_gas *g, const double *cp_air, const double *cp_burned, double r_air,
                 double r_burned);
/* F: burned-gas mass fraction in [0, 1]. h is sensible enthalpy from EN_T0;
 * u = h - R T (consistent with h = u + p v). */
double en_gas_r(const en_gas *g, double F);
double en_gas_cp(const en_gas *g, double T, double F);
double en_gas_h(const en_gas *g, double T, double F);
double en_gas_u(const en_gas *g, double T, double F);
/* The cp fits are used over [150, 3500] K (fitted over 300-2500 K): a
 * temperature outside is clamped for cp (h keeps its polynomial). */
#define EN_GAS_T_MIN 150.0
#define EN_GAS_T_MAX 3500.0
static inline double en_gas_clamp_T(double T)
{
    return T < EN_GAS_T_MIN ? EN_GAS_T_MIN : T > EN_GAS_T_MAX ? EN_GAS_T_MAX : T;
}
/* A burned-gas mass fraction held in [0, 1]. */
static inline double en_gas_clamp_F(double F)
{
    return F < 0 ? 0 : F > 1 ? 1 : F;
}
/* Fresh air's sensible enthalpy h [J/kg] and cp [J/kg/K] at T: the air half
 * of en_gas_eval (which calls it), alone for the compressor's outlet, solved
 * for on every right-hand side. */
static inline void en_air_eval(const en_gas *g, double T, double *h, double *cp)
{
    double Tc = en_gas_clamp_T(T);
    const double *a = g->cpT_a, *ha = g->hT_a;
    *cp = a[0] + Tc * (a[1] + Tc * (a[2] + Tc * a[3]));
    *h = ha[0] + T * (ha[1] + T * (ha[2] + T * (ha[3] + T * ha[4])));
}
/* Every property of one mixture at (T, F) from a single evaluation of the
 * species polynomials (the right-hand side's hot path; same values as the
 * separate functions). */
typedef struct en_gas_state {
    double R, cp, h, u, cv; /* [J/kg/K], [J/kg] */
    double dudF;            /* u_burned - u_air at T [J/kg] */
} en_gas_state;
/* inline: 16 calls per crank-angle right-hand side evaluation */
static inline void en_gas_eval(const en_gas *g, double T, double F, en_gas_state *s)
{
    F = en_gas_clamp_F(F);
    double Tc = en_gas_clamp_T(T);
    const double *b = g->cpT_b, *hb_ = g->hT_b;
    double ha, cpa;
    en_air_eval(g, T, &ha, &cpa);
    double cpb = b[0] + Tc * (b[1] + Tc * (b[2] + Tc * b[3]));
    double hb = hb_[0] + T * (hb_[1] + T * (hb_[2] + T * (hb_[3] + T * hb_[4])));
    s->R = (1 - F) * g->r_a + F * g->r_b;
    s->cp = (1 - F) * cpa + F * cpb;
    s->h = (1 - F) * ha + F * hb;
    s->u = s->h - s->R * T;
    s->cv = s->cp - s->R;
    s->dudF = (hb - g->r_b * T) - (ha - g->r_a * T);
}
/* dT/dt of a control volume (m, T, F) from its energy rate dE/dt = d(m u)/dt,
 * mass rate and composition rate; s evaluated at (T, F). */
static inline double en_gas_dTdt_s(const en_gas_state *s, double m, double dEdt, double dmdt,
                                   double dFdt)
{
    return (dEdt - s->u * dmdt - m * s->dudF * dFdt) / (m * s->cv);
}

/* ---- orifice flow (engine_manifold.c) ------------------------------------- */
/* en_orifice: mass flow [kg/s] from side 1 to side 2 (negative: reverse)
 * through effective area cda, quasi-steady compressible (choked above the
 * critical ratio), linearised within 1 % of equal pressures. gamma from the
 * upstream side. Inline with its parts (every open valve of the crank-angle
 * right-hand side calls it). */
#define EN_LIN_RATIO 0.99 /* below 1 % pressure difference the flow is linearised */

/* Flow function Psi(pr) with pr = p_down / p_up <= 1:
 *   Psi^2 = 2 g/(g-1) (pr^(2/g) - pr^((g+1)/g)) = 2 g/(g-1) a (a - pr),  a = pr^(1/g),
 * clamped at the critical ratio pr_c = (2/(g+1))^(g/(g-1)). In terms of a,
 * Psi^2 ~ a^2 - a^(g+1) peaks where a^(g-1) = pr / a = 2/(g+1), so the flow is
 * choked exactly when (g+1) pr < 2 a (no logarithm of the critical ratio), and
 * there Psi_c = sqrt(2 g/(g+1)) a_c, a_c = (2/(g+1))^(1/(g-1)). One log and one
 * exp per unchoked call (same value to rounding as the textbook powers). */
static inline double en_psi(double pr, double g)
{
    double a = exp(log(pr) / g);
    if ((g + 1.0) * pr < 2.0 * a) /* past the critical ratio: choked */
        return sqrt(2.0 * g / (g + 1.0)) * exp(log(2.0 / (g + 1.0)) / (g - 1.0));
    double v = 2.0 * g / (g - 1.0) * a * (a - pr);
    return sqrt(v > 0 ? v : 0);
}

/* Forward flow through area cda = upstream factor pu / sqrt(Ru Tu) x cda x
 * the ratio factor of pr = pd / pu (psi, or its linearisation near 1). The
 * ratio factor depends on (pr, gu) alone: en_ratio_of computes it once,
 * en_flow_area applies it to one area (en_orifice_pair: two orifices, one psi). */
typedef struct en_flow_ratio {
    double pr, psi; /* psi(pr, gu), or psi(EN_LIN_RATIO, gu) when linearised */
    int lin;        /* pr > EN_LIN_RATIO */
} en_flow_ratio;

static inline en_flow_ratio en_ratio_of(double pu, double gu, double pd)
{
    en_flow_ratio r;
    r.pr = pd / pu;
    r.lin = r.pr > EN_LIN_RATIO; /* linear through zero: no infinite slope at equal pressures */
    r.psi = en_psi(r.lin ? EN_LIN_RATIO : r.pr, gu);
    return r;
}

static inline double en_flow_area(const en_flow_ratio *r, double cda, double pu, double sRT)
{
    double base = cda * pu / sRT;
    if (r->lin) return base * r->psi * (1.0 - r->pr) / (1.0 - EN_LIN_RATIO);
    return base * r->psi;
}

static inline double en_flow1(double cda, double pu, double Tu, double Ru, double gu, double pd)
{
    en_flow_ratio r = en_ratio_of(pu, gu, pd);
    return en_flow_area(&r, cda, pu, sqrt(Ru * Tu));
}

static inline double en_orifice(double cda, double p1, double T1, double R1, double g1, double p2,
                                double T2, double R2, double g2)
{
    if (cda <= 0) return 0.0;
    if (p1 >= p2) return en_flow1(cda, p1, T1, R1, g1, p2);
    return -en_flow1(cda, p2, T2, R2, g2, p1);
}

/* Two orifices between the same sides (areas cda_a, cda_b; downstream
 * temperatures T2a, T2b used only for reverse flow): *m_a, *m_b as en_orifice
 * gives each (bitwise), with one evaluation of the pressure-ratio function
 * for forward flow (the turbine nozzle and the wastegate bypass). */
void en_orifice_pair(double cda_a, double cda_b, double p1, double T1, double R1, double g1,
                     double p2, double T2, double R2, double g2, double *m_a, double *m_b);

/* ---- cylinder kinematics and valves (engine_cylinder.c) ------------------- */
typedef struct en_geom {
    double bore, stroke, crank, rod; /* [m]; crank = stroke / 2 */
    double area;                     /* piston (bore) area [m^2] */
    double vd, vc;                   /* displaced and clearance volume per cylinder [m^3] */
    double circ, clear_h;            /* bore circumference [m], clearance height vc / area [m] */
} en_geom;
typedef struct en_kin {
    double V, dVdth;           /* volume [m^3] and dV/dtheta [m^3/rad] */
    double xp, dxdth, d2xdth2; /* piston distance from TDC [m] and derivatives */
} en_kin;
void en_kinematics(const en_geom *g, double th, en_kin *k);
/* The same from sin(th), cos(th) (the caller rotates one sincos to every cylinder).
 * This and the valve functions below are inline: the crank-angle right-hand
 * side calls them 12 and 2 x 12 times per evaluation (issue 6 speed-up). */
static inline void en_kinematics_sc(const en_geom *g, double s, double c, en_kin *k)
{
    double a = g->crank, l = g->rod;
    double r = sqrt(l * l - a * a * s * s), ir = 1.0 / r; /* one division */
    k->xp = a + l - (a * c + r);
    k->dxdth = a * s + a * a * s * c * ir;
    k->d2xdth2 =
        a * c + a * a * (c * c - s * s) * ir + a * a * a * a * s * s * c * c * (ir * ir * ir);
    k->V = g->vc + g->area * k->xp;
    k->dVdth = g->area * k->dxdth;
}
/* Lift [m] of a valve open on [open, close] (rad CA, close may exceed 4 pi),
 * smooth sine-squared-like profile (1 - cos) / 2. th in [0, 4 pi). */
static inline double en_valve_lift(double th, double open, double close, double lmax)
{
    double span = close - open;
    double d = th - open;
    if (d < 0) d += 4.0 * EN_PI;
    if (d > span) return 0.0;
    return lmax * 0.5 * (1.0 - cos(2.0 * EN_PI * d / span));
}
/* Effective flow area = cd x min(curtain, throat x seat area) x n valves
 * (throat: /engine/valve_throat_factor). */
static inline double en_valve_area(double lift, double diameter, int n, double cd, double throat)
{
    double curtain = EN_PI * diameter * lift;
    double seat = throat * EN_PI / 4.0 * diameter * diameter;
    return cd * n * (curtain < seat ? curtain : seat);
}

/* ---- combustion (engine_combustion.c) ------------------------------------- */
typedef struct en_watson {
    double a, b, c, c1k, c1e, c2, c3k, c3e, c4k;
    double duration; /* [rad] */
} en_watson;
/* Ignition delay [s] at p [Pa], T [K] (Arrhenius): a [s] (p / 1 bar)^-n
 * exp(ta / T). */
double en_ignition_delay(double a, double n, double ta, double p, double T);
/* Watson burned fraction X and dX/dtau at tau in [0, 1]; tau_id [ms], N [rpm],
 * phi overall equivalence ratio. */
void en_watson_burn(const en_watson *w, double tau, double tau_id_ms, double n_rpm, double phi,
                    double *X, double *dXdtau);
/* The same in two parts, for evaluating several phi at one (tau, tau_id, N):
 * the phi-independent premixed part, then the phi-dependent rest. */
typedef struct en_watson_tau {
    double tau, ltau, id_c, f1, df1;
} en_watson_tau;
void en_watson_pre(const en_watson *w, double tau, double tau_id_ms, double n_rpm,
                   en_watson_tau *p);
void en_watson_phi(const en_watson *w, const en_watson_tau *p, double phi, double *X,
                   double *dXdtau);

/* ---- heat transfer (engine_heat.c) ---------------------------------------- */
typedef struct en_cascade_in {
    double m, V;          /* charge mass [kg], volume [m^3] */
    double bore, area;    /* bore [m] and piston (bore) area [m^2] */
    double mdot_in, v_in; /* inflow [kg/s] and its jet velocity [m/s] */
    double mdot_out;      /* outflow [kg/s] */
    double drho_rho;      /* (1/rho) drho/dt [1/s] */
    double K, k;          /* mean-flow and turbulent kinetic energy [J] */
} en_cascade_in;
/* Energy cascade: dK/dt, dk/dt; returns the length scale L_I and u' through
 * pointers. Convective coefficient [W/m^2/K]: Nu = a Re^b on length L with
 * velocity u. Inline (engine_heat.c describes them): twelve calls each per
 * crank-angle right-hand side evaluation. */
/* The Nusselt law's constants: Nu = a Re^b, mu = exp(log_mu) T^mu_exp, Pr. */
typedef struct en_htc_law {
    double a, b, log_mu, mu_exp, prandtl;
} en_htc_law;

static inline void en_cascade(const en_cascade_in *c, double cbeta, double rdt, double *dK,
                              double *dk, double *L, double *u_turb, double *U_mean)
{
    double m = c->m;
    double Lh = c->V / c->area;
    if (Lh > c->bore / 2) Lh = c->bore / 2;
    double K = c->K > 0.0 ? c->K : 0.0, k = c->k > 1e-9 ? c->k : 1e-9;
    double im = 1.0 / m, iL = 1.0 / Lh, skm = sqrt(k * im); /* sqrt(k / m) */
    double up = sqrt(2.0 / 3.0) * skm;                      /* sqrt(2 k / (3 m)) */
    double P = 0.3307 * cbeta * (K * iL) * skm; /* Poulos & Heywood's production constant */
    double eps = up * up * up * iL;
    double out_m = c->mdot_out * im;
    *dK = 0.5 * c->mdot_in * c->v_in * c->v_in - P - K * out_m;
    *dk = P - m * eps - k * out_m + rdt * (2.0 / 3.0) * k * c->drho_rho;
    *L = Lh;
    *u_turb = up;
    *U_mean = sqrt(2.0 * K * im);
}

static inline double en_htc(const en_htc_law *h, double rho, double u, double L, double T,
                            double cp)
{
    /* h = a Re^b lambda / L with lambda = mu cp / Pr, mu = c T^n:
     *   h = (a cp / (Pr L)) (rho u L)^b mu^(1 - b), one exp and two logs */
    double lmu = h->log_mu + h->mu_exp * log(T > 200.0 ? T : 200.0);
    return h->a * cp / (h->prandtl * L) * exp(h->b * log(rho * u * L) + (1.0 - h->b) * lmu);
}

/* ---- walls (engine_wall.c) ------------------------------------------------ */
#define EN_WALL_NODES 11 /* vertex-centred nodes through one wall, node 0 on the gas side */
enum { EN_PISTON, EN_HEAD, EN_LINER, EN_NSURF };
typedef struct en_wall {
    double cap[EN_WALL_NODES];   /* heat capacity per area [J/m^2/K] */
    double cond[EN_WALL_NODES];  /* conductance node i -> i+1 per area [W/m^2/K]; last: to sink */
    double depth[EN_WALL_NODES]; /* node depth below the gas-side surface [m] */
    int coated_nodes;            /* nodes within the coating (0 for all-metal) */
} en_wall;
void en_wall_build(en_wall *w, double coating, double k_coat, double rc_coat, double metal,
                   double k_metal, double rc_metal, double h_back);
/* dT/dt of the nodes given gas-side heat flux q [W/m^2] and sink temperature. */
void en_wall_rates(const en_wall *w, const double *T, double q, double T_sink, double *dT,
                   double *q_back);

/* ---- turbocharger and intercooler (engine_turbo.c) ------------------------ */
typedef struct en_turbo {
    double d_c, d_t; /* scaled wheel diameters [m] */
    double psi0, phi_ch, eta_max, phi_opt, phi_w, eta_min;
    double mach_opt, mach_w;    /* tip-Mach efficiency fall-off */
    double a_t, eta_t, bsr_opt; /* turbine effective area [m^2], efficiency, u/c_s */
    double inertia, mech_eff;
    double r_air; /* gas constant of the compressor's air [J/kg/K] */
} en_turbo;
typedef struct en_comp_out {
    double mdot, T_out, power, eta;
    double h_out, cp_out; /* outlet air's sensible enthalpy [J/kg] and cp [J/kg/K] */
} en_comp_out;
typedef struct en_turb_out {
    double mdot, power, eta;
} en_turb_out;
/* Compressor from p01, T01 to p02 at rotor speed w [rad/s]; g gives the
 * outlet's air enthalpy (h(T_out) - h(T01) = power / mdot). */
void en_compressor(const en_turbo *t, const en_gas *g, double w, double p01, double T01, double p02,
                   en_comp_out *o);
/* Turbine of effective nozzle area a_t [m^2] from p03, T03 (gas R, cp) to
 * p4 at rotor speed w. */
void en_turbine(const en_turbo *t, double a_t, double w, double p03, double T03, double R,
                double cp, double p4, en_turb_out *o);
/* en_turbine given its nozzle flow mdot [kg/s] (en_orifice at a_t, the same
 * sides; en_exhaust_outflow computes it with the wastegate's). */
void en_turbine_flow(const en_turbo *t, double mdot, double w, double p03, double T03, double R,
                     double cp, double p4, en_turb_out *o);
/* Turbine geometry at crank speed omega [rad/s] from the open-loop schedule
 * (/engine/turb_sched_*, linear, held beyond the ends): nozzle effective
 * area [m^2] (turbo.a_t x turb_sched_nozzle), factor on the wastegate
 * actuator's opening, open-loop bypass area [m^2]. No schedule: turbo.a_t,
 * 1, 0. */
typedef struct en_turb_geometry {
    double a_t, gate, bypass;
} en_turb_geometry;
en_turb_geometry en_turb_schedule(const ts_engine *e, double omega);
/* Intercooler heat removal [W]: effectiveness form, eps = 1 - exp(-UA/(m cp)). */
double en_intercooler_heat(double ua, double mdot, double cp, double T_in, double T_wall);

/* ---- friction and inertia (engine_friction.c) ----------------------------- */
/* Millington-Hartles friction mean effective pressure [Pa] at omega [rad/s]. */
double en_fmep(const ts_engine_config *c, double omega);
/* Friction torque of the whole engine [N*m] at omega (every fidelity). */
double en_friction_torque(const ts_engine *e, double omega);

/* ---- the model ------------------------------------------------------------ */
/* Offsets of the state vector. Per cylinder (EN_CYL_NX): */
enum { CX_M, CX_T, CX_MB, CX_IGN, CX_BURN, CX_KMEAN, CX_KTURB, EN_CYL_NX };
/* Per bank (EN_BANK_NX): intercooler (m, T, F), intake (m, T, F), exhaust (m, T, F), rotor. */
enum { BX_ICM, BX_ICT, BX_ICF, BX_IMM, BX_IMT, BX_IMF, BX_EMM, BX_EMT, BX_EMF, BX_TC, EN_BANK_NX };
/* Ledger (cumulative integrals), order of ts_engine_ledger's first fields. */
enum { LX_FUEL_E, LX_WORK, LX_WALL, LX_HIN, LX_HOUT, LX_MIN, LX_MOUT, LX_MFUEL, EN_LEDGER_NX };
/* crank_angle: states before the walls (off_wall) and wall nodes: compile-time
 * sizes of the stepper's vector loops (constant trip counts vectorise) */
#define EN_CRANK_NGAS (2 + EN_NBANK * EN_BANK_NX + EN_LEDGER_NX + 2 + EN_NCYL * EN_CYL_NX)
#define EN_CRANK_NWALLX (EN_NCYL * EN_NSURF * EN_WALL_NODES)

struct ts_engine {
    ts_engine_config c; /* copy of the section */
    /* fidelity and variant: c.fidelity, c.variant */
    int nx; /* length of the state vector */
    int off_bank, off_ledger, off_cyl, off_wall, off_coolant, off_lag; /* -1 when absent */
    en_gas gas;
    en_htc_law htc; /* the in-cylinder Nusselt law (en_htc) */
    en_geom geom;
    en_watson watson;
    en_turbo turbo;
    ts_fuel_law fuel;
    en_wall wall[EN_NSURF];
    double surf_area[EN_NSURF]; /* piston and head areas; liner area at full stroke [m^2] */
    double cyl_offset[EN_NCYL]; /* firing offset of each cylinder [rad] */
    double cyl_sin[EN_NCYL], cyl_cos[EN_NCYL]; /* sin, cos of the offsets */
    /* valve phases for the lift's cosine by rotation (engine_crank.c): intake
     * (0) and exhaust (1), k = 2 pi / (close - open), phase = k (offset + open
     * - 4 pi n) for n = 0, 1, 2 wraps of the local angle; cos and sin */
    double valve_k[2], valve_cos[2][EN_NCYL][3], valve_sin[2][EN_NCYL][3];
    int cyl_bank[EN_NCYL];
    /* crank_angle: the error-controlled stepper's scale of each non-wall state
     * (ts_engine_atol at 1; the ledger's infinite: not controlled), built once */
    double bs_scale[EN_CRANK_NGAS];
    double mean_inertia;        /* crankshaft + cycle mean of the reciprocating parts' [kg*m^2] */
    double turbo_inertia_scale; /* 1, shrunk by ts_engine_steady (rotor inertia, map boost lag) */
    double thermal_scale;       /* 1, shrunk by ts_engine_steady (coolant, oil capacities) */
};

/* The variant's map tables (/engine/map_*_<variant>, /engine/pb_*_<variant>). */
static inline const ts_engine_map_table *en_map_table(const ts_engine *e)
{
    return &e->c.map[e->c.variant];
}

/* Piecewise-linear interpolation in the map tables (one value per
 * /engine/map_speed), clamped at the ends: en_map_at locates omega once,
 * en_lin_eval reads any table there (the right-hand sides read three or four
 * tables at one speed). */
typedef struct en_lin {
    int i0, i1; /* bracketing nodes (equal when clamped) */
    double f;   /* weight of i1 */
} en_lin;
/* Index i in [0, n - 2] of the interval [xs[i], xs[i + 1]] that holds x
 * (xs increasing, n >= 2; the end intervals below and above the table). */
int en_bracket(const double *xs, int n, double x);
/* Linear weights of x in the increasing abscissae xs[0..n), clamped at the ends. */
en_lin en_lin_at(const double *xs, int n, double x);
static inline en_lin en_map_at(const ts_engine *e, double omega)
{
    return en_lin_at(e->c.map_speed, e->c.map_speed_n, omega);
}
static inline double en_lin_eval(const en_lin *l, const double *y)
{
    return y[l->i0] + l->f * (y[l->i1] - y[l->i0]);
}

/* Bilinear interpolation in the part-boost tables (/engine/pb_*: row-major
 * spool_speed x spool_ratio), clamped at the edges (engine_mean.c): en_pb_at
 * locates (omega, ratio) once, en_bilin_eval reads any table there;
 * en_pb_interp does both. */
typedef struct en_bilin {
    int row0, row1, j; /* offsets of the bracketing speed rows, ratio node */
    double fw, fr;     /* weights of row1 and of node j + 1 */
} en_bilin;
en_bilin en_pb_at(const ts_engine *e, double omega, double ratio);
static inline double en_bilin_eval(const en_bilin *w, const double *y)
{
    const double *r0 = y + w->row0, *r1 = y + w->row1;
    int j = w->j;
    double a = r0[j] + w->fr * (r0[j + 1] - r0[j]);
    double b = r1[j] + w->fr * (r1[j + 1] - r1[j]);
    return a + w->fw * (b - a);
}
double en_pb_interp(const ts_engine *e, const double *y, double omega, double ratio);

/* The map fidelity's boost time constant at crank speed omega [s]
 * (/engine/spool_lag vs spool_speed, linear, clamped; engine_map.c). */
double en_spool_lag(const ts_engine *e, double omega);
/* Fuel per cylinder and cycle [kg]: in->fuel_per_cycle when >= 0, else the
 * fuel law (Eqs. 13-14) on the compressors' air flow [kg/s] (crank and mean). */
double en_fuel_command(const ts_engine *e, const ts_engine_inputs *in, double air_flow,
                       double omega);

TS_MUST_CHECK int en_crank_rhs(const ts_engine *e, double t, const double *x,
                               const ts_engine_inputs *in, double *xdot, ts_engine_outputs *out);
/* The crank-angle right-hand side with the walls FROZEN (multirate stepping,
 * engine.c): the wall nodes' derivatives are NOT written and q_wall receives
 * the gas-side heat flux into each wall [W/m^2 of the wall's full area]
 * (EN_NCYL x EN_NSURF, layout of the wall states); the coolant and oil see the
 * frozen walls' back-side heat. With q_wall NULL this is en_crank_rhs. */
TS_MUST_CHECK int en_crank_eval(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                                double *xdot, ts_engine_outputs *out, double *q_wall);
/* Gas temperatures en_crank_eval runs between [K] (its domain guards; outside
 * them the gas-property fits and the heat transfer mean nothing). */
#define EN_T_DOMAIN_MIN 100.0
#define EN_T_DOMAIN_MAX 5000.0
/* Which of en_crank_eval's domain guards state x fails (a manifold's or
 * intercooler's mass <= 0 or temperature <= 100 K, a cylinder's mass <= 0 or
 * temperature outside 100-5000 K) or which state is not finite, in words into
 * out (n bytes, terminated); 0 if x is inside the domain (out then ""). Any
 * fidelity: the volumes are checked where the engine has them (crank-angle,
 * mean-value), the cylinders where it has them (crank-angle). */
int en_domain_fault(const ts_engine *e, const double *x, char *out, size_t n);
/* What the wall heat fluxes, the cylinders' dT/dt and the crankshaft need from
 * the rest of the evaluation (engine_crank.c splits it in two). */
typedef struct en_cyl_part {
    double T, h, T4;                /* gas temperature [K], coefficient [W/m^2/K], T^4 if burning */
    double liner_area, liner_share; /* exposed liner [m^2] and its share of the full liner */
    double m, dm, dF, u, cv, dudF;  /* mass, rates and gas properties of en_gas_dTdt_s */
    double q_comb, pdv, hi, he;     /* energy rates but the wall heat [W] */
    int burning;
} en_cyl_part;
typedef struct en_crank_part {
    en_cyl_part cyl[EN_NCYL];
    double t_brake, J, dJ; /* brake torque [N*m], inertia with the load's [kg*m^2], dJ/dth */
} en_crank_part;
/* en_crank_eval that also returns the wall- and load-independent part in pc
 * (may be NULL). */
TS_MUST_CHECK int en_crank_eval_part(const ts_engine *e, const double *x,
                                     const ts_engine_inputs *in, double *xdot,
                                     ts_engine_outputs *out, double *q_wall, en_crank_part *pc);
/* Re-evaluate only what depends on the wall temperatures and the load torque
 * (dT/dt of the cylinders, the wall ledger, coolant, oil, crank speed, q_wall)
 * in an xdot computed by en_crank_eval_part at the same non-wall states and
 * the same inputs but load_torque: the result equals a full en_crank_eval at
 * (x, in) exactly (the same operations on the same values). */
void en_crank_refresh(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                      const en_crank_part *pc, double *xdot, double *q_wall);
/* Crank angle [rad] from x to the next angle where a cylinder's ignition or
 * burn clock switches its right-hand side (start and end of the injection
 * window, start and end of the re-arm window); *ign: estimated angle to the
 * next ignition (Livengood-Wu integral reaching 1, from xdot). For the
 * error-controlled stepper, which ends steps on these switches. */
double en_crank_next_switch(const ts_engine *e, const double *x, const double *xdot, double *ign);
/* Lift [m] of valve v (0 intake, 1 exhaust) of cylinder i at crank angle th
 * [rad] as the crank-angle right-hand side evaluates it (by rotation of the
 * precomputed valve phases); equals en_valve_lift at the cylinder's local
 * angle to rounding (tests/sim/test_engine_stepper.c). */
double en_crank_valve_lift(const ts_engine *e, int v, int i, double th);
/* Advance every wall stack over h [s] with the gas-side flux q (EN_NCYL x
 * EN_NSURF, as from en_crank_eval) held and the sinks at the coolant and oil
 * temperatures in x: Crank-Nicolson (A-stable, second order; the conduction
 * equations are linear). */
void en_walls_step(const ts_engine *e, double *x, const double *q, double h);
/* Crank-angle states at rest gas (p, T) in every cylinder, walls, coolant and oil. */
void en_crank_init(const ts_engine *e, double p, double T, double *x);
TS_MUST_CHECK int en_mean_rhs(const ts_engine *e, double t, const double *x,
                              const ts_engine_inputs *in, double *xdot, ts_engine_outputs *out);
TS_MUST_CHECK int en_map_rhs(const ts_engine *e, double t, const double *x,
                             const ts_engine_inputs *in, double *xdot, ts_engine_outputs *out);
/* Bank states shared by crank and mean: derivative of the manifolds and rotor
 * given the cylinders' flows into/out of the bank. */
typedef struct en_bank_flows {
    double m_in, h_in,
        mf_in; /* cylinders <- intake manifold: mass [kg/s], enthalpy [W], burned [kg/s] */
    double m_ex, h_ex, mf_ex; /* cylinders -> exhaust manifold */
    double omega;             /* crank speed [rad/s] (the turbine's vane schedule) */
    int have_co;              /* co holds the compressor at this state (else computed) */
    en_comp_out co;
    int have_gas; /* s_im, s_em hold the manifolds' gas at this state and the
                     en_bank_rhs o argument its en_bank_read (else computed) */
    en_gas_state s_im, s_em;
} en_bank_flows;
typedef struct en_bank_out {
    double p_ic, T_ic, F_ic; /* intercooler volume (compressor outlet) */
    double p_im, T_im, F_im, p_em, T_em, F_em, air_flow, turbo_speed;
} en_bank_out;
/* The bank-level channels of out (boost, intake and exhaust temperature: bank
 * means; air flow: sum; turbo speed: mean) from both banks' en_bank_out. */
void en_bank_outputs(const en_bank_out *bo, ts_engine_outputs *out);
/* Read the bank's intercooler and manifold states (p, T, F) without derivatives. */
void en_bank_read(const ts_engine *e, const double *xb, en_bank_out *o);
/* Open fraction of the wastegate [0, 1] at intake manifold pressure p_boost [Pa]. */
double en_wastegate_open(const ts_engine_config *c, double p_boost);
/* Outflows of the exhaust manifold at the bank state o (gas state s_em) and
 * crank speed omega: the turbine's (flow, power) and the wastegate bypass
 * flow m_wg >= 0 [kg/s]. */
void en_exhaust_outflow(const ts_engine *e, double omega, double w_tc, const en_bank_out *o,
                        const en_gas_state *s_em, double p_amb, double T_amb, en_turb_out *to,
                        double *m_wg);
void en_bank_rhs(const ts_engine *e, const double *xb, const en_bank_flows *f, double p_amb,
                 double T_amb, double *xbdot, en_bank_out *o);

#endif
