/*
 * tanksim.h — umbrella header of libtanksim, the simulation library.
 *
 * libtanksim reproduces the coupled M1 Abrams simulation of Assanis et al.,
 * "Modeling and Simulation of an M1 Abrams Tank with Advanced Track Dynamics
 * and Integrated Virtual Diesel Engine", Mech. Struct. & Mach. 27(4), 1999.
 * It knows nothing of HTTP, JSON or rendering. Not in a header means not API.
 *
 *   errors.h    result codes and the error record
 *   param.h     the parameter table (types, units, ranges of every config field)
 *   config.h    ts_config and its sections (cfg_*.h)
 *   model.h     the generic model interface: make, reset, advance, channels, state
 *   geometry.h  geometric snapshot for renderers
 *   solver.h    CVODE wrapper
 *   drive.h     prescribed sprocket torque
 *   track_span.h     one free track span: shallow-sag continuum, component modes (Eqs. 1-9)
 *   track_circuit.h  the upper track circuit and its eigenanalysis (Fig. 5)
 *   ivs_controller.h PI speed controller with saturation and gain schedule (Eq. 10, Fig. 27)
 *   zn_tuning.h      Ziegler-Nichols reaction-curve tuning (Eqs. 11-12, Fig. 26)
 *   governor.h       two-speed governor of the fuel actuator (Section IV.B.2)
 *   cosim.h          leading-following co-simulation driver (Section IV.A)
 */
#ifndef TANKSIM_H
#define TANKSIM_H

#include "config.h"
#include "drive.h"
#include "errors.h"
#include "geometry.h"
#include "model.h"
#include "param.h"
#include "solver.h"
#include "track_circuit.h"
#include "track_span.h"
#include "cosim.h"
#include "governor.h"
#include "ivs_controller.h"
#include "zn_tuning.h"
#include "version.h"

#endif
