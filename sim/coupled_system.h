/*
 * coupled_system.h — the integrated engine–vehicle system of paper Section IV:
 * the powertrain (powertrain.h: engine + torque converter + transmission +
 * final drive) drives the pitch-plane multibody vehicle with its track
 * (vehicle_model.h) at the drive sprocket (Fig. 22); the driver is a fixed
 * rack or the IVS speed controller (ivs_controller.h, Eq. 10, Fig. 25) feeding
 * the fuel actuator (constant-phi law of the engine, Eqs. 13-14, behind the
 * two-speed governor, governor.h).
 *
 * Two ways to integrate the same equations (/coupling/method):
 *   leading_following  the powertrain side (powertrain states + controller
 *       integral) is the LEADER on its own CVODE instance and macro step; it
 *       sees the sprocket speed predicted from the vehicle's last report and
 *       publishes sprocket-torque samples; the vehicle is the FOLLOWER on its
 *       own CVODE instance and macro step, taking the torque interpolated from
 *       the samples and reporting (t, omega, alpha) — cosim.h, Section IV.A.
 *   monolithic  one CVODE instance over [vehicle, powertrain, integral]: the
 *       reference for the coupling error.
 *
 * Interface quantities: sprocket speed omega and acceleration alpha are the
 * sprocket spin RELATIVE TO THE HULL (the driveline turns with the hull);
 * torque is at EACH sprocket (the vehicle model is one side). The controller
 * measures vehicle speed as omega x /vehicle/sprocket_radius (a wheel-speed
 * sensor on the final drive: no track slip, ripple from track vibration
 * included); in leading_following it sees the leader's predicted omega.
 * The powertrain's output inertia (transmission output, final drives,
 * sprockets, /driveline/output_inertia, both sides) is carried by the
 * vehicle's sprocket: its per-side spin inertia becomes
 * max(/vehicle/sprocket_inertia, output_inertia / 2) — the driveline figure
 * already includes the sprocket.
 * Leading-following exchanges the torque explicitly, and the leader's torque
 * carries the turbine's inertia torque through the PREDICTED acceleration
 * (with an applied range clutch the turbine turns with the sprocket): an
 * added-mass coupling that diverges when that inertia (J_t (g f)^2 / 2 per
 * side, 64 kg m^2 in 1st gear) exceeds the vehicle sprocket's (20 kg m^2).
 * So the leader publishes torque + J_a alpha_k together with J_a, and the
 * follower carries J_a on its sprocket (vm_rhs_torque's extra inertia), J_a =
 * /coupling/interface_inertia x the inertia the leader's torque really carries:
 *   J_a = T_wt f_w / f_wt^2   (f = dw_t/dt of the turbine, T the sprocket
 *                              torque; partial derivatives at the leader's state)
 * — the slaved turbine's -dT/d(alpha), with gear and final-drive efficiencies,
 * the clutch stiffness (0 when slipping, so J_a follows the gear and the
 * shifts) and the converter's damping. It must be EXACT for second order: the
 * part of the inertia left in the explicit exchange sees the held alpha_k,
 * an O(h) error (an earlier J_t f^2/2 sum g_i^2 (1 - (T_i/C_i)^2) was 12 %
 * off: no efficiencies, lock < 1 under load). J_a cancels as the step goes to
 * 0 (the monolithic run has none); it only removes the explicit added mass.
 * Two more terms keep the scheme second order (docs/coupled.md):
 *   - the turbine's lag tau = -1/f_wt (~50 us): the sample adds
 *     J_a dalpha/dt (tau - H q/(1-q)), q = exp(-H/tau), H the leader step,
 *     dalpha/dt from the last two reports (the leader's predicted alpha is
 *     constant within a step, so its torque lacks J_a tau dalpha/dt);
 *   - a consistent start: at reset the turbine sits on its clutch's
 *     quasi-static creep, accelerating with the sprocket, instead of taking up
 *     the converter torque in a 50-us boundary layer that the first torque
 *     sample cannot represent (both methods start from that state).
 *
 * Leaves out: track slip anywhere but the vehicle's anchor; the injection
 * system's dynamics (ideal, Section IV.C); a gain schedule that varies during
 * a run (the schedule variable — mass or grade — is a run constant).
 *
 * Ownership: ts_coupled_make / ts_coupled_free (immutable after make,
 * shareable); ts_coupled_run_make / ts_coupled_run_free (one per thread).
 */
#ifndef TS_COUPLED_SYSTEM_H
#define TS_COUPLED_SYSTEM_H

#include "config.h"
#include "errors.h"
#include "powertrain.h"
#include "vehicle_model.h"

typedef struct ts_coupled ts_coupled;

