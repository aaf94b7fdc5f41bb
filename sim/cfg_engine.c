/*
 * cfg_engine.c — parameter-table rows of the "engine" section (columns in
 * param.h). Defaults and sources: sim/data/defaults/engine.json, where every
 * constant is tagged paper [P], public source [S], literature correlation [R<n>]
 * (listed in its "_about"), derived [D], estimate [E] or calibrated [C ...].
 */
#include <stddef.h>

#include "config.h"

const char *const ts_engine_variant_names[] = {"conventional", "lhr05", "lhr10", NULL};
const char *const ts_engine_fidelity_names[] = {"crank_angle", "mean_value", "map", NULL};

#define F(field) offsetof(ts_config, engine.field)
#define D(name, unit, lo, hi, desc) \
    {"/engine/" #name, TS_PT_DOUBLE, F(name), unit, lo, hi, NULL, 0, 0, desc}
#define I(name, lo, hi, desc) {"/engine/" #name, TS_PT_INT, F(name), "1", lo, hi, NULL, 0, 0, desc}
#define A(name, cap, unit, lo, hi, desc) \
    {"/engine/" #name, TS_PT_DARRAY, F(name), unit, lo, hi, NULL, cap, F(name##_n), desc}
/* One table row of variant v (map index idx): /engine/<key>_<v>, member mem
 * of map[idx] with its count mem_n. */
#define MAPROW(v, idx, key, mem, unit, lo, hi, cap, desc)                                          \
    {"/engine/" key "_" v, TS_PT_DARRAY, F(map[idx].mem), unit, lo, hi, NULL, cap,                 \
     F(map[idx].mem##_n), desc " (" v ")"}
#define MAPROWS(v, idx)                                                                            \
    MAPROW(v, idx, "map_torque", torque, "N*m", 0, 2e4, TS_ENGINE_MAP_MAX,                         \
           "full-load brake torque at map_speed"),                                                 \
    MAPROW(v, idx, "map_boost", boost, "Pa", 5e4, 1e6, TS_ENGINE_MAP_MAX,                          \
           "full-load intake manifold pressure"),                                                  \
    MAPROW(v, idx, "map_fuel", fuel, "kg/s", 0, 1, TS_ENGINE_MAP_MAX,                              \
           "full-load fuel flow, whole engine"),                                                   \
    MAPROW(v, idx, "map_eta_v", eta_v, "1", 0.2, 1.5, TS_ENGINE_MAP_MAX,                           \
           "volumetric efficiency vs intake manifold"),                                            \
    MAPROW(v, idx, "map_eta_i", eta_i, "1", 0.1, 0.7, TS_ENGINE_MAP_MAX,                           \
           "gross indicated efficiency"),                                                          \
    MAPROW(v, idx, "map_q_wall", q_wall, "1", 0, 0.6, TS_ENGINE_MAP_MAX,                           \
           "in-cylinder heat loss / fuel energy"),                                                 \
    MAPROW(v, idx, "pb_eta_v", pb_eta_v, "1", 0.3, 2, TS_ENGINE_SPOOL_MAX,                         \
           "part-boost eta_v / full-load eta_v"),                                                  \
    MAPROW(v, idx, "pb_eta_i", pb_eta_i, "1", 0.3, 2, TS_ENGINE_SPOOL_MAX,                         \
           "part-boost eta_i / full-load eta_i"),                                                  \
    MAPROW(v, idx, "pb_q_wall", pb_q_wall, "1", 0.3, 3, TS_ENGINE_SPOOL_MAX,                       \
           "part-boost q_wall / full-load q_wall"),                                                \
    MAPROW(v, idx, "pb_torque", pb_torque, "1", 0, 2, TS_ENGINE_SPOOL_MAX,                         \
           "part-boost indicated torque / full-load indicated torque (map fidelity)")

static const ts_param engine_rows[] = {
    {"/engine/variant", TS_PT_ENUM, F(variant), "", 0, 0, ts_engine_variant_names, 0, 0,
     "combustion chamber: conventional (all metal), lhr05 or lhr10 (zirconia coating)"},
    {"/engine/fidelity", TS_PT_ENUM, F(fidelity), "", 0, 0, ts_engine_fidelity_names, 0, 0,
     "engine model: crank_angle, mean_value or map"},
    D(dyno_speed, "rad/s", 20, 300, "speed held by the dynamometer in engine_dyno runs"),
    D(bore, "m", 0.05, 0.3, "cylinder bore"),
    D(stroke, "m", 0.05, 0.3, "piston stroke"),
    D(rod_length, "m", 0.1, 0.8, "connecting-rod length"),
    D(compression_ratio, "1", 8, 25, "geometric compression ratio"),
    D(head_area_factor, "1", 1, 2, "head + fire-deck heat-transfer area / bore area"),
    D(piston_area_factor, "1", 1, 2.5, "piston crown (with bowl) area / bore area"),
    I(n_intake_valves, 1, 4, "intake valves per cylinder"),
    I(n_exhaust_valves, 1, 4, "exhaust valves per cylinder"),
    D(intake_valve_diameter, "m", 0.01, 0.1, "intake valve inner seat diameter"),
    D(exhaust_valve_diameter, "m", 0.01, 0.1, "exhaust valve inner seat diameter"),
    D(intake_max_lift, "m", 0.002, 0.03, "intake valve peak lift"),
    D(exhaust_max_lift, "m", 0.002, 0.03, "exhaust valve peak lift"),
    D(ivo, "rad", 0, 12.57, "intake valve opening, crank angle after firing TDC"),
    D(ivc, "rad", 0, 12.57, "intake valve closing, crank angle after firing TDC (>720 deg wraps)"),
    D(evo, "rad", 0, 12.57, "exhaust valve opening, crank angle after firing TDC"),
    D(evc, "rad", 0, 12.57, "exhaust valve closing, crank angle after firing TDC"),
    D(valve_cd, "1", 0.3, 1, "valve discharge coefficient on the curtain area"),
    D(valve_throat_factor, "1", 0.5, 1,
      "port throat area as a fraction of the inner seat area: the open valve's flow limit"),
    D(soi, "rad", 0, 1, "start of injection before firing TDC"),
    D(lhv, "J/kg", 3e7, 5e7, "fuel lower heating value"),
    D(afr_stoich, "1", 10, 20, "stoichiometric air/fuel ratio"),
    D(phi_rated, "1", 0.1, 1, "Eq. 13: target equivalence ratio at phi_speed"),
    D(phi_curvature, "s^2/rad^2", 0, 1e-4,
      "Eq. 13: growth of the target with (omega - phi_speed)^2 (the paper's per rpm^2 x "
      "(30/pi)^2)"),
    D(phi_speed, "rad/s", 50, 400, "Eq. 13: reference (rated) speed"),
    D(phi_max, "1", 0.3, 1.2, "upper limit on the equivalence ratio delivered by Eq. 14"),
    D(id_a, "s", 1e-4, 0.02, "ignition delay pre-factor: tau = a (p / 1 bar)^-n exp(ta/T)"),
    D(id_n, "1", 0.5, 2, "ignition delay pressure exponent"),
    D(id_ta, "K", 500, 10000, "ignition delay activation temperature"),
    D(burn_duration, "rad", 0.5, 4, "Watson burn duration"),
    D(watson_a, "1", 0, 2, "Watson premixed fraction: beta = 1 - a phi^b / tau_id^c"),
    D(watson_b, "1", 0, 2, "Watson premixed fraction exponent b"),
    D(watson_c, "1", 0, 2, "Watson premixed fraction exponent c"),
    D(watson_c1k, "1", 0, 1e-5, "Watson C1 = 2 + k (tau_id N)^e: k"),
    D(watson_c1e, "1", 0, 5, "Watson C1 exponent e"),
    D(watson_c2, "1", 1, 1e5, "Watson premixed C2"),
    D(watson_c3k, "1", 1, 100, "Watson diffusion C3 = k / phi^e: k"),
    D(watson_c3e, "1", 0, 2, "Watson diffusion C3 exponent e"),
    D(watson_c4k, "1", 0.1, 3, "Watson diffusion C4 = k C3^0.25: k"),
    A(cp_air, 4, "J/kg/K", -1e4, 1e4, "cp of air: c0 + c1 t + c2 t^2 + c3 t^3, t = T/1000 K"),
    A(cp_burned, 4, "J/kg/K", -1e4, 1e4, "cp of stoichiometric burned gas, same form"),
    D(r_air, "J/kg/K", 250, 320, "gas constant of air"),
    D(r_burned, "J/kg/K", 250, 320, "gas constant of stoichiometric burned gas"),
    D(nu_coeff, "1", 0.001, 1, "Nusselt correlation Nu = a Re^b: a"),
    D(nu_exp, "1", 0.5, 1, "Nusselt correlation exponent b"),
    D(gas_mu_coeff, "Pa*s", 1e-8, 1e-5,
      "gas viscosity mu = gas_mu_coeff T^gas_mu_exp (T in K): the coefficient"),
    D(gas_mu_exp, "1", 0.3, 1, "gas viscosity power law: the exponent of T"),
    D(gas_prandtl, "1", 0.5, 1, "gas Prandtl number (conductivity = mu cp / Pr)"),
    D(htc_piston_speed_share, "1", 0, 2,
      "share of the mean piston speed in the heat-transfer velocity beside U and u'"),
    D(cascade_cbeta, "1", 0.01, 2, "energy cascade: mean-flow to turbulence production constant"),
    D(cascade_rdt, "1", 0, 1, "energy cascade: rapid-distortion amplification of k in compression"),
    D(emissivity, "1", 0, 1, "effective gas emissivity during combustion"),
    D(metal_k, "W/m/K", 5, 200, "metal wall conductivity"),
    D(metal_rho_c, "J/m^3/K", 1e6, 1e7, "metal wall volumetric heat capacity"),
    D(piston_thickness, "m", 0.002, 0.05, "piston crown metal thickness"),
    D(head_thickness, "m", 0.002, 0.05, "fire-deck metal thickness"),
    D(liner_thickness, "m", 0.002, 0.05, "liner metal thickness"),
    D(zirconia_k, "W/m/K", 0.3, 5, "plasma-sprayed zirconia conductivity"),
    D(zirconia_rho_c, "J/m^3/K", 1e6, 5e6, "plasma-sprayed zirconia volumetric heat capacity"),
    D(coating_lhr05, "m", 0, 0.003, "zirconia thickness of variant lhr05"),
    D(coating_lhr10, "m", 0, 0.003, "zirconia thickness of variant lhr10"),
    {"/engine/coat_liner", TS_PT_BOOL, F(coat_liner), "", 0, 1, NULL, 0, 0,
     "LHR variants: zirconia also on the liner (otherwise piston and head only)"},
    D(h_coolant, "W/m^2/K", 100, 1e5, "head and liner back side to coolant"),
    D(h_oil, "W/m^2/K", 100, 1e5, "piston underside to oil"),
    D(coolant_temp, "K", 300, 420, "coolant thermostat set point"),
    D(oil_temp, "K", 300, 450, "oil cooler set point"),
    D(coolant_capacity, "J/K", 1e3, 1e7, "coolant + block lumped heat capacity"),
    D(oil_capacity, "J/K", 1e3, 1e7, "oil lumped heat capacity"),
    D(coolant_ua, "W/K", 10, 1e6, "radiator conductance at full thermostat opening"),
    D(oil_ua, "W/K", 10, 1e6, "oil cooler conductance at full opening"),
    D(thermostat_band, "K", 0.1, 50,
      "coolant and oil thermostats open linearly over this band centred on their set points"),
    D(fmep_a, "Pa", 0, 1e5, "Millington-Hartles: fmep = a (r_c - 4) + b omega + c S_p^2: a"),
    D(fmep_b, "Pa*s/rad", 0, 1e4, "Millington-Hartles b (per rad/s: the per-rpm b x 30/pi)"),
    D(fmep_c, "Pa*s^2/m^2", 0, 1e4, "Millington-Hartles c"),
    D(inertia, "kg*m^2", 0.1, 100, "engine + flywheel rotating inertia"),
    D(recip_mass, "kg", 0, 50, "reciprocating mass per cylinder (piston, pin, rod share)"),
    D(turbo_flow_scale, "1", 0.2, 5, "turbocharger flow scale over the reference truck unit"),
    D(comp_diameter_ref, "m", 0.02, 0.3, "reference compressor impeller tip diameter"),
    D(turb_diameter_ref, "m", 0.02, 0.3, "reference turbine wheel diameter"),
    D(comp_psi0, "1", 0.2, 2, "compressor isentropic head coefficient at zero flow"),
    D(comp_phi_choke, "1", 0.01, 0.5, "compressor choke flow coefficient"),
    D(comp_eta_max, "1", 0.4, 0.9, "compressor peak isentropic efficiency"),
    D(comp_phi_opt, "1", 0.01, 0.5, "flow coefficient of peak compressor efficiency"),
    D(comp_phi_width, "1", 0.01, 0.5, "half-width of the compressor efficiency island"),
    D(comp_eta_min, "1", 0.1, 0.8, "lower bound on compressor efficiency"),
    D(comp_mach_opt, "1", 0.3, 3.0,
      "tip Mach number U/a01 above which compressor efficiency falls"),
    D(comp_mach_width, "1", 0.1, 100.0,
      "tip Mach number span over which the efficiency falls to zero (quadratic)"),
    D(turb_area_ref, "m^2", 1e-5, 1e-2, "reference turbine effective nozzle area"),
    A(turb_sched_speed, TS_ENGINE_MAP_MAX, "rad/s", 0, 500,
      "engine speeds of the open-loop turbine geometry schedule (empty: fixed nozzle, "
      "boost-sensing wastegate alone)"),
    A(turb_sched_nozzle, TS_ENGINE_MAP_MAX, "1", 0.05, 5,
      "variable-geometry turbine: nozzle-area factor on turb_area_ref at turb_sched_speed"),
    A(turb_sched_gate, TS_ENGINE_MAP_MAX, "1", 0, 1,
      "factor on the wastegate actuator's boost-sensing opening at turb_sched_speed (1 as built, "
      "0 overridden)"),
    A(turb_sched_bypass, TS_ENGINE_MAP_MAX, "m^2", 0, 0.05,
      "turbine bypass effective area held open (engine-speed feed-forward) at turb_sched_speed, "
      "per bank"),
    D(turb_eta_max, "1", 0.4, 0.9, "turbine peak total-to-static efficiency"),
    D(turb_bsr_opt, "1", 0.4, 1, "blade-speed ratio of peak turbine efficiency"),
    D(turbo_inertia_ref, "kg*m^2", 1e-5, 1e-2, "reference rotor polar inertia"),
    D(turbo_mech_eff, "1", 0.5, 1, "turbocharger mechanical efficiency"),
    D(turbo_idle_speed, "rad/s", 0, 2e4, "rotor speed at ts_engine_init_state"),
    D(wg_area, "m^2", 0, 0.05, "wastegate (turbine bypass) effective area, fully open, per bank"),
    D(wg_crack, "Pa", 1e5, 1e6,
      "intake manifold pressure (absolute) at which the wastegate cracks open"),
    D(wg_full, "Pa", 1e5, 1e6,
      "intake manifold pressure (absolute) at which the wastegate is fully open"),
    D(ic_ua, "W/K", 10, 1e5, "intercooler overall conductance per bank"),
    D(ic_wall_temp, "K", 250, 400, "intercooler wall (coolant-side) temperature"),
    D(ic_cda, "m^2", 1e-4, 0.1, "intercooler outlet orifice effective area per bank"),
    D(ic_volume, "m^3", 1e-4, 0.5, "compressor outlet + intercooler volume per bank"),
    D(intake_volume, "m^3", 1e-4, 0.5, "intake manifold volume per bank"),
    D(exhaust_volume, "m^3", 1e-4, 0.5, "exhaust manifold volume per bank"),
    D(exhaust_ua, "W/K", 0, 1e4, "exhaust manifold heat loss conductance per bank"),
    D(ca_step, "rad", 1e-3, 0.1,
      "base crank-angle step of the engine's own integrators (fixed for cycle means; adaptive runs "
      "1/4 to 8 x)"),
    A(spool_speed, TS_ENGINE_MAP_MAX, "rad/s", 0, 500,
      "speeds of the part-boost tables /engine/pb_*"),
    A(spool_ratio, TS_ENGINE_MAP_MAX, "1", 0, 2,
      "intake manifold pressure / full-load boost (map_boost) of the part-boost tables"),
    A(spool_lag, TS_ENGINE_MAP_MAX, "s", 0.01, 100,
      "map fidelity: first-order boost time constant at spool_speed"),
    A(map_speed, TS_ENGINE_MAP_MAX, "rad/s", 0, 400, "speeds of the map tables"),
    MAPROWS("conventional", 0),
    MAPROWS("lhr05", 1),
    MAPROWS("lhr10", 2),
};
#undef F
#undef D
#undef I
#undef A
#undef MAPROWS

#define N(a) ((int)(sizeof a / sizeof a[0]))
const ts_param_section ts_section_engine = {"engine", "virtual V-12 diesel", engine_rows,
                                            N(engine_rows)};
#undef N
