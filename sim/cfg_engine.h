/*
 * cfg_engine.h — the "engine" section of a run config: the virtual V-12 diesel
 * (paper Section III.A-B.1, B.3; Figs. 15, 18) and its fuel law (Eqs. 13-14).
 *
 * Every number has its default and source in sim/data/defaults/engine.json;
 * the rows (units, ranges) are in cfg_engine.c. Groups: geometry and valves,
 * injection and fuel law, ignition delay and Watson burning, heat transfer and
 * walls, friction and inertia, turbochargers and intercoolers, manifolds, and
 * the map/mean-value tables produced by the crank-angle model's own sweep.
 */
#ifndef TS_CFG_ENGINE_H
#define TS_CFG_ENGINE_H

typedef enum ts_engine_variant {
    TS_ENGINE_CONVENTIONAL, /* all-metal combustion chamber */
    TS_ENGINE_LHR05,        /* 0.5 mm zirconia coating */
    TS_ENGINE_LHR10,        /* 1.0 mm zirconia coating */
    TS_NENGINE_VARIANT
} ts_engine_variant;
extern const char *const ts_engine_variant_names[];

typedef enum ts_engine_fidelity {
    TS_ENGINE_CRANK_ANGLE, /* twelve 0-D crank-angle cylinders */
    TS_ENGINE_MEAN_VALUE,  /* cycle-averaged cylinder, manifolds and turbos kept */
    TS_ENGINE_MAP,         /* torque map + first-order boost lag */
    TS_NENGINE_FIDELITY
} ts_engine_fidelity;
extern const char *const ts_engine_fidelity_names[];

#define TS_ENGINE_MAP_MAX 32 /* points of a map table */
#define TS_ENGINE_NCYL      12 /* cylinders of the V-12, two banks of six [P III.A] */
#define TS_ENGINE_SPOOL_MAX 96 /* points of a part-boost table (spool_speed x spool_ratio) */

/* Full-load steady-state tables of one variant vs /engine/map_speed, written by
 * `tanksim engine-map` from the crank-angle model (provenance in engine.json). */
typedef struct ts_engine_map_table {
    double torque[TS_ENGINE_MAP_MAX]; /* brake torque [N*m] */
    double boost[TS_ENGINE_MAP_MAX];  /* intake manifold pressure [Pa] */
    double fuel[TS_ENGINE_MAP_MAX];   /* fuel flow, whole engine [kg/s] */
    double eta_v[TS_ENGINE_MAP_MAX];  /* volumetric efficiency vs intake manifold [1] */
    double eta_i[TS_ENGINE_MAP_MAX];  /* gross indicated efficiency [1] */
    double q_wall[TS_ENGINE_MAP_MAX]; /* in-cylinder heat loss / fuel energy [1] */
    int torque_n, boost_n, fuel_n, eta_v_n, eta_i_n, q_wall_n;
    /* Part-boost factors from the crank-angle spool-ups (`tanksim engine-map
     * --spool`): value / full-load value at (spool_speed[i], spool_ratio[j]),
     * row-major by speed; ratio = intake manifold pressure / map_boost. */
    double pb_eta_v[TS_ENGINE_SPOOL_MAX], pb_eta_i[TS_ENGINE_SPOOL_MAX];
    double pb_q_wall[TS_ENGINE_SPOOL_MAX], pb_torque[TS_ENGINE_SPOOL_MAX];
    int pb_eta_v_n, pb_eta_i_n, pb_q_wall_n, pb_torque_n;
} ts_engine_map_table;

