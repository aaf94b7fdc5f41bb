/*
 * vehicle_model.c — the pitch-plane M1 multibody model (vehicle_model.h),
 * paper Section II.C (Fig. 7) with the fidelities of Section II.C.2.
 *
 * Equations: Lagrange's equations M(q) q_dd = Q(q, q_d, t) - (velocity-product
 * terms of the rigid bodies), M assembled from the bodies' Jacobians each
 * evaluation and solved by Cholesky. Forces:
 *   - torsion bars  M0_i - k (alpha_i - alpha_0), M0_i solved so the static
 *     arm angle is the design angle; rotary dampers and bump stops at the
 *     stations listed in /vehicle (1, 2, 7);
 *   - track elements (stretch in vehicle_model.h), acting along the tangent
 *     line on both wheels (dl/dc_b = u, the belt-length identity) and as
 *     torques rho T on the spins;
 *   - track–terrain foundation under each road wheel, compression only:
 *     N_z = k d + k3 d^3 + c d_dot (N_z >= 0, lift-off allowed) of the vertical
 *     compression d; its elastic part is the gradient of k d^2/2 + k3 d^4/4, so it
 *     acts along the terrain normal with magnitude N = N_z sqrt(1 + s^2), s the
 *     slope (until session 31 N_z along the unit normal: not a gradient where s
 *     varies, +44 J per crossing of the course's small bump without damping);
 *   - no slip under road wheel 4 [P II.C.1]: a stiff tangential spring between
 *     the track under that wheel and the ground; thrust is the tension the
 *     sprocket builds between itself and this anchor;
 *   - running-gear rolling resistance: at each loaded road wheel a force
 *     f N from the ground against the wheel centre's velocity along the
 *     terrain (f = f0 + f1 |v|, the point-mass model's law and coefficients
 *     of /vehicle, sign smoothed through standstill), so the model dissipates
 *     f N v like the point-mass vehicle, N summing to the side's weight less
 *     its track (the track's own weight is not on the wheels); aerodynamic
 *     drag at the CG, 1/4 rho CdA v^2 per side;
 *   - prescribed sprocket torque on the sprocket spin, its reaction on the hull;
 *   - gravity.
 * The idler sits on the track-adjusting link, locked while running (a grease
 * cylinder); its setting is solved with the equilibrium so the static tension
 * at the rear roller is P0 (the tensioner's setting). With
 * /vehicle/idler_compensation > 0 the idler is the M1's compensating idler:
 * the link joins it to road arm 1, so its place along the link is a function
 * of arm 1's angle (compensation_table: the travel that takes up that share of
 * the loop-length change arm 1 makes); its spans then move with arm 1 like a
 * road wheel's (span_arm). Its mass still rides in the hull body.
 *
 * Fidelities: static (massless chain); lumped (each upper span's mass on the
 * support rollers, as a point mass on the hull and spin inertia m r^2);
 * quasi_static (Guyan: the upper spans' longitudinal field interpolated
 * linearly between the end feeds -> consistent mass rho L/6 [2 1; 1 2] on the
 * end spins; their rigid motion with the hull, mass rho L at the middle of the
 * tangent line, rho L^3/12 about it); longitudinal / transverse /
 * coupled: the five free spans are track_span.h elements (see vehicle_spans).
 *
 * Span elements: the span's kinetic energy is its own (track_span.h M in the
 * chord frame) plus the frame's: the straight line between the two tangent
 * points, moving along itself with tangent point a and normal to itself as
 * the support centres do, interpolated linearly between them (the tangent
 * points' normal velocities are the centres'), so the frame's mass rho L sits
 * at the tangent line's middle (rigid mass rho L with the end velocities,
 * cross terms from rho int N_i and rho int (1 - s/L) phi_k, rho int (s/L)
 * phi_k), all assembled
 * into the global mass matrix, so the support accelerations of Eqs. 4-5 load
 * the modes implicitly (no lagged accelerations). Gravity: the frame's weight
 * on the supports, the sag (built in by track_span), the tension gradient
 * along the chord on the longitudinal sine modes. Kelvin-Voigt damping
 * -tau_d K x_d on each span, the same retardation time as the chain elements.
 *
 * The span blocks of M depend on the hull pitch and the end road arms; their
 * velocity terms dT/dq - (dM/dt) q_d are taken in closed form for the pitch
 * (span_pitch_terms: a pitch change is a rigid rotation) and by a forward
 * difference for the arms (span_velocity_terms), so the whole model is a
 * consistent Lagrangian system (tests/sim/test_vehicle_energy.c).
 *
 * Left out: track translation-speed (gyroscopic) terms; the chord-rotation
 * terms of ts_span_force (Coriolis, centripetal: the frame kinetic energy
 * above supplies the frame's inertia instead); the
 * weight of the rigid track feed around the circuit (only the free spans
 * carry mass, the whole closed loop would balance it); slip anywhere but the
 * anchor; track–hull impact; rebound stops; the anchor's release when road
 * wheel 4 lifts off (the no-slip spring always acts); a compliant tensioner
 * (the grease link is locked while running, so the static model's tension
 * follows the loop-length change of the suspension travel, less arm 1's share
 * under idler compensation).
 */
#include "vehicle_model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dense_small.h"
#include "drive.h"
#include "terrain.h"
#include "track_span.h"
#include "vehicle_layout.h"

#include "constants.h"
#define GRAVITY TS_GRAVITY
#define PI      TS_PI

enum { QX, QZ, QT, QA0, QS0 = QA0 + VM_NRW };
/* The coordinates the ASSEMBLED mass matrix depends on, bit for bit: theta
 * and the road-arm angles (the body Jacobians, the tangent lines), and x, z
 * (the tangent lines take differences of world body centres, so their
 * rounding depends on x, z, though M does not mathematically); not the spins
 * nor the span modes (M's span blocks are built from the tangent geometry and
 * the spans' constant chord-frame matrices). */
#define VM_NQ_MASS QS0
/* [rad] the forward-difference step of the span velocity terms in the arms */
#define SPAN_ARM_EPS 1e-5

const int vm_span_element[VM_NSPAN] = {0, 1, 2, 3, 10};
const char *const vm_span_names[VM_NSPAN] = {"sprocket_rear_roller", "rear_roller_front_roller",
                                             "front_roller_idler", "idler_rw1", "rw7_sprocket"};
const char *const vm_body_names[VM_NB] = {"sprocket", "rear_roller", "front_roller", "idler",
                                          "rw1",      "rw2",         "rw3",          "rw4",
                                          "rw5",      "rw6",         "rw7"};

/* Nodes of the compensating idler's travel table, over +-VM_COMP_RANGE rad
 * of road arm 1 about its design angle, built outward from it as far as a
 * travel solves (a steep link can run out of travel at deep droop or jounce).
 * Arm 1's own travel (compensation_reach: bump stop to hanging free) widened
 * by VM_COMP_MARGIN must lie within what solved. The margin: past the bump
 * stop 0.1 rad makes the default stop (1e6 N*m/rad) carry ~7x the static bar
 * torque; past the free-hanging angle the IVS bump run's arm 1 overshoots by
 * 0.03 rad (dynamics), so 0.1 leaves a factor 3. */
#define VM_COMP_N      97
#define VM_COMP_RANGE  1.2
#define VM_COMP_MARGIN 0.1 /* [rad] */

/* Jacobian of a body centre: up to 4 columns (x, z, theta, alpha_i). */
typedef struct jcol {
    int n;
    int idx[4];
    double v[4][2];
} jcol;

/* Compact column set of one span: hull (x, z, theta), the arms of a and b, the
 * spins of a and b, the modal coordinates. */
typedef struct cset {
    int n;
    int idx[8 + 2 * TS_SPAN_MAX_MODES];
} cset;

typedef struct span_el {
    ts_span *sp;                             /* NULL when the element is a massless spring */
    cset cs;       /* the span's compact columns (span_map_build), fixed by its end bodies */
    int ci[2][4];  /* compact column of each Jacobian column of ends a (0) and b (1) */
    int ci_spin[2]; /* compact columns of the spins of a and b */
    int elem;                                /* element index */
    int q0;                                  /* first modal coordinate in q */
    int nm;                                  /* modal coordinates */
    double rho, len;                         /* mass per length, reference chord length */
    double alpha[2 + 2 * TS_SPAN_MAX_MODES]; /* rho int N_i (longitudinal rows) */
    double beta0[2 + 2 * TS_SPAN_MAX_MODES]; /* rho int (1 - s/L) phi_k (transverse rows) */
    double beta1[2 + 2 * TS_SPAN_MAX_MODES]; /* rho int (s/L) phi_k */
} span_el;

struct vm {
    ts_config cfg;
    ts_terrain *terrain;
    int fidelity;
    int nq, ny, nmodal;
    /* per-side masses */
    double m_hull, i_hull;
    double m_w, m_arm, i_arm_cg, arm_len, arm0;
    double k_bar, c_damp[VM_NRW], bump[VM_NRW], bs_angle, k_bs;
    double m0[VM_NRW];               /* torsion-bar preloads (equilibrium) */
    double l_body[VM_NB][2];         /* hull-mounted bodies: offset from CG, hull frame */
    double l_pivot[VM_NRW][2];       /* road-arm pivots, hull frame */
    double link_dir[2], d_link;      /* idler link direction and setting */
    /* compensating idler: its travel along link_dir as a function of road arm
     * 1's angle, tabulated at VM_COMP_N nodes from comp_a0 in steps comp_da
     * (travel and slope; cubic Hermite between nodes comp_lo..comp_hi, the
     * ones that solved, constant outside); comp_fail: the angle of the first
     * node that did not solve below / above the design angle (NaN: none);
     * comp_on 0: the idler is fixed to the hull */
    int comp_on, comp_lo, comp_hi;
    double comp_a0, comp_da, comp_fail[2];
    double comp_s[VM_COMP_N], comp_ds[VM_COMP_N];
    double rho_b[VM_NB], j_b[VM_NB]; /* pitch-line radii, spin inertias */
    double wheel_ground;             /* hub to ground-contact surface: r + thickness */
    double ell0[VM_NB];
    double k_el[VM_NB];  /* element stiffness EA / L_e, L_e = chord + half of each wrap [N/m] */
    double u0[VM_NB][2]; /* element directions at the design configuration */
    double ea, p0, tau_d;
    double kf, kf3, cf, ka, ca;
    double rr0, rr1, rr_v0; /* running-gear rolling resistance f = rr0 + rr1 |v|, smoothing */
    double drag_side;       /* 1/4 rho CdA: half of the vehicle's 1/2 rho CdA [kg/m] */
    int anchor;             /* road-wheel index 0..6 */
    double x_anchor0;
    double x0, z0; /* design CG world position */
    double ground_scale; /* terrain heights' factor in the foundation: 1, below 1 only while
                          * the static equilibrium is continued from flat ground */
    int eq_on_terrain;   /* equilibrium unknowns: 0 the design ones (bar preloads, link
                          * setting), 1 those on the start's terrain (arm angles) */
    double dscale;
    int no_compression; /* /track/no_compression: slack law on the modal spans */
    /* fidelity extras */
    int npm;
    double pm_m[8], pm_l[8][2]; /* point masses on the hull (hull frame offsets) */
    double i_extra;             /* extra hull pitch inertia */
    double mqs[4][4];           /* quasi-static spin coupling among bodies 0..3 */
    span_el span[VM_NSPAN];
    const span_el *span_of[VM_NB]; /* element -> its dynamic span, NULL when massless */
    unsigned arm_span_bodies;      /* end bodies of the spans ending on a road wheel (bit b) */
    int dynamic;
    /* equilibrium */
    double *y_eq;
    double *rate; /* per coordinate: sqrt(K_ii / M_ii) at the equilibrium, 0 when K_ii <= 0 */
    int *mass_cand; /* the rows M's reversed Cholesky factor can fill (mass_structure) */
    double t_static;
    double g_eq;           /* loop geometric stretch at the equilibrium [m] */
    double c_loop, c_tail; /* compliance of the loop and of anchor wheel -> sprocket [m/N] */
};

typedef struct geom geom; /* forces()'s geometry at q (geom_eval) */

struct vm_work {
    double *M, *Q;
    geom *geo;      /* rhs_cached's: the geometry at the factor's coordinates (qf) */
    double *P;      /* nq x nq: vm_rhs's mass matrix, then its Cholesky factor (chol_solve) */
    int *pat;       /* nq (nq + 1): the factor's column patterns (dense_small.h) */
    double qf[VM_NQ_MASS + 1]; /* the mass coordinates and extra inertia of the factor in P */
    int qf_ok;                 /* ... when set (cleared by every other factorisation) */
    double sx[2 + 2 * TS_SPAN_MAX_MODES], sxd[2 + 2 * TS_SPAN_MAX_MODES],
        sf[2 + 2 * TS_SPAN_MAX_MODES];
};

typedef struct kin {
    double th, cth, sth, thd;
    double c[VM_NB][2], v[VM_NB][2];    /* body centres and velocities */
    double w[VM_NB][2];                 /* centre - hull CG (world) */
    double wp[VM_NRW][2], e[VM_NRW][2]; /* pivot offset, arm vector (world) */
    jcol j[VM_NB];
} kin;

typedef struct elem {
    double u[2], n[2], ell, dpsi;
} elem;

/* The span's velocity map: x_d = B q_d (compact columns cs), and the frame
 * velocities f_x = rx . q_d (tangent point 0 along the chord), f_y0 = ry0 . q_d,
 * f_y1 = ry1 . q_d (ends 0, 1 normal to it). Only B's dense rows 0, 1 (the
 * end feeds u0, u1) are stored: row 2 + m is the unit vector on the modal
 * coordinate q0 + m, whose compact column is cs.n - nm + m (the modal columns
 * come last). */
typedef struct span_map {
    cset cs;
    double B[2][8 + 2 * TS_SPAN_MAX_MODES];
    double rx[8 + 2 * TS_SPAN_MAX_MODES], ry0[8 + 2 * TS_SPAN_MAX_MODES],
        ry1[8 + 2 * TS_SPAN_MAX_MODES];
} span_map;

/* The geometry forces() takes from geom_eval: everything that depends on the
 * coordinates M depends on alone (VM_NQ_MASS), so rhs_cached keeps the one
 * of its factor (w->geo) and reuses it on the factor's hits (the
 * difference-quotient Jacobian's columns of the spins, span modes and
 * rates). */
struct geom {
    kin k;                  /* body centres, Jacobians; rates set by forces() */
    elem e[VM_NB];          /* tangent lines */
    span_map mp[VM_NSPAN];  /* span maps at q */
    span_map mpe[VM_NSPAN]; /* those of the spans ending on a road arm (span_arm) with
                             * every arm at + SPAN_ARM_EPS (span_velocity_terms) */
};

/* ---- small helpers -------------------------------------------------------- */

static void rot(const kin *k, const double l[2], double w[2])
{ /* hull frame -> world for clockwise pitch theta */
    w[0] = l[0] * k->cth + l[1] * k->sth;
    w[1] = -l[0] * k->sth + l[1] * k->cth;
}

/* A list of road-arm stations: whole numbers 1..VM_NRW (a station 9 of 7
 * wheels, or 1.5, was taken and silently went nowhere or was rounded). */
