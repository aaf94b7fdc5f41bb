/*
 * coupled_system.c — the integrated engine–vehicle system (coupled_system.h),
 * paper Section IV: powertrain + multibody vehicle, coupled at the sprocket
 * either leading–following (cosim.h, Section IV.A) or monolithically.
 *
 * The powertrain side's equations are one function (pt_side) used by both
 * methods: given its states [powertrain, IVS integral], the sprocket speed and
 * the rack mode it returns the derivatives and the sprocket torque; the
 * vehicle side is vm_rhs_torque. The monolithic right-hand side chains them at
 * the vehicle's own sprocket speed; leading–following gives the leader the
 * predicted speed and the follower the interpolated torque. So the two methods
 * differ only by the coupling — what the coupling-error test measures.
 *
 * Events: gear-shift start/end are roots of whichever integrator carries the
 * powertrain; at a root the discrete state is updated and that integrator
 * re-initialised (powertrain.h protocol). A new vehicle report does NOT
 * re-initialise the leader: its integrator never steps past its step end
 * (stop time), so the new prediction only acts from there on, and the error
 * test absorbs the small jump (lead_ode_advance). Nor the follower: the
 * published torque is a continuous piecewise-linear function of time, final
 * once published; the follower's integrator never steps past the last sample
 * (stop time). Both vehicle-side integrators use the standalone vehicle's
 * solver settings (vehicle_model.h: vm_abs_tolerances, VM_BDF_MAX_ORDER,
 * VM_JAC_EVAL_STEPS).
 * Second order in the macro step needs the interface terms of publish() and
 * the consistent start of ts_coupled_run_reset (coupled_system.h,
 * docs/coupled.md).
 */
#include "coupled_system.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cosim.h"
#include "governor.h"
#include "ivs_controller.h"
#include "scenario.h"
#include "solver.h"

#define SPIN_SPROCKET (10 + VM_SPROCKET) /* q index of the sprocket spin (vehicle_model.h) */
#define Q_THETA       2                  /* q index of the hull pitch */

struct ts_coupled {
    ts_config cfg;
    vm *v;
    ts_powertrain *pt;
    int nv, nq, npt, np; /* vehicle states, vehicle coordinates, powertrain states, np = npt + 1 */
    int ivs_on;
    ts_ivs ivs;
    ts_ivs_gains gains;
    ts_governor gov;
    double r_s;    /* sprocket pitch radius for the speed measurement [m] */
    double target; /* [m/s] */
};

/* ---- the model ------------------------------------------------------------- */

static ts_rc build_controller(ts_coupled *c, ts_err *err)
{
    const ts_control_config *cc = &c->cfg.control;
    c->ivs_on = cc->mode == TS_CONTROL_IVS;
    c->target = cc->target_speed;
    c->ivs.anti_windup = cc->anti_windup;
    c->ivs.fixed = (ts_ivs_gains){cc->kp, cc->ti};
    if (cc->schedule_kp_n != cc->schedule_n || cc->schedule_ti_n != cc->schedule_n)
        return ts_err_set(err, TS_ERR_PARAM, "/control/schedule_kp",
                          "/control/schedule_kp, schedule_ti: one value per schedule_x row (%d)",
                          cc->schedule_n);
    c->ivs.nschedule = cc->schedule_n;
    for (int i = 0; i < cc->schedule_n; i++) {
        c->ivs.sched_x[i] = cc->schedule_x[i];
        c->ivs.sched[i] = (ts_ivs_gains){cc->schedule_kp[i], cc->schedule_ti[i]};
    }
    ts_rc rc = ts_ivs_check(&c->ivs, err);
    if (rc != TS_OK) return rc;
    double x = cc->schedule_var == TS_SCHEDULE_GRADE ? c->cfg.vehicle.grade : c->cfg.vehicle.mass;
    c->gains = ts_ivs_gains_at(&c->ivs, x);
    return ts_governor_of_config(cc, &c->gov, err);
}

static ts_coupled *make(const ts_config *cfg, const ts_engine_port *port, ts_err *err)
{
    ts_coupled *c = calloc(1, sizeof *c);
    if (!c) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    c->cfg = *cfg;
    c->pt = port ? ts_powertrain_make_port(cfg, port, err) : ts_powertrain_make(cfg, err);
    if (!c->pt) goto fail;
    /* the run starts from standstill with the engine at its idle steady
     * state, as the point-mass launch does (powertrain.h): from
     * ts_engine_init_state's guessed turbo speed and ambient intercooler the
     * compressor passes far more air than the cylinders take, and Eq. 14
     * fuels on it (an 11-kN*m torque spike at 650 rpm in the first 25 ms) */
    if (ts_powertrain_idle_start(c->pt, err) != TS_OK) goto fail;
    /* the driveline's output inertia (both sides, sprockets included) rides on
     * the vehicle's sprocket spin, per side */
    ts_config vcfg = *cfg;
    double j_out = 0.5 * ts_powertrain_output_inertia(c->pt);
    if (j_out > vcfg.vehicle.sprocket_inertia) vcfg.vehicle.sprocket_inertia = j_out;
    vcfg.drive.kind = TS_DRIVE_POWERTRAIN; /* vm_rhs_torque ignores /drive anyway */
    c->v = vm_make(&vcfg, err);
    if (!c->v) goto fail;
    c->nv = vm_ny(c->v);
    c->nq = vm_nq(c->v);
    c->npt = ts_powertrain_nstate(c->pt);
    c->np = c->npt + 1;
    c->r_s = cfg->vehicle.sprocket_radius;
    if (build_controller(c, err) != TS_OK) goto fail;
    return c;
fail:
    ts_coupled_free(c);
    return NULL;
}

