/*
 * engine.h — the virtual V-12 diesel (paper Section III.A-B.1, B.3; Figs. 15, 18)
 * as a set of ODEs the CALLER integrates.
 *
 * Model/state split (as MuJoCo's mjModel/mjData): a ts_engine is built once
 * from a ts_config (/engine section) and is then read-only and shareable; the
 * engine's dynamic state is a plain double vector x[ts_engine_nstate(e)] owned
 * by the caller, so the powertrain (and the coupled vehicle run) can put the
 * engine's states into one ODE with the driveline and integrate them with its
 * own integrator (CVODE or anything else). ts_engine_rhs has no side effects.
 *
 * Fidelities (/engine/fidelity), same interface and same x[0], x[1]:
 *   crank_angle  twelve 0-D cylinders, valves, Watson burning, K-k heat
 *                transfer, layered walls, two turbo banks with intercoolers and
 *                filling-and-emptying manifolds, Millington-Hartles friction,
 *                crank-angle-varying inertia (512 states). ts_engine_advance
 *                integrates it with an error-controlled MULTIRATE scheme at
 *                ~12-17x real time at rated (2 cores shared; bench_engine);
 *                a caller's RK4 of all 512 states at the 0.5-deg
 *                /engine/ca_step costs ~10x more, CVODE ~100x more again. A
 *                caller that integrates a powertrain around the engine
 *                should co-simulate it with ts_engine_advance_load.
 *   mean_value   cycle-averaged cylinders (tables from the crank-angle sweep)
 *                with the intercoolers, manifolds and turbos kept (28 states).
 *   map          full-load torque map from the crank-angle sweep + first-order
 *                boost lag (3 states).
 * Each bank's turbine has a boost-sensing wastegate (/engine/wg_*; opening
 * linear in boost between crack and full): the turbine is sized for
 * low-speed boost and the wastegate, calibrated at the rated point, bypasses
 * exhaust at high speed (not in the paper; it also absorbs most of the LHR
 * engines' extra exhaust energy, see engine.json wg_area). A schedule in
 * engine speed (/engine/turb_sched_*) can open the nozzle (variable
 * geometry), override the gate and hold a bypass open. No governor: a
 * free-running engine at full rack with too little load overspeeds; speed
 * limiting belongs to the control layer.
 *
 * Fuel actuator hook: inputs.fuel_per_cycle >= 0 is injected as given (the
 * control layer owns the law); inputs.fuel_per_cycle < 0 means "use the default
 * fuel law": the constant-phi actuator of Eqs. 13-14 (fuel_actuator.h) driven by
 * inputs.rack and the engine's own intake air flow.
 *
 * Units: SI throughout (rad/s, N*m, Pa, K, kg/s); rpm only in Eq. 13/friction
 * correlations inside. Ownership: ts_engine_make / ts_engine_free (NULL no-op).
 */
#ifndef TS_ENGINE_H
#define TS_ENGINE_H

#include <stddef.h>

#include "config.h"
#include "errors.h"

typedef struct ts_engine ts_engine;

/* Indices into x fixed for every fidelity. */
#define TS_ENGINE_X_SPEED 0 /* crankshaft speed [rad/s] */
#define TS_ENGINE_X_ANGLE 1 /* crank angle, cylinder 1 firing TDC = 0, grows [rad] */

typedef struct ts_engine_inputs {
    double rack;           /* driver/IVS signal in [0, 1] (default fuel law) */
    double fuel_per_cycle; /* kg per cylinder per cycle; < 0: default law from rack */
    double load_torque;    /* load on the flywheel, opposing rotation [N*m] */
    double p_amb, T_amb;   /* ambient pressure [Pa] and temperature [K] */
    int hold_speed;        /* dynamometer: crank speed held (its derivative = 0) */
    double load_inertia;   /* inertia turning rigidly with the crankshaft beyond the
                              engine's own (e.g. the converter pump) [kg*m^2]; 0: none */
} ts_engine_inputs;

