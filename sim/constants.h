/*
 * constants.h — the physical and mathematical constants sim/ uses, defined once
 * (they were repeated per file). Not parameters: a parameter that a user may
 * change belongs in the parameter table and sim/data/defaults.
 */
#ifndef TS_CONSTANTS_H
#define TS_CONSTANTS_H

#define TS_PI      3.14159265358979323846 /* pi */
#define TS_GRAVITY 9.80665                /* standard gravity [m/s^2] (ISO 80000-3) */
#define TS_MPH     0.44704                /* m/s per mile per hour (exact) */
#define TS_LBF     4.44822                /* N per pound-force, for display only */
#define TS_HP      745.69987158227022     /* W per mechanical horsepower (550 ft*lbf/s), display only */

/* Cold-air properties of the compressor map (engine_turbo.c): its head and
 * tip Mach number are reduced with constant cp and gamma of dry air at
 * ~300 K (cp 1005 J/kg/K, gamma 1.4; SAE J1826 turbocharger test code
 * convention). The turbine is evaluated with the exhaust gas's own R and cp
 * (engine_manifold.c), and the cylinder and manifolds use temperature- and
 * composition-dependent properties (engine_gas.c). */
#define TS_CP_AIR_MAP    1005.0 /* [J/kg/K] */
#define TS_GAMMA_AIR_MAP 1.4    /* [1] */

#endif