ts_coupled *ts_coupled_make(const ts_config *cfg, ts_err *err)
{
    return make(cfg, NULL, err);
}

ts_coupled *ts_coupled_make_port(const ts_config *cfg, const ts_engine_port *port, ts_err *err)
{
    return make(cfg, port, err);
}

void ts_coupled_free(ts_coupled *c)
{
    if (!c) return;
    vm_free(c->v);
    ts_powertrain_free(c->pt);
    free(c);
}

const vm *ts_coupled_vehicle(const ts_coupled *c)
{
    return c->v;
}
const ts_powertrain *ts_coupled_powertrain(const ts_coupled *c)
{
    return c->pt;
}
double ts_coupled_kp(const ts_coupled *c)
{
    return c->gains.kp;
}
double ts_coupled_ti(const ts_coupled *c)
{
    return c->gains.ti;
}

/* Driver / controller and fuel actuator at powertrain-side state yp for the
 * sprocket speed w: rack demand, governed rack, speed error. */
typedef struct drive_cmd {
    double e, demand, rack;
} drive_cmd;

static drive_cmd command(const ts_coupled *c, double rack_fixed, const double *yp, double w)
{
    drive_cmd d = {0, rack_fixed, rack_fixed};
    if (c->ivs_on) {
        d.e = c->target - w * c->r_s; /* Eq. 10: e = V_r - V_a */
        d.demand = ts_ivs_rack(c->gains, d.e, yp[c->npt]);
    }
    double w_e = yp[ts_powertrain_engine_speed_index(c->pt)];
    d.rack = ts_governor_rack(&c->gov, d.demand, w_e);
    return d;
}

/* Powertrain-side derivatives (powertrain states, then the IVS integral). */
static int pt_side(const ts_coupled *c, const ts_powertrain_state *ps, double rack_fixed, double t,
                   const double *yp, double w, double *ypdot, ts_powertrain_out *out,
                   drive_cmd *cmd_out)
{
    drive_cmd d = command(c, rack_fixed, yp, w);
    int rc = ts_powertrain_rhs(c->pt, ps, t, yp, w, d.rack, ypdot, out);
    ypdot[c->npt] = c->ivs_on ? ts_ivs_integral_rate(&c->ivs, c->gains, d.e, yp[c->npt]) : 0.0;
    if (cmd_out) *cmd_out = d;
    return rc;
}

/* pt_side outside an integrator's step (an observation, a published torque,
 * the start): its failure is the run's error. */
static ts_rc pt_side_at(const ts_coupled *c, const ts_powertrain_state *ps, double rack_fixed,
                        double t, const double *yp, double w, double *ypdot, ts_powertrain_out *out,
                        drive_cmd *cmd_out, ts_err *err)
{
    return pt_side(c, ps, rack_fixed, t, yp, w, ypdot, out, cmd_out) != 0
               ? ts_powertrain_rhs_failed(t, err)
               : TS_OK;
}

static double sprocket_rel(const ts_coupled *c,
                           const double *yv) /* qd of the sprocket - qd of theta */
{
    return yv[c->nq + SPIN_SPROCKET] - yv[c->nq + Q_THETA];
}

/* ---- a run ------------------------------------------------------------------- */

struct ts_coupled_run {
    const ts_coupled *c;
    int method;
    ts_coupling_config co;
    double t, rack_fixed;
    double *yv, *yp;   /* vehicle state, powertrain-side state at t */
    double *ydv, *ydp; /* scratch derivatives (observation) */
    vm_work *w;
    ts_powertrain_state ps;
    ts_coupled_stats st;
    /* monolithic */
    ts_ode *mono;
    double *ym; /* [yv, yp] */
    /* leading-following */
    ts_ode *lead_ode, *follow_ode;
    ts_cosim *cosim;
    ts_cosim_report last; /* report the leader integrates with */
    int last_order;
    ts_cosim_report prev; /* the report before last (jerk estimate) */
    double step;          /* leader step of the current advance [s] */
    int lead_dirty; /* restart the leader before integrating (reset, restore, rack step, shift) */
    double lead_t;              /* leader time */
    ts_cosim_sample pub;        /* sample last published by the leader */
    const ts_cosim_torque *src; /* follower's torque source during its advance */
    double follow_stop;         /* follower's stop time: the last published sample */
    ts_cosim_report rep;        /* follower's last report */
    double *ylead_scratch;
    double *rk; /* 5 np: RK4 stages of the explicit leader */
    double *ja_scratch; /* 2 np: interface-inertia differences */
    double *ework; /* engine co-simulation scratch (ts_powertrain_work_size) */
};

/* monolithic right-hand side and roots */
static int mono_rhs(double t, const double *y, double *ydot, void *ud)
{
    ts_coupled_run *r = ud;
    const ts_coupled *c = r->c;
    ts_powertrain_out o;
    double w = sprocket_rel(c, y);
    int rc = pt_side(c, &r->ps, r->rack_fixed, t, y + c->nv, w, ydot + c->nv, &o, NULL);
    r->st.powertrain_rhs++;
    if (rc != 0) return rc;
    r->st.vehicle_rhs++;
    return vm_rhs_torque(c->v, r->w, t, y, o.sprocket_torque, 0.0, ydot, NULL);
}