typedef struct ts_engine_outputs {
    double speed;            /* crankshaft speed [rad/s] */
    double brake_torque;     /* indicated - friction: torque delivered to the load [N*m]
                                (instantaneous for crank_angle; load in steady state) */
    double indicated_torque; /* gas-pressure torque [N*m] */
    double friction_torque;  /* Millington-Hartles friction torque [N*m] */
    double boost;            /* intake manifold pressure, mean of the banks [Pa] */
    double intake_temp;      /* intake manifold temperature, mean of the banks [K] */
    double exhaust_temp;     /* exhaust manifold temperature, mean of the banks [K] */
    double air_flow;         /* compressor air mass flow, both banks [kg/s] */
    double fuel_flow;        /* fuel mass flow being injected, whole engine [kg/s] */
    double fuel_per_cycle;   /* fuel per cylinder per cycle actually commanded [kg] */
    double phi;              /* fuel/air equivalence ratio delivered [1] */
    double turbo_speed;      /* turbocharger rotor speed, mean of the banks [rad/s] */
    /* crank-angle fidelity only (0 otherwise): cylinder 1 */
    double cyl_pressure;        /* [Pa] */
    double cyl_temp;            /* [K] */
    double heat_release;        /* rate of fuel energy release, dQ/dt [W] */
    double piston_surface_temp; /* gas-side piston surface temperature [K] */
} ts_engine_outputs;

/* Build from cfg->engine. NULL on failure (err names the offending field). */
ts_engine *ts_engine_make(const ts_config *cfg, ts_err *err);
void ts_engine_free(ts_engine *e);

int ts_engine_get_fidelity(const ts_engine *e); /* ts_engine_fidelity enum value */
/* What an engine models, as bits of ts_engine_models, so that a channel table
 * can say what each channel needs. CYLINDERS: the cylinders' cycle and walls,
 * so the outputs cyl_pressure, cyl_temp, heat_release and piston_surface_temp
 * are set (the crank-angle fidelity). MANIFOLDS: the manifolds and
 * turbochargers, so intake_temp, exhaust_temp and turbo_speed are set
 * (crank-angle and mean-value; the map engine leaves them NaN). */
enum { TS_ENGINE_MODELS_CYLINDERS = 1u, TS_ENGINE_MODELS_MANIFOLDS = 2u };
unsigned ts_engine_models(const ts_engine *e);
/* Whether an engine that models `models` (ts_engine_models) sets a channel
 * that needs `needs` (TS_ENGINE_MODELS_* bits; 0: every engine does): the one
 * presence rule of the dyno's and the powertrain's channel tables. */
static inline int ts_engine_models_all(unsigned models, unsigned needs)
{
    return (needs & ~models) == 0;
}
int ts_engine_nstate(const ts_engine *e);       /* length of x */
/* Cycle-mean inertia of the crank train [kg*m^2]: /engine/inertia plus the mean
 * of the reciprocating parts' crank-angle-varying share (the inertia the
 * mean-value and map fidelities use; the crank-angle one varies about it). */
double ts_engine_mean_inertia(const ts_engine *e);

/* Initial state at crank speed omega [rad/s] and ambient p, T: manifolds at
 * ambient, turbos at /engine/turbo_idle_speed, walls at coolant temperature,
 * cylinders filled from the intake at their valve phase. */
void ts_engine_init_state(const ts_engine *e, double omega, double p_amb, double T_amb, double *x);

/* Idle steady state, the initial condition of a launch from standstill
 * ("a step increase of driver demand to 100 %" [P III.C.2] starts from an
 * idling engine): ts_engine_init_state, then ts_engine_steady at crank speed
 * omega [rad/s] with the rack found (secant, at most 6 steady searches) so
 * that the cycle-mean brake torque equals load_torque [N*m] (e.g. the
 * converter pump torque at stall) within 2 % or 5 N*m. Walls, coolant, oil,
 * manifolds and turbo rotors end at their idle steady values (the LHR's
 * insulated walls at their idle temperatures, not the coolant's; the turbo at
 * its idle speed, not spun up). The map fidelity has no such states: x is
 * ts_engine_init_state's. *rack (may be NULL) receives the idle rack [1].
 * Returns TS_OK, TS_ERR_NOMEM, or TS_ERR_DIVERGED (also when the secant ends
 * without meeting the load, e.g. a load above the full-rack torque; x then
 * holds the last search's state). */
TS_MUST_CHECK ts_rc ts_engine_idle_state(const ts_engine *e, double omega, double load_torque,
                                         double p_amb, double T_amb, double *x, double *rack,
                                         ts_err *err);

/* Set both turbocharger rotor speeds in x [rad/s] (no-op for the map
 * fidelity). With the constant-phi fuel law the turbo match can settle on a
 * low-boost branch; a steady-state search started from spun-up rotors finds
 * the full-load (high-boost) one, as a dynamometer lug-down from rated does. */