static ts_rc check_stations(const double *list, int n, const char *field, ts_err *err)
{
    for (int i = 0; i < n; i++)
        if (!(list[i] >= 1 && list[i] <= VM_NRW) || list[i] != floor(list[i])) {
            char ptr[64];
            snprintf(ptr, sizeof ptr, "%s/%d", field, i);
            return ts_err_set(err, TS_ERR_RANGE, ptr,
                              "%s: station %g is not a road-arm station 1..%d", ptr, list[i],
                              VM_NRW);
        }
    return TS_OK;
}

static int is_station(const double *list, int n, int station)
{
    for (int i = 0; i < n; i++)
        if ((int)lround(list[i]) == station) return 1;
    return 0;
}

/* ---- kinematics ---------------------------------------------------------- */

/* The compensating idler's travel along its link at road-arm-1 angle alpha
 * [m], and its slope d travel / d alpha in *slope [m/rad]: cubic Hermite on
 * the table vm_make built (compensation_table), constant beyond the nodes
 * that solved. A NaN angle (an integrator's failed state) gives NaN, so the
 * RHS fails recoverably as it does without the idler. */
static double comp_travel(const vm *v, double alpha, double *slope)
{
    double x = (alpha - v->comp_a0) / v->comp_da;
    /* negated so NaN takes this branch, never the table index below */
    if (!(x > v->comp_lo && x < v->comp_hi)) {
        if (isnan(x)) {
            *slope = NAN;
            return NAN;
        }
        *slope = 0;
        return x <= v->comp_lo ? v->comp_s[v->comp_lo] : v->comp_s[v->comp_hi];
    }
    int i = (int)x;
    double t = x - i, h = v->comp_da;
    double s0 = v->comp_s[i], s1 = v->comp_s[i + 1];
    double m0 = v->comp_ds[i] * h, m1 = v->comp_ds[i + 1] * h;
    double t2 = t * t, t3 = t2 * t;
    *slope = ((6 * t2 - 6 * t) * s0 + (3 * t2 - 4 * t + 1) * m0 + (6 * t - 6 * t2) * s1 +
              (3 * t2 - 2 * t) * m1) /
             h;
    return (2 * t3 - 3 * t2 + 1) * s0 + (t3 - 2 * t2 + t) * m0 + (3 * t2 - 2 * t3) * s1 +
           (t3 - t2) * m1;
}

#define ALL_BODIES ((1u << VM_NB) - 1)

/* The rates of kinematics_of: theta_d and the body centres' velocities (qd
 * NULL: at rest), from the Jacobians already in k. */
static void kin_rates(const double *qd, unsigned mask, kin *k)
{
    k->thd = qd ? qd[QT] : 0;
    double xd = qd ? qd[QX] : 0, zd = qd ? qd[QZ] : 0;
    for (int b = 0; b < VM_NB; b++) {
        if (!(mask >> b & 1u)) continue;
        const jcol *j = &k->j[b];
        k->v[b][0] = xd + k->thd * j->v[2][0];
        k->v[b][1] = zd + k->thd * j->v[2][1];
        if (j->n == 4) {
            double ad = qd ? qd[j->idx[3]] : 0;
            k->v[b][0] += ad * j->v[3][0];
            k->v[b][1] += ad * j->v[3][1];
        }
    }
}

/* Body centres, velocities and Jacobians; only the bodies in mask (bit b =
 * body b) are filled (the span velocity terms need only the spans' ends). */
static void kinematics_of(const vm *v, const double *q, const double *qd, unsigned mask, kin *k)
{
    k->th = q[QT];
    k->cth = cos(k->th);
    k->sth = sin(k->th);
    for (int b = 0; b < VM_NB; b++) {
        if (!(mask >> b & 1u)) continue;
        jcol *j = &k->j[b];
        j->n = 3;
        j->idx[0] = QX;
        j->idx[1] = QZ;
        j->idx[2] = QT;
        j->v[0][0] = 1, j->v[0][1] = 0;
        j->v[1][0] = 0, j->v[1][1] = 1;
        if (b < VM_RW1) {
            double l[2] = {v->l_body[b][0], v->l_body[b][1]};
            double ds = 0;
            if (b == VM_IDLER) {
                double d = v->d_link + (v->comp_on ? comp_travel(v, q[QA0], &ds) : 0);
                l[0] += d * v->link_dir[0];
                l[1] += d * v->link_dir[1];
            }
            rot(k, l, k->w[b]);
            if (b == VM_IDLER && v->comp_on) {
                /* compensating idler: the track-adjusting link ties it to road arm 1 */
                double g[2] = {ds * v->link_dir[0], ds * v->link_dir[1]};
                j->n = 4;
                j->idx[3] = QA0;
                rot(k, g, j->v[3]);
            }
        } else {
            int i = b - VM_RW1;
            rot(k, v->l_pivot[i], k->wp[i]);
            double zeta = q[QA0 + i] - k->th;
            k->e[i][0] = -v->arm_len * cos(zeta);
            k->e[i][1] = -v->arm_len * sin(zeta);
            k->w[b][0] = k->wp[i][0] + k->e[i][0];
            k->w[b][1] = k->wp[i][1] + k->e[i][1];
            j->n = 4;
            j->idx[3] = QA0 + i;
            j->v[3][0] = -k->e[i][1];
            j->v[3][1] = k->e[i][0];
        }
        j->v[2][0] = k->w[b][1];
        j->v[2][1] = -k->w[b][0];
        k->c[b][0] = q[QX] + k->w[b][0];
        k->c[b][1] = q[QZ] + k->w[b][1];
    }
    kin_rates(qd, mask, k);
}

static void kinematics(const vm *v, const double *q, const double *qd, kin *k)
{
    kinematics_of(v, q, qd, ALL_BODIES, k);
}

/* Tangent line of element el, from body el to body el + 1 (clockwise circuit,
 * outward = left): direction u, outward normal n, length ell and its turn dpsi
 * from the design direction v->u0[el], in (-pi, pi]. u is the centre line's
 * direction turned by asin(ratio), ratio = (rho_a - rho_b)/D, written with
 * that angle's cosine and sine (no trigonometric calls on the rhs path). */
static void tangent(const vm *v, const kin *k, int el, elem *e)
{
    int a = el, b = (el + 1) % VM_NB;
    double dx = k->c[b][0] - k->c[a][0], dz = k->c[b][1] - k->c[a][1];
    /* sqrt, not hypot: the centre distances are metres, far from overflow */
    double D2 = dx * dx + dz * dz, cr = v->rho_b[a] - v->rho_b[b];
    double inv = 1.0 / sqrt(D2);
    double ratio = cr * inv;
    if (ratio > 0.999) ratio = 0.999;
    if (ratio < -0.999) ratio = -0.999;
    double ca = sqrt(1.0 - ratio * ratio), cx = dx * inv, cz = dz * inv;
    e->u[0] = cx * ca + cz * ratio;
    e->u[1] = cz * ca - cx * ratio;
    e->n[0] = -e->u[1];
    e->n[1] = e->u[0];
    e->ell = sqrt(D2 - cr * cr);
    const double *u0 = v->u0[el];
    e->dpsi = atan2(u0[0] * e->u[1] - u0[1] * e->u[0], u0[0] * e->u[0] + u0[1] * e->u[1]);
}

/* ---- mass matrix pieces ---------------------------------------------------- */

/* Entry (i, j) of M's lower triangle, row-major: the one forces() assembles. */
static double *mass_at(double *M, int nq, int i, int j)
{
    return i >= j ? &M[i * nq + j] : &M[j * nq + i];
}

static void add_point_mass(const vm *v, double *M, double *Q, double m, const jcol *j,
                           const double bias[2], double g_on)
{
    int nq = v->nq;
    for (int r = 0; r < j->n; r++) {
        if (M) /* NULL: Q only; the symmetric block's lower triangle (mass_at) */
            for (int c = r; c < j->n; c++)
                *mass_at(M, nq, j->idx[r], j->idx[c]) +=
                    m * (j->v[r][0] * j->v[c][0] + j->v[r][1] * j->v[c][1]);
        /* -m J^T (bias) + gravity */
        Q[j->idx[r]] -= m * (j->v[r][0] * bias[0] + j->v[r][1] * bias[1]);
        Q[j->idx[r]] -= g_on * m * GRAVITY * j->v[r][1];
    }
}

static void add_force(double *Q, const jcol *j, const double f[2])
{
    for (int r = 0; r < j->n; r++)
        Q[j->idx[r]] += j->v[r][0] * f[0] + j->v[r][1] * f[1];
}

/* Jacobian of a hull-fixed point at world offset w from the CG. */
static void hull_point_jac(const double w[2], jcol *j)
{
    j->n = 3;
    j->idx[0] = QX, j->idx[1] = QZ, j->idx[2] = QT;
    j->v[0][0] = 1, j->v[0][1] = 0;
    j->v[1][0] = 0, j->v[1][1] = 1;
    j->v[2][0] = w[1], j->v[2][1] = -w[0];
}

/* Rigid-body mass matrix, velocity terms and gravity into M and Q (M NULL:
 * Q only). */
static void rigid_inertia(const vm *v, const kin *k, const double *qd, double *M, double *Q)
{
    int nq = v->nq;
    double thd2 = k->thd * k->thd;
    if (M) {
        M[QX * nq + QX] += v->m_hull;
        M[QZ * nq + QZ] += v->m_hull;
        M[QT * nq + QT] += v->i_hull + v->i_extra;
    }
    Q[QZ] -= v->m_hull * GRAVITY;
    for (int p = 0; p < v->npm; p++) {
        double w[2], bias[2];
        jcol j;
        rot(k, v->pm_l[p], w);
        hull_point_jac(w, &j);
        bias[0] = -thd2 * w[0];
        bias[1] = -thd2 * w[1];
        add_point_mass(v, M, Q, v->pm_m[p], &j, bias, 1.0);
    }
    for (int i = 0; i < VM_NRW; i++) {
        int b = VM_RW1 + i, ia = QA0 + i;
        double zd = qd ? qd[ia] - k->thd : 0;
        double bias[2] = {-thd2 * k->wp[i][0] - zd * zd * k->e[i][0],
                          -thd2 * k->wp[i][1] - zd * zd * k->e[i][1]};
        add_point_mass(v, M, Q, v->m_w, &k->j[b], bias, 1.0);
        /* arm: point mass at mid-arm + inertia about its CG at rate alpha_d - theta_d */
        jcol ja = k->j[b];
        double wm[2] = {k->wp[i][0] + 0.5 * k->e[i][0], k->wp[i][1] + 0.5 * k->e[i][1]};
        ja.v[2][0] = wm[1], ja.v[2][1] = -wm[0];
        ja.v[3][0] *= 0.5, ja.v[3][1] *= 0.5;
        double biasm[2] = {-thd2 * k->wp[i][0] - 0.5 * zd * zd * k->e[i][0],
                           -thd2 * k->wp[i][1] - 0.5 * zd * zd * k->e[i][1]};
        add_point_mass(v, M, Q, v->m_arm, &ja, biasm, 1.0);
        if (!M) continue;
        M[ia * nq + ia] += v->i_arm_cg;
        M[QT * nq + QT] += v->i_arm_cg;
        M[ia * nq + QT] -= v->i_arm_cg; /* ia > QT: lower triangle */
    }
    if (!M) return;
    for (int b = 0; b < VM_NB; b++)
        M[(QS0 + b) * nq + QS0 + b] += v->j_b[b];
    if (v->fidelity == TS_TRACK_QUASI_STATIC)
        for (int a = 0; a < 4; a++)
            for (int b = 0; b <= a; b++)
                M[(QS0 + a) * nq + QS0 + b] += v->mqs[a][b];
}

/* Cholesky solve of the symmetric positive-definite M x = b (b in place),
 * dense_small.h (single-threaded; threaded BLAS spent more time spinning than
 * factoring at n <= 31). M is sparse but its hull rows (x, z, theta, the
 * first three) are dense: factored in REVERSED order (modes, spins, arms,
 * hull last: an arrowhead ordering) the factor fills in only along the spans'
 * couplings, and the zero-skipping factorisation does a fraction of the
 * dense work; the factor's column patterns are kept (w->pat) so the two
 * triangular sweeps skip its zeros too (same result). The reversal is
 * ts_chol_factor_rev's view of M, no copy: M (in w->P) is overwritten by its
 * factor. Uses w->P, w->pat. */
static int chol_solve(const vm *v, vm_work *w, double *b, int n)
{
    if (ts_chol_factor_rev_cand(w->P, n, v->mass_cand, w->pat) != 0) return 1;
    ts_chol_solve_rev(w->P, n, w->pat, b);
    return 0;
}

/* Solve with the factor chol_solve left in w->P (same reordering). */
static void chol_resolve(vm_work *w, double *b, int n)
{
    ts_chol_solve_rev(w->P, n, w->pat, b);
}

/* M's upper triangle from its lower one (forces assembles the lower alone). */
static void mass_mirror(double *M, int nq)
{
    for (int i = 0; i < nq; i++)
        for (int j = 0; j < i; j++)
            M[j * nq + i] = M[i * nq + j];
}

/* ---- forces ----------------------------------------------------------------- */

/* The spans' kinetic energy t and momentum p (compact columns cols) at the
 * current q, with the spin rates qdv (= q_d with the spins zeroed): the base
 * point of the span velocity terms' differences, taken from the maps that
 * span_element builds anyway. */
typedef struct span_base {
    double qdv[VM_NQ_RIGID + VM_NSPAN * 2 * TS_SPAN_MAX_MODES];
    double t[VM_NSPAN];
    double p[VM_NSPAN][8 + 2 * TS_SPAN_MAX_MODES];
    cset cols[VM_NSPAN];
} span_base;

/* Defined with the spans. */
static void geom_eval(const vm *v, const double *q, int arm_maps, geom *g);

/* Span part of one element: forces and inertia from its map mp (and the base
 * point of the velocity terms when sb is non-NULL). */
static void span_element(const vm *v, vm_work *w, const span_map *mp, const span_el *se,
                         const elem *e, int a, int b, const double *q, const double *qd, double *M,
                         double *Q, vm_diag *diag, span_base *sb);

static span_base *span_base_init(const vm *v, const double *qd, span_base *sb);
static void span_velocity_terms(const vm *v, const geom *g, const span_base *sb, double *Q);

/* Quasi-static rear-roller tension of the massless track (vm_diag) for the
 * loop's geometric stretch g and the sprocket torque tau. Free wheels carry
 * one tension T_A from the sprocket round the top to the anchor wheel and
 * T_B = T_A + tau/r_s from there to the sprocket (sprocket torque balance);
 * the loop's stretch sum (T - P0) L_e/EA equals g (the spins telescope out):
 * T_A = P0 + (g - tau/r_s C_B)/C_loop, referred to the equilibrium; 0 when
 * that is negative (a chain cannot push: the elements' T >= 0 clip). */
static double quasi_static_tension(const vm *v, double g, double tau)
{
    double t = v->t_static + (g - v->g_eq - tau / v->rho_b[VM_SPROCKET] * v->c_tail) / v->c_loop;
    return t > 0 ? t : 0;
}

/* Generalised forces Q at (t, q, qd), the inertial velocity terms included
 * (none when qd is NULL: the static residual), and the mass matrix M unless
 * M is NULL (vm_rhs's factor cache, the equilibrium, the geometry), with g
 * the geometry at q (geom_eval; the displaced maps when qd is given and the
 * spans are dynamic); forces_at evaluates it. Only M's
 * lower triangle (row >= column, row-major: mass_at) is assembled, the half
 * the reversed Cholesky reads, so the upper one is neither cleared nor
 * written (mass_mirror completes M for the callers that read all of it);
 * clearing the whole 31 x 31 M was ~8 % of a vehicle run's instructions. */
