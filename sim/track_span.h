/*
 * track_span.h — one free track span as a shallow-sag elastic continuum,
 * discretised by component modes (paper Section II.A–C, Eqs. 1–9, Fig. 2, Fig. 6).
 *
 * WHAT
 *   A span runs between the tangent points of two support circles (sprocket,
 *   idler, roller, road wheel). In the CHORD FRAME (Fig. 6) — origin at tangent
 *   point 0, e_x along the chord from end 0 to end 1 (the direction of travel
 *   around the circuit), e_y = z_hat x e_x (e_x rotated +90 deg in the x–z
 *   plane; right-handed) — the track has the parabolic equilibrium sag
 *       Y0(s) = (kappa/2) s (L - s),   kappa = rho g_y / P0          (Eq. 9)
 *   (with translation_terms kappa = rho g_y / (P0 - rho c^2): a span moving
 *   at c along its chord hangs from the tension less the momentum flux,
 *   (P0 - rho c^2) Y0'' = -rho g_y, so V = 0 stays its equilibrium and the
 *   sag coupling k1 = EA kappa, k2 = EA kappa^2 (Irvine's lambda^2) grow)
 *   (g_y = gravity component along e_y, so the sag hangs along gravity) and
 *   small displacements U(s,t) along e_x and V(s,t) along e_y. The linear
 *   dynamic tension is
 *       tau = EA (U_x + kappa V)                                       (Eqs. 1-2)
 *   The paper prints tau = EA(U_x - kappa V) with y the outward normal; the
 *   sign follows the orientation of y and changes no frequency (kappa enters
 *   the frequencies only as kappa^2 = k2/EA).
 *   Energies:  T = 1/2 rho \int (U_t + c U_s)^2 + (V_t + c V_s)^2 ds
 *              W = 1/2 \int EA (U_x + kappa V)^2 + P0 V_x^2 ds (+ P0 * stretch)
 *   whose Euler–Lagrange equations are Eqs. 1–2 (c = track speed along e_x
 *   relative to the chord frame; c-terms only with translation_terms on).
 *
 * COORDINATES (Section II.C component modes). The span's n = 2 + n_long +
 * n_trans generalised coordinates x[] are, in this order:
 *   x[0] = u0  track displacement along e_x at end 0 (s = 0)     [m]
 *   x[1] = u1  track displacement along e_x at end 1 (s = L)     [m]
 *   x[2 .. 2+n_long-1]          longitudinal sine modes q_Lj     [m]
 *   x[2+n_long .. n-1]          transverse sine modes q_Tk       [m]
 *   U(s) = u0 (1 - s/L) + u1 s/L + sum_j q_Lj sin(j pi s/L)
 *   V(s) = sum_k q_Tk sin(k pi s/L)
 * (u0, u1) span the paper's rigid-body mode (track transport, u0 = u1) and
 * constraint mode (static stretch u1 - u0). They are SUPPORT coordinates: the
 * caller ties them to support motion, e.g. for a support of pitch radius r
 * turning by phi (positive feeding track along the circuit direction):
 *   u0 = r_a phi_a                  (the chord frame rides on tangent point 0)
 *   u1 = r_b phi_b + (L(t) - L_ref)  (a longer chord moves end 1 along e_x)
 * The modal coordinates q are the span's own DOFs (fixed–fixed sine modes).
 *
 * MATRICES (n x n, row-major, per span, in chord-frame coordinates; constant
 * for a given L, g_y, c):
 *   M  mass              rho \int N_i N_j
 *   K  stiffness         EA \int N_i' N_j'  (long.)   P0 \int phi' phi' + EA kappa^2 \int phi phi
 *                        (trans.)  EA kappa \int N_i' phi_k  (sag coupling, k1 of Eq. 9)
 *                        - rho c^2 \int N_i' N_j'  (translation_terms)
 *      with quasi_static_stretch (and n_long = 0) the longitudinal field is
 *      condensed to uniform tension (Irvine; paper fidelity "transverse"):
 *      W = EA/(2L) (u1 - u0 + kappa \int V)^2 + 1/2 P0 \int V_x^2.
 *   G  gyroscopic        rho c (\int N_i N_j' - \int N_i' N_j)   (zero unless
 *                        translation_terms and c != 0)
 *   C  damping           2 zeta sqrt(K_jj M_jj) on the modal diagonal only
 *   (G needs >= 2 modes of a family to act: one sine mode has no
 *   gyroscopic partner, only the -rho c^2 softening.)
 *   W  Coriolis          rho \int N_i phi_k (long. row i, trans. col k), minus
 *                        its transpose: the 2 theta_dot terms of Eqs. 4–5
 *   Equations of motion of all n coordinates in the (rotating, accelerating)
 *   chord frame:    M x_dd = f(x, x_d, motion)     with f from ts_span_force().
 *
 * HOW A VEHICLE MODEL USES A SPAN (Eqs. 4–8):
 *   - q (modal) rows:   M_qq q_dd = f_q - M_qb u_b_dd
 *     M_qb (rows 2.., columns 0..1) is the inertia coupling of the modes to
 *     the support coordinates. Either assemble it into the global mass matrix
 *     (M_qb d(u_b)/d(y) blocks, exact) or move -M_qb u_b_dd to the right-hand
 *     side with the previous step's support accelerations (explicit, lagged).
 *   - support rows (0, 1): f_b is the force the span puts on each support
 *     ALONG e_x (static tension P0 included): f[0] ~ +(P0 + tau0) pulls
 *     support 0 toward end 1, f[1] ~ -(P0 + tau1) pulls support 1 back. Add
 *     f_b to the support's feed equation (torque r * f on a wheel) and the
 *     span's inertia M_bb, M_bq to the support rows if the span mass is wanted
 *     there (M_bb is the track mass of the constraint/rigid modes).
 *   - ts_span_end_forces_eval() gives the full force vectors on both supports in
 *     the chord axes (tension along the chord + transverse shear from
 *     (Y0' + V_x) at the ends); rotate with the chord axes to hull/global.
 *   Included in f: elastic/geometric stiffness (Eqs. 1–2, 4–5 with k1, k2,
 *   P0), modal damping, gyroscopic transport terms (option), the support-
 *   acceleration inertial loading rho(x0_dd) on U (all longitudinal rows,
 *   so f[0] + f[1] carries the span mass times -a0x) and rho(y0_dd +
 *   s theta_dd) on V (modal rows), the centripetal -rho s theta_d^2 on U, the
 *   Coriolis -2 theta_d V_t (on U) and +2 theta_d U_t (on V) of Eqs. 4–5
 *   (with translation_terms also the transport's, +2 theta_d c on V, i.e.
 *   the load -2 theta_d c rho \int phi), and a change of g_y from the value
 *   the sag was built for.
 *   Left out (second order in small quantities or the caller's part):
 *   the Coriolis terms of the convected gradients, 2 theta_d c (V_s, -U_s);
 *   -theta_dd (Y0 + V) on U and -theta_d^2 (Y0 + V) on V; P0 U_x^2 geometric
 *   stiffness (P0/EA ~ 0.2 %); the tension gradient rho g_x along the chord
 *   (gravity along e_x); and the rigid-body Eqs. 6–8 of the segment NORMAL to
 *   the chord: V is measured from the chord, so the span's rigid mass moving
 *   with the tangent points normal to the chord is not in any row — lump
 *   m/2 = rho L/2 onto each tangent point (or use Eqs. 6–8 with m, n1,
 *   inertia of ts_span). The end forces of ts_span_end_forces_eval() are the
 *   elastic forces (P0 + tau along the track tangent) without inertia.
 *
 * OWNERSHIP: ts_span_make() allocates; ts_span_free() releases (NULL ok).
 * A ts_span is immutable after construction and may be shared read-only.
 */
