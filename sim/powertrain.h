/*
 * powertrain.h — engine + torque converter + transmission + final drive as ONE
 * subsystem with a narrow interface (paper Section III.B, Figs. 16-17): input
 * the sprocket speed (and the rack), output the torque at each sprocket. The
 * same object drives the point-mass vehicle (scenario_pointmass.c, monolithic:
 * its states appended to the vehicle's) and the multibody vehicle (leading-
 * following co-simulation or a monolithic reference).
 *
 * States (first-order, integrated by the CALLER's ODE): the engine's own states
 * (crankshaft speed among them; the converter pump turns with the crankshaft,
 * its inertia is added there), then the turbine / transmission-input speed.
 * Discrete state: ts_powertrain_state (gear, shift in progress).
 *
 * Events: gear-shift start and end are root functions of the caller's ODE
 * (ts_powertrain_roots, ts_powertrain_nroots of them); at a root the caller
 * calls ts_powertrain_update and, when it returns 1, re-initialises its
 * integrator at the same (t, y).
 *
 * The transmission output, propshaft, final drives and sprockets turn with
 * the sprocket: their inertia (ts_powertrain_output_inertia) belongs to the
 * caller's sprocket equation.
 *
 * Ownership: ts_powertrain_make / ts_powertrain_free (NULL is a no-op). A
 * ts_powertrain is read-only after make (the engine port's context is the
 * engine's immutable model); ts_powertrain_rhs is reentrant.
 */
#ifndef TS_POWERTRAIN_H
#define TS_POWERTRAIN_H

#include "config.h"
#include "errors.h"
#include "model.h"
#include "transmission.h"

/* What the powertrain needs from an engine (engine.h's model seen through a
 * port, so the powertrain does not depend on one engine fidelity). */
typedef struct ts_engine_obs {
    double speed;        /* crankshaft speed [rad/s] */
    double brake_torque; /* [N*m] */
    double boost;        /* intake manifold pressure [Pa] */
    double exhaust_temp; /* exhaust manifold temperature [K] */
    double turbo_speed;  /* turbocharger rotor speed [rad/s] */
    double piston_temp; /* piston gas-side surface temperature [K] (if port.models has CYLINDERS) */
    double fuel_flow;    /* whole engine [kg/s] */
} ts_engine_obs;

typedef struct ts_engine_port {
    void *ctx;          /* engine instance, borrowed by the port functions */
    int nstate;         /* engine states */
    int speed_index;    /* index of the crankshaft speed among them */
    double inertia;     /* crankshaft + flywheel inertia the engine integrates with [kg*m^2] */
    /* Initial engine state (idle, t = 0). */
    ts_rc (*reset)(void *ctx, double *y, ts_err *err);
    /* Derivatives at (t, y) with the rack in [0, 1] and the load torque on the
     * crankshaft [N*m]; fills obs. Returns 0, > 0 recoverable, < 0 fatal. */
    int (*rhs)(void *ctx, double t, const double *y, double rack, double load_torque,
               double *ydot, ts_engine_obs *obs);
    /* Typical magnitude of each state, for absolute tolerances (may be NULL: 1). */
    void (*scale)(void *ctx, double *scale);
    /* Fixed explicit step the engine needs at y [s] (crank-angle model: its
     * crank-angle step over the speed), or 0 when an implicit variable-step
     * integrator suits it (may be NULL: 0). */
    double (*explicit_step)(void *ctx, const double *y);
    void (*free)(void *ctx); /* may be NULL */
    /* Optional (may be NULL): the engine integrating ITSELF from t over dt with
     * the rack held, extra inertia load_inertia turning with the crankshaft and
     * the load torque load(lud, t, speed) [N*m] evaluated at its every internal
     * stage (engine.h ts_engine_advance_load); work: work_size doubles of
     * caller-owned scratch. Enables the co-simulation path (below). */
    ts_rc (*advance)(void *ctx, double *y, double t, double dt, double rack, double load_inertia,
                     double (*load)(void *lud, double t, double speed), void *lud, double *work,
                     ts_err *err);
    size_t work_size;
    unsigned models; /* engine.h TS_ENGINE_MODELS_* bits: CYLINDERS, obs.piston_temp
                      * is set; MANIFOLDS, obs.exhaust_temp and obs.turbo_speed are */
} ts_engine_port;

typedef struct ts_powertrain ts_powertrain;

typedef struct ts_powertrain_state {
    ts_shift_state shift;
} ts_powertrain_state;