static int mono_roots(double t, const double *y, double *g, void *ud)
{
    const ts_coupled_run *r = ud;
    ts_powertrain_roots(r->c->pt, &r->ps, t, y + r->c->nv, sprocket_rel(r->c, y), g);
    return 0;
}

/* The exchange's options from the run's coupling parameters. */
static ts_cosim_opts cosim_opts(const ts_coupled_run *r)
{
    return (ts_cosim_opts){r->co.leader_step, r->co.follower_step, r->co.lead,
                           r->co.predictor_order};
}

/* leader: powertrain side with the predicted sprocket speed */
static double lead_w(const ts_coupled_run *r, double t)
{
    return ts_cosim_predict(&r->last, r->last_order, t);
}

static int lead_rhs(double t, const double *y, double *ydot, void *ud)
{
    ts_coupled_run *r = ud;
    r->st.powertrain_rhs++;
    return pt_side(r->c, &r->ps, r->rack_fixed, t, y, lead_w(r, t), ydot, NULL, NULL);
}

static int lead_roots(double t, const double *y, double *g, void *ud)
{
    const ts_coupled_run *r = ud;
    ts_powertrain_roots(r->c->pt, &r->ps, t, y, lead_w(r, t), g);
    return 0;
}

/* follower: vehicle with the interpolated torque */
static int follow_rhs(double t, const double *y, double *ydot, void *ud)
{
    ts_coupled_run *r = ud;
    r->st.vehicle_rhs++;
    double tau = r->src ? ts_cosim_torque_at(r->src, t) : r->pub.torque;
    double j = r->src ? ts_cosim_inertia_at(r->src, t) : r->pub.inertia;
    return vm_rhs_torque(r->c->v, r->w, t, y, tau, j, ydot, NULL);
}

/* Discrete powertrain updates at (t, yp) with sprocket speed w; 1 if changed. */
static int settle(ts_coupled_run *r, double t, const double *yp, double w)
{
    return ts_powertrain_update(r->c->pt, &r->ps, t, yp, w);
}

/* The turbine equation f = dw_t/dt linearised at (t, yp, w): its partial
 * derivatives in the turbine speed and the sprocket speed, and that of the
 * sprocket torque in the turbine speed (central differences; the steps are
 * numerical constants, far below the clutch's creep band). */
typedef struct turbine_lin {
    double f, f_wt, f_w, T_wt;
} turbine_lin;

static turbine_lin linearise_turbine(ts_coupled_run *r, double t, const double *yp, double w)
{
    const ts_coupled *c = r->c;
    const int it = c->npt - 1; /* turbine speed */
    const double d_t = 1e-4, d_w = 1e-5; /* difference steps [rad/s] */
    double *y = r->ja_scratch, *yd = y + c->np;
    memcpy(y, yp, sizeof(double) * (size_t)c->np);
    /* the turbine equation does not depend on the rack (rhs_driveline only
     * reports it), so the driver/governor command is not evaluated here */
    const double rack = r->rack_fixed;
    ts_powertrain_out o;
    double f[4], T[2];
    for (int k = 0; k < 2; k++) {
        y[it] = yp[it] + (k ? -d_t : d_t);
        ts_powertrain_rhs_driveline(c->pt, &r->ps, t, y, w, rack, yd, &o);
        f[k] = yd[it];
        T[k] = o.sprocket_torque;
    }
    y[it] = yp[it];
    for (int k = 0; k < 2; k++) {
        ts_powertrain_rhs_driveline(c->pt, &r->ps, t, y, w + (k ? -d_w : d_w), rack, yd, NULL);
        f[2 + k] = yd[it];
    }
    ts_powertrain_rhs_driveline(c->pt, &r->ps, t, y, w, rack, yd, NULL);
    turbine_lin l = {yd[it], (f[0] - f[1]) / (2 * d_t), (f[2] - f[3]) / (2 * d_w),
                     (T[0] - T[1]) / (2 * d_t)};
    return l;
}

/* Interface inertia J_a: the inertia the leader's sprocket torque T carries
 * through the turbine, which its stiff range clutches slave to the sprocket.
 * With f(w_t, w) = dw_t/dt the turbine equation, the fast turbine relaxes
 * onto w_t = w_qs(w) - f_w alpha / f_wt^2 (+ slower terms), so
 *     dT/d(alpha) = -J_a,   J_a = T_wt f_w / f_wt^2,
 * from the leader's own equations (gear ratios, efficiencies, clutch
 * stiffness and the converter's damping all enter; a slipping clutch's
 * stiffness is ~0, so it carries none). */
static double interface_inertia(ts_coupled_run *r, double t, const double *yp, double w,
                                double *tau)
{
    const ts_coupled *c = r->c;
    *tau = 0.0;
    turbine_lin l = linearise_turbine(r, t, yp, w);
    if (!(fabs(l.f_wt) > 0)) return 0.0;
    *tau = l.f_wt < 0 ? -1.0 / l.f_wt : 0.0;
    double j = l.T_wt * l.f_w / (l.f_wt * l.f_wt);
    return c->cfg.coupling.interface_inertia * (j > 0 ? j : 0.0);
}

