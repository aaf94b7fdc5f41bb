/*
 * engine.c — the virtual V-12 diesel's model object (engine.h): construction
 * from the /engine section, state layout per fidelity, dispatch of the
 * right-hand side, a fixed-step RK4 integrator for callers that do not
 * integrate the engine themselves, per-cycle means and the dynamometer
 * steady-state search used by `tanksim engine-map` (paper Section III.B.3).
 *
 * State layout (offsets in struct ts_engine):
 *   x[0] crank speed, x[1] crank angle (all fidelities)
 *   map:         x[2] boost-lag state z in [0, 1]
 *   mean_value:  2 banks x EN_BANK_NX, ledger
 *   crank_angle: 2 banks x EN_BANK_NX, ledger, coolant and oil temperature,
 *                12 cylinders x EN_CYL_NX, 12 x 3 walls x EN_WALL_NODES
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_impl.h"

static ts_rc check_tables(const ts_engine_config *c, int v, ts_err *err)
{
    const ts_engine_map_table *t = &c->map[v];
    int n = c->map_speed_n;
    if (n < 2)
        return ts_err_set(err, TS_ERR_PARAM, "/engine/map_speed",
                          "/engine/map_speed: at least 2 speeds needed, got %d", n);
    for (int i = 1; i < n; i++)
        if (!(c->map_speed[i] > c->map_speed[i - 1]))
            return ts_err_set(err, TS_ERR_PARAM, "/engine/map_speed",
                              "/engine/map_speed: speeds must increase (index %d)", i);
    const int counts[] = {t->torque_n, t->boost_n, t->fuel_n, t->eta_v_n, t->eta_i_n, t->q_wall_n};
    static const char *const names[] = {"torque", "boost", "fuel", "eta_v", "eta_i", "q_wall"};
    for (int k = 0; k < 6; k++)
        if (counts[k] != n) {
            char ptr[64];
            snprintf(ptr, sizeof ptr, "/engine/map_%s_%s", names[k], ts_engine_variant_names[v]);
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: %d values expected (one per map_speed), got %d",
                              ptr, n, counts[k]);
        }
    return TS_OK;
}

ts_engine *ts_engine_make(const ts_config *cfg, ts_err *err)
{
    ts_err_clear(err);
    const ts_engine_config *c = &cfg->engine;
    if (check_tables(c, c->variant, err) != TS_OK) return NULL;
    if (c->cp_air_n != 4 || c->cp_burned_n != 4) {
        ts_err_set(err, TS_ERR_PARAM, "/engine/cp_air", "/engine/cp_air, cp_burned: 4 coefficients each");
        return NULL;
    }
    if (c->rod_length <= c->stroke / 2) {
        ts_err_set(err, TS_ERR_PARAM, "/engine/rod_length",
                   "/engine/rod_length: must exceed the crank radius (stroke / 2)");
        return NULL;
    }
    ts_engine *e = calloc(1, sizeof *e);
    if (!e) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    e->c = *c;
    e->fidelity = c->fidelity;
    e->variant = c->variant;
    e->fuel = ts_fuel_law_from_config(c);
    memcpy(e->gas.cp_a, c->cp_air, sizeof e->gas.cp_a);
    memcpy(e->gas.cp_b, c->cp_burned, sizeof e->gas.cp_b);
    e->gas.r_a = c->r_air;
    e->gas.r_b = c->r_burned;
    en_geom *g = &e->geom;
    g->bore = c->bore;
    g->stroke = c->stroke;
    g->crank = c->stroke / 2;
    g->rod = c->rod_length;
    g->area = EN_PI / 4 * c->bore * c->bore;
    g->vd = g->area * c->stroke;
    g->vc = g->vd / (c->compression_ratio - 1);
    e->watson = (en_watson){c->watson_a,  c->watson_b,  c->watson_c,  c->watson_c1k, c->watson_c1e,
                            c->watson_c2, c->watson_c3k, c->watson_c3e, c->watson_c4k,
                            c->burn_duration};
    /* Turbocharger scaled from the reference unit by geometric similarity
     * (parameters.md 3.6, Watson & Janota 1982): flow x s, diameter x sqrt(s)
     * (so speed x 1/sqrt(s) at equal tip speed), inertia x s^(5/2). */
    double s = c->turbo_flow_scale;
    e->turbo = (en_turbo){.d_c = c->comp_diameter_ref * sqrt(s),
                          .d_t = c->turb_diameter_ref * sqrt(s),
                          .psi0 = c->comp_psi0,
                          .phi_ch = c->comp_phi_choke,
                          .eta_max = c->comp_eta_max,
                          .phi_opt = c->comp_phi_opt,
                          .phi_w = c->comp_phi_width,
                          .eta_min = c->comp_eta_min,
                          .a_t = c->turb_area_ref * s,
                          .eta_t = c->turb_eta_max,
                          .bsr_opt = c->turb_bsr_opt,
                          .inertia = c->turbo_inertia_ref * pow(s, 2.5),
                          .mech_eff = c->turbo_mech_eff};
    /* Walls: coating per variant on the combustion-chamber surfaces (Section
     * III.B.3): piston and head, and the liner unless /engine/coat_liner is off. */
    double coat = c->variant == TS_ENGINE_LHR05 ? c->coating_lhr05
                : c->variant == TS_ENGINE_LHR10 ? c->coating_lhr10 : 0.0;
    en_wall_build(&e->wall[EN_PISTON], coat, c->zirconia_k, c->zirconia_rho_c, c->piston_thickness,
                  c->metal_k, c->metal_rho_c, c->h_oil);
    en_wall_build(&e->wall[EN_HEAD], coat, c->zirconia_k, c->zirconia_rho_c, c->head_thickness,
                  c->metal_k, c->metal_rho_c, c->h_coolant);
    en_wall_build(&e->wall[EN_LINER], c->coat_liner ? coat : 0.0, c->zirconia_k, c->zirconia_rho_c, c->liner_thickness,
                  c->metal_k, c->metal_rho_c, c->h_coolant);
    e->surf_area[EN_PISTON] = g->area * c->piston_area_factor;
    e->surf_area[EN_HEAD] = g->area * c->head_area_factor;
    e->surf_area[EN_LINER] = EN_PI * c->bore * c->stroke;
    /* Even 60-degree firing: the k-th cylinder of the firing order fires
     * k x 60 deg after cylinder 1; banks alternate (1L-6R-5L-2R-...). */
    for (int i = 0; i < EN_NCYL; i++) {
        e->cyl_offset[i] = i * EN_CYCLE / EN_NCYL;
        e->cyl_bank[i] = i % 2;
    }
    e->map_n = c->map_speed_n;
    const ts_engine_map_table *t = &c->map[c->variant];
    memcpy(e->map_tq, t->torque, sizeof e->map_tq);
    memcpy(e->map_boost, t->boost, sizeof e->map_boost);
    memcpy(e->map_fuel, t->fuel, sizeof e->map_fuel);
    memcpy(e->map_eta_v, t->eta_v, sizeof e->map_eta_v);
    memcpy(e->map_eta_i, t->eta_i, sizeof e->map_eta_i);
    memcpy(e->map_q_wall, t->q_wall, sizeof e->map_q_wall);
    e->turbo_inertia_scale = 1.0;
    e->thermal_scale = 1.0;
    e->speed_step = 5e-4;
    e->off_bank = e->off_ledger = e->off_cyl = e->off_wall = e->off_coolant = e->off_lag = -1;
    int n = 2;
    switch (e->fidelity) {
    case TS_ENGINE_MAP: e->off_lag = n++; break;
    case TS_ENGINE_MEAN_VALUE:
        e->off_bank = n;
        n += EN_NBANK * EN_BANK_NX;
        e->off_ledger = n;
        n += EN_LEDGER_NX;
        break;
    default:
        e->off_bank = n;
        n += EN_NBANK * EN_BANK_NX;
        e->off_ledger = n;
        n += EN_LEDGER_NX;
        e->off_coolant = n;
        n += 2;
        e->off_cyl = n;
        n += EN_NCYL * EN_CYL_NX;
        e->off_wall = n;
        n += EN_NCYL * EN_NSURF * EN_WALL_NODES;
        break;
    }
    e->nx = n;
    return e;
}

