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
 *   ivs_tune.h       the plant step that tuning is made from (point mass + powertrain)
 *   governor.h       two-speed governor of the fuel actuator (Section IV.B.2)
 *   cosim.h          leading-following co-simulation driver (Section IV.A)
 *   terrain.h        flat, bump-course and user-profile ground (Section II.D, Fig. 8)
 *   vehicle_model.h  the pitch-plane multibody vehicle with its track (Section II.C-D)
 *   fft.h            amplitude spectra (Figs. 13-14)
 *   engine.h         the virtual V-12 diesel, three fidelities (Section III.A-B)
 *   engine_sweep.h   its full-load dynamometer sweep (Fig. 18)
 *   fuel_actuator.h  constant-phi fuel law (Eqs. 13-14)
 *   torque_converter.h, transmission.h, final_drive.h  the driveline (Section III.B.2)
 *   powertrain.h     engine + driveline as one subsystem (Fig. 16-17)
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
#include "ivs_tune.h"
#include "engine.h"
#include "engine_sweep.h"
#include "fft.h"
#include "final_drive.h"
#include "fuel_actuator.h"
#include "powertrain.h"
#include "terrain.h"
#include "torque_converter.h"
#include "transmission.h"
#include "vehicle_model.h"
#include "version.h"

#endif