ts_coupled *ts_coupled_make(const ts_config *cfg, ts_err *err);
/* With a caller-supplied engine port (tests): see ts_powertrain_make_port. */
ts_coupled *ts_coupled_make_port(const ts_config *cfg, const ts_engine_port *port, ts_err *err);
void ts_coupled_free(ts_coupled *c);

const vm *ts_coupled_vehicle(const ts_coupled *c);
const ts_powertrain *ts_coupled_powertrain(const ts_coupled *c);
/* IVS gains in force (schedule evaluated at the run's mass or grade). */
double ts_coupled_kp(const ts_coupled *c);
double ts_coupled_ti(const ts_coupled *c);

/* Everything observable at the current time of a run. */
typedef struct ts_coupled_obs {
    double t;                /* [s] */
    const double *y_vehicle; /* vehicle state (vm_ny values), borrowed until the next call */
    const double *ydot_vehicle;
    double sprocket_speed;  /* relative to the hull [rad/s] */
    double sprocket_accel;  /* [rad/s^2] */
    double sprocket_torque; /* powertrain output at each sprocket [N*m] (leading-following:
                               the leader's, without the interface-inertia term) */
    double speed_measured;  /* omega x sprocket radius, what the controller sees [m/s] */
    double speed_error;     /* target - measured (IVS), 0 in rack mode [m/s] */
    double integral;        /* IVS integral state [m] */
    double rack_demand;     /* driver or controller rack, before the governor [1] */
    double rack;            /* governed rack seen by the engine [1] */
    vm_diag diag;           /* vehicle element forces */
    ts_powertrain_out pt;   /* every shaft */
    ts_powertrain_state ps; /* gear, shift */
} ts_coupled_obs;

typedef struct ts_coupled_stats {
    long vehicle_rhs, powertrain_rhs;     /* right-hand-side evaluations */
    long exchanges;                       /* co-simulation messages */
    double vehicle_wall, powertrain_wall; /* wall seconds inside each side's integrator */
    /* CVODE counters of the integrator carrying the vehicle (the follower, or
     * the monolithic one): steps, Jacobian evaluations, error-test failures,
     * Newton iterations, Newton convergence failures */
    long vehicle_steps, vehicle_jacs, vehicle_err_fails, vehicle_newton, vehicle_newton_fails;
    long powertrain_steps;  /* the leader's CVODE steps (0 for the RK4 / co-simulated leader) */
    long powertrain_setups; /* the leader's Newton-matrix factorisations */
    long powertrain_rk4_steps; /* the leader's fixed RK4 steps (explicit / co-simulated paths) */
    int powertrain_n;       /* powertrain-side states (powertrain + IVS integral) */
    long leader_inits;      /* leader CVODE (re)starts */
} ts_coupled_stats;

typedef struct ts_coupled_run ts_coupled_run;

/* method: ts_coupling_method; the coupling options come from the config. */
ts_coupled_run *ts_coupled_run_make(const ts_coupled *c, int method, ts_err *err);
void ts_coupled_run_free(ts_coupled_run *r);

/* t = 0: vehicle at its static equilibrium, at rest; powertrain reset (idle,
 * 1st gear); controller integral 0. */
TS_MUST_CHECK ts_rc ts_coupled_run_reset(ts_coupled_run *r, ts_err *err);
/* Integrate to exactly t_to. */
TS_MUST_CHECK ts_rc ts_coupled_run_advance(ts_coupled_run *r, double t_to, ts_err *err);
double ts_coupled_run_time(const ts_coupled_run *r);
/* Rack demand of mode "rack" from now on (a driver's step; `tanksim tune`). */
TS_MUST_CHECK ts_rc ts_coupled_run_set_rack(ts_coupled_run *r, double rack, ts_err *err);
/* Observation at the current time (evaluates both right-hand sides; fails,
 * TS_ERR_DIVERGED, when either cannot be evaluated there). */
TS_MUST_CHECK ts_rc ts_coupled_run_observe(ts_coupled_run *r, ts_coupled_obs *o, ts_err *err);
void ts_coupled_run_stats(const ts_coupled_run *r, ts_coupled_stats *s);
/* The run's integrators as ts_integrator_stats entries (model.h): the
 * monolithic one, or the follower (vehicle) and the leader (powertrain; its
 * RK4 path and its CVODE path each an entry once used). Returns the count
 * (at most max). */
int ts_coupled_run_integrators(const ts_coupled_run *r, ts_integrator_stats *out, int max);

/* Saved-state size (bytes), the same for every run of c. */
size_t ts_coupled_state_size(const ts_coupled *c);
void ts_coupled_run_save(const ts_coupled_run *r, void *buf);
TS_MUST_CHECK ts_rc ts_coupled_run_restore(ts_coupled_run *r, const void *buf, ts_err *err);

#endif