typedef struct ts_engine_config {
    int variant;       /* ts_engine_variant */
    int fidelity;      /* ts_engine_fidelity */
    double dyno_speed; /* speed held by the dynamometer in engine_dyno runs [rad/s] */

    /* geometry */
    double bore, stroke, rod_length; /* [m] */
    double compression_ratio;        /* [1] */
    double head_area_factor;         /* head + fire-deck area / bore area [1] */
    double piston_area_factor;       /* piston crown (bowl) area / bore area [1] */
    /* valves (per cylinder; angles from firing TDC, 0..720 deg CA, in rad) */
    int n_intake_valves, n_exhaust_valves;
    double intake_valve_diameter, exhaust_valve_diameter; /* [m] */
    double intake_max_lift, exhaust_max_lift;             /* [m] */
    double ivo, ivc, evo, evc;                            /* valve events [rad CA] */
    double valve_cd;                                      /* discharge coefficient [1] */
    double valve_throat_factor; /* port throat area / inner seat area [1] */
    /* injection and fuel law */
    double soi;            /* start of injection, before firing TDC [rad CA] */
    double lhv;            /* fuel lower heating value [J/kg] */
    double afr_stoich;     /* stoichiometric air/fuel ratio [1] */
    double phi_rated;      /* Eq. 13 constant term [1] */
    double phi_curvature;  /* Eq. 13 coefficient [s^2/rad^2] */
    double phi_speed;      /* Eq. 13 reference speed [rad/s] */
    double phi_max;        /* smoke limit on the trapped equivalence ratio [1] */
    /* ignition delay (Arrhenius, Livengood-Wu integral) */
    double id_a, id_n, id_ta; /* tau [s] = a (p / 1 bar)^-n exp(ta/T): [s], [1], [K] */
    /* Watson burning */
    double burn_duration;                 /* [rad CA] */
    double watson_a, watson_b, watson_c;  /* premixed fraction */
    double watson_c1k, watson_c1e, watson_c2, watson_c3k, watson_c3e, watson_c4k;
    /* gas properties: cp(T) = c0 + c1 t + c2 t^2 + c3 t^3, t = T/1000 K */
    double cp_air[4], cp_burned[4];
    int cp_air_n, cp_burned_n;
    double r_air, r_burned; /* gas constants [J/kg/K] */
    /* heat transfer */
    double nu_coeff, nu_exp;  /* Nu = a Re^b */
    double gas_mu_coeff, gas_mu_exp; /* gas viscosity mu = coeff T^exp [Pa*s, T in K] */
    double gas_prandtl;              /* [1] */
    double htc_piston_speed_share;   /* share of the mean piston speed in the velocity [1] */
    double cascade_cbeta;     /* energy-cascade production constant [1] */
    double cascade_rdt;       /* rapid-distortion (compression) coefficient [1] */
    double emissivity;        /* radiation during combustion [1] */
    /* walls: metal (piston, head, liner), coating, coolant and oil */
    double metal_k, metal_rho_c;           /* [W/m/K], [J/m^3/K] */
    double piston_thickness, head_thickness, liner_thickness; /* metal [m] */
    double zirconia_k, zirconia_rho_c;     /* [W/m/K], [J/m^3/K] */
    double coating_lhr05, coating_lhr10;   /* coating thickness per variant [m] */
    int coat_liner;                        /* LHR coating also on the liner (bool) */
    double h_coolant, h_oil;               /* back-side film coefficients [W/m^2/K] */
    double coolant_temp, oil_temp;         /* thermostat set points [K] */
    double coolant_capacity, oil_capacity; /* lumped heat capacities [J/K] */
    double coolant_ua, oil_ua;             /* radiator / oil cooler at full opening [W/K] */
    double thermostat_band;                /* opening band around each set point [K] */
    /* friction and inertia */
    double fmep_a, fmep_b, fmep_c; /* Millington-Hartles [Pa], [Pa*s/rad], [Pa/(m/s)^2] */
    double inertia;                /* engine + flywheel, rotating [kg*m^2] */
    double recip_mass;             /* reciprocating mass per cylinder [kg] */
    /* turbocharger (per bank): reference truck unit + flow scale factor */
    double turbo_flow_scale;                      /* s_m [1] */
    double comp_diameter_ref, turb_diameter_ref;  /* [m] */
    double comp_psi0, comp_phi_choke;             /* isentropic head / flow coefficients [1] */
    double comp_eta_max, comp_phi_opt, comp_phi_width, comp_eta_min;
    double comp_mach_opt, comp_mach_width; /* efficiency fall-off with tip Mach number [1] */
    double turb_area_ref;                         /* effective nozzle area [m^2] */
    /* turbine geometry scheduled OPEN LOOP in engine speed (full-load
     * feed-forward; linear between the nodes, held beyond; empty tables = the
     * fixed nozzle and the boost-sensing wastegate alone): at
     * turb_sched_speed the nozzle area is x turb_sched_nozzle, the wastegate
     * actuator's opening x turb_sched_gate, and a bypass of turb_sched_bypass
     * is held open beside it */
    double turb_sched_speed[TS_ENGINE_MAP_MAX]; /* [rad/s] */
    int turb_sched_speed_n;
    double turb_sched_nozzle[TS_ENGINE_MAP_MAX]; /* nozzle-area factor [1] */
    int turb_sched_nozzle_n;
    double turb_sched_gate[TS_ENGINE_MAP_MAX]; /* wastegate actuator authority [1] */
    int turb_sched_gate_n;
    double turb_sched_bypass[TS_ENGINE_MAP_MAX]; /* open-loop bypass area [m^2] */
    int turb_sched_bypass_n;
    double turb_eta_max, turb_bsr_opt;            /* peak efficiency, blade-speed ratio */
    double turbo_inertia_ref;                     /* [kg*m^2] */
    double turbo_mech_eff;                        /* [1] */
    double turbo_idle_speed;                      /* initial rotor speed [rad/s] */
    double wg_area;                               /* wastegate full-open effective area [m^2] */
    double wg_crack, wg_full;                     /* boost at which it cracks / is fully open [Pa] */
    /* intercooler and manifolds (per bank) */
    double ic_ua, ic_wall_temp, ic_cda, ic_volume; /* [W/K], [K], [m^2], [m^3] */
    double intake_volume, exhaust_volume;           /* [m^3] */
    double exhaust_ua;                              /* exhaust manifold heat loss [W/K] */
    /* numerics of the crank-angle model */
    double ca_step;          /* base step of the engine's integrators [rad CA] */
    /* map and mean-value fidelities */
    double spool_speed[TS_ENGINE_MAP_MAX]; /* part-boost tables: speeds [rad/s] */
    int spool_speed_n;
    double spool_ratio[TS_ENGINE_MAP_MAX]; /* part-boost tables: p_im / map_boost [1] */
    int spool_ratio_n;
    double spool_lag[TS_ENGINE_MAP_MAX]; /* map: boost time constant at spool_speed [s] */
    int spool_lag_n;
    double map_speed[TS_ENGINE_MAP_MAX]; /* [rad/s] */
    int map_speed_n;
    ts_engine_map_table map[TS_NENGINE_VARIANT];
} ts_engine_config;

#endif