typedef struct ts_powertrain_out {
    double sprocket_torque;   /* at EACH of the two sprockets [N*m] */
    double sprocket_speed;    /* input echoed [rad/s] */
    double rack;              /* [1] */
    double engine_speed;      /* = pump speed [rad/s] */
    double engine_torque;     /* brake torque [N*m] */
    double engine_power;      /* brake power [W] */
    double boost;             /* intake manifold pressure [Pa] */
    double exhaust_temp, turbo_speed, piston_temp, fuel_flow; /* as ts_engine_obs */
    double pump_torque;       /* converter load on the engine [N*m] */
    double turbine_torque;    /* converter output [N*m] */
    double turbine_speed;     /* = transmission input speed [rad/s] */
    double speed_ratio, torque_ratio, tc_efficiency; /* converter [1] */
    double gear;              /* engaged gear; fractional during a shift [1] */
    double clutch_offgoing, clutch_oncoming; /* range-clutch torques, input side [N*m] */
    double out_speed;         /* transmission output speed [rad/s] */
    double out_torque;        /* transmission output (propshaft) torque [N*m] */
} ts_powertrain_out;

/* Build with the engine selected by cfg->engine (variant, fidelity). */
ts_powertrain *ts_powertrain_make(const ts_config *cfg, ts_err *err);
/* Build with a caller-supplied engine port (tests, other engines). The port is
 * copied; its ctx is freed with port->free at ts_powertrain_free. */
ts_powertrain *ts_powertrain_make_port(const ts_config *cfg, const ts_engine_port *port,
                                       ts_err *err);
void ts_powertrain_free(ts_powertrain *pt);

int ts_powertrain_nstate(const ts_powertrain *pt);
int ts_powertrain_nroots(const ts_powertrain *pt);
int ts_powertrain_engine_speed_index(const ts_powertrain *pt); /* in the powertrain's states */
double ts_powertrain_output_inertia(const ts_powertrain *pt);  /* at the sprocket, both sides [kg*m^2] */
double ts_powertrain_sprocket_radius(const ts_powertrain *pt); /* [m] */

/* Integration method the powertrain asks for: 0 = implicit variable step
 * (CVODE BDF, shift events as roots); otherwise the largest step [s] of a
 * classical RK4 at y — the engine's crank-angle step (or, with the engine
 * co-simulated, ts_powertrain_macro_step > 0, no engine limit), capped by the
 * explicit stability limit of the applied clutch (2 w_s J_t / C). With RK4,
 * events are found by running ts_powertrain_update at every step end. */
double ts_powertrain_explicit_step(const ts_powertrain *pt, const double *y);

/* ---- engine co-simulation (crank-angle engine) ----------------------------
 * When ts_powertrain_macro_step > 0 (crank-angle engine whose port can advance
 * itself, /driveline/engine_macro_step > 0) the engine's states are NOT
 * integrated by the caller's RK4. Per macro step H from t:
 *   1. ts_powertrain_engine_advance: the engine block of y over [t, t + H]
 *      with the converter's pump torque at (engine speed, turbine speed of y
 *      held) as its load at every internal stage and the pump inertia on the
 *      crankshaft;
 *   2. the caller's RK4 over [t, t + H] of the other states (turbine, vehicle)
 *      at ts_powertrain_explicit_step with ts_powertrain_rhs_driveline (engine
 *      speed held at its new value), the shift state machine at every
 *      sub-step end as before.
 * Explicit exchange every H: first-order in H; the converter coupling is not
 * stiff (engine.h), the clutches stay inside the sub-stepped RK4.
 * ts_powertrain_explicit_step then returns the driveline's step (the clutch
 * limit), not the engine's crank-angle step. */
double ts_powertrain_macro_step(const ts_powertrain *pt); /* H [s]; 0: no co-simulation */
size_t ts_powertrain_work_size(const ts_powertrain *pt);  /* doubles for work */
/* Step 1 above. y: the powertrain's states (the engine block is advanced, the
 * rest read). Returns TS_OK or TS_ERR_DIVERGED / the engine's error. */
TS_MUST_CHECK ts_rc ts_powertrain_engine_advance(const ts_powertrain *pt, double t, double H,
                                                 double *y, double rack, double *work, ts_err *err);
/* Derivative of the driveline states only (engine states held): writes
 * ydot[ts_powertrain_nstate - 1] (turbine) and NOT the engine entries; out
 * (may be NULL) as ts_powertrain_rhs but with the engine's own observations
 * (torque, boost, temperatures, fuel) zero — take those from ts_powertrain_rhs
 * when sampling. Cannot fail (the engine is not evaluated). */
void ts_powertrain_rhs_driveline(const ts_powertrain *pt, const ts_powertrain_state *ps, double t,
                                 const double *y, double w_sprocket, double rack, double *ydot,
                                 ts_powertrain_out *out);

/* Per-state magnitudes for absolute tolerances (nstate values). */
void ts_powertrain_scale(const ts_powertrain *pt, double *scale);

/* Make every later ts_powertrain_reset start the engine from its IDLE steady
 * state (engine.h ts_engine_idle_state: walls, coolant, manifolds and turbo
 * rotors steady at /driveline/launch_engine_speed against the converter at
 * stall, turbine at rest) instead of ts_engine_init_state's coolant-temperature
 * walls and guessed turbo speed: the standing start of a launch, "a step
 * increase of driver demand to 100 %" [P III.C.2]. Costly (the engine's steady
 * cycles), so run once per powertrain, by callers that start from standstill.
 * No-op for the map fidelity (no such states) and for engines bound through
 * ts_powertrain_make_port. Returns TS_OK, TS_ERR_NOMEM or the engine's error. */