void ts_engine_set_turbo_speed(const ts_engine *e, double *x, double w);

/* Absolute tolerance scale of each state for a caller's integrator (n values). */
void ts_engine_atol(const ts_engine *e, double atol, double *atol_v);

/* xdot = f(t, x, inputs); out (may be NULL) receives the outputs at (t, x).
 * Returns 0, or > 0 when x is outside the model's domain (e.g. a negative
 * mass: a CVODE-style recoverable failure; retry with a smaller step). */
TS_MUST_CHECK int ts_engine_rhs(const ts_engine *e, double t, const double *x,
                                const ts_engine_inputs *in, double *xdot, ts_engine_outputs *out);

/* The error of a ts_engine_rhs that failed at (t, x) outside an integrator's
 * step (a sample): TS_ERR_DIVERGED naming the state outside the domain.
 * Returns the code. */
ts_rc ts_engine_rhs_failed(const ts_engine *e, double t, const double *x, ts_err *err);

/* Explicit integration of x from t over dt for callers that do not
 * integrate the engine themselves (engine_dyno, engine-map, vehicle runs
 * through ts_engine_advance_load). map and mean_value: fixed-step RK4. crank
 * angle: MULTIRATE and error-controlled (engine.c): every state but the walls
 * by Bogacki-Shampine 3(2) with the walls frozen over a step, steps ended on
 * the ignition/burn clocks' switching angles, crank-angle steps between
 * /engine/ca_step / 4 and 8 x ca_step; every second step each wall stack
 * by one implicit Crank-Nicolson step with the mean heat flux of those steps.
 * Agrees with an RK4 of
 * all 512 states at ca_step within 0.3 % in torque, work and heat per cycle
 * (closer to the converged solution than that RK4: tests/sim/
 * test_engine_regression.c, report of issue 6/10). work:
 * ts_engine_work_size(e) doubles owned by the caller (scratch: the result
 * depends on x and the inputs only; crank_angle keeps the last derivative
 * there for the next call, used only when x and the inputs but the load
 * torque are unchanged, and then exactly equal to a fresh evaluation).
 * Returns TS_OK or TS_ERR_DIVERGED. */
size_t ts_engine_work_size(const ts_engine *e);
TS_MUST_CHECK ts_rc ts_engine_advance(const ts_engine *e, double *x, double t, double dt,
                                      const ts_engine_inputs *in, double *work, ts_err *err);

/* Load torque on the crankshaft [N*m] at time t [s] and crank speed omega
 * [rad/s], for ts_engine_advance_load. */
typedef double (*ts_engine_load_fn)(void *ud, double t, double omega);

/* As ts_engine_advance, with the load torque a function of (t, crank speed)
 * evaluated at every stage of every internal step (load NULL: in->load_torque
 * held; this is ts_engine_advance).
 *
 * Powertrain co-simulation (the intended use, issue 10): integrating the
 * crank-angle engine's 512 states inside the powertrain's ODE forces the
 * powertrain's integrator onto the engine's crank-angle step and evaluates the
 * walls in every stage; instead, per macro step H of the powertrain (e.g. 1 ms,
 * ~13 deg at 2100 rpm; the engine sub-steps itself):
 *   in.load_inertia = pump inertia (turns with the crankshaft);
 *   load(ud, t, w_e) = converter pump torque at (w_e, w_t) with the turbine
 *                      speed w_t held (or extrapolated) over H;
 *   ts_engine_advance_load(e, x_engine, t, H, &in, load, &ctx, work, err);
 *   then advance the turbine/transmission (and vehicle) states over H with the
 *   converter evaluated at the engine's new speed (or the mean over H).
 * The engine's states stay in x_engine (not in the powertrain's ODE); its
 * outputs at the step end come from ts_engine_rhs(e, t, x_engine, ...). The
 * coupling through the converter is not stiff (d T_pump / d w_e ~ 2 T / w:
 * time constant ~ J / 45 N*m*s ~ 0.2 s), so the explicit exchange every H is
 * stable and first-order accurate in H. work: ts_engine_work_size(e)
 * doubles. Returns TS_OK or TS_ERR_DIVERGED. */
