/*
 * vehicle_layout.h — the cross-field checks of a vehicle layout.
 *
 * Each /vehicle field has its own range (cfg_vehicle.c); this module checks
 * what no single range can: that the bodies keep the order of the circuit the
 * multibody model (vehicle_model.c) and the circuit eigenanalysis
 * (track_circuit.c) both assemble, Fig. 1 of the paper — a rear sprocket, road
 * wheels 1 (front) .. n (rear) under the hull, the idler at the front and the
 * two support rollers on the upper run between them — that the hull's CG
 * lies over the ground contact, and that a road arm's inertia about its pivot
 * exceeds what its mass alone at mid-length gives.
 */
#ifndef TANKSIM_VEHICLE_LAYOUT_H
#define TANKSIM_VEHICLE_LAYOUT_H

#include "config.h"
#include "errors.h"

/* TS_OK, or TS_ERR_PARAM naming the field of the first body out of order. */
TS_MUST_CHECK ts_rc ts_vehicle_layout_check(const ts_vehicle_config *vc, ts_err *err);

#endif
