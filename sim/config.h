/*
 * config.h — ts_config, the plain-C run configuration every model is built from.
 *
 * One struct per JSON section (cfg_*.h), filled by api/ from JSON through the
 * parameter table (param.h) starting from the defaults in sim/data/. A config
 * is a value: copy it, edit it, build a new model from it. The model keeps its
 * own copy (ts_model_config), so callers may free theirs.
 */
#ifndef TS_CONFIG_H
#define TS_CONFIG_H

#include "cfg_control.h"
#include "cfg_driveline.h"
#include "cfg_engine.h"
#include "cfg_run.h"
#include "cfg_track.h"
#include "cfg_vehicle.h"
#include "param.h"

typedef struct ts_config {
    ts_run_config run;
    ts_track_config track;
    ts_vehicle_config vehicle;
    ts_terrain_config terrain;
    ts_drive_config drive;
    ts_engine_config engine;
    ts_driveline_config driveline;
    ts_control_config control;
    ts_coupling_config coupling;
} ts_config;

/* Sections of the parameter table, one per struct above (defined in cfg_*.c). */
extern const ts_param_section ts_section_run, ts_section_track, ts_section_vehicle,
    ts_section_terrain, ts_section_drive, ts_section_engine, ts_section_driveline,
    ts_section_control, ts_section_coupling;

#endif