#ifndef TS_TRACK_SPAN_H
#define TS_TRACK_SPAN_H

#include "errors.h"

#define TS_SPAN_MAX_MODES    16 /* per family (longitudinal, transverse) */
#define TS_SPAN_SLACK_POINTS 48 /* points of the slack law's rule (ts_span_slack_force) */

/* A support circle in the x–z plane (hull or global frame) [m]. */
typedef struct ts_span_support {
    double x, z;   /* centre [m] */
    double radius; /* pitch-line (wrap) radius [m], >= 0 */
    int side;      /* +1: circle lies LEFT of the direction of travel (the track
                      wraps it counter-clockwise — every wheel of a loop run
                      counter-clockwise in x–z); -1: right (clockwise wrap) */
} ts_span_support;

/* Common tangent of two support circles, leaving a, arriving at b. */
typedef struct ts_span_geometry {
    double p0[2], p1[2]; /* tangent points (x, z) on a and b [m] */
    double length;       /* chord length L = |p1 - p0| [m] */
    double angle;        /* chord angle theta: e_x = (cos, sin) in x–z [rad] */
    double ex[2], ey[2]; /* chord axes in x–z; ey = (-ex_z, ex_x) */
} ts_span_geometry;

/* Tangent points, chord length and angle from two support circles.
 * TS_ERR_RANGE when the circles overlap so that no such tangent exists.   */