/* The leader's sample at t: torque + J_a alpha_k + the turbine-lag term (J_a
 * rides on the follower's sprocket; the two cancel as the step goes to 0).
 *
 * Turbine lag. The slaved turbine's next term is a lag tau = -1/f_wt (~50 us
 * with an applied clutch): for a smooth sprocket speed the leader's torque is
 *     T = T_static(w) - J_a alpha + J_a tau dalpha/dt + ...
 * but within a leader step the predictor's alpha is the constant alpha_k, so
 * T lacks J_a tau dalpha/dt at every step longer than tau: an error that does
 * not shrink with h (observed: a plateau of ~1.5e-4 RMS in sprocket speed on
 * the static-track launch, below 1 ms steps). Its exact value for a held
 * alpha_k over steps H (first-order lag of step inputs rising by
 * dalpha/dt H per step) leaves the filtered alpha behind alpha_k by
 * dalpha/dt H q/(1-q), q = exp(-H/tau); the sample adds
 *     J_a dalpha/dt (tau - H q/(1-q))
 * with dalpha/dt from the last two reports (tau for H >> tau, -> 0 for
 * H << tau, where the leader resolves the lag itself). Explicit, from
 * reported data only; its error is O(tau h), below the O(h^2) of the
 * predictor at the steps used. */
static ts_cosim_sample publish(ts_coupled_run *r, double t, const double *yp, double w,
                               const ts_powertrain_out *o)
{
    double tau;
    double j = interface_inertia(r, t, yp, w, &tau);
    double lag = 0.0;
    if (r->prev.t < r->last.t && tau > 0 && r->step > 0) {
        double jerk = (r->last.alpha - r->prev.alpha) / (r->last.t - r->prev.t);
        double q = exp(-r->step / tau);
        lag = j * jerk * (tau - r->step * q / (1.0 - q));
    }
    ts_cosim_sample s = {t, o->sprocket_torque + j * r->last.alpha + lag, j};
    r->pub = s;
    return s;
}

/* Explicit leader path (crank-angle engine with /driveline/engine_macro_step
 * = 0, powertrain.h): classical RK4 at
 * ts_powertrain_explicit_step, the shift state machine at every step end. */
static ts_rc lead_explicit(ts_coupled_run *r, double t_to, ts_err *err)
{
    const ts_coupled *c = r->c;
    double *y = r->yp;
    while (r->lead_t < t_to - 1e-12 * (1.0 + fabs(t_to))) {
        double h = ts_powertrain_explicit_step(c->pt, y), t = r->lead_t;
        if (t + h > t_to) h = t_to - t;
        if (ts_rk4_step(c->np, lead_rhs, r, t, h, y, r->rk))
            return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                              "powertrain state left its domain at t = %.6f s", t);
        r->st.powertrain_rk4_steps++;
        r->lead_t = t + h;
        settle(r, r->lead_t, y, lead_w(r, r->lead_t));
    }
    r->lead_t = t_to;
    r->lead_dirty = 1; /* the implicit path (if the engine ever leaves RK4) restarts */
    return TS_OK;
}

/* Leader's turbine + IVS-integral derivatives with the engine held (engine
 * co-simulation, powertrain.h). */
static void lead_rhs_driveline(ts_coupled_run *r, double t, const double *y, double *ydot)
{
    const ts_coupled *c = r->c;
    double w = lead_w(r, t);
    drive_cmd d = command(c, r->rack_fixed, y, w);
    ts_powertrain_rhs_driveline(c->pt, &r->ps, t, y, w, d.rack, ydot, NULL);
    ydot[c->npt] = c->ivs_on ? ts_ivs_integral_rate(&c->ivs, c->gains, d.e, y[c->npt]) : 0.0;
    r->st.powertrain_rhs++;
}

/* Co-simulated engine (crank-angle, ts_powertrain_macro_step > 0): per macro
 * step the engine advances itself with the rack of the step start, then RK4
 * sub-steps of the turbine and the IVS integral with the engine held; the
 * shift state machine at every sub-step end. */
static int lead_rhs_held(double t, const double *y, double *ydot, void *ud)
{
    lead_rhs_driveline(ud, t, y, ydot);
    return 0;
}

static ts_rc lead_cosim(ts_coupled_run *r, double t_to, ts_err *err)
{
    const ts_coupled *c = r->c;
    double *y = r->yp, *yd = r->rk, work[10];
    const int idx[2] = {c->npt - 1, c->npt}; /* turbine, IVS integral */
    while (r->lead_t < t_to - 1e-12 * (1.0 + fabs(t_to))) {
        double t_end = r->lead_t + ts_powertrain_macro_step(c->pt);
        if (t_end > t_to - 1e-12 * (1.0 + fabs(t_to))) t_end = t_to;
        drive_cmd d = command(c, r->rack_fixed, y, lead_w(r, r->lead_t));
        ts_rc rc = ts_powertrain_engine_advance(c->pt, r->lead_t, t_end - r->lead_t, y, d.rack,
                                                r->ework, err);
        if (rc != TS_OK) return rc;
        while (r->lead_t < t_end - 1e-12 * (1.0 + fabs(t_end))) {
            double h = ts_powertrain_explicit_step(c->pt, y), t0 = r->lead_t;
            if (t0 + h > t_end) h = t_end - t0;
            if (ts_rk4_step_subset(2, idx, lead_rhs_held, r, t0, h, y, yd, work))
                return ts_err_set(err, TS_ERR_DIVERGED, NULL,
                                  "powertrain state left its domain at t = %.6f s", t0);
            r->st.powertrain_rk4_steps++;
            r->lead_t = t0 + h;
            settle(r, r->lead_t, y, lead_w(r, r->lead_t));
        }
        r->lead_t = t_end;
    }
    r->lead_t = t_to;
    r->lead_dirty = 1;
    return TS_OK;
}

