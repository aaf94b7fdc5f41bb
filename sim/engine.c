/*
 * engine.c — the virtual V-12 diesel's model object (engine.h): construction
 * from the /engine section, state layout per fidelity, dispatch of the
 * right-hand side, the engine's own integrators for callers that do not
 * integrate it themselves, per-cycle means and the dynamometer steady-state
 * search used by `tanksim engine-map` (paper Section III.B.3).
 *
 * Integrators (performance work of issues 6/10; the equations are untouched):
 *   rk4      map and mean_value, fixed step.
 *   mr_step  crank_angle, fixed crank-angle step /engine/ca_step: RK4 on every
 *            state but the 396 wall nodes, walls frozen in the stages, then
 *            one Crank-Nicolson step per wall stack with the RK4-mean flux.
 *            Used for the cycle means (cycle_run: steady search, engine map),
 *            whose quadrature wants uniform steps; matches the former RK4 of
 *            all states to < 0.01 % (test_engine_regression.c).
 *   bs23     crank_angle in ts_engine_advance(_load): the same split with an
 *            error-controlled Bogacki-Shampine 3(2) (steps of 1/4..8 x
 *            ca_step, ended on the clocks' switching angles so no stage
 *            straddles a switch of the ignition/burn clocks); ~10x fewer
 *            operations than the former RK4 at equal or better accuracy;
 *            the walls take one Crank-Nicolson step per two gas steps.
 *            Issue 6's 20x goal: the last derivative is carried in the work
 *            buffer to the next call (the powertrain's next macro step), where
 *            only its wall- and load-dependent part is re-evaluated
 *            (en_crank_refresh, exact); relative tolerance 3e-3. Its vector
 *            operations on the non-wall states have compile-time lengths and
 *            restrict pointers (they vectorise; the same operations).
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
#include "solver.h"

/* TS_ERR_PARAM unless a[0..n) strictly increases (pointer: the array's). */
static ts_rc check_increasing(const double *a, int n, const char *ptr, const char *what,
                              ts_err *err)
{
    for (int i = 1; i < n; i++)
        if (!(a[i] > a[i - 1]))
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: %s must increase (index %d)", ptr, what,
                              i);
    return TS_OK;
}

/* TS_ERR_PARAM unless every /engine/<prefix><names[k]>[_<variant>] has want
 * values (variant NULL: fields without a per-variant suffix). */
static ts_rc check_counts(const int *counts, const char *const *names, int k_n, const char *prefix,
                          const char *variant, int want, const char *what, ts_err *err)
{
    for (int k = 0; k < k_n; k++)
        if (counts[k] != want) {
            char ptr[64];
            snprintf(ptr, sizeof ptr, "/engine/%s%s%s%s", prefix, names[k], variant ? "_" : "",
                     variant ? variant : "");
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: %d values expected (%s), got %d", ptr,
                              want, what, counts[k]);
        }
    return TS_OK;
}

static ts_rc check_tables(const ts_engine_config *c, int v, ts_err *err)
{
    const ts_engine_map_table *t = &c->map[v];
    int n = c->map_speed_n;
    if (n < 2)
        return ts_err_set(err, TS_ERR_PARAM, "/engine/map_speed",
                          "/engine/map_speed: at least 2 speeds needed, got %d", n);
    ts_rc rc = check_increasing(c->map_speed, n, "/engine/map_speed", "speeds", err);
    if (rc != TS_OK) return rc;
    const int counts[] = {t->torque_n, t->boost_n, t->fuel_n, t->eta_v_n, t->eta_i_n, t->q_wall_n};
    static const char *const names[] = {"torque", "boost", "fuel", "eta_v", "eta_i", "q_wall"};
    rc = check_counts(counts, names, 6, "map_", ts_engine_variant_names[v], n, "one per map_speed",
                      err);
    if (rc != TS_OK) return rc;
    int ns = c->spool_speed_n, nr = c->spool_ratio_n;
    if (ns < 1 || nr < 2 || c->spool_lag_n != ns)
        return ts_err_set(err, TS_ERR_PARAM, "/engine/spool_ratio",
                          "/engine/spool_speed, spool_ratio, spool_lag: at least 1 speed and 2 "
                          "ratios needed, one spool_lag per speed");
    rc = check_increasing(c->spool_speed, ns, "/engine/spool_speed", "speeds", err);
    if (rc == TS_OK) rc = check_increasing(c->spool_ratio, nr, "/engine/spool_ratio", "ratios", err);
    if (rc != TS_OK) return rc;
    const int pb_counts[] = {t->pb_eta_v_n, t->pb_eta_i_n, t->pb_q_wall_n, t->pb_torque_n};
    static const char *const pb_names[] = {"eta_v", "eta_i", "q_wall", "torque"};
    return check_counts(pb_counts, pb_names, 4, "pb_", ts_engine_variant_names[v], ns * nr,
                        "spool_speed x spool_ratio", err);
}

/* The turbine schedule (/engine/turb_sched_*): none, or >= 2 increasing
 * speeds and one nozzle factor, gate factor and bypass area per speed. */
static ts_rc check_schedule(const ts_engine_config *c, ts_err *err)
{
    int n = c->turb_sched_speed_n;
    if (n == 1)
        return ts_err_set(err, TS_ERR_PARAM, "/engine/turb_sched_speed",
                          "/engine/turb_sched_speed: none or at least 2 speeds, got 1");
    const int counts[] = {c->turb_sched_nozzle_n, c->turb_sched_gate_n, c->turb_sched_bypass_n};
    static const char *const names[] = {"nozzle", "gate", "bypass"};
    ts_rc rc =
        check_counts(counts, names, 3, "turb_sched_", NULL, n, "one per turb_sched_speed", err);
    if (rc != TS_OK) return rc;
    return check_increasing(c->turb_sched_speed, n, "/engine/turb_sched_speed", "speeds", err);
}