static void forces(const vm *v, vm_work *w, geom *g, double t, const double *q, const double *qd,
                   double *M, double *Q, int drive_on, vm_diag *diag)
{
    int nq = v->nq;
    kin *k = &g->k; /* positions from g (geom_eval at q), rates set here */
    kin_rates(qd, ALL_BODIES, k);
    memset(Q, 0, (size_t)nq * sizeof *Q);
    if (M)
        for (int i = 0; i < nq; i++)
            memset(M + (size_t)i * nq, 0, (size_t)(i + 1) * sizeof *M);
    rigid_inertia(v, k, qd, M, Q);
    /* track elements */
    span_base sb_store;
    span_base *sb = qd && v->dynamic ? span_base_init(v, qd, &sb_store) : NULL;
    double fr[VM_NB][2];
    memset(fr, 0, sizeof fr);
    double rr_force[2] = {0, 0};
    double loop_stretch = 0;
    for (int el = 0; el < VM_NB; el++) {
        int a = el, b = (el + 1) % VM_NB;
        const elem *e = &g->e[el];
        /* geometric stretch: the chord's and the wraps' (the spins come below) */
        double g_el = (e->ell - v->ell0[el]) + (v->rho_b[b] - v->rho_b[a]) * e->dpsi;
        loop_stretch += g_el;
        const span_el *se = v->span_of[el];
        if (se) {
            span_element(v, w, &g->mp[se - v->span], se, e, a, b, q, qd, M, Q, diag, sb);
            if (diag && (a == VM_REAR_ROLLER || b == VM_REAR_ROLLER)) {
                /* end force of the span on the rear roller (chord axes -> world) */
                ts_span_end_forces ef;
                ts_span_end_forces_eval(se->sp, w->sx, &ef);
                double fx = b == VM_REAR_ROLLER ? ef.f1x : ef.f0x;
                double fy = b == VM_REAR_ROLLER ? ef.f1y : ef.f0y;
                double te = b == VM_REAR_ROLLER ? ef.tension1 : ef.tension0;
                if (v->no_compression && te < 0) fx = fy = 0; /* slack at the roller */
                rr_force[0] += fx * e->u[0] + fy * e->n[0];
                rr_force[1] += fx * e->u[1] + fy * e->n[1];
            }
            continue;
        }
        double vrel = (k->v[b][0] - k->v[a][0]) * e->u[0] + (k->v[b][1] - k->v[a][1]) * e->u[1];
        double s = g_el + v->rho_b[b] * q[QS0 + b] - v->rho_b[a] * q[QS0 + a];
        double sd = vrel + (qd ? v->rho_b[b] * qd[QS0 + b] - v->rho_b[a] * qd[QS0 + a] : 0);
        double kel = v->k_el[el];
        double tn = v->p0 + kel * s + v->dscale * kel * v->tau_d * sd;
        if (tn < 0) tn = 0;
        double f[2] = {tn * e->u[0], tn * e->u[1]};
        fr[a][0] += f[0], fr[a][1] += f[1];
        fr[b][0] -= f[0], fr[b][1] -= f[1];
        Q[QS0 + a] += tn * v->rho_b[a];
        Q[QS0 + b] -= tn * v->rho_b[b];
        if (b == VM_REAR_ROLLER) rr_force[0] -= f[0], rr_force[1] -= f[1];
        if (a == VM_REAR_ROLLER) rr_force[0] += f[0], rr_force[1] += f[1];
        if (diag) diag->tension[el] = diag->tension_end0[el] = diag->tension_end1[el] = tn;
    }
    for (int b = 0; b < VM_NB; b++)
        add_force(Q, &k->j[b], fr[b]);
    if (sb) span_velocity_terms(v, g, sb, Q);
    /* foundation and anchor */
    for (int i = 0; i < VM_NRW; i++) {
        int b = VM_RW1 + i;
        double slope, h = ts_terrain_height(v->terrain, k->c[b][0], &slope);
        h *= v->ground_scale, slope *= v->ground_scale;
        double d = h + v->wheel_ground - k->c[b][1];
        double nload = 0;
        if (d > 0) {
            double dd = slope * k->v[b][0] - k->v[b][1];
            double nz = v->kf * d + v->kf3 * d * d * d + v->dscale * v->cf * dd;
            if (nz < 0) nz = 0;
            /* -grad of V(d) = k d^2/2 + k3 d^4/4 with d the vertical compression:
             * nz (-s, 1), along the terrain normal, so the normal force is
             * nz sqrt(1 + s^2); (tx, tz) is the terrain's unit tangent */
            double tx = 1.0 / sqrt(1.0 + slope * slope), tz = slope * tx;
            double f[2] = {-slope * nz, nz};
            nload = nz / tx;
            add_force(Q, &k->j[b], f);
            if (nload > 0 && qd) {
                /* running-gear rolling resistance: f N against the wheel
                 * centre's velocity along the terrain, from the ground (the
                 * hysteresis moment N e of the tyre on the track is balanced
                 * by a contact force N e / r; the track under the wheel grips
                 * the ground, so the force goes to the ground, not along the
                 * track to the anchor) */
                double vt = k->v[b][0] * tx + k->v[b][1] * tz;
                double f_roll =
                    v->dscale * (v->rr0 + v->rr1 * fabs(vt)) * nload * tanh(vt / v->rr_v0);
                double fr_t[2] = {-f_roll * tx, -f_roll * tz};
                add_force(Q, &k->j[b], fr_t);
            }
        }
        if (diag) {
            diag->wheel_load[i] = nload;
            diag->arm_angle[i] = q[QA0 + i];
        }
        /* torsion bar, damper, bump stop */
        double al = q[QA0 + i], ald = qd ? qd[QA0 + i] : 0;
        double tq = v->m0[i] - v->k_bar * (al - v->arm0) - v->dscale * v->c_damp[i] * ald;
        if (v->bump[i] && al < v->bs_angle) tq += v->k_bs * (v->bs_angle - al);
        Q[QA0 + i] += tq;
    }
    {
        int b = VM_RW1 + v->anchor;
        double xi = k->c[b][0] - v->rho_b[b] * q[QS0 + b] - v->x_anchor0;
        double xid = k->v[b][0] - (qd ? v->rho_b[b] * qd[QS0 + b] : 0);
        double fa = -v->ka * xi - v->dscale * v->ca * xid;
        double f[2] = {fa, 0};
        add_force(Q, &k->j[b], f);
        Q[QS0 + b] -= v->rho_b[b] * fa;
        if (diag) diag->anchor_force = fa;
    }
    /* aerodynamic drag on the hull, at the CG (its pitch moment left out) */
    if (qd) Q[QX] -= v->dscale * v->drag_side * qd[QX] * fabs(qd[QX]);
    /* drive */
    double tau = drive_on ? ts_drive_torque(&v->cfg.drive, t) : 0.0;
    Q[QS0 + VM_SPROCKET] += tau;
    Q[QT] -= tau;
    if (diag) {
        diag->drive_torque = tau;
        diag->loop_stretch = loop_stretch;
        diag->tension_quasi_static = quasi_static_tension(v, loop_stretch, tau);
        double up[2] = {k->sth, k->cth};
        diag->rear_roller_normal = -(rr_force[0] * up[0] + rr_force[1] * up[1]);
    }
}

/* forces() with its geometry evaluated here (every caller but rhs_cached). */
static void forces_at(const vm *v, vm_work *w, double t, const double *q, const double *qd,
                      double *M, double *Q, int drive_on, vm_diag *diag)
{
    geom g;
    geom_eval(v, q, qd && v->dynamic, &g);
    forces(v, w, &g, t, q, qd, M, Q, drive_on, diag);
}

/* ---- dynamic spans (track_span.h elements) ---------------------------------- */

static int cset_add(cset *c, int i)
{
    for (int k = 0; k < c->n; k++)
        if (c->idx[k] == i) return k;
    c->idx[c->n] = i;
    return c->n++;
}

static void span_map_build(const vm *v, const kin *k, const span_el *se, const elem *e, int a,
                           int b, span_map *mp)
{
    /* mp is this function's output: nothing in it is read before it is written */
    /* cppcheck-suppress ctuuninitvar */
    double(*B)[8 + 2 * TS_SPAN_MAX_MODES] = mp->B;
    double *rx = mp->rx, *ry0 = mp->ry0, *ry1 = mp->ry1;
    int ncap = 8 + se->nm; /* hull 3, two arms, two spins, the modes (+1 spare) */
    for (int c = 0; c < ncap; c++)
        B[0][c] = B[1][c] = rx[c] = ry0[c] = ry1[c] = 0;
    double ell = e->ell;
    /* rows 0, 1: u0 = rho_a (Phi_a + dpsi), u1 = rho_b (Phi_b + dpsi) + l - l0 */
    for (int side = 0; side < 2; side++) {
        const jcol *j = side ? &k->j[b] : &k->j[a];
        double sg = side ? 1.0 : -1.0;
        for (int c = 0; c < j->n; c++) {
            int ci = se->ci[side][c];
            double dpsi = sg * (e->n[0] * j->v[c][0] + e->n[1] * j->v[c][1]) / ell;
            /* dl/dc_b = u + (rho_a - rho_b)/l n (d = l u + (rho_a - rho_b) n) */
            double cr = (v->rho_b[a] - v->rho_b[b]) / ell;
            double dl = sg * ((e->u[0] + cr * e->n[0]) * j->v[c][0] +
                              (e->u[1] + cr * e->n[1]) * j->v[c][1]);
            B[0][ci] += v->rho_b[a] * dpsi;
            B[1][ci] += v->rho_b[b] * dpsi + dl;
            /* the frame rides on tangent point 0, p_a = c_a + rho_a n, whose
             * velocity along the chord is u . c_a_d - rho_a psi_d (n turns
             * with the chord: n_d = -psi_d u), and u0 is measured from it */
            rx[ci] -= v->rho_b[a] * dpsi;
            if (side == 0) {
                rx[ci] += e->u[0] * j->v[c][0] + e->u[1] * j->v[c][1];
                ry0[ci] += e->n[0] * j->v[c][0] + e->n[1] * j->v[c][1];
            } else {
                ry1[ci] += e->n[0] * j->v[c][0] + e->n[1] * j->v[c][1];
            }
        }
    }
    B[0][se->ci_spin[0]] += v->rho_b[a];
    B[1][se->ci_spin[1]] += v->rho_b[b];
    mp->cs = se->cs;
}

/* The compact columns of span se (ends a, b): end a's Jacobian columns, end
 * b's not already there, the two spins, the modes; and where each Jacobian
 * column lands (span_map_build). Fixed by the bodies, found once. */
static void span_columns(const vm *v, span_el *se)
{
    int a = se->elem, b = (se->elem + 1) % VM_NB;
    double q0[VM_NQ_RIGID] = {0};
    kin k;
    kinematics_of(v, q0, NULL, 1u << a | 1u << b, &k); /* only the column indices are read */
    cset *cs = &se->cs;
    cs->n = 0;
    for (int side = 0; side < 2; side++) {
        const jcol *j = side ? &k.j[b] : &k.j[a];
        for (int c = 0; c < j->n; c++)
            se->ci[side][c] = cset_add(cs, j->idx[c]);
    }
    se->ci_spin[0] = cset_add(cs, QS0 + a);
    se->ci_spin[1] = cset_add(cs, QS0 + b);
    for (int m = 0; m < se->nm; m++) /* unique to this span */
        cs->idx[cs->n++] = se->q0 + m;
}

/* Kinetic energy of a span (its own motion in the chord frame, the frame's,
 * and their cross terms) and its momentum p_c = dT/d(q_d) on the first np
 * compact columns (p may be NULL; np = mp->cs.n: all). Consistent with the
 * mass-matrix block assembled in span_element: p = M_span q_d. */
static double span_ke(const span_el *se, const span_map *mp, const double *qd, double *p, int np)
{
    const ts_span *sp = se->sp;
    int n = sp->n, nc = mp->cs.n;
    double xd[2 + 2 * TS_SPAN_MAX_MODES], mx[2 + 2 * TS_SPAN_MAX_MODES];
    double fx = 0, fy0 = 0, fy1 = 0;
    for (int c = 0; c < nc; c++) {
        double u = qd[mp->cs.idx[c]];
        fx += mp->rx[c] * u, fy0 += mp->ry0[c] * u, fy1 += mp->ry1[c] * u;
    }
    /* rows 0, 1 are dense; row 2 + k is the unit vector on the modal
     * coordinate q0 + k (span_map_build), so its product is that rate */
    for (int r = 0; r < 2 && r < n; r++) {
        double s = 0;
        for (int c = 0; c < nc; c++)
            s += mp->B[r][c] * qd[mp->cs.idx[c]];
        xd[r] = s;
    }
    for (int r = 2; r < n; r++)
        xd[r] = qd[se->q0 + r - 2];
    double m = se->rho * se->len, t = 0, ax = 0, a0 = 0, a1 = 0;
    for (int r = 0; r < n; r++) {
        double s = 0;
        for (int kk = 0; kk < n; kk++)
            s += sp->M[r * n + kk] * xd[kk];
        mx[r] = s + se->alpha[r] * fx + se->beta0[r] * fy0 + se->beta1[r] * fy1;
        t +=
            0.5 * xd[r] * s + xd[r] * (se->alpha[r] * fx + se->beta0[r] * fy0 + se->beta1[r] * fy1);
        ax += se->alpha[r] * xd[r], a0 += se->beta0[r] * xd[r], a1 += se->beta1[r] * xd[r];
    }
    t += 0.5 * m * fx * fx + m / 6.0 * (fy0 * fy0 + fy0 * fy1 + fy1 * fy1);
    if (p)
        for (int c = 0; c < np; c++) {
            double s = 0;
            for (int r = 0; r < 2 && r < n; r++)
                s += mp->B[r][c] * mx[r];
            int mc = mp->cs.idx[c] - se->q0; /* modal column: unit row 2 + mc */
            if (mc >= 0 && mc < se->nm) s += mx[2 + mc];
            s += mp->rx[c] * (ax + m * fx) + mp->ry0[c] * (a0 + m / 3.0 * fy0 + m / 6.0 * fy1) +
                 mp->ry1[c] * (a1 + m / 3.0 * fy1 + m / 6.0 * fy0);
            p[c] = s;
        }
    return t;
}

/* The road-arm coordinate a span between bodies a and b moves with, or -1
 * when both ends ride on the hull: a road wheel's arm, or arm 1 for the
 * compensating idler (no span ends on two different arms). */
static int span_arm(const vm *v, int a, int b)
{
    if (a >= VM_RW1) return QA0 + a - VM_RW1;
    if (b >= VM_RW1) return QA0 + b - VM_RW1;
    if (v->comp_on && (a == VM_IDLER || b == VM_IDLER)) return QA0;
    return -1;
}

/* The geometry at q; the displaced maps mpe only with arm_maps (the velocity
 * terms' need: q_d given, dynamic spans). */