/* The leader's CVODE to t_to (implicit path), never stepping past t_to: the
 * next report changes the predicted sprocket speed from t_to on, which the
 * integrator's history must not have seen. It is NOT restarted at a report:
 * the prediction jumps by the last macro step's prediction error (O(h^2) in
 * omega) and the integrator's error test absorbs that jump in a step or two,
 * where a restart (order 1, a fresh initial step) cost ~40 right-hand sides
 * per 1-ms exchange (bench_coupled: ~4x the leader's right-hand sides). If
 * the error test cannot get past a jump (tight tolerances: rtol 1e-9 with a
 * stiff turbine), it restarts there, once per call. Restarts always after a
 * discrete update (gear-shift event) and when lead_dirty is set. */
static ts_rc lead_ode_advance(ts_coupled_run *r, double t_to, ts_err *err)
{
    const ts_coupled *c = r->c;
    ts_rc rc = TS_OK;
    int restarted = 0;
    if (r->lead_dirty) {
        rc = ts_ode_init(r->lead_ode, r->lead_t, r->yp, err);
        r->lead_dirty = 0;
        r->st.leader_inits++;
        restarted = 1;
    }
    if (rc == TS_OK) rc = ts_ode_set_stop(r->lead_ode, t_to, err);
    while (rc == TS_OK && r->lead_t < t_to) {
        int root = 0;
        ts_err e1;
        rc = ts_ode_advance(r->lead_ode, t_to, &r->lead_t, &root, &e1);
        if (rc != TS_OK) {
            if (restarted) {
                if (err) *err = e1;
                break;
            }
            restarted = 1;
            r->st.leader_inits++;
            rc = ts_ode_init(r->lead_ode, r->lead_t, r->yp, err);
            if (rc == TS_OK) rc = ts_ode_set_stop(r->lead_ode, t_to, err);
            continue;
        }
        memcpy(r->yp, ts_ode_y(r->lead_ode), sizeof(double) * (size_t)c->np);
        if (root && settle(r, r->lead_t, r->yp, lead_w(r, r->lead_t))) {
            rc = ts_ode_init(r->lead_ode, r->lead_t, r->yp, err);
            if (rc == TS_OK && r->lead_t < t_to) rc = ts_ode_set_stop(r->lead_ode, t_to, err);
        }
    }
    return rc;
}

static ts_rc lead_advance(void *ud, double t_to, const ts_cosim_report *last, int order,
                          ts_cosim_sample *out, ts_err *err)
{
    ts_coupled_run *r = ud;
    const ts_coupled *c = r->c;
    double w0 = ts_monotonic_seconds();
    r->step = t_to - r->lead_t;
    if (memcmp(last, &r->last, sizeof *last) != 0 || order != r->last_order) {
        if (last->t > r->last.t) r->prev = r->last;
        r->last = *last;
        r->last_order = order;
        /* no restart: the leader's integrator carries on across the
         * predictor's jump (lead_ode_advance) */
    }
    ts_rc rc = TS_OK;
    if (settle(r, r->lead_t, r->yp, lead_w(r, r->lead_t))) r->lead_dirty = 1;
    if (ts_powertrain_macro_step(c->pt) > 0) {
        rc = lead_cosim(r, t_to, err);
    } else if (ts_powertrain_explicit_step(c->pt, r->yp) > 0) {
        rc = lead_explicit(r, t_to, err);
    } else {
        rc = lead_ode_advance(r, t_to, err);
    }
    if (rc == TS_OK) {
        ts_powertrain_out o;
        rc = pt_side_at(c, &r->ps, r->rack_fixed, r->lead_t, r->yp, lead_w(r, r->lead_t),
                        r->ylead_scratch, &o, NULL, err);
        if (rc == TS_OK) *out = publish(r, r->lead_t, r->yp, lead_w(r, r->lead_t), &o);
    }
    r->st.powertrain_wall += ts_monotonic_seconds() - w0;
    return rc;
}

static ts_rc vehicle_report(ts_coupled_run *r, double t, ts_cosim_sample s, ts_cosim_report *rep,
                            ts_err *err)
{
    const ts_coupled *c = r->c;
    if (vm_rhs_torque(c->v, r->w, t, r->yv, s.torque, s.inertia, r->ydv, NULL) != 0)
        return vm_rhs_failed(c->v, t, r->yv, err);
    rep->t = t;
    rep->omega = sprocket_rel(c, r->yv);
    rep->alpha = r->ydv[c->nq + SPIN_SPROCKET] - r->ydv[c->nq + Q_THETA];
    return TS_OK;
}

static ts_rc follow_advance(void *ud, double t_to, const ts_cosim_torque *src, ts_cosim_report *out,
                            ts_err *err)
{
    ts_coupled_run *r = ud;
    double w0 = ts_monotonic_seconds();
    r->src = src;
    double t;
    /* never step past the last published sample: CVODE would step beyond t_to
     * with the torque held there and keep that in its history (measured: 34 %
     * of the follower's right-hand sides at the default tolerances) */
    ts_rc rc = TS_OK;
    double t_stop = ts_cosim_torque_end(src);
    if (t_stop > r->follow_stop) {
        rc = ts_ode_set_stop(r->follow_ode, t_stop, err);
        r->follow_stop = t_stop;
    }
    if (rc == TS_OK) {
        rc = ts_ode_advance(r->follow_ode, t_to, &t, NULL, err);
        if (rc != TS_OK) vm_err_add_state(r->c->v, ts_ode_y(r->follow_ode), err);
    }
    if (rc == TS_OK) {
        memcpy(r->yv, ts_ode_y(r->follow_ode), sizeof(double) * (size_t)r->c->nv);
        r->t = t_to;
        ts_cosim_sample s = {t_to, ts_cosim_torque_at(src, t_to), ts_cosim_inertia_at(src, t_to)};
        rc = vehicle_report(r, t_to, s, out, err);
        if (rc == TS_OK) r->rep = *out;
    }
    r->src = NULL;
    r->st.vehicle_wall += ts_monotonic_seconds() - w0;
    return rc;
}

