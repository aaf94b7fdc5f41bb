/*
 * vehicle_model.h — the pitch-plane M1 model of paper Section II.C (Fig. 7):
 * hull, seven road arms with torsion bars, dampers and bump stops, road wheels,
 * rear sprocket, front idler on the (locked, grease) track-adjusting link, two
 * support rollers, and the track as a closed chain of elements between the
 * tangent points of neighbouring wheels, on a track–terrain foundation.
 *
 * Frame: x forward (direction of travel), z up, world origin on the ground at
 * the course start; pitch theta positive nose-down (clockwise in x–z). Every
 * wheel's spin Phi is ABSOLUTE and positive clockwise (rolling forward), so the
 * track runs clockwise around the circuit: sprocket -> rear roller -> front
 * roller -> idler -> road wheel 1 -> ... -> road wheel 7 -> sprocket.
 *
 * ONE SIDE is modelled: half the hull mass and pitch inertia on one track and
 * its running gear (both tracks identical: a pitch-plane model). Wheel loads and tensions
 * are per side; the sprocket torque is the torque at each sprocket.
 *
 * Generalised coordinates q (21 for the rigid bodies, as the paper's static model):
 *   0 x, 1 z (hull CG, world), 2 theta, 3..9 road-arm angles alpha_1..7 (below
 *   hull x, relative to the hull), 10..20 spins Phi of the circuit bodies in
 *   circuit order (sprocket, rear roller, front roller, idler, road wheels 1..7),
 *   then the span modal coordinates of the dynamic fidelities (per free span:
 *   n_long longitudinal, then n_trans transverse).
 * State y = [q, dq/dt].
 *
 * Track element between bodies a -> b (stretch s):
 *   s = (l - l0) + (rho_b - rho_a)(psi - psi0) + rho_b Phi_b - rho_a Phi_a,
 * l the tangent length, psi the chord angle; the (rho_b - rho_a) dpsi term is
 * the change of the wrap arcs, so sum(s) is the change of the whole loop.
 * Static fidelity: T = P0 + EA/L s + EA tau_d/L ds/dt (massless chain).
 * Dynamic fidelities: each free span is a track_span.h element whose end
 * coordinates are u0 = rho_a (Phi_a + dpsi), u1 = rho_b (Phi_b + dpsi) + l - l0.
 *
 * Ownership: vm_make / vm_free; vm_work_make / vm_work_free (scratch for one
 * thread). A vm is read-only after vm_make (which solves the static
 * equilibrium) and may be shared.
 */
#ifndef TS_VEHICLE_MODEL_H
#define TS_VEHICLE_MODEL_H

#include "config.h"
#include "errors.h"
#include "geometry.h"

#define VM_NRW      7  /* road wheels per side (the layout must give 7) */
#define VM_NB       11 /* bodies the track wraps */
#define VM_NSPAN    5  /* free spans */
#define VM_NQ_RIGID 21 /* rigid-body DOF */

enum vm_body {
    VM_SPROCKET,
    VM_REAR_ROLLER,
    VM_FRONT_ROLLER,
    VM_IDLER,
    VM_RW1 /* .. VM_RW1 + 6 */
};
/* Track elements: element k runs from body k to body (k + 1) % VM_NB. Free spans
 * are elements 0 (sprocket -> rear roller), 1 (rear -> front roller), 2 (front
 * roller -> idler), 3 (idler -> road wheel 1), 10 (road wheel 7 -> sprocket). */
extern const int vm_span_element[VM_NSPAN];
extern const char *const vm_span_names[VM_NSPAN];
extern const char *const vm_body_names[VM_NB];

typedef struct vm vm;
typedef struct vm_work vm_work;

/* Diagnostics of one right-hand-side evaluation. */
typedef struct vm_diag {
    double tension[VM_NB]; /* element tension (spans: mean of the two ends) [N] */
    double tension_end0[VM_NB], tension_end1[VM_NB]; /* at the a and b ends [N] */
    double wheel_load[VM_NRW];            /* foundation normal force per road wheel [N] */
    double arm_angle[VM_NRW];             /* [rad] */
    double rear_roller_normal;            /* track on the rear roller, along hull -z [N] */
    double anchor_force;                  /* tangential ground force at the anchor [N] */
    double span_mid_deflection[VM_NSPAN]; /* dynamic transverse V at mid-span [m] */
    double span_mid_tension[VM_NSPAN];    /* total tension at mid-span [N] */
    double drive_torque;                  /* [N*m] */
    /* Quasi-static reference (Fig. 12's "dynamic amplification"): the tension
     * a massless track (the static fidelity's element law T = P0 + EA/L s,
     * no damping, free-turning rollers, idler and road wheels) would have at
     * the rear roller for the CURRENT support positions and sprocket torque:
     *   T_qs = max(0, T_static + (G - G_eq - (tau / r_s) C_B) / C_loop),
     * G the loop's geometric stretch (sum over the elements of
     * (l - l0) + (rho_b - rho_a) dpsi), G_eq its value at the static
     * equilibrium, C_loop = sum L_e/EA the loop compliance, C_B that of the
     * elements from the anchor wheel to the sprocket (the sprocket makes their
     * tension tau/r_s higher than the rest of the loop's). Same for every
     * fidelity, so T_rear_roller - T_qs is the dynamic part. */
    double loop_stretch;         /* G [m] */
    double tension_quasi_static; /* T_qs [N] */
} vm_diag;

