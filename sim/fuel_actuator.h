/*
 * fuel_actuator.h — the constant-phi fuel law of paper Section IV.B
 * (Eqs. 13-14): the injected fuel per cylinder and cycle follows the measured
 * intake air flow so that the engine runs at a target equivalence ratio
 * phi_tgt(N) scaled by the rack signal. The injection system is ideal (reacts
 * instantly, Section IV.C).
 *
 * The engine uses it as its default fuel law (ts_engine_inputs.fuel_per_cycle
 * < 0); the control layer may call it itself and pass fuel_per_cycle. A
 * two-speed governor is not here: it belongs to the control layer.
 */
#ifndef TS_FUEL_ACTUATOR_H
#define TS_FUEL_ACTUATOR_H

#include "cfg_engine.h"

typedef struct ts_fuel_law {
    double phi_rated;     /* Eq. 13 constant [1] */
    double phi_curvature; /* Eq. 13 coefficient [s^2/rad^2] */
    double speed_rated;   /* Eq. 13 reference speed [rad/s] */
    double phi_max;       /* cap on phi_tgt [1] */
    double afr_stoich;    /* (A/F)_s [1] */
    int n_cyl;            /* cylinders (TS_ENGINE_NCYL) */
} ts_fuel_law;

/* Law from the engine section (n_cyl = TS_ENGINE_NCYL). */
ts_fuel_law ts_fuel_law_from_config(const ts_engine_config *c);

/* Eq. 13: target equivalence ratio at speed omega [rad/s]. */
double ts_fuel_phi_target(const ts_fuel_law *f, double omega);

/* Eq. 14: fuel per cylinder per cycle [kg] from the intake air flow [kg/s],
 * speed omega [rad/s] (clamped below at 10 rad/s) and rack (clamped to [0, 1]). */
double ts_fuel_per_cycle(const ts_fuel_law *f, double air_flow, double omega, double rack);

#endif