void ts_coupled_run_free(ts_coupled_run *r)
{
    if (!r) return;
    ts_ode_free(r->mono);
    ts_ode_free(r->lead_ode);
    ts_ode_free(r->follow_ode);
    ts_cosim_free(r->cosim);
    vm_work_free(r->w);
    free(r->ework);
    free(r->yv);
    free(r);
}

ts_coupled_run *ts_coupled_run_make(const ts_coupled *c, int method, ts_err *err)
{
    ts_coupled_run *r = calloc(1, sizeof *r);
    if (!r) goto nomem;
    r->c = c;
    r->method = method;
    r->co = c->cfg.coupling;
    r->rack_fixed = c->cfg.control.rack;
    int n = c->nv + c->np;
    /* yv, yp, ydv, ydp, ym (n), atol (n), lead scratch (np), RK4 stages (5 np),
     * interface-inertia differences (2 np) */
    r->yv = calloc((size_t)(4 * n + 8 * c->np), sizeof(double));
    r->w = vm_work_make(c->v);
    if (!r->yv || !r->w) goto nomem;
    size_t nw = ts_powertrain_work_size(c->pt);
    if (nw && !(r->ework = malloc(nw * sizeof *r->ework))) goto nomem;
    r->yp = r->yv + c->nv;
    r->ydv = r->yv + n;
    r->ydp = r->ydv + c->nv;
    r->ym = r->yv + 2 * n;
    double *atol = r->yv + 3 * n;
    r->ylead_scratch = r->yv + 4 * n;
    r->rk = r->ylead_scratch + c->np;
    r->ja_scratch = r->rk + 5 * c->np;
    const ts_run_config *rc = &c->cfg.run;
    vm_abs_tolerances(c->v, rc->atol, atol);
    ts_powertrain_scale(c->pt, atol + c->nv);
    for (int i = 0; i < c->npt; i++)
        atol[c->nv + i] *= rc->atol;
    atol[c->nv + c->npt] = rc->atol;
    if (method == TS_COUPLING_MONOLITHIC) {
        ts_ode_opts o = {.rtol = rc->rtol,
                         .atol = rc->atol,
                         .atol_v = atol,
                         .max_step = rc->max_step,
                         .max_steps = 1000000,
                         .nroots = ts_powertrain_nroots(c->pt),
                         .roots = mono_roots,
                         .small_dense = 1,
                         .max_order = VM_BDF_MAX_ORDER,
                         .jac_eval_frequency = VM_JAC_EVAL_STEPS};
        r->mono = ts_ode_make(n, mono_rhs, r, &o, err);
        if (!r->mono) goto fail;
    } else if (method == TS_COUPLING_LEADING_FOLLOWING) {
        /* the exchange is built at reset: its options are refused here */
        ts_cosim_opts co = cosim_opts(r);
        if (ts_cosim_check(&co, err) != TS_OK) goto fail;
        ts_ode_opts lo = {.rtol = rc->rtol,
                          .atol = rc->atol,
                          .atol_v = atol + c->nv,
                          .max_step = rc->max_step,
                          .max_steps = 1000000,
                          .nroots = ts_powertrain_nroots(c->pt),
                          .roots = lead_roots,
                          .small_dense = 1};
        r->lead_ode = ts_ode_make(c->np, lead_rhs, r, &lo, err);
        if (!r->lead_ode) goto fail;
        ts_ode_opts fo = {.rtol = rc->rtol,
                          .atol = rc->atol,
                          .atol_v = atol,
                          .max_step = rc->max_step,
                          .max_steps = 1000000,
                          .second_order = 1, /* y = [q, qd]: half-size Schur solves */
                          .max_order = VM_BDF_MAX_ORDER,
                          .jac_eval_frequency = VM_JAC_EVAL_STEPS};
        r->follow_ode = ts_ode_make(c->nv, follow_rhs, r, &fo, err);
        if (!r->follow_ode) goto fail;
    } else {
        ts_err_set(err, TS_ERR_PARAM, "/coupling/method", "/coupling/method: unknown method %d",
                   method);
        goto fail;
    }
    return r;
nomem:
    ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
fail:
    ts_coupled_run_free(r);
    return NULL;
}

/* (Re)start the integrators at r->t from yv, yp, with the leader's last
 * report and published torque given (leading-following). */
static ts_rc restart(ts_coupled_run *r, ts_cosim_report rep, ts_cosim_report prev,
                     ts_cosim_sample pub, ts_err *err)
{
    const ts_coupled *c = r->c;
    if (r->method == TS_COUPLING_MONOLITHIC) {
        memcpy(r->ym, r->yv, sizeof(double) * (size_t)(c->nv + c->np));
        settle(r, r->t, r->yp, sprocket_rel(c, r->yv));
        return ts_ode_init(r->mono, r->t, r->ym, err);
    }
    r->lead_t = r->t;
    r->prev = prev;
    r->step = 0.0;
    r->last = rep;
    r->last_order = r->co.predictor_order;
    r->rep = rep;
    r->pub = pub;
    r->lead_dirty = 1;
    ts_rc rc = ts_ode_init(r->follow_ode, r->t, r->yv, err);
    if (rc != TS_OK) return rc;
    r->follow_stop = r->t;
    ts_cosim_free(r->cosim);
    ts_cosim_opts co = cosim_opts(r);
    r->cosim = ts_cosim_make_sample(&co, (ts_cosim_leader){r, lead_advance},
                                    (ts_cosim_follower){r, follow_advance}, r->t, rep, pub, err);
    return r->cosim ? TS_OK : (err ? err->code : TS_ERR_INTERNAL);
}

