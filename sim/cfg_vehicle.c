/*
 * cfg_vehicle.c — parameter-table rows of the "vehicle", "terrain" and "drive"
 * sections (columns defined in param.h). Defaults: sim/data/vehicle.json etc.
 */
#include <stddef.h>

#include "config.h"

const char *const ts_terrain_kind_names[] = {"flat", "bumps", "profile", NULL};
const char *const ts_drive_kind_names[] = {"constant", "ramp", "table", "powertrain", NULL};

#define F(field) offsetof(ts_config, vehicle.field)
static const ts_param vehicle_rows[] = {
    {"/vehicle/mass", TS_PT_DOUBLE, F(mass), "kg", 1000, 200000, NULL, 0, 0,
     "combat mass of the whole vehicle"},
    {"/vehicle/sprocket_radius", TS_PT_DOUBLE, F(sprocket_radius), "m", 0.1, 1.0, NULL, 0, 0,
     "drive sprocket pitch radius"},
    {"/vehicle/rolling_resistance", TS_PT_DOUBLE, F(rolling_resistance), "1", 0, 0.5, NULL, 0, 0,
     "rolling-resistance coefficient at rest (point-mass runs)"},
    {"/vehicle/rolling_resistance_speed", TS_PT_DOUBLE, F(rolling_resistance_speed), "s/m", 0,
     0.1, NULL, 0, 0, "growth of the rolling-resistance coefficient with speed"},
    {"/vehicle/cda", TS_PT_DOUBLE, F(cda), "m^2", 0, 50, NULL, 0, 0,
     "aerodynamic drag coefficient times frontal area"},
    {"/vehicle/air_density", TS_PT_DOUBLE, F(air_density), "kg/m^3", 0, 2, NULL, 0, 0,
     "air density for drag"},
    {"/vehicle/grade", TS_PT_DOUBLE, F(grade), "rad", -0.6, 0.6, NULL, 0, 0,
     "road slope, positive uphill (point-mass runs)"},
    {"/vehicle/rotating_mass_factor", TS_PT_DOUBLE, F(rotating_mass_factor), "1", 1, 2, NULL, 0,
     0, "effective over actual mass, for rotating parts in point-mass runs"},
    {"/vehicle/sprocket_x", TS_PT_DOUBLE, F(sprocket_x), "m", -2, 12, NULL, 0, 0,
     "sprocket centre x (layout origin: ground below the sprocket axle)"},
    {"/vehicle/sprocket_z", TS_PT_DOUBLE, F(sprocket_z), "m", 0.1, 3, NULL, 0, 0,
     "sprocket centre height"},
    {"/vehicle/rear_roller_x", TS_PT_DOUBLE, F(rear_roller_x), "m", -2, 12, NULL, 0, 0,
     "rear (second) support roller centre x"},
    {"/vehicle/rear_roller_z", TS_PT_DOUBLE, F(rear_roller_z), "m", 0.1, 3, NULL, 0, 0,
     "rear support roller centre height"},
    {"/vehicle/front_roller_x", TS_PT_DOUBLE, F(front_roller_x), "m", -2, 12, NULL, 0, 0,
     "front support roller centre x"},
    {"/vehicle/front_roller_z", TS_PT_DOUBLE, F(front_roller_z), "m", 0.1, 3, NULL, 0, 0,
     "front support roller centre height"},
    {"/vehicle/roller_radius", TS_PT_DOUBLE, F(roller_radius), "m", 0.02, 1, NULL, 0, 0,
     "support roller radius"},
    {"/vehicle/idler_x", TS_PT_DOUBLE, F(idler_x), "m", -2, 12, NULL, 0, 0,
     "idler centre x at static equilibrium"},
    {"/vehicle/idler_z", TS_PT_DOUBLE, F(idler_z), "m", 0.1, 3, NULL, 0, 0, "idler centre height"},
    {"/vehicle/idler_radius", TS_PT_DOUBLE, F(idler_radius), "m", 0.05, 1, NULL, 0, 0,
     "idler radius"},
    {"/vehicle/road_wheel_x", TS_PT_DARRAY, F(road_wheel_x), "m", -2, 12, NULL,
     TS_MAX_ROAD_WHEELS, F(road_wheel_n), "road-wheel hub x, front (1) to rear (7)"},
    {"/vehicle/road_wheel_z", TS_PT_DOUBLE, F(road_wheel_z), "m", 0.1, 2, NULL, 0, 0,
     "road-wheel hub height at static equilibrium"},
    {"/vehicle/road_wheel_radius", TS_PT_DOUBLE, F(road_wheel_radius), "m", 0.05, 1, NULL, 0, 0,
     "road-wheel radius"},
};
#undef F

#define F(field) offsetof(ts_config, terrain.field)
static const ts_param terrain_rows[] = {
    {"/terrain/kind", TS_PT_ENUM, F(kind), "", 0, 0, ts_terrain_kind_names, 0, 0,
     "flat, bumps (a shipped course) or profile (user CSV)"},
    {"/terrain/course", TS_PT_STRING, F(course), "", 0, 0, NULL, TS_NAME_LEN, 0,
     "name of a shipped bump course (sim/data/terrain/NAME.json)"},
    {"/terrain/profile_csv", TS_PT_STRING, F(profile_csv), "", 0, 0, NULL, TS_PATH_LEN, 0,
     "path of a CSV terrain profile: distance m, height m per row"},
};
#undef F

#define F(field) offsetof(ts_config, drive.field)
static const ts_param drive_rows[] = {
    {"/drive/kind", TS_PT_ENUM, F(kind), "", 0, 0, ts_drive_kind_names, 0, 0,
     "constant, ramp, table (prescribed sprocket torque) or powertrain"},
    {"/drive/torque", TS_PT_DOUBLE, F(torque), "N*m", -2e5, 2e5, NULL, 0, 0,
     "prescribed torque at each of the two sprockets"},
    {"/drive/ramp_time", TS_PT_DOUBLE, F(ramp_time), "s", 0, 600, NULL, 0, 0,
     "time for the ramp drive to reach the full torque"},
    {"/drive/table_t", TS_PT_DARRAY, F(table_t), "s", 0, 3600, NULL, TS_DRIVE_TABLE_MAX,
     F(table_n), "times of the torque history (increasing)"},
    {"/drive/table_torque", TS_PT_DARRAY, F(table_torque), "N*m", -2e5, 2e5, NULL,
     TS_DRIVE_TABLE_MAX, F(table_torque_n), "torque at each sprocket at table_t"},
};
#undef F

const ts_param_section ts_section_vehicle = {
    "vehicle", "whole-vehicle mass, sprocket and resistance data", vehicle_rows,
    (int)(sizeof vehicle_rows / sizeof vehicle_rows[0])};
const ts_param_section ts_section_terrain = {
    "terrain", "ground profile under the vehicle", terrain_rows,
    (int)(sizeof terrain_rows / sizeof terrain_rows[0])};
const ts_param_section ts_section_drive = {
    "drive", "what turns the sprockets", drive_rows, (int)(sizeof drive_rows / sizeof drive_rows[0])};