static void geom_eval(const vm *v, const double *q, int arm_maps, geom *g)
{
    kinematics_of(v, q, NULL, ALL_BODIES, &g->k);
    for (int el = 0; el < VM_NB; el++)
        tangent(v, &g->k, el, &g->e[el]);
    for (int s = 0; s < VM_NSPAN; s++) {
        const span_el *se = &v->span[s];
        if (se->sp)
            span_map_build(v, &g->k, se, &g->e[se->elem], se->elem, (se->elem + 1) % VM_NB,
                           &g->mp[s]);
    }
    if (!arm_maps) return;
    double qs[VM_NQ_RIGID + VM_NSPAN * 2 * TS_SPAN_MAX_MODES];
    memcpy(qs, q, (size_t)v->nq * sizeof *qs);
    for (int i = 0; i < VM_NRW; i++) /* no span ends on two road wheels */
        qs[QA0 + i] += SPAN_ARM_EPS;
    kin k; /* only the spans' end bodies are placed */
    kinematics_of(v, qs, NULL, v->arm_span_bodies, &k);
    for (int s = 0; s < VM_NSPAN; s++) {
        const span_el *se = &v->span[s];
        int a = se->elem, b = (se->elem + 1) % VM_NB;
        if (!se->sp || span_arm(v, a, b) < 0) continue;
        elem e;
        tangent(v, &k, se->elem, &e);
        span_map_build(v, &k, se, &e, a, b, &g->mpe[s]);
    }
}

/* Kinetic energy t[s] and momentum p[s][c] of the spans ending on a road arm
 * at the displaced maps g->mpe. */
static void arm_spans_at(const vm *v, const geom *g, const double *qd, double t[VM_NSPAN],
                         double p[VM_NSPAN][8 + 2 * TS_SPAN_MAX_MODES])
{
    for (int s = 0; s < VM_NSPAN; s++) {
        const span_el *se = &v->span[s];
        if (!se->sp || span_arm(v, se->elem, (se->elem + 1) % VM_NB) < 0) continue;
        t[s] = span_ke(se, &g->mpe[s], qd, p[s], g->mpe[s].cs.n);
    }
}

/* Base point of the velocity terms: q_d with the spin rates zeroed. */
static span_base *span_base_init(const vm *v, const double *qd, span_base *sb)
{
    /* the track's transport around the circuit (the spins) is left out of these
     * terms, as the paper drops the transport-speed terms of Eqs. 1-2 (II.B) */
    memcpy(sb->qdv, qd, (size_t)v->nq * sizeof *sb->qdv);
    for (int b = 0; b < VM_NB; b++)
        sb->qdv[QS0 + b] = 0;
    memset(sb->t, 0, sizeof sb->t);
    return sb;
}

/* Velocity terms of the span mass blocks, which depend on the hull pitch and
 * on the road arms at the spans' ends: Q += dT/dq - (dM/dt) q_d. The pitch
 * part in closed form (span_pitch_terms, from span_element); the arm part by
 * a forward difference from q (base point from span_element) in all arms at
 * once (no span ends on two road wheels), giving dT/dalpha and dp/dalpha,
 * (dM/dt) q_d = sum alpha_d dp/dalpha over the spans' end arms. Truncation
 * error ~eps/2 relative (1e-5 rad against geometry that changes over ~1 rad),
 * far below the integration tolerances. */
static void span_velocity_terms(const vm *v, const geom *g, const span_base *sb, double *Q)
{
    const double eps = SPAN_ARM_EPS;
    const double *qd = sb->qdv;
    double tp[VM_NSPAN] = {0};
    double pp[VM_NSPAN][8 + 2 * TS_SPAN_MAX_MODES];
    /* cppcheck-suppress legacyUninitvar */
    arm_spans_at(v, g, qd, tp, pp);
    for (int s = 0; s < VM_NSPAN; s++) {
        if (!v->span[s].sp) continue;
        int a = v->span[s].elem, b = (a + 1) % VM_NB;
        int iq = span_arm(v, a, b);
        if (iq < 0) continue;
        Q[iq] += (tp[s] - sb->t[s]) / eps; /* dT/dalpha */
        /* (dM/dalpha alpha_d) q_d = alpha_d dp/dalpha; the compact column sets
         * at q and q + eps e_alpha are the same (span_map_build adds the
         * columns in a fixed order) */
        double rate = qd[iq];
        if (rate == 0) continue;
        const int *idx = sb->cols[s].idx;
        for (int c = 0; c < sb->cols[s].n; c++)
            Q[idx[c]] -= rate * (pp[s][c] - sb->p[s][c]) / eps;
    }
}

/* The hull-pitch part of a span's velocity terms, in closed form. Turning
 * theta with the arm angles (hull-relative), spins and modes held is a rigid
 * rotation of the whole running gear about the CG: every map entry is a chord
 * vector dotted with a body Jacobian column, and the columns of theta and the
 * arms turn with the chord, so only the (x, z) columns change, as if (x_d,
 * z_d) were turned the other way. The span's block obeys
 * Ms(theta + d) = S(d)^T Ms S(d), S = rotation R(d) on the (x, z) entries, so
 * with S' = dS/dd at 0 ([0 -1; 1 0] on (x, z)) and p = Ms q_d:
 *   dT/dtheta = p . S' q_d = x_d p_z - z_d p_x,
 *   (dMs/dtheta) q_d = S'^T p + Ms S' q_d.
 * Adds dT/dtheta - theta_d (dMs/dtheta) q_d (q_d with the spin rates zeroed,
 * sb->qdv) to Q. The energy tests do not resolve this part (drift 0.18 %
 * without it, 0.12 % with, tolerance 0.5 %); tests/sim/test_vehicle_energy.c
 * pitch_velocity_terms_are_lagrangian checks it against the numerical
 * derivative of vm_mass. */
static void span_pitch_terms(const span_base *sb, const cset *cs,
                             double Mc[][8 + 2 * TS_SPAN_MAX_MODES], int s, double *Q)
{
    const double *qd = sb->qdv, *p = sb->p[s];
    /* span_map_build adds end a's Jacobian columns first, and every body's
     * Jacobian begins with x, z (kinematics_of): compact columns 0 and 1 */
    const int cx = 0, cz = 1;
    double xd = qd[QX], zd = qd[QZ], thd = qd[QT];
    Q[QT] += xd * p[cz] - zd * p[cx];
    if (thd == 0) return;
    for (int c = 0; c < cs->n; c++)
        Q[cs->idx[c]] -= thd * (xd * Mc[c][cz] - zd * Mc[c][cx]);
    Q[QX] -= thd * p[cz];
    Q[QZ] += thd * p[cx];
}

/* The modal sums sum_r ay_r x_r and sum_r alpha_r x_r over the span's modes
 * (x's entries 2..n-1): the span's weight load normal to the chord and along
 * it, shared by the force (span_element) and its potential (vm_energy). */
static void span_modal_sums(const span_el *se, const double *x, double *ax, double *ay)
{
    *ax = *ay = 0;
    for (int r = 2; r < se->sp->n; r++)
        *ay += se->sp->ay[r] * x[r], *ax += se->alpha[r] * x[r];
}

static void span_element(const vm *v, vm_work *w, const span_map *mp, const span_el *se,
                         const elem *e, int a, int b, const double *q, const double *qd, double *M,
                         double *Q, vm_diag *diag, span_base *sb)
{
    const ts_span *sp = se->sp;
    int n = sp->n, nq = v->nq;
    if (sb) {
        int s = (int)(se - v->span);
        /* the spans between hull-mounted bodies enter only the pitch terms,
         * which read p on the x, z columns (compact 0, 1) alone */
        int np = span_arm(v, a, b) < 0 ? 2 : mp->cs.n;
        sb->t[s] = span_ke(se, mp, sb->qdv, sb->p[s], np);
        sb->cols[s] = mp->cs;
    }
    const cset cs = mp->cs;
    const double(*B)[8 + 2 * TS_SPAN_MAX_MODES] = mp->B;
    const double *rx = mp->rx, *ry0 = mp->ry0, *ry1 = mp->ry1;
    double ell = e->ell;
    /* local state */
    double *x = w->sx, *xd = w->sxd, *f = w->sf;
    double u0 = v->rho_b[a] * (q[QS0 + a] + e->dpsi);
    double u1 = v->rho_b[b] * (q[QS0 + b] + e->dpsi) + ell - v->ell0[se->elem];
    x[0] = 0;
    x[1] = u1 - u0;
    for (int m = 0; m < se->nm; m++)
        x[2 + m] = q[se->q0 + m];
    /* B's rows 0, 1 are dense; row 2 + m is the unit vector on the modal
     * coordinate q0 + m, compact column cm0 + m (span_map) */
    const int cm0 = cs.n - se->nm;
    for (int r = 0; r < 2; r++) {
        double s = 0;
        if (qd)
            for (int c = 0; c < cs.n; c++)
                s += B[r][c] * qd[cs.idx[c]];
        xd[r] = s;
    }
    for (int r = 2; r < n; r++)
        xd[r] = qd ? qd[se->q0 + r - 2] : 0;
    double gx = -GRAVITY * e->u[1], gy = -GRAVITY * e->n[1];
    /* The frame's translation and rotation enter through the mass matrix (the
     * frame-velocity coupling below), so no support accelerations are passed;
     * the chord's rotation rate is not passed either: its centripetal term
     * would do work the lumped frame kinetic energy does not account for, and
     * its Coriolis term 2 theta_d W x_d (no work) is left out as a term of the
     * track's transport speed, which the paper drops (II.B: the c-terms of
     * Eqs. 1-2, small below ~20 mph; span_base_init leaves the spins out of
     * the velocity terms for the same reason). It is NOT small in the motion:
     * the end feeds u0_d, u1_d carry the track speed, so on V it is first
     * order, 2 theta_d rho \int phi (u0_d N0 + u1_d N1) = 2 theta_d rho c
     * \int phi for a uniform feed c: on span 0 (L 1.83 m, mode 1) 1.92 kN at
     * 10 m/s and theta_d = 0.5 rad/s, as large as the span's own weight load
     * rho g \int phi = 1.88 kN. */
    ts_span_motion mo = {0, 0, 0, 0, gy};
    ts_span_force(sp, &mo, x, xd, f);
    /* Kelvin-Voigt track damping, the same retardation time as the chain
     * elements: -tau_d K x_d (stiffness-proportional, damps the span's
     * high longitudinal modes hard and its transverse string modes lightly) */
    double kv = v->dscale * v->tau_d;
    if (kv > 0)
        for (int r = 0; r < n; r++) {
            double s = 0;
            for (int c = 0; c < n; c++)
                s += sp->K[r * n + c] * xd[c];
            f[r] -= kv * s;
        }
    /* gravity along the chord on the longitudinal sine modes (the tension
     * gradient); not on the rigid feed u0, u1: over the whole closed loop the
     * track's weight along the circuit sums to zero, and only the free spans
     * carry mass here, so keeping it would make the track creep round. */
    for (int r = 2; r < n; r++)
        f[r] += gx * se->alpha[r];
    /* a track cannot push: the compressive part of the axial stress out (elastic
     * and Kelvin-Voigt together, so a span unloading fast goes slack too) */
    if (v->no_compression) ts_span_slack_force(sp, x, qd ? xd : NULL, kv, f);
    /* generalised forces: B^T f + frame gravity, -dV/dq of vm_energy's
     * V = m g (p_a,z + L_ref u_z / 2) - (g_y - g_y,sag) ay.x - g_x alpha.x:
     * the frame rides on tangent point 0 (rx), the chord turns by
     * dpsi = (ry1 - ry0) . dq / l, so the span's centre of mass, L_ref / 2 down
     * the chord, moves normal to it by ry0 + L_ref / (2 l) (ry1 - ry0); and
     * turning the chord turns gravity's components on the modal loads,
     * dV/dpsi = g_x ay.x - g_y alpha.x (dg_x/dpsi = g_y, dg_y/dpsi = -g_x) */
    double m = se->rho * se->len, hl = 0.5 * se->len / ell, ay, ax;
    span_modal_sums(se, x, &ax, &ay);
    double turn = (gx * ay - gy * ax) / ell;
    for (int c = 0; c < cs.n; c++) {
        double s = B[0][c] * f[0] + B[1][c] * f[1];
        if (c >= cm0) s += f[2 + c - cm0];
        s += m * gx * rx[c] + m * gy * (ry0[c] + hl * (ry1[c] - ry0[c]));
        s -= turn * (ry1[c] - ry0[c]);
        Q[cs.idx[c]] += s;
    }
    if (M || sb) {
        /* block B^T Ms B + B^T C + C^T B + frame terms, C = alpha rx + beta0
         * ry0 + beta1 ry1 (n x nc); Y = Ms B + C. Symmetric: the upper
         * triangle of compact columns is computed and mirrored. */
        double Cm[2 + 2 * TS_SPAN_MAX_MODES][8 + 2 * TS_SPAN_MAX_MODES];
        double Y[2 + 2 * TS_SPAN_MAX_MODES][8 + 2 * TS_SPAN_MAX_MODES];
        for (int r = 0; r < n; r++) {
            const double *msr = sp->M + r * n;
            for (int c = 0; c < cs.n; c++) {
                double cm = se->alpha[r] * rx[c] + se->beta0[r] * ry0[c] + se->beta1[r] * ry1[c];
                double mb = msr[0] * B[0][c] + msr[1] * B[1][c];
                if (c >= cm0) mb += msr[2 + c - cm0];
                Cm[r][c] = cm;
                Y[r][c] = mb + cm;
            }
        }
        double Mc[8 + 2 * TS_SPAN_MAX_MODES][8 + 2 * TS_SPAN_MAX_MODES]; /* the block */
        /* the frame terms m rx rx' + m/3 (ry0 ry0' + ry1 ry1') + m/6 (ry0 ry1' + ry1 ry0')
         * as rx . fx' + ry0 . f0' + ry1 . f1' (three products per entry instead of eight) */
        double fxm[8 + 2 * TS_SPAN_MAX_MODES], f0m[8 + 2 * TS_SPAN_MAX_MODES],
            f1m[8 + 2 * TS_SPAN_MAX_MODES];
        for (int c = 0; c < cs.n; c++) {
            fxm[c] = m * rx[c];
            f0m[c] = m / 3.0 * ry0[c] + m / 6.0 * ry1[c];
            f1m[c] = m / 3.0 * ry1[c] + m / 6.0 * ry0[c];
        }
        /* Without M only Mc's columns x, z (compact 0, 1) are needed, i.e.
         * its upper triangle's rows 0 and 1. The row's own factors are held
         * in locals and M is added to after the block is complete (the loop
         * stored through M, so every factor was loaded again). */
        for (int c1 = 0; c1 < cs.n && (M || c1 < 2); c1++) {
            const double b0 = B[0][c1], b1 = B[1][c1], k0 = Cm[0][c1], k1 = Cm[1][c1];
            const double x1 = rx[c1], y01 = ry0[c1], y11 = ry1[c1];
            const double *ym = c1 >= cm0 ? Y[2 + c1 - cm0] : NULL;
            for (int c2 = c1; c2 < cs.n; c2++) {
                double s = b0 * Y[0][c2] + b1 * Y[1][c2] + k0 * B[0][c2] + k1 * B[1][c2];
                if (ym) s += ym[c2];
                if (c2 >= cm0) s += Cm[2 + c2 - cm0][c1];
                s += x1 * fxm[c2] + y01 * f0m[c2] + y11 * f1m[c2];
                Mc[c1][c2] = Mc[c2][c1] = s;
            }
        }
        if (M) /* each entry of M gets one term from this span: the order is free */
            for (int c1 = 0; c1 < cs.n; c1++)
                for (int c2 = c1; c2 < cs.n; c2++)
                    *mass_at(M, nq, cs.idx[c1], cs.idx[c2]) += Mc[c1][c2];
        if (sb) span_pitch_terms(sb, &cs, Mc, (int)(se - v->span), Q);
    }
    if (diag) {
        ts_span_end_forces ef;
        ts_span_end_forces_eval(sp, x, &ef);
        double t0 = ef.tension0, t1 = ef.tension1;
        int s = (int)(se - v->span);
        double U, V, tau;
        ts_span_eval(sp, x, 0.5 * sp->p.length, &U, &V, &tau);
        double tm = v->p0 + tau;
        if (v->no_compression) t0 = fmax(t0, 0), t1 = fmax(t1, 0), tm = fmax(tm, 0);
        diag->tension_end0[se->elem] = t0;
        diag->tension_end1[se->elem] = t1;
        diag->tension[se->elem] = 0.5 * (t0 + t1);
        diag->span_mid_deflection[s] = V;
        diag->span_mid_tension[s] = tm;
    }
}