void ts_engine_free(ts_engine *e) { free(e); }
int ts_engine_get_fidelity(const ts_engine *e) { return e->fidelity; }
int ts_engine_nstate(const ts_engine *e) { return e->nx; }

double en_map_interp(const ts_engine *e, const double *y, double omega)
{
    const double *xs = e->c.map_speed;
    int n = e->map_n;
    if (omega <= xs[0]) return y[0];
    if (omega >= xs[n - 1]) return y[n - 1];
    int i = 0;
    while (i < n - 2 && omega > xs[i + 1]) i++;
    double f = (omega - xs[i]) / (xs[i + 1] - xs[i]);
    return y[i] + f * (y[i + 1] - y[i]);
}

double en_fuel_command(const ts_engine *e, const ts_engine_inputs *in, double air_flow,
                       double omega)
{
    if (in->fuel_per_cycle >= 0) return in->fuel_per_cycle;
    return ts_fuel_per_cycle(&e->fuel, air_flow, omega, in->rack); /* Eqs. 13-14 */
}

void ts_engine_init_state(const ts_engine *e, double omega, double p_amb, double T_amb, double *x)
{
    memset(x, 0, sizeof(double) * (size_t)e->nx);
    x[TS_ENGINE_X_SPEED] = omega;
    x[TS_ENGINE_X_ANGLE] = 0.0;
    if (e->fidelity == TS_ENGINE_MAP) {
        x[e->off_lag] = 0.0;
        return;
    }
    for (int b = 0; b < EN_NBANK; b++) {
        double *xb = x + e->off_bank + b * EN_BANK_NX;
        double R = e->gas.r_a;
        xb[BX_ICT] = T_amb;
        xb[BX_ICM] = p_amb * e->c.ic_volume / (R * T_amb);
        xb[BX_IMT] = T_amb;
        xb[BX_IMM] = p_amb * e->c.intake_volume / (R * T_amb);
        xb[BX_IMF] = 0.0;
        xb[BX_EMT] = 600.0; /* warm exhaust manifold, any value settles in a few cycles */
        xb[BX_EMM] = p_amb * e->c.exhaust_volume / (R * xb[BX_EMT]);
        xb[BX_EMF] = 0.5;
        xb[BX_TC] = e->c.turbo_idle_speed;
    }
    if (e->fidelity == TS_ENGINE_CRANK_ANGLE) en_crank_init(e, omega, p_amb, T_amb, x);
}