vm *vm_make(const ts_config *cfg, ts_err *err);
void vm_free(vm *v);

int vm_nq(const vm *v);  /* generalised coordinates */
int vm_ny(const vm *v);  /* first-order states, 2 nq */
int vm_dof(const vm *v); /* = nq */

/* Static-equilibrium state (velocities zero), ny values. The torsion bars'
 * preloads (arms at their design angle) and the idler link's setting (rear-
 * roller tension P0) are those of the design equilibrium on level ground; where
 * the ground under the road wheels is uneven at t = 0 the vehicle then settles
 * on it with those preloads and that setting, so its arm angles and rest
 * tension are the terrain's (vm_static_tension gives that tension). */
const double *vm_equilibrium(const vm *v);
/* Each coordinate's own rate sqrt(K_ii / M_ii) at the static equilibrium [1/s]
 * (nq values; K_ii = -dQ_i/dq_i with the other coordinates held, M_ii the mass
 * matrix's diagonal), 0 where K_ii <= 0: the scale that relates a velocity
 * error to a coordinate error of the same energy (scenario_vehicle.c's
 * absolute tolerances). */
const double *vm_rates(const vm *v);

/* Integrator settings for the vehicle's states, shared by the standalone
 * vehicle (scenario_vehicle.c) and the coupled runs (coupled_system.c).
 * Numerical choices, not physics; measured in vehicle_model.c (above
 * vm_abs_tolerances) against rtol 1e-6 reference runs. */
#define VM_BDF_MAX_ORDER  3    /* highest BDF order */
#define VM_JAC_EVAL_STEPS 1000 /* most steps between Jacobian evaluations */
/* Absolute tolerances of the ny states into out: atol for each coordinate
 * (m, rad), atol omega_i (vm_rates) for its rate, atol / 0.01 s for the rate
 * of a coordinate without a restoring stiffness. */
void vm_abs_tolerances(const vm *v, double atol, double *out);
/* Static quantities found by the equilibrium solve. */
double vm_static_tension(const vm *v);   /* rear-roller tension at rest [N] */
double vm_preload(const vm *v, int arm); /* torsion-bar torque at the design angle [N*m] */
double vm_supported_weight(const vm *v); /* weight carried by the road wheels, one side [N] */

vm_work *vm_work_make(const vm *v);
void vm_work_free(vm_work *w);

/* dy/dt at (t, y). Returns 0, or > 0 for a recoverable failure (bad geometry).
 * diag (may be NULL) receives the element forces of this evaluation. */
TS_MUST_CHECK int vm_rhs(const vm *v, vm_work *w, double t, const double *y, double *ydot,
                         vm_diag *diag);

/* Total mechanical energy (kinetic + elastic + gravity) of state y [J], with
 * the same consistent approximations as vm_rhs (see vehicle_model.c). */
double vm_energy(const vm *v, vm_work *w, const double *y);

/* Generalised forces Q(q, dq/dt, t) of state y (nq values): everything but the
 * inertia M q_dd (rigid-body velocity terms and gravity included). */
void vm_forces(const vm *v, vm_work *w, double t, const double *y, int drive_on, double *Q);

/* Mass matrix M(q) of state y (nq x nq, row-major, symmetric). */
void vm_mass(const vm *v, vm_work *w, const double *y, double *M);

/* Geometry snapshot (geometry.h) of state y at time t. */
void vm_geometry(const vm *v, vm_work *w, double t, const double *y, ts_geom *g);

/* Hull CG world x at t = 0 [m]. */
double vm_x0(const vm *v);

/* Where state y stands, for an error message (writes at most n bytes, always
 * terminated): the hull CG's world x, z and pitch and the lowest and highest
 * ground under the road wheels, so that a run the integrator gave up on names
 * the terrain it met. */
void vm_describe_state(const vm *v, const double *y, char *out, size_t n);

/* The same appended to err's message ("; ..."), as far as it has room; a
 * NULL err is left alone. */
void vm_err_add_state(const vm *v, const double *y, ts_err *err);

/* The error of a vm_rhs / vm_rhs_torque that failed at (t, y) outside an
 * integrator's step (a sample, a coupling report): TS_ERR_DIVERGED, the
 * state described. Returns the code. */
ts_rc vm_rhs_failed(const vm *v, double t, const double *y, ts_err *err);

/* vm_rhs with the torque at EACH sprocket given by the caller [N*m] instead of
 * the prescribed /drive (which is then not applied), and an extra hull-mounted
 * inertia turning with the sprocket relative to the hull [kg*m^2] (0: none):
 * the powertrain coupling (coupled_system.h). Added by the coupled branch
 * (issue 10). */
TS_MUST_CHECK int vm_rhs_torque(const vm *v, vm_work *w, double t, const double *y,
                                double sprocket_torque, double sprocket_inertia, double *ydot,
                                vm_diag *diag);

#endif