/* ---- construction and static equilibrium ---------------------------------- */

static void mark_pairs(unsigned char *nz, int nq, const int *idx, int n)
{
    for (int r = 0; r < n; r++)
        for (int c = 0; c < n; c++)
            nz[idx[r] * nq + idx[c]] = 1;
}

/* Where M can be nonzero, whatever the state: the index sets every write to
 * M goes through (forces: the body Jacobians, hull included, the spin
 * inertias, the quasi-static spin coupling, each span's compact columns;
 * rhs_cached: the sprocket inertia on theta), and from it the rows its
 * reversed Cholesky factor can fill (v->mass_cand): chol_solve looks at
 * those alone instead of scanning all of each column of M for nonzeros (a
 * third of the factorisation's instructions; ~100 of the 465 below the
 * diagonal are nonzero). A new write to M must be added here;
 * tests/sim/test_vehicle_rhs_paths.c checks vm_rhs against a full-scan
 * factorisation of vm_mass. */
static ts_rc mass_structure(vm *v, ts_err *err)
{
    int nq = v->nq;
    unsigned char *nz = calloc((size_t)nq * (size_t)nq, 1);
    v->mass_cand = malloc(sizeof(int) * (size_t)nq * (size_t)(nq + 1));
    if (!nz || !v->mass_cand) {
        free(nz);
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
    }
    double q0[VM_NQ_RIGID] = {0};
    kin k;
    kinematics_of(v, q0, NULL, ALL_BODIES, &k); /* only the column indices are read */
    for (int b = 0; b < VM_NB; b++) {
        mark_pairs(nz, nq, k.j[b].idx, k.j[b].n);
        nz[(QS0 + b) * nq + QS0 + b] = 1; /* its spin inertia */
    }
    if (v->fidelity == TS_TRACK_QUASI_STATIC) { /* mqs couples spins 0..3 */
        int spin[4] = {QS0, QS0 + 1, QS0 + 2, QS0 + 3};
        mark_pairs(nz, nq, spin, 4);
    }
    int sprocket[2] = {QT, QS0 + VM_SPROCKET};
    mark_pairs(nz, nq, sprocket, 2);
    for (int s = 0; s < VM_NSPAN; s++)
        if (v->span[s].sp) mark_pairs(nz, nq, v->span[s].cs.idx, v->span[s].cs.n);
    ts_chol_symbolic_rev(nz, nq, v->mass_cand);
    free(nz);
    return TS_OK;
}

void vm_free(vm *v)
{
    if (!v) return;
    ts_terrain_free(v->terrain);
    for (int s = 0; s < VM_NSPAN; s++)
        ts_span_free(v->span[s].sp);
    free(v->y_eq);
    free(v->rate);
    free(v->mass_cand);
    free(v);
}

int vm_nq(const vm *v)
{
    return v->nq;
}
int vm_ny(const vm *v)
{
    return v->ny;
}
int vm_dof(const vm *v)
{
    return v->nq;
}
const double *vm_equilibrium(const vm *v)
{
    return v->y_eq;
}
const double *vm_rates(const vm *v)
{
    return v->rate;
}

/* Absolute tolerances: atol for the coordinates (m, rad), and for each rate
 * atol times that coordinate's own rate omega_i = sqrt(K_ii / M_ii) at the
 * equilibrium (vm_rates): a velocity error omega_i atol carries the same
 * energy, M_ii (omega_i atol)^2 = K_ii atol^2, as the coordinate error atol,
 * so no state is held tighter than the others in the energy norm. omega_i
 * with the default layout (one mode per span and family): 25-85 1/s
 * (transverse span modes), 38-61 1/s (hull x, z, pitch), 320-620 1/s (road
 * arms), 320-2,300 1/s (spins), 490-1,800 1/s (longitudinal span modes);
 * higher modes scale with their number. A coordinate without a restoring
 * stiffness (none in the six fidelities: test_vehicle_static.c) falls back to
 * a position error of atol accrued over FALLBACK_TIME.
 *
 * VM_JAC_EVAL_STEPS (CVODE's default is 51): a difference-quotient Jacobian
 * costs 2 nq right-hand sides; the model's Jacobian changes slowly between
 * contact events, and CVODE re-evaluates it anyway when Newton fails to
 * converge with a stale one. 1000: Jacobians 374 -> ~70 per 30-s bump run,
 * steps and results unchanged within the bench pins.
 *
 * VM_BDF_MAX_ORDER: orders 4 and 5 are stable in a narrower wedge about the
 * negative real axis (A(alpha) stability, alpha = 73 and 52 degrees, against
 * 86 for order 3), and the model's lightly damped modes (transverse span
 * modes, hull bounce and pitch: damping ratios 0.03-0.05) lie near the
 * imaginary axis: at orders 4-5 CVODE's steps over the bump course are
 * limited by them. Measured on the coupled 30-s bump run (rtol 0.9e-3, 1e-3,
 * 1.1e-3) when the cap was set: 12,800-17,800 steps at order 5,
 * 12,200-12,400 at order 3. Re-measured after the span mass-block rounding
 * change (the step sequence over the bumps is chaotic, so the gain moves with
 * rounding): coupled 12,600-13,900 at order 5 against 12,200-12,300 at order
 * 3 (3-13 % fewer), static 8,000-9,200 against 8,000-8,600, longitudinal
 * 12,000-12,400 against 11,600-11,800 (0-7 % fewer); the rate tolerances do
 * most of the step reduction (coupled 17,200 -> 12,600 at order 5, rtol
 * 1e-3). Figures against the rtol 1e-6 reference in
 * tests/bench/bench_vehicle.c; the coupled runs' in docs/coupled.md. */
#define FALLBACK_TIME 0.01 /* s (numerical choice) */
void vm_abs_tolerances(const vm *v, double atol, double *out)
{
    for (int i = 0; i < v->nq; i++) {
        out[i] = atol;
        out[v->nq + i] = atol * (v->rate[i] > 0 ? v->rate[i] : 1.0 / FALLBACK_TIME);
    }
}

double vm_static_tension(const vm *v)
{
    return v->t_static;
}
double vm_preload(const vm *v, int arm)
{
    return v->m0[arm];
}
double vm_x0(const vm *v)
{
    return v->y_eq[QX];
}

double vm_supported_weight(const vm *v)
{
    double m = v->m_hull + VM_NRW * (v->m_w + v->m_arm);
    for (int p = 0; p < v->npm; p++)
        m += v->pm_m[p];
    for (int s = 0; s < VM_NSPAN; s++)
        if (v->span[s].sp) m += v->span[s].rho * v->span[s].len;
    return m * GRAVITY;
}

vm_work *vm_work_make(const vm *v)
{
    vm_work *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    size_t nq = (size_t)v->nq;
    w->M = calloc(nq * nq, sizeof(double));
    w->Q = calloc(nq, sizeof(double));
    w->P = calloc(nq * nq, sizeof(double));
    w->pat = calloc(nq * (nq + 1), sizeof(int));
    w->geo = malloc(sizeof *w->geo);
    if (!w->M || !w->Q || !w->P || !w->pat || !w->geo) {
        vm_work_free(w);
        return NULL;
    }
    return w;
}

void vm_work_free(vm_work *w)
{
    if (!w) return;
    free(w->M);
    free(w->Q);
    free(w->P);
    free(w->pat);
    free(w->geo);
    free(w);
}

#define EQ_GROUND_SCAN_STEP 0.05 /* [m] the start's scan of the ground under the wheels */

/* Static unknowns: x, z, theta, every spin but the anchor wheel's (gauge: the
 * vehicle rolling with its track is a null mode of the potential), the
 * preloads (arms held at the design angle), the link setting and the span
 * modes. Equations: every generalised force but the anchor wheel's spin (it
 * follows from the others: Q_x + sum Q_Phi_b / rho_b = 0 identically) and the
 * tensioner condition T_rear_roller = P0. The anchor reference stays at its
 * design value, so the anchor carries whatever the massive spans' weight along
 * the circuit needs. That is the DESIGN equilibrium, on level ground: the
 * preloads and the link setting are the vehicle's (bars and adjuster set up
 * on level ground). On uneven ground (v->eq_on_terrain) they stay as found
 * there and the arm angles take their place; the tensioner condition goes
 * with the link setting (the rest tension is what the terrain makes it). */
static int eq_unknowns(const vm *v)
{
    return 3 + VM_NB - 1 + VM_NRW + (v->eq_on_terrain ? 0 : 1) + v->nmodal;
}

static void eq_apply(vm *v, const double *u, double *q)
{
    int p = 0;
    q[QX] = u[p++];
    q[QZ] = u[p++];
    q[QT] = u[p++];
    for (int b = 0; b < VM_NB; b++)
        if (b != VM_RW1 + v->anchor) q[QS0 + b] = u[p++];
    if (v->eq_on_terrain) {
        for (int i = 0; i < VM_NRW; i++)
            q[QA0 + i] = u[p++];
    } else {
        for (int i = 0; i < VM_NRW; i++)
            v->m0[i] = u[p++];
        v->d_link = u[p++];
    }
    for (int m = 0; m < v->nmodal; m++)
        q[VM_NQ_RIGID + m] = u[p++];
}

/* The terrain unknowns of the state q (the inverse of eq_apply's terrain branch). */
static void eq_terrain_unknowns(const vm *v, const double *q, double *u)
{
    int p = 0;
    u[p++] = q[QX];
    u[p++] = q[QZ];
    u[p++] = q[QT];
    for (int b = 0; b < VM_NB; b++)
        if (b != VM_RW1 + v->anchor) u[p++] = q[QS0 + b];
    for (int i = 0; i < VM_NRW; i++)
        u[p++] = q[QA0 + i];
    for (int m = 0; m < v->nmodal; m++)
        u[p++] = q[VM_NQ_RIGID + m];
}

static void eq_residual(vm *v, vm_work *w, const double *u, double *q, double *r)
{
    eq_apply(v, u, q);
    vm_diag dg;
    forces_at(v, w, 0.0, q, NULL, NULL, w->Q, 0, &dg);
    int p = 0;
    r[p++] = w->Q[QX];
    r[p++] = w->Q[QZ];
    r[p++] = w->Q[QT];
    for (int i = 0; i < VM_NRW; i++)
        r[p++] = w->Q[QA0 + i];
    for (int b = 0; b < VM_NB; b++)
        if (b != VM_RW1 + v->anchor) r[p++] = w->Q[QS0 + b];
    if (!v->eq_on_terrain) r[p++] = dg.tension_end1[0] - v->p0;
    for (int m = 0; m < v->nmodal; m++)
        r[p++] = w->Q[VM_NQ_RIGID + m];
}

static int has_nonfinite(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 1;
    return 0;
}

static double eq_norm(const double *r, int nu)
{
    double rn = 0;
    for (int i = 0; i < nu; i++)
        rn = fmax(rn, fabs(r[i])); /* fmax drops a NaN: callers check */
    return rn;
}

/* Newton on eq_residual from u (updated in place): TS_OK, or TS_ERR_SOLVER
 * with the reason. J, r, r2 hold nu values (J nu x nu), q nq, piv nu, us nu
 * (the line search's start). Each step is cut back (halved up to 10 times)
 * until the largest residual falls: with the arms free on uneven ground
 * wheels lift off and touch down between iterations, and full steps cycled
 * across those kinks (session-31 review: 55-60 % grades, 0.5-1.0 m bumps
 * under a wheel). For every preset (level ground) each full step is taken:
 * their series.csv are bit for bit those of plain Newton (checked with cmp,
 * session 31). The residual at the accepted point is the next iteration's. */
static ts_rc eq_newton(vm *v, vm_work *w, double *u, double *q, double *r, double *r2, double *J,
                       int *piv, double *us, int nu, ts_err *err)
{
    double scale_f = vm_supported_weight(v);
    enum { NIT = 100 };
    eq_residual(v, w, u, q, r);
    for (int it = 0; it < NIT; it++) {
        double rn = eq_norm(r, nu);
        if (has_nonfinite(r, nu))
            return ts_err_set(err, TS_ERR_SOLVER, "/vehicle",
                              "static equilibrium: residual not finite at Newton step %d "
                              "(check the layout)",
                              it);
        if (rn < 1e-7 * scale_f) return TS_OK;
        for (int j = 0; j < nu; j++) {
            double h = 1e-7 * fmax(1.0, fabs(u[j]));
            double keep = u[j];
            u[j] = keep + h;
            eq_residual(v, w, u, q, r2);
            u[j] = keep;
            for (int i = 0; i < nu; i++) /* column-major (dense_small.h) */
                J[(size_t)j * nu + i] = (r2[i] - r[i]) / h;
        }
        for (int i = 0; i < nu; i++)
            r[i] = -r[i];
        /* dense_small.h's LU, not LAPACK: a threaded BLAS's workers would
         * spin for the rest of the run after this one tiny solve */
        if (ts_lu_factor(J, nu, piv) != 0)
            return ts_err_set(err, TS_ERR_SOLVER, "/vehicle",
                              "static equilibrium: singular Jacobian (check the layout)");
        ts_lu_solve(J, nu, piv, r);
        memcpy(us, u, (size_t)nu * sizeof(double));
        double a = 1.0;
        for (int cut = 0; cut <= 10; cut++, a *= 0.5) {
            for (int i = 0; i < nu; i++)
                u[i] = us[i] + a * r[i];
            eq_residual(v, w, u, q, r2);
            if (!has_nonfinite(r2, nu) && eq_norm(r2, nu) < rn) break;
        }
        memcpy(r, r2, (size_t)nu * sizeof(double));
    }
    return ts_err_set(err, TS_ERR_SOLVER, "/vehicle",
                      "static equilibrium did not converge in %d Newton steps", (int)NIT);
}

/* Newton's start: the hull level at x0, the road arms at their design angle
 * carrying an equal share of the supported weight, the hull lowered by one
 * share's foundation compression (linear part) below ground height hg.
 * With on_ground the wheels' design height over the ground (the layout's
 * road_wheel_z less the wheel radius and track thickness: +2.5 mm in the M1
 * data) is taken out too. The first start ignores it, and every published
 * figure comes from it (a different start converges to the same equilibrium
 * within Newton's tolerance, and the chaotic bump runs then move ~1 %), so it
 * is tried first; but with a stiffer foundation (2e7 N/m and up), a thinner
 * track or smaller wheels it left every wheel off the ground (no vertical
 * stiffness: a singular Jacobian), and the second start is tried after it. */
