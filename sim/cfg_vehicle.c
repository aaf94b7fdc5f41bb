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
     "rolling-resistance coefficient at rest (point-mass and multibody runs)"},
    {"/vehicle/rolling_resistance_speed", TS_PT_DOUBLE, F(rolling_resistance_speed), "s/m", 0, 0.1,
     NULL, 0, 0, "growth of the rolling-resistance coefficient with speed"},
    {"/vehicle/rolling_resistance_smoothing", TS_PT_DOUBLE, F(rolling_resistance_smoothing), "m/s",
     1e-4, 1, NULL, 0, 0,
     "speed over which the rolling resistance's sign goes smoothly through zero (point-mass "
     "and multibody runs)"},
    {"/vehicle/cda", TS_PT_DOUBLE, F(cda), "m^2", 0, 50, NULL, 0, 0,
     "aerodynamic drag coefficient times frontal area"},
    {"/vehicle/air_density", TS_PT_DOUBLE, F(air_density), "kg/m^3", 0, 2, NULL, 0, 0,
     "air density for drag"},
    {"/vehicle/grade", TS_PT_DOUBLE, F(grade), "rad", -0.6, 0.6, NULL, 0, 0,
     "road slope, positive uphill: point-mass runs (the multibody vehicle takes its slope "
     "from /terrain, and a coupled run reads this only as its IVS gain schedule's grade)"},
    {"/vehicle/rotating_mass_factor", TS_PT_DOUBLE, F(rotating_mass_factor), "1", 1, 2, NULL, 0, 0,
     "effective over actual mass, for rotating parts in point-mass runs"},
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
    {"/vehicle/road_wheel_x", TS_PT_DARRAY, F(road_wheel_x), "m", -2, 12, NULL, TS_MAX_ROAD_WHEELS,
     F(road_wheel_n), "road-wheel hub x, front (1) to rear (7)"},
    {"/vehicle/road_wheel_z", TS_PT_DOUBLE, F(road_wheel_z), "m", 0.1, 2, NULL, 0, 0,
     "road-wheel hub height at static equilibrium"},
    {"/vehicle/road_wheel_radius", TS_PT_DOUBLE, F(road_wheel_radius), "m", 0.05, 1, NULL, 0, 0,
     "road-wheel radius"},
    {"/vehicle/hull_pitch_inertia", TS_PT_DOUBLE, F(hull_pitch_inertia), "kg*m^2", 1e3, 1e7, NULL,
     0, 0, "hull pitch inertia about its CG, whole vehicle"},
    {"/vehicle/cg_x", TS_PT_DOUBLE, F(cg_x), "m", -2, 12, NULL, 0, 0, "hull CG x (layout frame)"},
    {"/vehicle/cg_z", TS_PT_DOUBLE, F(cg_z), "m", 0, 4, NULL, 0, 0,
     "hull CG height (layout frame)"},
    {"/vehicle/road_wheel_mass", TS_PT_DOUBLE, F(road_wheel_mass), "kg", 1, 2000, NULL, 0, 0,
     "dual road wheel mass, per station per side"},
    {"/vehicle/road_wheel_inertia", TS_PT_DOUBLE, F(road_wheel_inertia), "kg*m^2", 0.01, 100, NULL,
     0, 0, "road-wheel spin inertia"},
    {"/vehicle/road_arm_mass", TS_PT_DOUBLE, F(road_arm_mass), "kg", 1, 2000, NULL, 0, 0,
     "road-arm mass, per station per side"},
    {"/vehicle/road_arm_inertia", TS_PT_DOUBLE, F(road_arm_inertia), "kg*m^2", 0.01, 100, NULL, 0,
     0, "road-arm inertia about its pivot"},
    {"/vehicle/road_arm_length", TS_PT_DOUBLE, F(road_arm_length), "m", 0.1, 1.5, NULL, 0, 0,
     "road arm, pivot to hub"},
    {"/vehicle/road_arm_angle", TS_PT_DOUBLE, F(road_arm_angle), "rad", -0.5, 1.2, NULL, 0, 0,
     "design static road-arm angle below horizontal (trailing arm)"},
    {"/vehicle/torsion_bar_rate", TS_PT_DOUBLE, F(torsion_bar_rate), "N*m/rad", 1e3, 1e7, NULL, 0,
     0, "torsion-bar rate per arm"},
    {"/vehicle/damper_station", TS_PT_DARRAY, F(damper_station), "1", 1, TS_MAX_ROAD_WHEELS, NULL,
     TS_MAX_ROAD_WHEELS, F(damper_station_n), "road-arm stations (1 = front) with rotary dampers"},
    {"/vehicle/damper_rate", TS_PT_DOUBLE, F(damper_rate), "N*m*s/rad", 0, 1e6, NULL, 0, 0,
     "rotary damper coefficient"},
    {"/vehicle/bump_stop_station", TS_PT_DARRAY, F(bump_stop_station), "1", 1, TS_MAX_ROAD_WHEELS,
     NULL, TS_MAX_ROAD_WHEELS, F(bump_stop_station_n), "road-arm stations with bump stops"},
    {"/vehicle/bump_stop_angle", TS_PT_DOUBLE, F(bump_stop_angle), "rad", -1, 1, NULL, 0, 0,
     "road-arm angle at which the bump stop engages"},
    {"/vehicle/bump_stop_rate", TS_PT_DOUBLE, F(bump_stop_rate), "N*m/rad", 0, 1e9, NULL, 0, 0,
     "bump-stop rotational stiffness"},
    {"/vehicle/sprocket_inertia", TS_PT_DOUBLE, F(sprocket_inertia), "kg*m^2", 0.01, 1000, NULL, 0,
     0, "sprocket spin inertia (with the driveline reflected to it)"},
    {"/vehicle/idler_inertia", TS_PT_DOUBLE, F(idler_inertia), "kg*m^2", 0.01, 100, NULL, 0, 0,
     "idler spin inertia"},
    {"/vehicle/roller_inertia", TS_PT_DOUBLE, F(roller_inertia), "kg*m^2", 0.001, 100, NULL, 0, 0,
     "support-roller spin inertia"},
    {"/vehicle/track_pitch_offset", TS_PT_DOUBLE, F(track_pitch_offset), "m", 0, 0.3, NULL, 0, 0,
     "track pitch line outside the rims of road wheels, idler and rollers"},
    {"/vehicle/track_thickness", TS_PT_DOUBLE, F(track_thickness), "m", 0, 0.3, NULL, 0, 0,
     "track thickness between a road-wheel rim and the ground"},
    {"/vehicle/track_damping_time", TS_PT_DOUBLE, F(track_damping_time), "s", 0, 0.1, NULL, 0, 0,
     "Kelvin-Voigt retardation time of the track elements (damping = EA*time/L)"},
    {"/vehicle/idler_link_angle", TS_PT_DOUBLE, F(idler_link_angle), "rad", -1.6, 1.6, NULL, 0, 0,
     "direction of the track-adjusting link (idler moves forward along it), above hull x"},
    {"/vehicle/idler_compensation", TS_PT_DOUBLE, F(idler_compensation), "1", 0, 1.5, NULL, 0, 0,
     "compensating idler: fraction of road arm 1's loop-length change the track-adjusting link "
     "takes up (0: idler fixed to the hull)"},
    {"/vehicle/foundation_stiffness", TS_PT_DOUBLE, F(foundation_stiffness), "N/m", 1e4, 1e10, NULL,
     0, 0, "track-terrain foundation stiffness under each road wheel"},
    {"/vehicle/foundation_cubic", TS_PT_DOUBLE, F(foundation_cubic), "N/m^3", 0, 1e14, NULL, 0, 0,
     "cubic stiffening of the foundation"},
    {"/vehicle/foundation_damping", TS_PT_DOUBLE, F(foundation_damping), "N*s/m", 0, 1e7, NULL, 0,
     0, "foundation damping under each road wheel (compression only)"},
    {"/vehicle/anchor_stiffness", TS_PT_DOUBLE, F(anchor_stiffness), "N/m", 1e4, 1e11, NULL, 0, 0,
     "tangential stiffness of the no-slip anchor of the ground run"},
    {"/vehicle/anchor_damping", TS_PT_DOUBLE, F(anchor_damping), "N*s/m", 0, 1e8, NULL, 0, 0,
     "tangential damping of the no-slip anchor"},
    {"/vehicle/anchor_station", TS_PT_INT, F(anchor_station), "1", 1, TS_MAX_ROAD_WHEELS, NULL, 0,
     0, "road wheel under which the track does not slip (4 = middle)"},
    {"/vehicle/traction_limit", TS_PT_DOUBLE, F(traction_limit), "1", 0.1, 2, NULL, 0, 0,
     "prescribed-torque runs: the largest pull on a track (sprocket torque over sprocket "
     "radius) a run accepts, as a share of the weight on that track (multibody: on its road "
     "wheels); no model lets the track slip, so a larger pull would be carried regardless"},
    {"/vehicle/damping_scale", TS_PT_DOUBLE, F(damping_scale), "1", 0, 10, NULL, 0, 0,
     "multibody model: factor on every damper, the foundation, anchor and track damping, the "
     "rolling resistance and the drag (0 for energy checks)"},
};
#undef F