TS_MUST_CHECK ts_rc ts_engine_advance_load(const ts_engine *e, double *x, double t, double dt,
                                           const ts_engine_inputs *in, ts_engine_load_fn load,
                                           void *ud, double *work, ts_err *err);

/* Cumulative integrals carried in x (crank_angle and mean_value; zeros for map):
 * energy and mass book-keeping for balance checks. Differences between two
 * states give per-interval totals. */
typedef struct ts_engine_ledger {
    double fuel_energy;  /* fuel burned x LHV [J] */
    double work;         /* indicated (p dV) work [J] */
    double wall_heat;    /* heat to the walls [J] */
    double enthalpy_in;  /* enthalpy into the cylinders through valves [J] */
    double enthalpy_out; /* enthalpy out of the cylinders through valves [J] */
    double mass_in;      /* mass into the cylinders [kg] */
    double mass_out;     /* mass out of the cylinders [kg] */
    double fuel_mass;    /* fuel burned [kg] */
    double cyl_energy;   /* sum of cylinder internal energies now [J] */
    double cyl_mass;     /* sum of cylinder masses now [kg] */
} ts_engine_ledger;
void ts_engine_ledger_get(const ts_engine *e, const double *x, ts_engine_ledger *l);

/* Cycle-mean results of ts_engine_steady (one engine cycle, 4 pi of crank). */
/* Fields a fidelity does not model are NaN: peak_pressure without cylinders,
 * eta_v, eta_i, q_wall and the residuals without a ledger (map), bsfc at zero
 * or negative brake power. */
typedef struct ts_engine_cycle {
    ts_engine_outputs mean; /* cycle-mean outputs (cylinder fields: cylinder 1 means) */
    double peak_pressure;   /* cylinder 1 peak pressure [Pa] */
    double bsfc;            /* fuel flow / brake power [kg/J] */
    double eta_v;           /* volumetric efficiency: net air through the intake valves (overlap
                               short-circuit included) vs intake-manifold density [1] */
    double eta_i;           /* net indicated work (p dV over all 720 deg) / fuel energy [1] */
    double q_wall;          /* wall heat / fuel energy [1] */
    double energy_residual; /* (fuel - work - wall heat - net enthalpy out - dE)/fuel [1] */
    double mass_residual;   /* (in + fuel - out - dm)/in over the cycle [1] */
    int cycles;             /* cycles simulated to reach it */
} ts_engine_cycle;

/* Run one engine cycle (4 pi of crank) from x with the given inputs and return
 * its means in cyc (may be NULL). speed_held: dynamometer. */
TS_MUST_CHECK ts_rc ts_engine_cycle_run(const ts_engine *e, double *x, const ts_engine_inputs *in,
                                        double *work, ts_engine_cycle *cyc, ts_err *err);

/* Steady state on the dynamometer: integrate with speed held at omega and the
 * given inputs until the cycle-mean brake torque changes by less than tol
 * (relative) between cycles, at most max_cycles cycles. While searching, the
 * coolant and oil capacities, the turbo inertia and the map boost lag are
 * shrunk, and after every cycle each wall's temperature profile is moved half
 * way to the steady conduction profile of that cycle's mean heat flux (the
 * steady state depends on none of these); the final cycle is run with the
 * real model. x holds the start (e.g. a previous steady state) and
 * receives the final state; cyc (may be NULL) the last cycle's means. */
TS_MUST_CHECK ts_rc ts_engine_steady(const ts_engine *e, double *x, double omega,
                                     const ts_engine_inputs *in, int max_cycles, double tol,
                                     ts_engine_cycle *cyc, ts_err *err);

/* Speed floor of the crank-angle model's time step (ca_step / speed) [rad/s]:
 * the engine's own steppers and the powertrain's explicit path use it alike. */
#define TS_ENGINE_MIN_STEP_SPEED 30.0

/* The full-load sweep's and the dynamometer's steady searches: their cycle
 * cap and relative tolerance of the cycle-mean brake torque, and the rotor
 * speed a search from ts_engine_init_state starts at (~76 krpm; the turbo
 * match has a low-boost and a high-boost branch, and this start finds the
 * high-boost one, which the paper's Fig. 18 shows: engine.json's notes). */
#define TS_ENGINE_STEADY_CYCLES 80
#define TS_ENGINE_STEADY_TOL    2e-4
#define TS_ENGINE_SEARCH_TURBO  8000.0 /* [rad/s] */

#endif