TS_MUST_CHECK ts_rc ts_span_tangent(const ts_span_support *a, const ts_span_support *b,
                                    ts_span_geometry *g, ts_err *err);

/* What a span is built from. */
typedef struct ts_span_params {
    double length;            /* chord length L [m] > 0 */
    double g_y;               /* gravity along e_y [m/s^2], ts_span_gravity_normal() */
    double rho;               /* mass per length [kg/m] > 0 */
    double ea;                /* axial stiffness EA [N] > 0 */
    double tension;           /* static tension P0 [N] > 0 */
    double speed;             /* track speed c along e_x, chord frame [m/s] */
    int translation_terms;    /* 1: keep the c-terms of Eqs. 1–2 (G and -rho c^2) */
    int quasi_static_stretch; /* 1: uniform-tension (Irvine) stretch; needs n_long = 0 */
    int n_long;               /* longitudinal sine modes, 0..TS_SPAN_MAX_MODES */
    int n_trans;              /* transverse sine modes, 0..TS_SPAN_MAX_MODES */
    double damping_ratio;     /* modal damping ratio zeta of the sine modes [1] */
} ts_span_params;

/* A built span (all arrays row-major n x n or length n; read-only). */
typedef struct ts_span {
    ts_span_params p; /* copy of the inputs */
    int n;            /* coordinates: 2 + n_long + n_trans */
    int i_long;       /* index of the first longitudinal mode (2) */
    int i_trans;      /* index of the first transverse mode (2 + n_long) */
    /* Eq. 9 constants */
    double kappa;          /* equilibrium curvature rho g_y / (P0 [- rho c^2]) [1/m] */
    double k;              /* kappa L [1] (shallow sag: |k| < 1) */
    double m;              /* rho L [kg] */
    double n1;             /* 1/2 rho L^2 [kg m] (the paper's n) */
    double inertia;        /* 1/3 rho L^3 [kg m^2] (the paper's I, about end 0) */
    double k1;             /* EA kappa [N/m] */
    double k2;             /* EA kappa^2 [N/m^2] */
    double sag;            /* mid-span sag Y0(L/2) = kappa L^2 / 8 [m], along e_y */
    double *M, *K, *G, *C; /* n x n mass, stiffness, gyroscopic, damping */
    double *W;             /* n x n Coriolis matrix (skew), see header comment */
    double *ax;            /* [n] rho \int N_i (longitudinal rows), 0 else: load per x0_dd */
    double *ay;            /* [n] rho \int phi_k (transverse rows), 0 else: load per y0_dd */
    double *sx;            /* [n] rho \int s N_i (longitudinal rows): centripetal load */
    double *sy;            /* [n] rho \int s phi_k (transverse rows): load per theta_dd */
    /* the slack law's rule: strain basis de/dx_i at its points, their weight */
    double *slack_b;    /* [TS_SPAN_SLACK_POINTS x n] */
    double *slack_bmax; /* [n] max over the points of |de/dx_i| (a quick stress bound) */
    double slack_w;     /* weight of each point [m] */
} ts_span;

/* Support motion in the chord frame, for ts_span_force(). */
typedef struct ts_span_motion {
    double a0x, a0y; /* acceleration of tangent point 0 along e_x, e_y [m/s^2] */
    double theta_d;  /* chord angular velocity [rad/s] (counter-clockwise in x–z) */
    double theta_dd; /* chord angular acceleration [rad/s^2] */
    double g_y;      /* gravity along e_y now [m/s^2] (the sag was built for p.g_y) */
} ts_span_motion;

/* Force of the span on each support, chord axes (excludes span inertia). */
typedef struct ts_span_end_forces {
    double f0x, f0y;           /* on support 0 along e_x, e_y [N] */
    double f1x, f1y;           /* on support 1 along e_x, e_y [N] */
    double tension0, tension1; /* P0 + tau at s = 0 and s = L [N] */
} ts_span_end_forces;