ts_rc ts_coupled_run_reset(ts_coupled_run *r, ts_err *err)
{
    const ts_coupled *c = r->c;
    r->t = 0.0;
    r->rack_fixed = c->cfg.control.rack;
    memcpy(r->yv, vm_equilibrium(c->v), sizeof(double) * (size_t)c->nv);
    double w0 = sprocket_rel(c, r->yv);
    ts_rc rc = ts_powertrain_reset(c->pt, &r->ps, r->yp, w0, err);
    if (rc != TS_OK) return rc;
    r->yp[c->npt] = 0.0;
    settle(r, 0.0, r->yp, w0);
    ts_powertrain_out o;
    ts_cosim_report rep = {0.0, w0, 0.0};
    r->last = r->prev = rep;
    r->step = 0.0;
    ts_cosim_sample pub = {0.0, 0.0, 0.0};
    /* Consistent start: the turbine on its clutch's quasi-static creep,
     * accelerating with the sprocket (dw_t/dt = -f_w/f_wt alpha), alpha the
     * sprocket's answer to that torque. Without this the clutch takes up the
     * converter torque in a ~50-us boundary layer after t = 0 that a torque
     * sample at t = 0 cannot represent: the follower would interpolate a step
     * over the first macro step and lose half its impulse (O(h) forever). */
    for (int it = 0; it <= 4; it++) { /* four corrections, then the start's exchange */
        for (int k = 0; it < 4 && k < 8; k++) {
            turbine_lin l = linearise_turbine(r, 0.0, r->yp, w0);
            if (!(fabs(l.f_wt) > 0)) break;
            double g = l.f + l.f_w / l.f_wt * rep.alpha;
            r->yp[c->npt - 1] -= g / l.f_wt;
        }
        rc = pt_side_at(c, &r->ps, r->rack_fixed, 0.0, r->yp, w0, r->ydp, &o, NULL, err);
        if (rc != TS_OK) return rc;
        pub = publish(r, 0.0, r->yp, w0, &o);
        rc = vehicle_report(r, 0.0, pub, &rep, err);
        if (rc != TS_OK) return rc;
        r->last = rep;
    }
    if (r->method != TS_COUPLING_LEADING_FOLLOWING)
        pub = (ts_cosim_sample){0.0, o.sprocket_torque, 0.0};
    return restart(r, rep, rep, pub, err);
}

ts_rc ts_coupled_run_advance(ts_coupled_run *r, double t_to, ts_err *err)
{
    const ts_coupled *c = r->c;
    if (r->method == TS_COUPLING_LEADING_FOLLOWING) {
        ts_rc rc = ts_cosim_advance(r->cosim, t_to, err);
        r->st.exchanges = ts_cosim_exchanges(r->cosim);
        return rc;
    }
    double w0 = ts_monotonic_seconds();
    ts_rc rc = TS_OK;
    while (rc == TS_OK && r->t < t_to) {
        int root = 0;
        rc = ts_ode_advance(r->mono, t_to, &r->t, &root, err);
        if (rc != TS_OK) { /* the vehicle's states lead the monolithic vector */
            vm_err_add_state(c->v, ts_ode_y(r->mono), err);
            break;
        }
        memcpy(r->ym, ts_ode_y(r->mono), sizeof(double) * (size_t)(c->nv + c->np));
        memcpy(r->yv, r->ym, sizeof(double) * (size_t)(c->nv + c->np));
        if (root && settle(r, r->t, r->yp, sprocket_rel(c, r->yv)))
            rc = ts_ode_init(r->mono, r->t, r->ym, err);
    }
    /* one integrator: its wall time is shared; book it on the vehicle side */
    r->st.vehicle_wall += ts_monotonic_seconds() - w0;
    return rc;
}

double ts_coupled_run_time(const ts_coupled_run *r)
{
    return r->t;
}

ts_rc ts_coupled_run_set_rack(ts_coupled_run *r, double rack, ts_err *err)
{
    if (!(rack >= 0 && rack <= 1))
        return ts_err_set(err, TS_ERR_RANGE, "/control/rack", "/control/rack: %g not in [0, 1]",
                          rack);
    r->rack_fixed = rack;
    if (r->method == TS_COUPLING_MONOLITHIC) return ts_ode_init(r->mono, r->t, r->ym, err);
    r->lead_dirty = 1;
    return TS_OK;
}