static void eq_start(const vm *v, double hg, int on_ground, double *u, int nu)
{
    double wsup = vm_supported_weight(v), bottom = 0;
    for (int i = 0; i < VM_NRW; i++) /* design wheel bottom relative to the hull's z */
        bottom += (v->l_pivot[i][1] - v->arm_len * sin(v->arm0) - v->wheel_ground) / VM_NRW;
    memset(u, 0, (size_t)nu * sizeof(double));
    u[0] = v->x0;
    u[1] = (on_ground ? hg - bottom : v->z0 + hg) - wsup / VM_NRW / v->kf;
    for (int i = 0; i < VM_NRW; i++)
        u[3 + VM_NB - 1 + i] = wsup / VM_NRW * v->arm_len * cos(v->arm0);
}

static ts_rc equilibrium(vm *v, ts_err *err)
{
    v->eq_on_terrain = 0;
    int nu = eq_unknowns(v), nq = v->nq; /* the design unknowns: the larger set */
    vm_work *w = vm_work_make(v);
    double *u = calloc((size_t)nu, sizeof(double)), *r = calloc((size_t)nu, sizeof(double)),
           *r2 = calloc((size_t)nu, sizeof(double)),
           *J = calloc((size_t)nu * (size_t)nu, sizeof(double)),
           *q = calloc((size_t)nq, sizeof(double)), *ub = calloc((size_t)nu, sizeof(double)),
           *ul = calloc((size_t)nu, sizeof(double));
    int *piv = calloc((size_t)nu, sizeof(int));
    ts_rc rc = TS_OK;
    if (!w || !u || !r || !r2 || !J || !q || !ub || !ul || !piv) {
        rc = ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        goto done;
    }
    for (int i = 0; i < VM_NRW; i++)
        q[QA0 + i] = v->arm0;
    /* start on the ground under the road wheels, the foundation compressed;
     * the ground is read where the foundation reads it, under the hubs, and
     * scanned every EQ_GROUND_SCAN_STEP (5 cm: a bump narrower than that can
     * fall between the samples) from a wheel radius behind the last hub to one ahead
     * of the first, so a bump between or under the hubs counts as uneven (the
     * arm pivots, read until session 31, stand 0.39 m ahead of the hubs) */
    double hg = 0, hmin = INFINITY, hmax = -INFINITY, xlo = INFINITY, xhi = -INFINITY;
    for (int i = 0; i < VM_NRW; i++) {
        double xh = v->x0 + v->l_pivot[i][0] - v->arm_len * cos(v->arm0);
        hg += ts_terrain_height(v->terrain, xh, NULL) / VM_NRW;
        xlo = fmin(xlo, xh - v->rho_b[VM_RW1 + i]);
        xhi = fmax(xhi, xh + v->rho_b[VM_RW1 + i]);
    }
    for (double x = xlo; x <= xhi + 1e-9; x += EQ_GROUND_SCAN_STEP) {
        double h = ts_terrain_height(v->terrain, fmin(x, xhi), NULL);
        hmin = fmin(hmin, h);
        hmax = fmax(hmax, h);
    }
    /* Uneven ground under the wheels has more than one equilibrium: Newton
     * from the level start found the hull standing 1.3 rad nose-down on road
     * wheel 1 over a 0.3-m bump (review, session 28). There the terrain is
     * raised from flat in steps (below), which follows the branch a vehicle
     * settling onto the ground follows; the level start only where the
     * wheels stand level (every preset; a uniform grade tilts in steps).
     * The bars' preloads and the link setting are those of the design
     * equilibrium on level ground (flat, heights scaled by 0); from there
     * the arm angles are the unknowns instead (eq_apply). */
    int uneven = hmax - hmin > 1e-9;
    for (int on_ground = 0; on_ground < 2; on_ground++) {
        ts_err first;
        if (on_ground && err) first = *err; /* the first start's reason */
        v->eq_on_terrain = 0;
        for (int i = 0; i < VM_NRW; i++)
            q[QA0 + i] = v->arm0;
        eq_start(v, hg, on_ground, u, nu);
        rc = uneven ? ts_err_set(err, TS_ERR_SOLVER, "/terrain",
                                 "static equilibrium: uneven ground under the wheels")
                    : eq_newton(v, w, u, q, r, r2, J, piv, ul, nu, err);
        if (rc == TS_ERR_SOLVER) {
            /* A bump under a wheel can leave every wheel off the ground at
             * that start (no wheel, no vertical stiffness: a singular
             * Jacobian) or make Newton cycle on the lift-off kinks. Continue
             * instead from flat ground, raising the terrain in steps from one
             * equilibrium to the next, the step halved where Newton fails. */
            double s = 0, ds = 0.25;
            v->ground_scale = 0;
            eq_start(v, 0, on_ground, u, nu);
            rc = eq_newton(v, w, u, q, r, r2, J, piv, ul, nu, err);
            int n = nu;
            if (rc == TS_OK && uneven) {
                eq_apply(v, u, q); /* the design preloads and link setting */
                v->eq_on_terrain = 1;
                n = eq_unknowns(v);
                eq_terrain_unknowns(v, q, u);
            }
            while (rc == TS_OK && s < 1) {
                double next = fmin(1.0, s + ds);
                memcpy(ub, u, (size_t)n * sizeof(double));
                v->ground_scale = next;
                rc = eq_newton(v, w, u, q, r, r2, J, piv, ul, n, err);
                if (rc == TS_OK) {
                    s = next;
                    ds = fmin(0.5, 2 * ds);
                } else if (ds > 1.0 / 4096) {
                    memcpy(u, ub, (size_t)n * sizeof(double));
                    ds /= 2;
                    rc = TS_OK;
                }
            }
            v->ground_scale = 1.0;
            if (rc != TS_OK && err && uneven) /* the ground's fault, not the vehicle's */
                snprintf(err->pointer, sizeof err->pointer, "/terrain/start_x");
            if (rc != TS_OK && err && v->cfg.terrain.kind != TS_TERRAIN_FLAT)
                snprintf(err->msg + strlen(err->msg), sizeof err->msg - strlen(err->msg),
                         "; also when the terrain was raised from flat in steps: the road "
                         "wheels find no equilibrium on this ground at t = 0 (start the run "
                         "on level ground, before the obstacle or grade: /terrain/start_x)");
        }
        if (rc != TS_ERR_SOLVER) break;
        if (on_ground && err) *err = first; /* both failed: the first start's message */
    }
    if (rc != TS_OK) goto done;
    eq_apply(v, u, q);
    v->eq_on_terrain = 0;
    {
        vm_diag dg;
        forces_at(v, w, 0.0, q, NULL, NULL, w->Q, 0, &dg);
        v->t_static = dg.tension_end1[0];
        v->g_eq = dg.loop_stretch;
    }
    memcpy(v->y_eq, q, (size_t)nq * sizeof(double));
    /* each coordinate's own rate sqrt(K_ii / M_ii) (the others held) at the
     * equilibrium: K_ii = -dQ_i/dq_i by a forward difference of the static
     * forces (h: a numerical step, far below every geometric length), M_ii
     * from the mass matrix */
    {
        const double h = 1e-7; /* [m or rad] */
        /* scratch of nq values: r2 holds nu, and nu == nq because the
         * unknowns trade coordinates one for one (the arm angles for the bar
         * preloads, the anchor wheel's spin for the idler link setting) */
        _Static_assert(3 + VM_NB - 1 + VM_NRW + 1 == VM_NQ_RIGID,
                       "equilibrium unknowns: one per rigid coordinate");
        double *Q0 = r2;
        forces_at(v, w, 0.0, q, NULL, w->M, Q0, 0, NULL);
        for (int i = 0; i < nq; i++) {
            double keep = q[i], mii = w->M[(size_t)i * nq + i];
            q[i] = keep + h;
            forces_at(v, w, 0.0, q, NULL, NULL, w->Q, 0, NULL);
            q[i] = keep;
            double kii = -(w->Q[i] - Q0[i]) / h;
            v->rate[i] = kii > 0 && mii > 0 ? sqrt(kii / mii) : 0.0;
        }
    }
done:
    vm_work_free(w);
    free(u);
    free(r);
    free(r2);
    free(J);
    free(q);
    free(ub);
    free(ul);
    free(piv);
    return rc;
}

static ts_rc build_spans(vm *v, ts_err *err)
{
    const ts_track_config *tc = &v->cfg.track;
    int nl = 0, nt = 0, qs = 0;
    switch (v->fidelity) {
    case TS_TRACK_LONGITUDINAL:
        nl = tc->n_long;
        break;
    case TS_TRACK_TRANSVERSE:
        nt = tc->n_trans, qs = 1;
        break;
    case TS_TRACK_COUPLED:
        /* n_long = 0: Irvine's uniform tension (quasi-static stretch), the
         * meaning track_circuit.h and `tanksim modes` give it, not the
         * linear-U stretch of the bare support shapes */
        nl = tc->n_long, nt = tc->n_trans, qs = nl == 0;
        break;
    default:
        return TS_OK;
    }
    if (nl + nt == 0) {
        /* name the count this fidelity reads: the transverse fidelity only n_trans */
        const char *ptr = tc->fidelity == TS_TRACK_TRANSVERSE ? "/track/n_trans" : "/track/n_long";
        return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: the %s track fidelity needs span modes",
                          ptr, ts_track_fidelity_names[tc->fidelity]);
    }
    int q0 = VM_NQ_RIGID;
    for (int s = 0; s < VM_NSPAN; s++) {
        span_el *se = &v->span[s];
        int el = vm_span_element[s];
        ts_span_params p = {.length = v->ell0[el],
                            .g_y = -GRAVITY * v->u0[el][0], /* g . n, n = (-u_z, u_x) */
                            .rho = tc->mass_per_length,
                            .ea = tc->ea,
                            .tension = tc->tension,
                            .speed = 0,
                            .translation_terms = 0,
                            .quasi_static_stretch = qs,
                            .n_long = nl,
                            .n_trans = nt,
                            .damping_ratio = tc->damping_ratio * v->dscale};
        se->sp = ts_span_make(&p, err);
        if (!se->sp) {
            ts_span_err_to_config(err, "/vehicle"); /* lengths and slopes: the layout */
            return err ? err->code : TS_ERR_PARAM;
        }
        se->elem = el;
        se->q0 = q0;
        se->nm = nl + nt;
        se->rho = tc->mass_per_length;
        se->len = v->ell0[el];
        q0 += se->nm;
        v->span_of[el] = se;
        span_columns(v, se);
        /* frame-coupling integrals from the span's load vectors: rho int N_i
         * (longitudinal rows) and, for the transverse frame velocity
         * interpolated between the ends, rho int (1 - s/L) phi_k = ay - sy/L and
         * rho int (s/L) phi_k = sy/L */
        for (int r = 0; r < se->sp->n; r++) {
            se->alpha[r] = se->sp->ax[r];
            se->beta1[r] = se->sp->sy[r] / se->len;
            se->beta0[r] = se->sp->ay[r] - se->beta1[r];
        }
    }
    v->nmodal = q0 - VM_NQ_RIGID;
    v->dynamic = 1;
    for (int s = 0; s < VM_NSPAN; s++) {
        int a = v->span[s].elem, b = (a + 1) % VM_NB;
        if (span_arm(v, a, b) >= 0) v->arm_span_bodies |= 1u << a | 1u << b;
    }
    return TS_OK;
}

/* Length of the track loop's pitch line at coordinates q, less the design
 * loop's (the spins and modes do not enter): the tangent lengths' change plus
 * each wrap's, rho_b (dpsi_prev - dpsi_b), as the elements' stretch counts
 * it (a wrap may go negative: the chain keeps to the wheel). Needs v->ell0,
 * v->u0. */
static double loop_length(const vm *v, const double *q)
{
    kin k;
    kinematics(v, q, NULL, &k);
    double dpsi[VM_NB], L = 0;
    for (int el = 0; el < VM_NB; el++) {
        elem e;
        tangent(v, &k, el, &e);
        dpsi[el] = e.dpsi;
        L += e.ell - v->ell0[el];
    }
    for (int b = 0; b < VM_NB; b++)
        L += v->rho_b[b] * (dpsi[(b + VM_NB - 1) % VM_NB] - dpsi[b]);
    return L;
}

/* Loop length with the idler moved by travel along its link (the idler
 * fixed to the hull while the table is built). */
static double loop_length_at(vm *v, double *q, double travel)
{
    double keep = v->d_link;
    v->d_link = keep + travel;
    double L = loop_length(v, q);
    v->d_link = keep;
    return L;
}

/* The error of a compensating idler that cannot follow road arm 1 at angle
 * alpha [rad]. */
static ts_rc comp_error(ts_err *err, double alpha, const char *where)
{
    return ts_err_set(err, TS_ERR_PARAM, "/vehicle/idler_compensation",
                      "/vehicle/idler_compensation, /vehicle/idler_link_angle: no idler travel "
                      "along the link keeps the loop length at road arm 1 angle %.3f rad%s",
                      alpha, where);
}

/* The compensating idler's travel table: at each arm-1 angle the travel that
 * takes up the given share of the change of the loop's length from the
 * design configuration q (other arms at their design angle), by Newton from
 * the neighbouring node; the slope from the implicit function theorem. Built
 * outward from the design angle, each way up to the first node without a
 * solution (comp_lo, comp_hi, comp_fail; compensation_reach checks arm 1
 * cannot get there). TS_ERR_PARAM when not even the design node solves. */
static ts_rc compensation_table(vm *v, double *q, double share, ts_err *err)
{
    const double h = 1e-6, keep = q[QA0];
    double L0 = loop_length(v, q);
    v->comp_da = 2 * VM_COMP_RANGE / (VM_COMP_N - 1);
    v->comp_a0 = v->arm0 - VM_COMP_RANGE;
    v->comp_lo = 0;
    v->comp_hi = VM_COMP_N - 1;
    int mid = (VM_COMP_N - 1) / 2;
    for (int dir = -1; dir <= 1; dir += 2) {
        double s = 0;
        v->comp_fail[dir > 0] = NAN;
        for (int n = mid; n >= 0 && n < VM_COMP_N; n += dir) {
            q[QA0] = v->comp_a0 + n * v->comp_da;
            double La = loop_length_at(v, q, 0), Ls = 0;
            double target = L0 + (1 - share) * (La - L0);
            int it;
            for (it = 0; it < 30; it++) {
                double r = loop_length_at(v, q, s) - target;
                Ls = (loop_length_at(v, q, s + h) - loop_length_at(v, q, s - h)) / (2 * h);
                if (!isfinite(r) || !(fabs(Ls) > 1e-6)) break;
                double step = r / Ls;
                s -= step;
                if (fabs(step) < 1e-12) break;
            }
            double Lq = (loop_length_at(v, q, s) - target);
            double dq = 1e-6;
            q[QA0] += dq;
            double La1 = loop_length_at(v, q, s);
            q[QA0] -= 2 * dq;
            double La0 = loop_length_at(v, q, s);
            q[QA0] += dq;
            /* d/dalpha [L(alpha, s) - target(alpha)] = 0, target' = (1 - share) L_alpha(alpha, 0) */
            q[QA0] += dq;
            double T1 = loop_length_at(v, q, 0);
            q[QA0] -= 2 * dq;
            double T0 = loop_length_at(v, q, 0);
            q[QA0] += dq;
            double dtarget = (1 - share) * (T1 - T0) / (2 * dq);
            double slope = -((La1 - La0) / (2 * dq) - dtarget) / Ls;
            if (it == 30 || !isfinite(Lq) || fabs(Lq) > 1e-9 || !isfinite(slope)) {
                double alpha = v->comp_a0 + n * v->comp_da;
                if (n == mid) {
                    q[QA0] = keep;
                    return comp_error(err, alpha, " (the design angle)");
                }
                /* the table ends at the last node that solved */
                if (dir < 0)
                    v->comp_lo = n + 1;
                else
                    v->comp_hi = n - 1;
                v->comp_fail[dir > 0] = alpha;
                break;
            }
            v->comp_s[n] = s;
            v->comp_ds[n] = slope;
        }
    }
    q[QA0] = keep;
    v->comp_on = 1;
    return TS_OK;
}