TS_MUST_CHECK ts_rc ts_powertrain_idle_start(ts_powertrain *pt, ts_err *err);

/* Initial state: engine from its reset (idle), 1st gear applied, turbine
 * turning with the output at sprocket speed w_sprocket. */
TS_MUST_CHECK ts_rc ts_powertrain_reset(const ts_powertrain *pt, ts_powertrain_state *ps, double *y,
                                        double w_sprocket, ts_err *err);

/* Derivatives of the powertrain states for sprocket speed w_sprocket and rack;
 * out (may be NULL) receives every shaft's speed and torque. Same return
 * convention as ts_rhs_fn. */
TS_MUST_CHECK int ts_powertrain_rhs(const ts_powertrain *pt, const ts_powertrain_state *ps,
                                    double t, const double *y, double w_sprocket, double rack,
                                    double *ydot, ts_powertrain_out *out);

/* The error of a ts_powertrain_rhs that failed at t outside an integrator's
 * step (a sample, a published torque): TS_ERR_DIVERGED. Returns the code. */
ts_rc ts_powertrain_rhs_failed(double t, ts_err *err);

/* Root functions (ts_powertrain_nroots values) at sprocket speed w_sprocket
 * [rad/s]. */
void ts_powertrain_roots(const ts_powertrain *pt, const ts_powertrain_state *ps, double t,
                         const double *y, double w_sprocket, double *g);

/* Discrete updates at an event, repeated until nothing changes (a completed
 * shift can start the next one); 1 when the state changed (re-init needed). */
int ts_powertrain_update(const ts_powertrain *pt, ts_powertrain_state *ps, double t,
                         const double *y, double w_sprocket);

/* ---- the powertrain on its own integrator --------------------------------
 * For callers that integrate the powertrain separately from the vehicle (the
 * leading side of the leading-following co-simulation): one CVODE instance
 * over the powertrain states (or, when ts_powertrain_explicit_step > 0 — the
 * crank-angle engine — RK4 at that step), shift events handled inside, the
 * sprocket speed given as a function of time (e.g. the predictor), the rack
 * held per call. */
typedef double (*ts_sprocket_speed_fn)(void *ud, double t);
typedef struct ts_powertrain_sim ts_powertrain_sim;

/* pt is borrowed and must outlive the sim. atol is scaled per state. */
ts_powertrain_sim *ts_powertrain_sim_make(const ts_powertrain *pt, double rtol, double atol,
                                          double max_step, ts_err *err);
void ts_powertrain_sim_free(ts_powertrain_sim *s);
/* Initial state (ts_powertrain_reset) at time t0 for sprocket speed w0. */
TS_MUST_CHECK ts_rc ts_powertrain_sim_reset(ts_powertrain_sim *s, double t0, double w0,
                                            ts_err *err);
/* Integrate to t_to with sprocket speed w(ud, t) and the rack; out (may be
 * NULL) receives the shafts at t_to. */
TS_MUST_CHECK ts_rc ts_powertrain_sim_advance(ts_powertrain_sim *s, double t_to,
                                              ts_sprocket_speed_fn w, void *ud, double rack,
                                              ts_powertrain_out *out, ts_err *err);
double ts_powertrain_sim_time(const ts_powertrain_sim *s);
const double *ts_powertrain_sim_y(const ts_powertrain_sim *s);            /* nstate values */
const ts_powertrain_state *ts_powertrain_sim_state(const ts_powertrain_sim *s);
/* Snapshot (states, discrete state, time): ts_powertrain_sim_state_size bytes. */
size_t ts_powertrain_sim_state_size(const ts_powertrain_sim *s);
void ts_powertrain_sim_save(const ts_powertrain_sim *s, void *buf);
TS_MUST_CHECK ts_rc ts_powertrain_sim_restore(ts_powertrain_sim *s, const void *buf, ts_err *err);

/* Output channels of pt's engine: names, units and descriptions in channel
 * order (ts_powertrain_nchannel of them), and the values of one row from a
 * ts_powertrain_out. exhaust.temperature and turbo.speed (the 21st and 22nd
 * of the TS_POWERTRAIN_NCHANNEL) exist only when the engine models its
 * manifolds and turbochargers (port.models: not the map engine),
 * piston.surface_temperature (the 23rd) only when it models its walls (the
 * crank-angle fidelity); the others keep their order without them. */
#define TS_POWERTRAIN_NCHANNEL 24
const ts_channel *ts_powertrain_channels(const ts_powertrain *pt);
int ts_powertrain_nchannel(const ts_powertrain *pt);
void ts_powertrain_channel_values(const ts_powertrain *pt, const ts_powertrain_out *o,
                                  double *values);

#endif