ts_rc ts_coupled_run_observe(ts_coupled_run *r, ts_coupled_obs *o, ts_err *err)
{
    const ts_coupled *c = r->c;
    memset(o, 0, sizeof *o);
    o->t = r->t;
    double w_pt;
    if (r->method == TS_COUPLING_MONOLITHIC) {
        w_pt = sprocket_rel(c, r->yv);
    } else {
        w_pt = lead_w(r, r->lead_t); /* the leader's view of the sprocket */
    }
    drive_cmd d;
    ts_rc rc = pt_side_at(c, &r->ps, r->rack_fixed, r->t, r->yp, w_pt, r->ydp, &o->pt, &d, err);
    if (rc != TS_OK) return rc;
    ts_cosim_sample s = {r->t, o->pt.sprocket_torque, 0.0};
    if (r->method == TS_COUPLING_LEADING_FOLLOWING) s = r->pub;
    if (vm_rhs_torque(c->v, r->w, r->t, r->yv, s.torque, s.inertia, r->ydv, &o->diag) != 0)
        return vm_rhs_failed(c->v, r->t, r->yv, err);
    o->diag.drive_torque = o->pt.sprocket_torque;
    o->y_vehicle = r->yv;
    o->ydot_vehicle = r->ydv;
    o->sprocket_speed = sprocket_rel(c, r->yv);
    o->sprocket_accel = r->ydv[c->nq + SPIN_SPROCKET] - r->ydv[c->nq + Q_THETA];
    o->sprocket_torque = o->pt.sprocket_torque;
    o->speed_measured = w_pt * c->r_s;
    o->speed_error = d.e;
    o->integral = r->yp[c->npt];
    o->rack_demand = d.demand;
    o->rack = d.rack;
    o->ps = r->ps;
    return TS_OK;
}

void ts_coupled_run_stats(const ts_coupled_run *r, ts_coupled_stats *s)
{
    *s = r->st;
    ts_ode *v = r->mono ? r->mono : r->follow_ode;
    ts_ode_stats os;
    if (v) {
        ts_ode_get_stats(v, &os);
        s->vehicle_steps = os.steps;
        s->vehicle_jacs = os.jac_evals;
        s->vehicle_err_fails = os.err_test_fails;
        s->vehicle_newton = os.nonlin_iters;
        s->vehicle_newton_fails = os.nonlin_fails;
    }
    if (r->lead_ode) {
        ts_ode_get_stats(r->lead_ode, &os);
        s->powertrain_steps = os.steps;
        s->powertrain_setups = os.lin_setups;
    }
    s->powertrain_n = r->c->np;
}

int ts_coupled_run_integrators(const ts_coupled_run *r, ts_integrator_stats *out, int max)
{
    int n = 0;
    if (max <= 0) return 0;
    if (r->mono) {
        ts_integrator_stats_of_ode(r->mono, "vehicle+powertrain",
                                   "CVODE BDF (order <= 3), Newton, dense LU (monolithic)", out);
        return 1;
    }
    if (r->follow_ode)
        ts_integrator_stats_of_ode(r->follow_ode, "vehicle",
                                   "CVODE BDF (order <= 3), Newton, Schur-complement solves "
                                   "(follower)",
                                   &out[n++]);
    if (n < max && r->st.powertrain_rk4_steps > 0) {
        long k = r->st.powertrain_rk4_steps;
        out[n++] = (ts_integrator_stats){.name = "powertrain",
                                         .method = "classical RK4, fixed step (leader)",
                                         .steps = k,
                                         .rhs_evals = 4 * k,
                                         .jac_evals = -1,
                                         .lin_setups = -1,
                                         .err_test_fails = -1,
                                         .newton_iters = -1,
                                         .newton_fails = -1};
    }
    if (n < max && r->lead_ode) {
        ts_integrator_stats s;
        ts_integrator_stats_of_ode(r->lead_ode, "powertrain", "CVODE BDF, Newton, dense LU (leader)",
                                   &s);
        if (s.steps > 0 || r->st.powertrain_rk4_steps == 0) out[n++] = s;
    }
    return n;
}

/* Saved state: t, rack_fixed, report (t, omega, alpha), published torque and
 * inertia, the report before (t, omega, alpha; turbine-lag term), then yv,
 * yp, then the discrete powertrain state. */
#define SAVE_HEAD 10

size_t ts_coupled_state_size(const ts_coupled *c)
{
    return sizeof(double) * (size_t)(SAVE_HEAD + c->nv + c->np) + sizeof(ts_powertrain_state);
}

void ts_coupled_run_save(const ts_coupled_run *r, void *buf)
{
    /* the follower's last report is the leader's current one; the one before */
    const ts_cosim_report *pr = r->last.t < r->rep.t ? &r->last : &r->prev;
    double head[SAVE_HEAD] = {r->t,          r->rack_fixed, r->rep.t,  r->rep.omega,
                              r->rep.alpha,  r->pub.torque, r->pub.inertia, pr->t,
                              pr->omega,     pr->alpha};
    char *b = buf;
    size_t n = (size_t)(r->c->nv + r->c->np);
    memcpy(b, head, sizeof head);
    memcpy(b + sizeof head, r->yv, sizeof(double) * n);
    memcpy(b + sizeof head + sizeof(double) * n, &r->ps, sizeof r->ps);
}

ts_rc ts_coupled_run_restore(ts_coupled_run *r, const void *buf, ts_err *err)
{
    double head[SAVE_HEAD];
    const char *b = buf;
    size_t n = (size_t)(r->c->nv + r->c->np);
    memcpy(head, b, sizeof head);
    memcpy(r->yv, b + sizeof head, sizeof(double) * n);
    memcpy(&r->ps, b + sizeof head + sizeof(double) * n, sizeof r->ps);
    r->t = head[0];
    r->rack_fixed = head[1];
    ts_cosim_report rep = {head[2], head[3], head[4]}, prev = {head[7], head[8], head[9]};
    return restart(r, rep, prev, (ts_cosim_sample){head[0], head[5], head[6]}, err);
}