void ts_engine_set_turbo_speed(const ts_engine *e, double *x, double w)
{
    if (e->off_bank < 0) return;
    for (int b = 0; b < EN_NBANK; b++) x[e->off_bank + b * EN_BANK_NX + BX_TC] = w;
}

void ts_engine_atol(const ts_engine *e, double atol, double *v)
{
    for (int i = 0; i < e->nx; i++) v[i] = atol;
    v[TS_ENGINE_X_SPEED] = atol * 1e3;
    v[TS_ENGINE_X_ANGLE] = atol * 1e3;
    if (e->off_bank >= 0)
        for (int b = 0; b < EN_NBANK; b++) {
            double *vb = v + e->off_bank + b * EN_BANK_NX;
            vb[BX_ICM] = vb[BX_IMM] = vb[BX_EMM] = atol * 1e-1;
            vb[BX_ICT] = vb[BX_IMT] = vb[BX_EMT] = atol * 1e4;
            vb[BX_TC] = atol * 1e5;
        }
    if (e->off_ledger >= 0)
        for (int i = 0; i < EN_LEDGER_NX; i++) v[e->off_ledger + i] = i < LX_MIN ? atol * 1e6 : atol;
    if (e->off_cyl >= 0)
        for (int i = 0; i < EN_NCYL; i++) {
            double *vc = v + e->off_cyl + i * EN_CYL_NX;
            vc[CX_M] = vc[CX_MB] = atol * 1e-3;
            vc[CX_T] = atol * 1e4;
            vc[CX_BURN] = atol * 1e2;
        }
    if (e->off_coolant >= 0) v[e->off_coolant] = v[e->off_coolant + 1] = atol * 1e4;
    if (e->off_wall >= 0)
        for (int i = 0; i < EN_NCYL * EN_NSURF * EN_WALL_NODES; i++) v[e->off_wall + i] = atol * 1e4;
}