/* Temperatures over which the cp polynomials must give cv > 0 [K]: below the
 * lowest /driveline/ambient_temperature (220 K) to above the adiabatic flame
 * temperature of the leanest-to-stoichiometric diesel burn (~2700 K) [E]. */
#define GAS_T_CHECK_LO 200.0
#define GAS_T_CHECK_HI 3000.0

ts_engine *ts_engine_make(const ts_config *cfg, ts_err *err)
{
    ts_err_clear(err);
    const ts_engine_config *c = &cfg->engine;
    if (check_tables(c, c->variant, err) != TS_OK) return NULL;
    if (check_schedule(c, err) != TS_OK) return NULL;
    if (c->wg_area > 0 && !(c->wg_full > c->wg_crack)) {
        ts_err_set(err, TS_ERR_PARAM, "/engine/wg_full",
                   "/engine/wg_full (%g Pa) must exceed /engine/wg_crack (%g Pa)", c->wg_full,
                   c->wg_crack);
        return NULL;
    }
    if (c->cp_air_n != 4 || c->cp_burned_n != 4) {
        ts_err_set(err, TS_ERR_PARAM, "/engine/cp_air", "/engine/cp_air, cp_burned: 4 coefficients each");
        return NULL;
    }
    /* cv = cp - R must stay positive where the gas can be (ambient to flame
     * temperature): with cp <= R the energy equation divides by cv <= 0 and the
     * integrators fail with no field named (fuzz finding: cp_air reversed) */
    for (int g = 0; g < 2; g++) {
        const double *cp = g ? c->cp_burned : c->cp_air;
        double r = g ? c->r_burned : c->r_air;
        for (double T = GAS_T_CHECK_LO; T <= GAS_T_CHECK_HI; T += 50.0) {
            double t = T * 1e-3, v = cp[0] + t * (cp[1] + t * (cp[2] + t * cp[3]));
            if (!(v > r)) {
                const char *ptr = g ? "/engine/cp_burned" : "/engine/cp_air";
                ts_err_set(err, TS_ERR_PARAM, ptr,
                           "%s: cp(%.0f K) = %.4g J/kg/K is not above the gas constant %g "
                           "(cv must be > 0 from %.0f to %.0f K)",
                           ptr, T, v, r, GAS_T_CHECK_LO, GAS_T_CHECK_HI);
                return NULL;
            }
        }
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
    e->fuel = ts_fuel_law_from_config(c);
    en_gas_init(&e->gas, c->cp_air, c->cp_burned, c->r_air, c->r_burned);
    e->htc =
        (en_htc_law){c->nu_coeff, c->nu_exp, log(c->gas_mu_coeff), c->gas_mu_exp, c->gas_prandtl};
    en_geom *g = &e->geom;
    g->bore = c->bore;
    g->stroke = c->stroke;
    g->crank = c->stroke / 2;
    g->rod = c->rod_length;
    g->area = EN_PI / 4 * c->bore * c->bore;
    g->vd = g->area * c->stroke;
    g->vc = g->vd / (c->compression_ratio - 1);
    g->circ = EN_PI * c->bore;
    g->clear_h = g->vc / g->area;
    e->watson = (en_watson){c->watson_a,  c->watson_b,  c->watson_c,  c->watson_c1k, c->watson_c1e,
                            c->watson_c2, c->watson_c3k, c->watson_c3e, c->watson_c4k,
                            c->burn_duration};
    /* Turbocharger scaled from the reference unit by geometric similarity
     * (geometric similarity, Watson & Janota 1982): flow x s, diameter x sqrt(s)
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
                          .mach_opt = c->comp_mach_opt,
                          .mach_w = c->comp_mach_width,
                          .a_t = c->turb_area_ref * s,
                          .eta_t = c->turb_eta_max,
                          .bsr_opt = c->turb_bsr_opt,
                          .inertia = c->turbo_inertia_ref * pow(s, 2.5),
                          .mech_eff = c->turbo_mech_eff,
                          .r_air = c->r_air};
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
        e->cyl_sin[i] = sin(e->cyl_offset[i]);
        e->cyl_cos[i] = cos(e->cyl_offset[i]);
        e->cyl_bank[i] = i % 2;
        const double vo[2] = {c->ivo, c->evo}, vcl[2] = {c->ivc, c->evc};
        for (int v = 0; v < 2; v++) {
            e->valve_k[v] = 2.0 * EN_PI / (vcl[v] - vo[v]);
            for (int n = 0; n < 3; n++) {
                double ph = e->valve_k[v] * (e->cyl_offset[i] + vo[v] - n * EN_CYCLE);
                e->valve_cos[v][i][n] = cos(ph);
                e->valve_sin[v][i][n] = sin(ph);
            }
        }
    }
    /* The crank-angle engine's inertia varies with crank angle: c->inertia +
     * sum recip_mass (dx/dtheta)^2 (engine_crank.c). The cycle-averaged
     * fidelities use its mean: twelve times one cylinder's mean over a
     * revolution (dx/dtheta repeats each turn; midpoint rule, exact to
     * rounding for this smooth periodic integrand). */
    double jr = 0;
    for (int i = 0; i < 360; i++) {
        en_kin k;
        en_kinematics(g, (i + 0.5) * 2.0 * EN_PI / 360, &k);
        jr += k.dxdth * k.dxdth;
    }
    e->mean_inertia = c->inertia + EN_NCYL * c->recip_mass * jr / 360;
    e->turbo_inertia_scale = 1.0;
    e->thermal_scale = 1.0;
    e->off_bank = e->off_ledger = e->off_cyl = e->off_wall = e->off_coolant = e->off_lag = -1;
    int n = 2;
    switch (e->c.fidelity) {
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
    if (e->c.fidelity == TS_ENGINE_CRANK_ANGLE) {
        _Static_assert(EN_CRANK_NGAS == 2 + EN_NBANK * EN_BANK_NX + EN_LEDGER_NX + 2 +
                                            EN_NCYL * EN_CYL_NX,
                       "the layout above");
        double v[EN_CRANK_NGAS + EN_CRANK_NWALLX];
        ts_engine_atol(e, 1.0, v);
        for (int i = 0; i < EN_LEDGER_NX; i++) v[e->off_ledger + i] = INFINITY;
        memcpy(e->bs_scale, v, sizeof e->bs_scale);
    }
    return e;
}

void ts_engine_free(ts_engine *e) { free(e); }
int ts_engine_get_fidelity(const ts_engine *e) { return e->c.fidelity; }
unsigned ts_engine_models(const ts_engine *e)
{
    switch (e->c.fidelity) {
    case TS_ENGINE_CRANK_ANGLE:
        return TS_ENGINE_MODELS_CYLINDERS | TS_ENGINE_MODELS_MANIFOLDS;
    case TS_ENGINE_MEAN_VALUE:
        return TS_ENGINE_MODELS_MANIFOLDS;
    default:
        return 0; /* map */
    }
}
int ts_engine_nstate(const ts_engine *e) { return e->nx; }

double ts_engine_mean_inertia(const ts_engine *e)
{
    return e->mean_inertia;
}

int en_bracket(const double *xs, int n, double x)
{
    int i = 0;
    while (i < n - 2 && x > xs[i + 1]) i++;
    return i;
}

en_lin en_lin_at(const double *xs, int n, double x)
{
    if (x <= xs[0]) return (en_lin){0, 0, 0.0};
    if (x >= xs[n - 1]) return (en_lin){n - 1, n - 1, 0.0};
    int i = en_bracket(xs, n, x);
    return (en_lin){i, i + 1, (x - xs[i]) / (xs[i + 1] - xs[i])};
}

double en_fuel_command(const ts_engine *e, const ts_engine_inputs *in, double air_flow,
                       double omega)
{
    if (in->fuel_per_cycle >= 0) return in->fuel_per_cycle;
    return ts_fuel_per_cycle(&e->fuel, air_flow, omega, in->rack); /* Eqs. 13-14 */
}

/* The start's exhaust manifolds: warm, half burned gas (starting guesses:
 * any value settles in a few cycles) */
#define INIT_EXHAUST_T      600.0 /* [K] */
#define INIT_EXHAUST_BURNED 0.5   /* burned-gas fraction [1] */

void ts_engine_init_state(const ts_engine *e, double omega, double p_amb, double T_amb, double *x)
{
    memset(x, 0, sizeof(double) * (size_t)e->nx);
    x[TS_ENGINE_X_SPEED] = omega;
    x[TS_ENGINE_X_ANGLE] = 0.0;
    if (e->c.fidelity == TS_ENGINE_MAP) {
        x[e->off_lag] = 0.0;
        return;
    }
    for (int b = 0; b < EN_NBANK; b++) {
        double *xb = x + e->off_bank + b * EN_BANK_NX;
        double R = e->gas.r_a;
        xb[BX_ICT] = T_amb;
        xb[BX_ICM] = p_amb * e->c.ic_volume / (R * T_amb);
        xb[BX_ICF] = 0.0;
        xb[BX_IMT] = T_amb;
        xb[BX_IMM] = p_amb * e->c.intake_volume / (R * T_amb);
        xb[BX_IMF] = 0.0;
        xb[BX_EMT] = INIT_EXHAUST_T;
        xb[BX_EMM] = p_amb * e->c.exhaust_volume / (R * xb[BX_EMT]);
        xb[BX_EMF] = INIT_EXHAUST_BURNED;
        xb[BX_TC] = e->c.turbo_idle_speed;
    }
    if (e->c.fidelity == TS_ENGINE_CRANK_ANGLE) en_crank_init(e, p_amb, T_amb, x);
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
    switch (e->c.fidelity) {
    case TS_ENGINE_MAP: return en_map_rhs(e, t, x, in, xdot, out);
    case TS_ENGINE_MEAN_VALUE: return en_mean_rhs(e, t, x, in, xdot, out);
    default: return en_crank_rhs(e, t, x, in, xdot, out);
    }
}

#define EN_NWALL (EN_NCYL * EN_NSURF) /* wall stacks of the crank-angle model */

/* Carried from one ts_engine_advance_load call to the next (crank_angle): the
 * last step's derivative and its wall- and load-independent part, with the
 * states and inputs it was evaluated at; the next call re-evaluates only the
 * part that the wall step and the new load change (en_crank_refresh), which
 * gives exactly the derivative a full evaluation would. */
#define CARRY_HEAD 9 /* magic, engine, rack, fuel_per_cycle, p_amb, T_amb, hold, load_inertia, pad */
#define CARRY_MAGIC 0x1.d1cep-3
#define CARRY_PART ((sizeof(en_crank_part) + sizeof(double) - 1) / sizeof(double))
static size_t carry_size(const ts_engine *e) { return CARRY_HEAD + 2 * (size_t)e->off_wall + CARRY_PART; }

size_t ts_engine_work_size(const ts_engine *e)
{
    /* crank_angle: stages, error scales, wall fluxes and the carried derivative */
    return e->c.fidelity == TS_ENGINE_CRANK_ANGLE ? 8 * (size_t)e->nx + 5 * EN_NWALL + carry_size(e)
                                               : 5 * (size_t)e->nx;
}

#define MV_STEP 5e-4 /* map and mean_value fixed RK4 step [s] (numerical setting of
                        the engine's own integrator; callers with CVODE do not use it) */

/* Step size [s]: a fixed crank-angle step for the crank-angle model. */
static double step_size(const ts_engine *e, const double *x)
{
    if (e->c.fidelity != TS_ENGINE_CRANK_ANGLE) return MV_STEP;
    double w = fmax(fabs(x[TS_ENGINE_X_SPEED]), TS_ENGINE_MIN_STEP_SPEED);
    return e->c.ca_step / w;
}

/* Field to name when a fixed-step integration leaves the state's domain: the
 * crank-angle model's step is the user's /engine/ca_step (a coarser step than
 * the gas dynamics tolerate diverges); the other fidelities' step is MV_STEP. */
static const char *step_pointer(const ts_engine *e)
{
    return e->c.fidelity == TS_ENGINE_CRANK_ANGLE ? "/engine/ca_step" : "/engine";
}

/* The error of a fixed step h at t that left the state's domain (cycle_run,
 * ts_engine_advance_load); x: the step's start or, for RK4, the stage state
 * whose slopes were not finite (solver.c); work: the stepper's (the
 * crank-angle stage state at 4 nx): the first of them outside the domain is
 * described. */
static ts_rc step_diverged(const ts_engine *e, double t, double h, const double *x,
                           const double *work, ts_err *err)
{
    int crank = e->c.fidelity == TS_ENGINE_CRANK_ANGLE;
    char why[160] = "";
    if (!crank || !en_domain_fault(e, work + 4 * (size_t)e->nx, why + 2, sizeof why - 2))
        en_domain_fault(e, x, why + 2, sizeof why - 2);
    if (why[2])
        why[0] = ':', why[1] = ' ';
    else
        why[0] = '\0';
    return ts_err_set(
        err, TS_ERR_DIVERGED, step_pointer(e),
        "engine state left its domain at t = %.6f s (fixed step %.3g s)%s%s", t, h, why,
        crank              ? "; a smaller /engine/ca_step cures a step too coarse for the gas "
                             "dynamics; if it persists at the smallest, another /engine "
                             "parameter is outside what the model can run"
        : e->off_bank >= 0 ? "; this fidelity's step is fixed, too coarse for a volume that its "
                             "flows fill or empty faster (a small /engine/ic_volume, "
                             "intake_volume or exhaust_volume against a wide passage such as "
                             "/engine/ic_cda)"
                           : "");
}

ts_rc ts_engine_rhs_failed(const ts_engine *e, double t, const double *x, ts_err *err)
{
    char why[160] = "";
    en_domain_fault(e, x, why, sizeof why);
    return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                      "the engine's equations cannot be evaluated at t = %.6f s: %s", t,
                      why[0] ? why : "its state is outside the model's domain");
}

/* Load torque on the crankshaft as a function of (t, speed) at every stage. */
typedef struct stage_load {
    ts_engine_load_fn fn; /* NULL: in->load_torque held */
    void *ud;
    ts_engine_inputs in;
} stage_load;

static const ts_engine_inputs *at(stage_load *sl, double t, const double *x)
{
    if (sl->fn) sl->in.load_torque = sl->fn(sl->ud, t, x[TS_ENGINE_X_SPEED]);
    return &sl->in;
}

/* One classical RK4 step of size h (map and mean_value): solver.h's, with the
 * load evaluated at every stage. */
typedef struct rk4_ud {
    const ts_engine *e;
    stage_load *sl;
} rk4_ud;

static int rk4_rhs(double t, const double *x, double *xdot, void *ud)
{
    const rk4_ud *r = ud;
    return ts_engine_rhs(r->e, t, x, at(r->sl, t, x), xdot, NULL);
}

static int rk4(const ts_engine *e, double *x, double t, double h, stage_load *sl, double *work)
{
    rk4_ud r = {e, sl};
    return ts_rk4_step(e->nx, rk4_rhs, &r, t, h, x, work);
}

/* Multirate step of the crank-angle model (issue 6/10 speed-up): the gas,
 * turbulence, combustion, manifold, turbo, crank, coolant and ledger states
 * (the first off_wall states) by classical RK4 with every wall stack FROZEN
 * during the step, then each wall stack by one Crank-Nicolson step driven by
 * the RK4-weighted mean of its four stage fluxes (the flux RK4 itself would
 * integrate). The wall conduction is linear and far slower than the step
 * except in its surface cell, which the A-stable implicit step takes without
 * the explicit limit; the gas sees the surface temperature of the step start
 * (lagged by at most one crank step). Energy is conserved: the heat the gas
 * loses in the step is the heat the walls receive. */
static int mr_step(const ts_engine *e, double *x, double t, double h, stage_load *sl,
                   double *work)
{
    int n = e->off_wall; /* the walls are the last states */
    int nx = e->nx;
    double *k1 = work, *k2 = work + nx, *k3 = work + 2 * nx, *k4 = work + 3 * nx;
    double *xt = work + 4 * nx, *q = work + 5 * nx;
    double *q1 = q, *q2 = q + EN_NWALL, *q3 = q + 2 * EN_NWALL, *q4 = q + 3 * EN_NWALL;
    memcpy(xt + n, x + n, sizeof(double) * (size_t)(nx - n)); /* frozen walls */
    if (en_crank_eval(e, x, at(sl, t, x), k1, NULL, q1)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k1[i];
    if (en_crank_eval(e, xt, at(sl, t + 0.5 * h, xt), k2, NULL, q2)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + 0.5 * h * k2[i];
    if (en_crank_eval(e, xt, at(sl, t + 0.5 * h, xt), k3, NULL, q3)) return 1;
    for (int i = 0; i < n; i++) xt[i] = x[i] + h * k3[i];
    if (en_crank_eval(e, xt, at(sl, t + h, xt), k4, NULL, q4)) return 1;
    for (int i = 0; i < n; i++) {
        x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        if (!isfinite(x[i])) return 1;
    }
    for (int j = 0; j < EN_NWALL; j++) q1[j] = (q1[j] + 2 * q2[j] + 2 * q3[j] + q4[j]) / 6.0;
    en_walls_step(e, x, q1, h);
    for (int i = n; i < nx; i++)
        if (!isfinite(x[i])) return 1;
    return 0;
}

static int step(const ts_engine *e, double *x, double t, double h, stage_load *sl, double *work)
{
    if (e->c.fidelity == TS_ENGINE_CRANK_ANGLE) return mr_step(e, x, t, h, sl, work);
    return rk4(e, x, t, h, sl, work);
}

static void carry_head(const ts_engine *e, const ts_engine_inputs *in, double *h)
{
    memset(h, 0, sizeof(double) * CARRY_HEAD);
    h[0] = CARRY_MAGIC;
    _Static_assert(sizeof e <= sizeof(double), "the engine's address fits one double");
    memcpy(h + 1, &e, sizeof e);
    h[2] = in->rack;
    h[3] = in->fuel_per_cycle;
    h[4] = in->p_amb;
    h[5] = in->T_amb;
    h[6] = in->hold_speed;
    h[7] = in->load_inertia;
}

/* The carried derivative into k1 and q1 if it belongs to (e, x, in); 1: done. */
static int carry_get(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                     const double *carry, double *k1, double *q1)
{
    int n = e->off_wall;
    double h[CARRY_HEAD];
    carry_head(e, in, h);
    if (memcmp(h, carry, sizeof h) || memcmp(x, carry + CARRY_HEAD, sizeof(double) * (size_t)n))
        return 0;
    en_crank_part pc;
    memcpy(k1, carry + CARRY_HEAD + n, sizeof(double) * (size_t)n);
    memcpy(&pc, carry + CARRY_HEAD + 2 * n, sizeof pc);
    en_crank_refresh(e, x, in, &pc, k1, q1);
    return 1;
}

static void carry_put(const ts_engine *e, const double *x, const ts_engine_inputs *in,
                      const double *k, const en_crank_part *pc, double *carry)
{
    int n = e->off_wall;
    memcpy(carry + CARRY_HEAD, x, sizeof(double) * (size_t)n);
    memcpy(carry + CARRY_HEAD + n, k, sizeof(double) * (size_t)n);
    memcpy(carry + CARRY_HEAD + 2 * n, pc, sizeof *pc);
    carry_head(e, in, carry);
}

/* Error-controlled multirate step of the crank-angle model: Bogacki-Shampine
 * 3(2) (FSAL) on every state but the walls, walls frozen over the step; every
 * BS_WALL_EVERY accepted steps (and at the end of the call) each wall stack by
 * one Crank-Nicolson step with the mean heat flux of those steps (each step's
 * flux with the scheme's own weights: the heat the gas lost is the heat the
 * walls receive). The step adapts in crank angle between
 * /engine/ca_step / 4 and 8 ca_step (fine through the premixed burn and the
 * valve events, coarse through compression and expansion). tol: relative
 * tolerance on the engine's state scales (ts_engine_atol). */
/* BS_TOL: relative tolerance. 3e-3 (1e-3 until the speed-up of issue 6's 20x
 * goal): the Table 2 point-mass figures moved < 0.03 % and the lug transient
 * of test_engine_regression.c < 0.05 %; against tol 1e-4 the Table 2 figures
 * differ by <= 0.11 % at 3e-3 and <= 0.10 % at 1e-3 (the error is dominated
 * by the multirate wall coupling, not by the gas states' local tolerance) */
#define BS_TOL 3e-3
#define BS_MIN 0.25  /* smallest step, x /engine/ca_step */
#define BS_MAX 8.0   /* largest step, x /engine/ca_step */
#define BS_START 4.0 /* first step of a call, x /engine/ca_step */
#define BS_WALL_EVERY 2 /* accepted steps per wall step (the walls' mean flux over them) */
#define BS_IGNITION 1.0 /* step after an ignition at most this x /engine/ca_step (the
                           premixed burn starts there; a larger step is rejected) */
/* The stepper's vector operations on the EN_CRANK_NGAS non-wall states, with
 * restrict pointers (disjoint arrays: state, stages, scratch), which lets the
 * compiler vectorise them (the same element-wise operations). */
/* out = x + a k (a: the stage's coefficient x h, formed by the caller) */
static void bs_stage(double *restrict out, const double *restrict x, double a,
                     const double *restrict k)
{
    for (int i = 0; i < EN_CRANK_NGAS; i++) out[i] = x[i] + a * k[i];
}

/* y1 = x + h (2/9 k1 + 1/3 k2 + 4/9 k3) */
static void bs_y1(double *restrict y1, const double *restrict x, double h,
                  const double *restrict k1, const double *restrict k2, const double *restrict k3)
{
    for (int i = 0; i < EN_CRANK_NGAS; i++)
        y1[i] = x[i] + h * (2.0 / 9.0 * k1[i] + 1.0 / 3.0 * k2[i] + 4.0 / 9.0 * k3[i]);
}

/* |e_i| of the embedded error estimate and its scale d_i = tol (sc_i + |y1_i|) */
static void bs_err(double *restrict a, double *restrict d, double h, double tol,
                   const double *restrict sc, const double *restrict y1,
                   const double *restrict k1, const double *restrict k2,
                   const double *restrict k3, const double *restrict k4)
{
    for (int i = 0; i < EN_CRANK_NGAS; i++) {
        double ei = h * (-5.0 / 72.0 * k1[i] + 1.0 / 12.0 * k2[i] + 1.0 / 9.0 * k3[i] -
                         1.0 / 8.0 * k4[i]);
        a[i] = fabs(ei);
        d[i] = tol * (sc[i] + fabs(y1[i]));
    }
}

static ts_rc bs23_advance(const ts_engine *e, double *x, double t, double dt, stage_load *sl,
                          double *work, ts_err *err)
{
    /* n = off_wall and nx as compile-time constants: the vector loops below
     * vectorise (element-wise, the same operations) */
    enum { n = EN_CRANK_NGAS, nx = EN_CRANK_NGAS + EN_CRANK_NWALLX };
    double *k1 = work, *k2 = work + nx, *k3 = work + 2 * nx, *k4 = work + 3 * nx;
    double *xt = work + 4 * nx, *y1 = work + 5 * nx;
    const double *sc = e->bs_scale; /* the ledger's infinite: not controlled */
    double *q1 = work + 8 * nx, *q2 = q1 + EN_NWALL, *q3 = q2 + EN_NWALL, *q4 = q3 + EN_NWALL;
    const double tol = BS_TOL;
    double t_end = t + dt;
    /* first crank-angle step of every call: BS_START x ca_step (the error test
     * corrects it; a function of x only, so results do not depend on how a
     * run is cut into calls' history or on the work buffer's contents) */
    double dth = BS_START * e->c.ca_step;
    double *qacc = q4 + EN_NWALL, hacc = 0; /* wall heat accumulated since the last wall step */
    int nacc = 0;
    memset(qacc, 0, sizeof(double) * EN_NWALL);
    memcpy(xt + n, x + n, sizeof(double) * (size_t)(nx - n));
    memcpy(y1 + n, x + n, sizeof(double) * (size_t)(nx - n));
    double *carry = qacc + EN_NWALL;
    en_crank_part part4; /* of the last k4 */
    int have_k1 = carry_get(e, x, at(sl, t, x), carry, k1, q1), stepped = 0, rejected = 0;
    carry[0] = 0.0; /* invalid until this call ends */
    while (t < t_end - 1e-15) {
        double w = fmax(fabs(x[TS_ENGINE_X_SPEED]), TS_ENGINE_MIN_STEP_SPEED);
        if (!have_k1 && en_crank_eval(e, x, at(sl, t, x), k1, NULL, q1)) goto diverged;
        have_k1 = 1;
        double d_ign, d_sw = en_crank_next_switch(e, x, k1, &d_ign);
        double dstep = dth;
        int trunc = 0;
        if (d_sw * 1.002 + 1e-6 < dstep) {
            dstep = d_sw * 1.002 + 1e-6; /* end just past the switch */
            trunc = 1;
        }
        if (d_ign * 1.002 + 1e-6 < dstep) {
            dstep = d_ign * 1.002 + 1e-6; /* estimated: checked at the last inner stage */
            trunc = 2;
        }
        double h = dstep / w;
        int last = 0;
        if (t + h >= t_end) {
            h = t_end - t;
            last = 1;
        }
        bs_stage(xt, x, 0.5 * h, k1);
        int bad = en_crank_eval(e, xt, at(sl, t + 0.5 * h, xt), k2, NULL, q2);
        if (!bad) {
            bs_stage(xt, x, 0.75 * h, k2);
            bad = en_crank_eval(e, xt, at(sl, t + 0.75 * h, xt), k3, NULL, q3);
        }
        if (!bad && trunc == 2) /* no ignition before the step's end (I grows monotonically) */
            for (int i = 0; i < EN_NCYL; i++) {
                int o = e->off_cyl + i * EN_CYL_NX + CX_IGN;
                if (x[o] < 1.0 && xt[o] >= 1.0) trunc = 0; /* estimate missed: error test */
            }
        if (!bad) {
            bs_y1(y1, x, h, k1, k2, k3);
            bad = en_crank_eval_part(e, y1, at(sl, t + h, y1), k4, NULL, q4, &part4);
        }
        double en = 0;
        /* error norm max |e_i| / d_i (0 for the ledger: d = inf), dividing only
         * where the maximum may grow; not needed after a truncated step, whose
         * stages that build y1 lie before the switch */
        if (!bad && !trunc) {
            double ea[n], ed[n]; /* |e_i|, d_i (vectorised), then the maximum in order */
            bs_err(ea, ed, h, tol, sc, y1, k1, k2, k3, k4);
            for (int i = 0; i < n; i++) {
                if (ea[i] <= en * ed[i]) continue;
                double r = ea[i] / ed[i];
                if (!(r <= en)) en = isnan(r) ? INFINITY : r;
            }
        }
        if (bad || !(en <= 1.0)) {
            if (dth <= BS_MIN * e->c.ca_step * 1.0000001) {
                /* at the smallest step: accept (the fixed-step scheme would) unless broken;
                 * broken there means the step floor, set by /engine/ca_step, is too coarse
                 * for this engine state: name that field so the user can act on it */
                if (bad)
                    return ts_err_set(err, TS_ERR_DIVERGED, "/engine/ca_step",
                                      "engine state left its domain at t = %.6f s even at the "
                                      "smallest crank-angle step (ca_step / %g = %.4g rad); "
                                      "a smaller ca_step may resolve it",
                                      t, 1.0 / BS_MIN, BS_MIN * e->c.ca_step);
            } else {
                double f = bad || !isfinite(en) ? 0.25 : fmax(0.25, 0.9 * cbrt(1.0 / en));
                dth = fmax(dth * f, BS_MIN * e->c.ca_step);
                rejected = 1;
                continue;
            }
        }
        for (int j = 0; j < EN_NWALL; j++)
            qacc[j] += h * (2.0 / 9.0 * q1[j] + 1.0 / 3.0 * q2[j] + 4.0 / 9.0 * q3[j]);
        hacc += h;
        memcpy(x, y1, sizeof(double) * (size_t)n);
        stepped = 1;
        if (++nacc == BS_WALL_EVERY || last) {
            for (int j = 0; j < EN_NWALL; j++) qacc[j] /= hacc;
            en_walls_step(e, x, qacc, hacc);
            /* NaN or inf in any wall node makes a partial sum non-finite (four
             * partial sums: independent additions) */
            double ws[4] = {0.0, 0.0, 0.0, 0.0};
            _Static_assert((nx - n) % 4 == 0, "wall nodes in fours");
            for (int i = n; i < nx; i += 4)
                for (int j = 0; j < 4; j++) ws[j] += x[i + j];
            if (!isfinite(ws[0] + ws[1] + ws[2] + ws[3])) goto diverged;
            memset(qacc, 0, sizeof(double) * EN_NWALL);
            hacc = 0;
            nacc = 0;
            memcpy(xt + n, x + n, sizeof(double) * (size_t)(nx - n)); /* the stages' walls */
            memcpy(y1 + n, x + n, sizeof(double) * (size_t)(nx - n));
        }
        memcpy(k1, k4, sizeof(double) * (size_t)n); /* FSAL (walls lag by this step) */
        memcpy(q1, q4, sizeof(double) * EN_NWALL);
        t += h;
        if (!last && !trunc) {
            double f = en > 0 ? 0.9 * cbrt(1.0 / en) : 4.0;
            if (rejected && f > 1.0) f = 1.0; /* no growth right after a rejection */
            dth = fmin(fmax(dth * fmin(f, 4.0), BS_MIN * e->c.ca_step), BS_MAX * e->c.ca_step);
        }
        if (trunc == 2) dth = fmin(dth, BS_IGNITION * e->c.ca_step); /* a cylinder ignites */
        rejected = 0;
        if (last) break;
    }
    if (stepped) carry_put(e, x, &sl->in, k1, &part4, carry);
    return TS_OK;
diverged:
    return ts_err_set(err, TS_ERR_DIVERGED, "/engine", "engine state left its domain at t = %.6f s",
                      t);
}

ts_rc ts_engine_advance_load(const ts_engine *e, double *x, double t, double dt,
                             const ts_engine_inputs *in, ts_engine_load_fn load, void *ud,
                             double *work, ts_err *err)
{
    stage_load sl = {load, ud, *in};
    if (e->c.fidelity == TS_ENGINE_CRANK_ANGLE)
        return bs23_advance(e, x, t, dt, &sl, work, err);
    double t_end = t + dt;
    while (t < t_end - 1e-15) {
        double h = step_size(e, x);
        if (t + h > t_end) h = t_end - t;
        if (step(e, x, t, h, &sl, work)) return step_diverged(e, t, h, x, work, err);
        t += h;
    }
    return TS_OK;
}

ts_rc ts_engine_advance(const ts_engine *e, double *x, double t, double dt,
                        const ts_engine_inputs *in, double *work, ts_err *err)
{
    return ts_engine_advance_load(e, x, t, dt, in, NULL, NULL, work, err);
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
    double *xdot = work + 4 * (size_t)e->nx; /* the steppers use this slot only inside a step */
    ts_engine_outputs o;
    while (x[TS_ENGINE_X_ANGLE] < th0 + EN_CYCLE - 1e-9) {
        double w = fmax(fabs(x[TS_ENGINE_X_SPEED]), TS_ENGINE_MIN_STEP_SPEED);
        double h = step_size(e, x);
        double left = (th0 + EN_CYCLE - x[TS_ENGINE_X_ANGLE]) / w;
        if (h > left) h = left;
        if (ts_engine_rhs(e, t, x, in, xdot, &o)) return step_diverged(e, t, h, x, work, err);
        const double *ov = (const double *)&o;
        for (size_t k = 0; k < OUT_NFIELDS; k++) sum[k] += ov[k] * h;
        if (o.cyl_pressure > peak) peak = o.cyl_pressure;
        if (wmean)
            for (int i = 0; i < nw; i++) wmean[i] += x[e->off_wall + i] * h;
        stage_load sl = {NULL, NULL, *in};
        if (step(e, x, t, h, &sl, work)) return step_diverged(e, t, h, x, work, err);
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
    /* what this fidelity does not model is NaN, not 0 (a 0-Pa peak pressure or
     * 0-g/kWh BSFC read as results; CLI review, session 20): peak pressure
     * without cylinders, the ledger's ratios without a ledger (map), BSFC at
     * zero or negative brake power */
    cyc->peak_pressure = ts_engine_models(e) & TS_ENGINE_MODELS_CYLINDERS ? peak : NAN;
    cyc->eta_v = cyc->eta_i = cyc->q_wall = NAN;
    cyc->energy_residual = cyc->mass_residual = NAN;
    ts_engine_ledger_get(e, x, &l1);
    double fuel_e = l1.fuel_energy - l0.fuel_energy, work_i = l1.work - l0.work;
    double wall = l1.wall_heat - l0.wall_heat;
    double hnet = (l1.enthalpy_out - l0.enthalpy_out) - (l1.enthalpy_in - l0.enthalpy_in);
    double dE = l1.cyl_energy - l0.cyl_energy;
    double min = l1.mass_in - l0.mass_in, mout = l1.mass_out - l0.mass_out;
    double mf = l1.fuel_mass - l0.fuel_mass, dm = l1.cyl_mass - l0.cyl_mass;
    double p_brake = cyc->mean.brake_torque * cyc->mean.speed;
    cyc->bsfc = p_brake > 0 ? cyc->mean.fuel_flow / p_brake : NAN;
    if (fuel_e > 0) {
        cyc->eta_i = work_i / fuel_e;
        cyc->q_wall = wall / fuel_e;
        cyc->energy_residual = (fuel_e - work_i - wall - hnet - dE) / fuel_e;
    }
    if (min > 0) cyc->mass_residual = (min + mf - mout - dm) / min;
    if (min > 0 && cyc->mean.boost > 0 && cyc->mean.intake_temp > 0) {
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

/* The steady searches' numerics: the slow capacities (turbo rotors, walls,
 * coolant and oil) shrunk by this factor in the search's cycles, and the
 * floor of the convergence test's scale (tol x max(|torque|, floor)). */
#define STEADY_SLOW_SCALE   0.01
#define STEADY_TORQUE_FLOOR 100.0 /* [N*m] */

/* The idle search (ts_engine_idle_state): a secant on the rack from this
 * start, each point a steady search of at most IDLE_CYCLES to IDLE_TOL, until
 * the brake torque matches the load within IDLE_MATCH_REL or IDLE_MATCH_ABS;
 * without a usable slope the rack is scaled up or down. */
#define IDLE_RACK_START 0.15
#define IDLE_CYCLES     40
#define IDLE_TOL        2e-3
#define IDLE_SEARCHES   6
#define IDLE_MATCH_REL  0.02
#define IDLE_MATCH_ABS  5.0 /* [N*m] */
#define IDLE_RACK_UP    1.5
#define IDLE_RACK_DOWN  0.6

ts_rc ts_engine_steady(const ts_engine *e, double *x, double omega, const ts_engine_inputs *in,
                       int max_cycles, double tol, ts_engine_cycle *cyc, ts_err *err)
{
    ts_engine fast = *e; /* private copy with shrunk slow capacities */
    fast.turbo_inertia_scale = STEADY_SLOW_SCALE;
    fast.thermal_scale = STEADY_SLOW_SCALE;
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
        if (isfinite(prev) && fabs(tq - prev) <= tol * fmax(fabs(tq), STEADY_TORQUE_FLOOR)) {
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

ts_rc ts_engine_idle_state(const ts_engine *e, double omega, double load_torque, double p_amb,
                           double T_amb, double *x, double *rack, ts_err *err)
{
    ts_engine_init_state(e, omega, p_amb, T_amb, x);
    if (rack) *rack = 0.0;
    if (e->c.fidelity == TS_ENGINE_MAP) return TS_OK;
    ts_engine_inputs in = {
        .rack = IDLE_RACK_START, .fuel_per_cycle = -1.0, .p_amb = p_amb, .T_amb = T_amb};
    ts_engine_cycle cyc;
    /* secant on the rack: brake torque is nearly linear in it at fixed speed */
    double r_prev = NAN, tq_prev = NAN, r = in.rack, tq = NAN;
    int found = 0;
    for (int it = 0; it < IDLE_SEARCHES && !found; it++) {
        ts_rc rc = ts_engine_steady(e, x, omega, &in, IDLE_CYCLES, IDLE_TOL, &cyc, err);
        if (rc != TS_OK) return rc;
        tq = cyc.mean.brake_torque;
        r = in.rack;
        found = fabs(tq - load_torque) <= fmax(IDLE_MATCH_REL * fabs(load_torque), IDLE_MATCH_ABS);
        if (found) break;
        double slope = isfinite(r_prev) && fabs(r - r_prev) > 1e-6 ? (tq - tq_prev) / (r - r_prev)
                                                                   : 0.0;
        double r_new = slope > 0 ? r + (load_torque - tq) / slope
                                 : r * (tq < load_torque ? IDLE_RACK_UP : IDLE_RACK_DOWN);
        r_prev = r;
        tq_prev = tq;
        in.rack = fmin(fmax(r_new, 0.01), 1.0);
    }
    if (!found) /* e.g. a load beyond the full-rack torque at this speed */
        return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                          "idle steady state: no rack in [0.01, 1] found that gives %.6g N*m at "
                          "%.6g rpm in %d steady searches (last: rack %.4g, %.6g N*m)",
                          load_torque, omega * EN_RPM, IDLE_SEARCHES, r, tq);
    x[TS_ENGINE_X_SPEED] = omega;
    if (rack) *rack = r;
    return TS_OK;
}