/* Chord kinematics from the two tangent points (positions P, velocities Vp,
 * accelerations Ap, x–z frame, index 0/1 = end 0/1; Ap may be NULL for
 * zero): fills the chord frame of the current position (length, angle, axes)
 * and the motion terms of Eqs. 4–8 (theta_d, theta_dd, a0x, a0y in chord
 * axes; g_y = gravity g along -z projected on e_y). *ldot gets dL/dt (for
 * u1's chord-length term). With L the chord, d = P1 - P0 = L e_x:
 *   L_d = (V1 - V0).e_x,  theta_d = (V1 - V0).e_y / L,
 *   theta_dd = ((A1 - A0).e_y - 2 L_d theta_d) / L.                         */
void ts_span_kinematics(const double P[2][2], const double Vp[2][2], const double Ap[2][2],
                        double g, ts_span_geometry *geom, ts_span_motion *mo, double *ldot);

/* Gravity component along e_y for a chord at angle theta (x–z, gravity -z). */
double ts_span_gravity_normal(double theta, double g);

/* Build a span. NULL on failure (err names the offending ts_span_params field
 * as "/span/<field>": TS_ERR_RANGE for out-of-range values, TS_ERR_NOMEM). */
ts_span *ts_span_make(const ts_span_params *p, ts_err *err);
void ts_span_free(ts_span *sp);

/* Rewrite a ts_span_make error's "/span/<field>" pointer as the run-config
 * field the span parameter comes from (/track/tension, /track/ea, ...), so a
 * caller building spans from a ts_config reports a field the user can change.
 * layout: the pointer for the geometry-derived fields (length, g_y), e.g.
 * "/vehicle" or "/track/span_length". Other pointers are left alone. */
void ts_span_err_to_config(ts_err *err, const char *layout);

/* Generalised forces f[n] on all coordinates (everything but -M x_dd):
 *   f = -P0 [-1, 1, 0..] - K x - (C + G) x_d + 2 theta_d (W x_d - c ay)
 *       - a0x ax - a0y ay + theta_d^2 sx - theta_dd sy + (g_y - p.g_y) ay
 * (c = p.speed with translation_terms, else 0)
 * (ay is rho \int phi, so the last term is the load of the changed weight).
 * x, x_d [n]; motion may be NULL (fixed supports). f may not alias x/x_d. */
void ts_span_force(const ts_span *sp, const ts_span_motion *mo, const double *x, const double *xd,
                   double *f);

/* End forces on the two supports from the state x [n] (chord axes): tension
 * P0 + tau (tau = EA(U_x + kappa V) evaluated at the end) along the chord and
 * the transverse shear P0 (Y0' + V_x) + tau Y0' normal to it. */
void ts_span_end_forces_eval(const ts_span *sp, const double *x, ts_span_end_forces *ef);

/* Field along the span at s in [0, L] from x [n]: U, V (dynamic, chord axes)
 * and tau (dynamic tension; total tension = P0 + tau). Any output may be NULL.
 * The static sag is ts_span_sag(sp, s). */
void ts_span_eval(const ts_span *sp, const double *x, double s, double *U, double *V, double *tau);

/* No-compression (slack) law: a track cannot push. The span's axial stress
 * field is sigma(s) = P0 + EA (e(s) + t_kv e_d(s)), e = U_x + kappa V (the
 * uniform Irvine stretch with quasi_static_stretch), t_kv a Kelvin-Voigt
 * retardation time [s] (0: elastic only; xd may then be NULL). The linear span
 * of ts_span_force carries every sigma, compression included; this adds to
 * f[n] the generalised forces that take the compressive part out:
 *     f_i += \int_0^L min(sigma, 0) de/dx_i ds
 * i.e. the forces of the strain energy density P0 e + EA e^2/2 made flat
 * below sigma = 0. The transverse geometric stiffness keeps P0 (left out: the
 * slack span's string stiffness). The integral is a fixed composite
 * Gauss-Legendre rule (TS_SPAN_SLACK_POINTS points), the same as
 * ts_span_slack_energy's, so the two are an exact gradient pair. Returns 1
 * when some point of the span is slack, 0 when none is (f untouched; a
 * cheap bound skips the quadrature for a span far from slack). */
int ts_span_slack_force(const ts_span *sp, const double *x, const double *xd, double t_kv,
                        double *f);

/* The strain energy the slack law removes from the linear span's at x:
 * \int_{sigma < 0} sigma^2 / (2 EA) ds with sigma = P0 + EA e (elastic) [J],
 * on the same points as ts_span_slack_force. */
double ts_span_slack_energy(const ts_span *sp, const double *x);

/* Equilibrium sag Y0(s) along e_y [m]. */
double ts_span_sag(const ts_span *sp, double s);

#endif