/* Road arm 1's travel: from the bump stop (/vehicle/bump_stop_angle, taken
 * as the jounce end at every station) to where it hangs free (wheel off the
 * ground, hull level: the bar's preload m0 less k (alpha - alpha0) against
 * the weight of wheel and arm, m g a cos alpha; the track's pull, which only
 * lifts the wheel, left out), widened by VM_COMP_MARGIN. TS_ERR_PARAM when
 * the compensating idler's table (compensation_table) stopped inside it
 * (a travel wider than the table's +-VM_COMP_RANGE, which no preset comes
 * near, is held constant beyond it unchecked). Needs the preloads
 * (equilibrium). */
static ts_rc compensation_reach(const vm *v, ts_err *err)
{
    if (!v->comp_on) return TS_OK;
    double mga = GRAVITY * v->arm_len * (v->m_w + 0.5 * v->m_arm);
    /* f(alpha) = m0 - k (alpha - alpha0) + mga cos alpha is >= 0 at lo and
     * <= 0 at hi: bisection to the free-hanging angle */
    double lo = v->arm0 + (v->m0[0] - mga) / v->k_bar, hi = v->arm0 + (v->m0[0] + mga) / v->k_bar;
    for (int it = 0; it < 60; it++) {
        double a = 0.5 * (lo + hi);
        if (v->m0[0] - v->k_bar * (a - v->arm0) + mga * cos(a) > 0)
            lo = a;
        else
            hi = a;
    }
    double reach[2] = {v->bs_angle - VM_COMP_MARGIN, 0.5 * (lo + hi) + VM_COMP_MARGIN};
    for (int d = 0; d < 2; d++) {
        double a = v->comp_fail[d];
        if (isnan(a) || (d == 0 ? a < reach[0] : a > reach[1])) continue;
        char where[160];
        snprintf(where, sizeof where,
                 ", inside arm 1's travel %.3f .. %.3f rad (bump stop to hanging free, "
                 "+-%.2f rad)",
                 reach[0], reach[1], VM_COMP_MARGIN);
        return comp_error(err, a, where);
    }
    return TS_OK;
}

/* Smallest free length of a track element in the design layout [m]: a
 * numerical floor (1 mm, far below any real span or wheel gap), not physics;
 * the tangent's direction is undefined as the free length goes to zero. */
#define LAYOUT_MIN_GAP 1e-3

/* Config field that places body b (for layout errors). */
static const char *layout_pointer(int b)
{
    switch (b) {
    case VM_SPROCKET:
        return "/vehicle/sprocket_x";
    case VM_REAR_ROLLER:
        return "/vehicle/rear_roller_x";
    case VM_FRONT_ROLLER:
        return "/vehicle/front_roller_x";
    case VM_IDLER:
        return "/vehicle/idler_x";
    default:
        return "/vehicle/road_wheel_x";
    }
}

vm *vm_make(const ts_config *cfg, ts_err *err)
{
    const ts_vehicle_config *vc = &cfg->vehicle;
    const ts_track_config *tc = &cfg->track;
    if (vc->road_wheel_n != VM_NRW) {
        ts_err_set(err, TS_ERR_PARAM, "/vehicle/road_wheel_x",
                   "/vehicle/road_wheel_x: the pitch-plane model needs %d road wheels, got %d",
                   VM_NRW, vc->road_wheel_n);
        return NULL;
    }
    if (vc->anchor_station > VM_NRW) {
        ts_err_set(err, TS_ERR_RANGE, "/vehicle/anchor_station",
                   "/vehicle/anchor_station: must be 1..%d", VM_NRW);
        return NULL;
    }
    if (ts_vehicle_layout_check(vc, err) != TS_OK ||
        check_stations(vc->damper_station, vc->damper_station_n, "/vehicle/damper_station", err) !=
            TS_OK ||
        check_stations(vc->bump_stop_station, vc->bump_stop_station_n, "/vehicle/bump_stop_station",
                       err) != TS_OK)
        return NULL;
    vm *v = calloc(1, sizeof *v);
    if (!v) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    v->cfg = *cfg;
    v->fidelity = tc->fidelity;
    v->terrain = ts_terrain_make(&cfg->terrain, err);
    if (!v->terrain) goto fail;
    v->dscale = vc->damping_scale;
    v->no_compression = cfg->track.no_compression;
    /* masses per side: sprocket, idler and rollers ride in the hull body */
    v->m_w = vc->road_wheel_mass;
    v->m_arm = vc->road_arm_mass;
    v->arm_len = vc->road_arm_length;
    v->arm0 = vc->road_arm_angle;
    /* > 0: ts_vehicle_layout_check */
    v->i_arm_cg = vc->road_arm_inertia - v->m_arm * 0.25 * v->arm_len * v->arm_len;
    v->k_bar = vc->torsion_bar_rate;
    for (int i = 0; i < VM_NRW; i++) {
        v->c_damp[i] =
            is_station(vc->damper_station, vc->damper_station_n, i + 1) ? vc->damper_rate : 0;
        v->bump[i] = is_station(vc->bump_stop_station, vc->bump_stop_station_n, i + 1);
    }
    v->bs_angle = vc->bump_stop_angle;
    v->k_bs = vc->bump_stop_rate;
    v->rr0 = vc->rolling_resistance;
    v->rr1 = vc->rolling_resistance_speed;
    v->rr_v0 = vc->rolling_resistance_smoothing;
    v->drag_side = 0.25 * vc->air_density * vc->cda;
    v->ea = tc->ea;
    v->p0 = tc->tension;
    v->tau_d = vc->track_damping_time;
    v->kf = vc->foundation_stiffness;
    v->kf3 = vc->foundation_cubic;
    v->cf = vc->foundation_damping;
    v->ka = vc->anchor_stiffness;
    v->ca = vc->anchor_damping;
    v->anchor = vc->anchor_station - 1;
    v->link_dir[0] = cos(vc->idler_link_angle);
    v->link_dir[1] = sin(vc->idler_link_angle);
    v->wheel_ground = vc->road_wheel_radius + vc->track_thickness;
    /* layout (hull frame, relative to the CG) */
    double bx[VM_NB], bz[VM_NB];
    bx[VM_SPROCKET] = vc->sprocket_x, bz[VM_SPROCKET] = vc->sprocket_z;
    bx[VM_REAR_ROLLER] = vc->rear_roller_x, bz[VM_REAR_ROLLER] = vc->rear_roller_z;
    bx[VM_FRONT_ROLLER] = vc->front_roller_x, bz[VM_FRONT_ROLLER] = vc->front_roller_z;
    bx[VM_IDLER] = vc->idler_x, bz[VM_IDLER] = vc->idler_z;
    for (int i = 0; i < VM_NRW; i++)
        bx[VM_RW1 + i] = vc->road_wheel_x[i], bz[VM_RW1 + i] = vc->road_wheel_z;
    for (int b = 0; b < VM_RW1; b++) {
        v->l_body[b][0] = bx[b] - vc->cg_x;
        v->l_body[b][1] = bz[b] - vc->cg_z;
    }
    for (int i = 0; i < VM_NRW; i++) {
        v->l_pivot[i][0] = bx[VM_RW1 + i] + v->arm_len * cos(v->arm0) - vc->cg_x;
        v->l_pivot[i][1] = bz[VM_RW1 + i] + v->arm_len * sin(v->arm0) - vc->cg_z;
    }
    v->rho_b[VM_SPROCKET] = vc->sprocket_radius;
    v->rho_b[VM_REAR_ROLLER] = v->rho_b[VM_FRONT_ROLLER] =
        vc->roller_radius + vc->track_pitch_offset;
    v->rho_b[VM_IDLER] = vc->idler_radius + vc->track_pitch_offset;
    for (int i = 0; i < VM_NRW; i++)
        v->rho_b[VM_RW1 + i] = vc->road_wheel_radius + vc->track_pitch_offset;
    v->j_b[VM_SPROCKET] = vc->sprocket_inertia;
    v->j_b[VM_REAR_ROLLER] = v->j_b[VM_FRONT_ROLLER] = vc->roller_inertia;
    v->j_b[VM_IDLER] = vc->idler_inertia;
    for (int i = 0; i < VM_NRW; i++)
        v->j_b[VM_RW1 + i] = vc->road_wheel_inertia;
    v->x0 = cfg->terrain.start_x + vc->cg_x;
    v->ground_scale = 1.0;
    v->z0 = vc->cg_z;
    /* design configuration: element reference lengths and angles */
    v->nq = VM_NQ_RIGID;
    double q[VM_NQ_RIGID] = {0};
    q[QX] = v->x0;
    q[QZ] = v->z0;
    for (int i = 0; i < VM_NRW; i++)
        q[QA0 + i] = v->arm0;
    kin k;
    kinematics(v, q, NULL, &k);
    v->x_anchor0 = k.c[VM_RW1 + v->anchor][0];
    double loop = 0, psi0[VM_NB], len_el[VM_NB];
    for (int el = 0; el < VM_NB; el++) {
        elem e;
        tangent(v, &k, el, &e); /* v->u0 still zero: e.dpsi meaningless here */
        /* every track element needs a free length: tangent() gives NaN for
         * coincident or nested bodies (e.g. two road wheels at one x) */
        if (!(e.ell > LAYOUT_MIN_GAP)) {
            int a = el, b = (el + 1) % VM_NB;
            ts_err_set(err, TS_ERR_PARAM, layout_pointer(b),
                       "%s: the %s and %s centres are %.4g m apart; the track between them "
                       "needs more than the difference of their radii (%.4g m) plus a free length",
                       layout_pointer(b), vm_body_names[a], vm_body_names[b],
                       hypot(k.c[b][0] - k.c[a][0], k.c[b][1] - k.c[a][1]),
                       fabs(v->rho_b[a] - v->rho_b[b]));
            goto fail;
        }
        v->ell0[el] = e.ell;
        v->u0[el][0] = e.u[0];
        v->u0[el][1] = e.u[1];
        psi0[el] = atan2(e.u[1], e.u[0]);
    }
    for (int el = 0; el < VM_NB; el++) {
        int a = el, b = (el + 1) % VM_NB, prev = (el + VM_NB - 1) % VM_NB, next = (el + 1) % VM_NB;
        /* wrap on a: from the entry of element prev to the exit of el (clockwise) */
        double wa = fmod(psi0[prev] - psi0[el] + 4 * PI, 2 * PI);
        double wb = fmod(psi0[el] - psi0[next] + 4 * PI, 2 * PI);
        if (wa > 1.9 * PI) wa = 0;
        if (wb > 1.9 * PI) wb = 0;
        len_el[el] = v->ell0[el] + 0.5 * (wa * v->rho_b[a] + wb * v->rho_b[b]);
        v->k_el[el] = v->ea / len_el[el];
        loop += v->ell0[el] + wa * v->rho_b[a];
    }
    for (int el = 0; el < VM_NB; el++) {
        v->c_loop += len_el[el] / v->ea;
        if (el >= VM_RW1 + v->anchor) v->c_tail += len_el[el] / v->ea;
    }
    double m_track = tc->mass_per_length * loop; /* one side */
    double m_body = 0.5 * vc->mass - m_track - VM_NRW * (v->m_w + v->m_arm);
    if (m_body <= 0) {
        ts_err_set(err, TS_ERR_PARAM, "/vehicle/mass",
                   "/vehicle/mass: %.0f kg leaves no hull mass after track and running gear",
                   vc->mass);
        goto fail;
    }
    v->m_hull = m_body;
    v->i_hull = 0.5 * vc->hull_pitch_inertia;
    /* fidelity extras on the upper spans (elements 0, 1, 2) */
    double rho = tc->mass_per_length;
    if (v->fidelity == TS_TRACK_LUMPED) {
        double m0 = rho * v->ell0[0], m1 = rho * v->ell0[1], m2 = rho * v->ell0[2];
        double mr = m0 + 0.5 * m1, mf = 0.5 * m1 + m2;
        v->pm_m[0] = mr;
        memcpy(v->pm_l[0], v->l_body[VM_REAR_ROLLER], sizeof v->pm_l[0]);
        v->pm_m[1] = mf;
        memcpy(v->pm_l[1], v->l_body[VM_FRONT_ROLLER], sizeof v->pm_l[1]);
        v->npm = 2;
        v->j_b[VM_REAR_ROLLER] += mr * v->rho_b[VM_REAR_ROLLER] * v->rho_b[VM_REAR_ROLLER];
        v->j_b[VM_FRONT_ROLLER] += mf * v->rho_b[VM_FRONT_ROLLER] * v->rho_b[VM_FRONT_ROLLER];
    } else if (v->fidelity == TS_TRACK_QUASI_STATIC) {
        for (int el = 0; el < 3; el++) {
            int a = el, b = el + 1;
            double m = rho * v->ell0[el], L = v->ell0[el];
            v->mqs[a][a] += m / 3 * v->rho_b[a] * v->rho_b[a];
            v->mqs[b][b] += m / 3 * v->rho_b[b] * v->rho_b[b];
            v->mqs[a][b] += m / 6 * v->rho_b[a] * v->rho_b[b];
            v->mqs[b][a] += m / 6 * v->rho_b[a] * v->rho_b[b];
            /* rigid motion with the hull: mass at the middle of the tangent line,
             * (p_a + p_b) / 2 = (c_a + c_b) / 2 + (rho_a + rho_b) / 2 n, as the
             * span elements' frame weight; rho L^3/12 about it */
            elem e;
            tangent(v, &k, el, &e);
            double hr = 0.5 * (v->rho_b[a] + v->rho_b[b]);
            double mid[2] = {0.5 * (k.c[a][0] + k.c[b][0]) + hr * e.n[0] - q[QX],
                             0.5 * (k.c[a][1] + k.c[b][1]) + hr * e.n[1] - q[QZ]};
            v->pm_m[v->npm] = m;
            memcpy(v->pm_l[v->npm], mid, sizeof mid);
            v->npm++;
            v->i_extra += m * L * L / 12;
        }
    }
    if (vc->idler_compensation > 0 &&
        compensation_table(v, q, vc->idler_compensation, err) != TS_OK)
        goto fail;
    if (build_spans(v, err) != TS_OK) goto fail;
    /* the ground run is held by the no-slip anchor, which transmits any
     * force, wheels loaded or not: a 200 kN*m drive launched the hull at 2 g
     * and flipped it while the anchor kept pushing with every wheel in the air */
    if (ts_drive_check_traction(&cfg->drive, vc->sprocket_radius, vm_supported_weight(v),
                                vc->traction_limit, err) != TS_OK)
        goto fail;
    v->nq = VM_NQ_RIGID + v->nmodal;
    v->ny = 2 * v->nq;
    v->y_eq = calloc((size_t)v->ny, sizeof(double));
    v->rate = calloc((size_t)v->nq, sizeof(double));
    if (!v->y_eq || !v->rate) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        goto fail;
    }
    if (mass_structure(v, err) != TS_OK) goto fail;
    if (equilibrium(v, err) != TS_OK) goto fail;
    if (compensation_reach(v, err) != TS_OK) goto fail;
    return v;