#define F(field) offsetof(ts_config, terrain.field)
static const ts_param terrain_rows[] = {
    {"/terrain/kind", TS_PT_ENUM, F(kind), "", 0, 0, ts_terrain_kind_names, 0, 0,
     "flat, bumps (a shipped course) or profile (user CSV)"},
    {"/terrain/course", TS_PT_STRING, F(course), "", 0, 0, NULL, TS_NAME_LEN, 0,
     "name of a shipped bump course (COURSE_DIR/NAME.txt, whitespace table)"},
    {"/terrain/course_dir", TS_PT_STRING, F(course_dir), "", 0, 0, NULL, TS_PATH_LEN, 0,
     "directory of the course files, relative to the working directory; the default "
     "sim/data/terrain is the shipped one (built in), another is read from disk"},
    {"/terrain/profile_csv", TS_PT_STRING, F(profile_csv), "", 0, 0, NULL, TS_PATH_LEN, 0,
     "path of a CSV terrain profile: distance m, height m per row"},
    {"/terrain/bump_start", TS_PT_DARRAY, F(bump_start), "m", 0, 1e5, NULL, TS_TERRAIN_BUMPS_MAX,
     F(bump_n), "inline bump list: start of each 1-cos bump (replaces the course file)"},
    {"/terrain/bump_height", TS_PT_DARRAY, F(bump_height), "m", -2, 2, NULL, TS_TERRAIN_BUMPS_MAX,
     F(bump_height_n), "inline bump list: heights"},
    {"/terrain/bump_length", TS_PT_DARRAY, F(bump_length), "m", 0.01, 1000, NULL,
     TS_TERRAIN_BUMPS_MAX, F(bump_length_n), "inline bump list: lengths"},
    {"/terrain/start_x", TS_PT_DOUBLE, F(start_x), "m", -1e4, 1e5, NULL, 0, 0,
     "distance along the course of the layout origin (ground below the sprocket) at t = 0"},
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
    {"/drive/table_t", TS_PT_DARRAY, F(table_t), "s", 0, 3600, NULL, TS_DRIVE_TABLE_MAX, F(table_n),
     "times of the torque history (increasing)"},
    {"/drive/table_torque", TS_PT_DARRAY, F(table_torque), "N*m", -2e5, 2e5, NULL,
     TS_DRIVE_TABLE_MAX, F(table_torque_n), "torque at each sprocket at table_t"},
};
#undef F

const ts_param_section ts_section_vehicle = {
    "vehicle", "whole-vehicle mass, sprocket and resistance data", vehicle_rows,
    (int)(sizeof vehicle_rows / sizeof vehicle_rows[0])};
const ts_param_section ts_section_terrain = {"terrain", "ground profile under the vehicle",
                                             terrain_rows,
                                             (int)(sizeof terrain_rows / sizeof terrain_rows[0])};
const ts_param_section ts_section_drive = {"drive", "what turns the sprockets", drive_rows,
                                           (int)(sizeof drive_rows / sizeof drive_rows[0])};