int ts_engine_rhs(const ts_engine *e, double t, const double *x, const ts_engine_inputs *in,
                  double *xdot, ts_engine_outputs *out)
{
    if (out) memset(out, 0, sizeof *out);
    switch (e->fidelity) {
    case TS_ENGINE_MAP: return en_map_rhs(e, t, x, in, xdot, out);
    case TS_ENGINE_MEAN_VALUE: return en_mean_rhs(e, t, x, in, xdot, out);
    default: return en_crank_rhs(e, t, x, in, xdot, out);
    }
}

size_t ts_engine_work_size(const ts_engine *e) { return 5 * (size_t)e->nx; }

/* Step size [s]: a fixed crank-angle step for the crank-angle model. */
static double step_size(const ts_engine *e, const double *x)
{
    if (e->fidelity != TS_ENGINE_CRANK_ANGLE) return e->speed_step;
    double w = fmax(fabs(x[TS_ENGINE_X_SPEED]), 30.0);
    return e->c.ca_step / w;
}

/* One classical RK4 step of size h. */
static int rk4(const ts_engine *e, double *x, double t, double h, const ts_engine_inputs *in,
               double *work)
{
    int n = e->nx;
    double *k1 = work, *k2 = work + n, *k3 = work + 2 * n, *k4 = work + 3 * n, *xt = work + 4 * n;
    if (ts_engine_rhs(e, t, x, in, k1, NULL)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k1[i];
    if (ts_engine_rhs(e, t + 0.5 * h, xt, in, k2, NULL)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k2[i];
    if (ts_engine_rhs(e, t + 0.5 * h, xt, in, k3, NULL)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + h * k3[i];
    if (ts_engine_rhs(e, t + h, xt, in, k4, NULL)) return 1;
    for (int i = 0; i < n; i++) {
        x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        if (!isfinite(x[i])) return 1;
    }
    return 0;
}

ts_rc ts_engine_advance(const ts_engine *e, double *x, double t, double dt,
                        const ts_engine_inputs *in, double *work, ts_err *err)
{
    double t_end = t + dt;
    while (t < t_end - 1e-15) {
        double h = step_size(e, x);
        if (t + h > t_end) h = t_end - t;
        if (rk4(e, x, t, h, in, work))
            return ts_err_set(err, TS_ERR_DIVERGED, "/engine",
                              "engine state left its domain at t = %.6f s", t);
        t += h;
    }
    return TS_OK;
}

void ts_engine_ledger_get(const ts_engine *e, const double *x, ts_engine_ledger *l)
{
    memset(l, 0, sizeof *l);
    if (e->off_ledger < 0) return;
    const double *xl = x + e->off_ledger;
    l->fuel_energy = xl[LX_FUEL_E];
    l->work = xl[LX_WORK];
    l->wall_heat = xl[LX_WALL];
    l->enthalpy_in = xl[LX_HIN];
    l->enthalpy_out = xl[LX_HOUT];
    l->mass_in = xl[LX_MIN];
    l->mass_out = xl[LX_MOUT];
    l->fuel_mass = xl[LX_MFUEL];
    if (e->off_cyl < 0) return;
    for (int i = 0; i < EN_NCYL; i++) {
        const double *xc = x + e->off_cyl + i * EN_CYL_NX;
        double m = xc[CX_M], F = fmin(fmax(xc[CX_MB] / m, 0.0), 1.0);
        l->cyl_energy += m * en_gas_u(&e->gas, xc[CX_T], F);
        l->cyl_mass += m;
    }
}

#define OUT_NFIELDS (sizeof(ts_engine_outputs) / sizeof(double))

/* One cycle; wmean (may be NULL, crank_angle only) receives the cycle-mean
 * temperature of every wall node (EN_NCYL x EN_NSURF x EN_WALL_NODES). */
static ts_rc cycle_run(const ts_engine *e, double *x, const ts_engine_inputs *in, double *work,
                       ts_engine_cycle *cyc, double *wmean, double *span_out, ts_err *err)
{
    int nw = e->off_wall >= 0 ? EN_NCYL * EN_NSURF * EN_WALL_NODES : 0;
    if (wmean)
        for (int i = 0; i < nw; i++) wmean[i] = 0;
    ts_engine_ledger l0, l1;
    ts_engine_ledger_get(e, x, &l0);
    double th0 = x[TS_ENGINE_X_ANGLE], t = 0.0, span = 0.0;
    double sum[OUT_NFIELDS] = {0}, peak = 0.0;
    double *xdot = work + 4 * (size_t)e->nx; /* rk4 uses its last slot only inside a step */
    ts_engine_outputs o;
    while (x[TS_ENGINE_X_ANGLE] < th0 + EN_CYCLE - 1e-9) {
        double w = fmax(fabs(x[TS_ENGINE_X_SPEED]), 30.0);
        double h = step_size(e, x);
        double left = (th0 + EN_CYCLE - x[TS_ENGINE_X_ANGLE]) / w;
        if (h > left) h = left;
        if (ts_engine_rhs(e, t, x, in, xdot, &o))
            return ts_err_set(err, TS_ERR_DIVERGED, "/engine", "engine state left its domain");
        const double *ov = (const double *)&o;
        for (size_t k = 0; k < OUT_NFIELDS; k++) sum[k] += ov[k] * h;
        if (o.cyl_pressure > peak) peak = o.cyl_pressure;
        if (wmean)
            for (int i = 0; i < nw; i++) wmean[i] += x[e->off_wall + i] * h;
        if (rk4(e, x, t, h, in, work))
            return ts_err_set(err, TS_ERR_DIVERGED, "/engine",
                              "engine state left its domain at t = %.6f s", t);
        t += h;
        span += h;
    }
    if (wmean)
        for (int i = 0; i < nw; i++) wmean[i] /= span;
    if (span_out) *span_out = span;
    if (!cyc) return TS_OK;
    memset(cyc, 0, sizeof *cyc);
    double *mv = (double *)&cyc->mean;
    for (size_t k = 0; k < OUT_NFIELDS; k++) mv[k] = sum[k] / span;
    cyc->peak_pressure = peak;
    ts_engine_ledger_get(e, x, &l1);
    double fuel_e = l1.fuel_energy - l0.fuel_energy, work_i = l1.work - l0.work;
    double wall = l1.wall_heat - l0.wall_heat;
    double hnet = (l1.enthalpy_out - l0.enthalpy_out) - (l1.enthalpy_in - l0.enthalpy_in);
    double dE = l1.cyl_energy - l0.cyl_energy;
    double min = l1.mass_in - l0.mass_in, mout = l1.mass_out - l0.mass_out;
    double mf = l1.fuel_mass - l0.fuel_mass, dm = l1.cyl_mass - l0.cyl_mass;
    double p_brake = cyc->mean.brake_torque * cyc->mean.speed;
    cyc->bsfc = p_brake > 0 ? cyc->mean.fuel_flow / p_brake : 0.0;
    if (fuel_e > 0) {
        cyc->eta_i = work_i / fuel_e;
        cyc->q_wall = wall / fuel_e;
        cyc->energy_residual = (fuel_e - work_i - wall - hnet - dE) / fuel_e;
    }
    if (min > 0) cyc->mass_residual = (min + mf - mout - dm) / min;
    if (cyc->mean.boost > 0 && cyc->mean.intake_temp > 0) {
        double rho = cyc->mean.boost / (e->gas.r_a * cyc->mean.intake_temp);
        cyc->eta_v = min / (rho * e->geom.vd * EN_NCYL);
    }
    return TS_OK;
}

ts_rc ts_engine_cycle_run(const ts_engine *e, double *x, const ts_engine_inputs *in,
                          double *work, ts_engine_cycle *cyc, ts_err *err)
{
    return cycle_run(e, x, in, work, cyc, NULL, NULL, err);
}

/* Wall acceleration for the steady-state search: shift every wall stack's
 * temperature profile (keeping its periodic part) part of the way towards the
 * steady conduction profile that carries the cycle's mean gas-side flux to the
 * coolant or oil. The mean flux is the stack's energy gain over the cycle plus
 * its mean back-side loss. Relaxation 0.5 converges for h R up to ~3 (h: the
 * cycle-mean gas-side coefficient, R: wall + film resistance). */
static void wall_jump(const ts_engine *e, double *x, const double *x0, const double *wmean,
                      double span)
{
    const double relax = 0.5;
    for (int i = 0; i < EN_NCYL; i++)
        for (int sf = 0; sf < EN_NSURF; sf++) {
            const en_wall *w = &e->wall[sf];
            int o = (i * EN_NSURF + sf) * EN_WALL_NODES;
            double *xw = x + e->off_wall + o;
            const double *xw0 = x0 + e->off_wall + o;
            const double *tm = wmean + o;
            double T_sink = x[e->off_coolant + (sf == EN_PISTON ? 1 : 0)];
            double gain = 0;
            for (int n = 0; n < EN_WALL_NODES; n++) gain += w->cap[n] * (xw[n] - xw0[n]);
            double q = gain / span + w->cond[EN_WALL_NODES - 1] * (tm[EN_WALL_NODES - 1] - T_sink);
            double r = 1.0 / w->cond[EN_WALL_NODES - 1];
            for (int n = EN_WALL_NODES - 1; n >= 0; n--) {
                if (n < EN_WALL_NODES - 1) r += 1.0 / w->cond[n];
                double t_ss = T_sink + q * r;
                xw[n] += relax * (t_ss - tm[n]);
            }
        }
}

ts_rc ts_engine_steady(const ts_engine *e, double *x, double omega, const ts_engine_inputs *in,
                       int max_cycles, double tol, ts_engine_cycle *cyc, ts_err *err)
{
    ts_engine fast = *e; /* private copy with shrunk slow capacities */
    fast.turbo_inertia_scale = 0.01;
    fast.thermal_scale = 0.01;
    ts_engine_inputs held = *in;
    held.hold_speed = 1;
    x[TS_ENGINE_X_SPEED] = omega;
    double *work = malloc(sizeof(double) * ts_engine_work_size(e));
    if (!work) return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    ts_engine_cycle c;
    double prev = NAN;
    int calm = 0, k;
    ts_rc rc = TS_OK;
    int nw = e->off_wall >= 0 ? EN_NCYL * EN_NSURF * EN_WALL_NODES : 0;
    double *x0 = nw ? malloc(sizeof(double) * (size_t)e->nx) : NULL;
    double *wmean = nw ? malloc(sizeof(double) * (size_t)nw) : NULL;
    if (nw && (!x0 || !wmean)) {
        free(x0);
        free(wmean);
        free(work);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    for (k = 0; k < max_cycles; k++) {
        double span = 0;
        if (nw) memcpy(x0, x, sizeof(double) * (size_t)e->nx);
        rc = cycle_run(&fast, x, &held, work, &c, wmean, &span, err);
        if (rc != TS_OK) break;
        if (nw) wall_jump(e, x, x0, wmean, span);
        double tq = c.mean.brake_torque;
        if (isfinite(prev) && fabs(tq - prev) <= tol * fmax(fabs(tq), 100.0)) {
            if (++calm >= 2) break;
        } else {
            calm = 0;
        }
        prev = tq;
    }
    free(x0);
    free(wmean);
    if (rc == TS_OK) rc = ts_engine_cycle_run(e, x, &held, work, &c, err);
    free(work);
    if (rc != TS_OK) return rc;
    c.cycles = k + 1;
    if (cyc) *cyc = c;
    return TS_OK;
}