fail:
    vm_free(v);
    return NULL;
}

/* ---- evaluation ------------------------------------------------------------ */

/* ydot = [q_d, M^-1 Q] from the M (in w->P) and w->Q that forces() left. */
static int first_order(const vm *v, vm_work *w, const double *y, double *ydot)
{
    int nq = v->nq;
    w->qf_ok = 0;
    memcpy(ydot, y + nq, (size_t)nq * sizeof(double));
    memcpy(ydot + nq, w->Q, (size_t)nq * sizeof(double));
    return chol_solve(v, w, ydot + nq, nq);
}

/* The right-hand side with the mass matrix's factor cache: M depends on the
 * VM_NQ_MASS coordinates alone (and the extra sprocket inertia), so when they
 * are bit for bit those of the factor left by the previous call (a
 * difference-quotient Jacobian's columns of the spins, span modes and every
 * velocity), M is neither assembled nor factored again, nor is forces()'s
 * geometry (w->geo) evaluated; the result is the same to the bit. drive_on:
 * the prescribed /drive (vm_rhs); otherwise the caller's sprocket torque and
 * inertia (vm_rhs_torque). */
static int rhs_cached(const vm *v, vm_work *w, double t, const double *y, int drive_on,
                      double sprocket_torque, double sprocket_inertia, double *ydot,
                      vm_diag *diag)
{
    int nq = v->nq;
    size_t qsz = (size_t)nq * sizeof(double), msz = VM_NQ_MASS * sizeof(double);
    int hit = w->qf_ok && memcmp(w->qf, y, msz) == 0 && w->qf[VM_NQ_MASS] == sprocket_inertia;
    /* M is assembled straight into w->P, where it is factored in place */
    double *M = hit ? NULL : w->P;
    if (!hit) geom_eval(v, y, v->dynamic, w->geo);
    forces(v, w, w->geo, t, y, y + nq, M, w->Q, drive_on, diag);
    if (!drive_on) {
        /* the caller's torque on the sprocket spin, its reaction on the hull
         * (as the drive in forces) */
        w->Q[QS0 + VM_SPROCKET] += sprocket_torque;
        w->Q[QT] -= sprocket_torque;
        if (diag) {
            diag->drive_torque = sprocket_torque;
            diag->tension_quasi_static =
                quasi_static_tension(v, diag->loop_stretch, sprocket_torque);
        }
    }
    if (hit) {
        memcpy(ydot, y + nq, qsz);
        memcpy(ydot + nq, w->Q, qsz);
        chol_resolve(w, ydot + nq, nq);
        return 0;
    }
    if (!drive_on) {
        /* hull-mounted inertia turning with the sprocket: kinetic energy
         * J/2 (Phi_s' - theta')^2 */
        int is = QS0 + VM_SPROCKET;
        M[is * nq + is] += sprocket_inertia;
        M[QT * nq + QT] += sprocket_inertia;
        M[is * nq + QT] -= sprocket_inertia; /* lower triangle, as forces() */
    }
    int rc = first_order(v, w, y, ydot);
    if (rc == 0) {
        memcpy(w->qf, y, msz);
        w->qf[VM_NQ_MASS] = sprocket_inertia;
        w->qf_ok = 1;
    }
    return rc;
}

int vm_rhs(const vm *v, vm_work *w, double t, const double *y, double *ydot, vm_diag *diag)
{
    return rhs_cached(v, w, t, y, 1, 0.0, 0.0, ydot, diag);
}

int vm_rhs_torque(const vm *v, vm_work *w, double t, const double *y, double sprocket_torque,
                  double sprocket_inertia, double *ydot, vm_diag *diag)
{
    return rhs_cached(v, w, t, y, 0, sprocket_torque, sprocket_inertia, ydot, diag);
}

double vm_energy(const vm *v, vm_work *w, const double *y)
{
    int nq = v->nq;
    const double *q = y, *qd = y + nq;
    forces_at(v, w, 0.0, q, qd, w->M, w->Q, 0, NULL);
    mass_mirror(w->M, nq);
    double ke = 0;
    for (int i = 0; i < nq; i++)
        for (int j = 0; j < nq; j++)
            ke += 0.5 * qd[i] * w->M[i * nq + j] * qd[j];
    kin k;
    kinematics(v, q, qd, &k);
    double pe = v->m_hull * GRAVITY * q[QZ];
    for (int p = 0; p < v->npm; p++) {
        double wv[2];
        rot(&k, v->pm_l[p], wv);
        pe += v->pm_m[p] * GRAVITY * (q[QZ] + wv[1]);
    }
    for (int i = 0; i < VM_NRW; i++) {
        int b = VM_RW1 + i;
        pe += v->m_w * GRAVITY * k.c[b][1];
        pe += v->m_arm * GRAVITY * (q[QZ] + k.wp[i][1] + 0.5 * k.e[i][1]);
        double da = q[QA0 + i] - v->arm0;
        pe += -v->m0[i] * da + 0.5 * v->k_bar * da * da;
        if (v->bump[i] && q[QA0 + i] < v->bs_angle) {
            double pen = v->bs_angle - q[QA0 + i];
            pe += 0.5 * v->k_bs * pen * pen;
        }
        double d = ts_terrain_height(v->terrain, k.c[b][0], NULL) + v->wheel_ground - k.c[b][1];
        if (d > 0) pe += 0.5 * v->kf * d * d + 0.25 * v->kf3 * d * d * d * d;
    }
    {
        int b = VM_RW1 + v->anchor;
        double xi = k.c[b][0] - v->rho_b[b] * q[QS0 + b] - v->x_anchor0;
        pe += 0.5 * v->ka * xi * xi;
    }
    for (int el = 0; el < VM_NB; el++) {
        int a = el, b = (el + 1) % VM_NB;
        elem e;
        tangent(v, &k, el, &e);
        const span_el *se = v->span_of[el];
        double u0 = v->rho_b[a] * (q[QS0 + a] + e.dpsi);
        double u1 = v->rho_b[b] * (q[QS0 + b] + e.dpsi) + e.ell - v->ell0[el];
        if (!se) {
            double s = u1 - u0, kel = v->k_el[el];
            if (s < -v->p0 / kel) s = -v->p0 / kel; /* slack: T = 0, energy flat */
            pe += v->p0 * s + 0.5 * kel * s * s;
            continue;
        }
        const ts_span *sp = se->sp;
        int n = sp->n;
        double x[2 + 2 * TS_SPAN_MAX_MODES];
        x[0] = 0;
        x[1] = u1 - u0;
        for (int m = 0; m < se->nm; m++)
            x[2 + m] = q[se->q0 + m];
        double xk = 0;
        for (int r = 0; r < n; r++)
            for (int c = 0; c < n; c++)
                xk += 0.5 * x[r] * sp->K[r * n + c] * x[c];
        double gx = -GRAVITY * e.u[1], gy = -GRAVITY * e.n[1];
        double ax, ay;
        span_modal_sums(se, x, &ax, &ay);
        double m = se->rho * se->len;
        if (v->no_compression) xk -= ts_span_slack_energy(sp, x);
        pe += v->p0 * x[1] + xk - (gy - sp->p.g_y) * ay;
        /* the frame's weight from tangent point 0 (span_element's frame gravity) */
        pe += m * GRAVITY * (k.c[a][1] + v->rho_b[a] * e.n[1]) - 0.5 * m * se->len * gx - gx * ax;
    }
    return ke + pe;
}

/* ---- geometry snapshot ------------------------------------------------------ */

static void geom_point(ts_geom *g, double x, double z, double dx, double dz, double t)
{
    if (g->ntrack >= TS_GEOM_MAX_TRACK) return;
    int i = g->ntrack++;
    g->track_x[i] = x, g->track_z[i] = z;
    g->track_dx[i] = dx, g->track_dz[i] = dz;
    g->track_tension[i] = t;
}

void vm_describe_state(const vm *v, const double *y, char *out, size_t n)
{
    kin k;
    kinematics(v, y, NULL, &k);
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < VM_NRW; i++) /* each wheel's footprint, centre +- one radius */
        for (int j = -2; j <= 2; j++) {
            double x = k.c[VM_RW1 + i][0] + 0.5 * j * v->rho_b[VM_RW1 + i];
            double h = ts_terrain_height(v->terrain, x, NULL) * v->ground_scale;
            lo = fmin(lo, h), hi = fmax(hi, h);
        }
    snprintf(out, n,
             "hull CG at x = %.3f m, z = %.3f m, pitch %.3f rad; ground within a wheel radius of "
             "the road wheels %.3f .. %.3f m high (/terrain)",
             y[QX], y[QZ], y[QT], lo, hi);
}

void vm_err_add_state(const vm *v, const double *y, ts_err *err)
{
    if (!err) return;
    size_t len = strlen(err->msg);
    if (len + 4 >= sizeof err->msg) return;
    memcpy(err->msg + len, "; ", 3);
    vm_describe_state(v, y, err->msg + len + 2, sizeof err->msg - len - 2);
}

ts_rc vm_rhs_failed(const vm *v, double t, const double *y, ts_err *err)
{
    ts_err_set(err, TS_ERR_DIVERGED, NULL,
               "the vehicle's equations cannot be evaluated at t = %.6f s (its mass matrix is "
               "not positive definite)",
               t);
    vm_err_add_state(v, y, err);
    return TS_ERR_DIVERGED;
}

void vm_geometry(const vm *v, vm_work *w, double t, const double *y, ts_geom *g)
{
    const ts_vehicle_config *vc = &v->cfg.vehicle;
    int nq = v->nq;
    const double *q = y, *qd = y + nq;
    memset(g, 0, sizeof *g);
    vm_diag dg;
    memset(&dg, 0, sizeof dg);
    forces_at(v, w, t, q, qd, NULL, w->Q, 1, &dg); /* the diagnostics only */
    kin k;
    kinematics(v, q, qd, &k);
    g->t = t;
    g->hull_x = q[QX];
    g->hull_z = q[QZ];
    g->hull_pitch = q[QT];
    g->hull_length = (vc->idler_x + vc->idler_radius) - (vc->sprocket_x - vc->sprocket_radius);
    g->hull_height = 2.0 * vc->cg_z; /* framing only: CG taken at mid-height */
    g->speed = qd[QX];
    g->gear = 0;
    static const int role[VM_NB] = {TS_WHEEL_SPROCKET, TS_WHEEL_ROLLER, TS_WHEEL_ROLLER,
                                    TS_WHEEL_IDLER,    TS_WHEEL_ROAD,   TS_WHEEL_ROAD,
                                    TS_WHEEL_ROAD,     TS_WHEEL_ROAD,   TS_WHEEL_ROAD,
                                    TS_WHEEL_ROAD,     TS_WHEEL_ROAD};
    for (int b = 0; b < VM_NB && g->nwheel < TS_GEOM_MAX_WHEELS; b++) {
        ts_geom_wheel *gw = &g->wheel[g->nwheel++];
        gw->role = role[b];
        gw->x = k.c[b][0], gw->z = k.c[b][1];
        gw->radius = b == VM_SPROCKET ? v->rho_b[b] : v->rho_b[b] - vc->track_pitch_offset;
        gw->angle = q[QS0 + b];
        gw->pivot_x = gw->x, gw->pivot_z = gw->z;
        if (b >= VM_RW1) {
            int i = b - VM_RW1;
            gw->pivot_x = q[QX] + k.wp[i][0];
            gw->pivot_z = q[QZ] + k.wp[i][1];
        }
    }
    g->track_static_tension = v->t_static;
    g->track_pitch = v->cfg.track.pitch;
    g->track_pitch_offset = vc->track_pitch_offset;
    elem e[VM_NB];
    for (int el = 0; el < VM_NB; el++)
        tangent(v, &k, el, &e[el]);
    for (int el = 0; el < VM_NB; el++) {
        int a = el, b = (el + 1) % VM_NB, next = (el + 1) % VM_NB;
        const span_el *se = v->span_of[el];
        double pa[2] = {k.c[a][0] + v->rho_b[a] * e[el].n[0], k.c[a][1] + v->rho_b[a] * e[el].n[1]};
        int free_span = el <= 3 || el == 10;
        int npt = free_span ? 12 : 2;
        double kappa = v->cfg.track.mass_per_length * (-GRAVITY * e[el].n[1]) / v->p0;
        double x[2 + 2 * TS_SPAN_MAX_MODES] = {0};
        if (se) {
            double dpsi = e[el].dpsi;
            x[1] = v->rho_b[b] * (q[QS0 + b] + dpsi) + e[el].ell - v->ell0[el] -
                   v->rho_b[a] * (q[QS0 + a] + dpsi);
            for (int m = 0; m < se->nm; m++)
                x[2 + m] = q[se->q0 + m];
        }
        for (int i = 0; i < npt; i++) {
            double s = e[el].ell * i / npt;
            double sag = free_span ? 0.5 * kappa * s * (e[el].ell - s) : 0;
            double U = 0, V = 0, tau = 0, tt = dg.tension[el];
            if (se) {
                double sl = s * se->len / e[el].ell;
                sag = ts_span_sag(se->sp, sl);
                ts_span_eval(se->sp, x, sl, &U, &V, &tau);
                tt = v->p0 + tau;
            }
            geom_point(g, pa[0] + s * e[el].u[0] + sag * e[el].n[0],
                       pa[1] + s * e[el].u[1] + sag * e[el].n[1], V * e[el].n[0], V * e[el].n[1],
                       tt);
        }
        /* wrap on b, clockwise from this element's normal to the next one's */
        double a0 = atan2(e[el].n[1], e[el].n[0]), a1 = atan2(e[next].n[1], e[next].n[0]);
        double sweep = fmod(a0 - a1 + 4 * PI, 2 * PI);
        if (sweep > 1.9 * PI) sweep = 0;
        int na = (int)(sweep / (PI / 12)) + 1;
        for (int i = 0; i < na; i++) {
            double ang = a0 - sweep * i / na;
            geom_point(g, k.c[b][0] + v->rho_b[b] * cos(ang), k.c[b][1] + v->rho_b[b] * sin(ang), 0,
                       0, dg.tension[el]);
        }
    }
    int nt = 200;
    double x0 = q[QX] - 10.0, x1 = q[QX] + 10.0;
    for (int i = 0; i < nt && i < TS_GEOM_MAX_TERRAIN; i++) {
        double x = x0 + (x1 - x0) * i / (nt - 1);
        g->terrain_x[i] = x;
        g->terrain_z[i] = ts_terrain_height(v->terrain, x, NULL);
        g->nterrain = i + 1;
    }
}

void vm_forces(const vm *v, vm_work *w, double t, const double *y, int drive_on, double *Q)
{
    forces_at(v, w, t, y, y + v->nq, w->M, w->Q, drive_on, NULL);
    memcpy(Q, w->Q, (size_t)v->nq * sizeof(double));
}

void vm_mass(const vm *v, vm_work *w, const double *y, double *M)
{
    forces_at(v, w, 0.0, y, y + v->nq, w->M, w->Q, 0, NULL);
    mass_mirror(w->M, v->nq);
    memcpy(M, w->M, (size_t)v->nq * (size_t)v->nq * sizeof(double));
}
