/*
 * track_circuit.h — the upper track circuit with the front (1) and rear (7)
 * road wheels fixed to a fixed hull (paper Section II.A, Fig. 5), assembled
 * from span elements (track_span.h), and its eigenanalysis.
 *
 * The circuit, in the direction of travel around the loop (counter-clockwise
 * in x–z: up the front, rearward along the top, down the back):
 *     road wheel 1 -> idler -> front roller -> rear roller -> sprocket -> road wheel 7
 * five free spans between tangent points (the paper's five dynamic spans,
 * Section II.D). Road wheels 1 and 7 are fixed (centre and spin: the ground
 * run anchors the track). Idler, rollers and sprocket turn freely about fixed
 * centres; wheel w's spin phi_w enters as the track feed u_w = r_w phi_w, which
 * is the end coordinate of both neighbouring spans, so a spin couples their
 * longitudinal motion. Its mass is J_w / r_w^2 plus the track wrapped on it
 * (rho r_w alpha_w, alpha_w = wrap angle), which moves with it.
 *
 * DOFs: [u_idler, u_front_roller, u_rear_roller, u_sprocket, span 0 modes,
 * span 1 modes, ...] with each span's (q_L..., q_T...) as in track_span.h.
 *
 * Eigenanalysis: symmetric K phi = w^2 M phi by LAPACKE_dsygv; with
 * gyroscopic terms (translation_terms and c != 0) the first-order form
 * [0 I; -K -G] z = lambda [I 0; 0 M] z by LAPACKE_dggev.
 *
 * Leaves out: wheel-centre motion (hull fixed), the lower run and tensioner,
 * damping (undamped modes).
 *
 * OWNERSHIP: ts_circuit_make/ts_circuit_free; ts_circuit_modes allocates a
 * ts_modes result freed by ts_modes_free (NULL ok for both).
 */
#ifndef TS_TRACK_CIRCUIT_H
#define TS_TRACK_CIRCUIT_H

#include "config.h"
#include "errors.h"
#include "track_span.h"

#define TS_CIRCUIT_NSPANS    5
#define TS_CIRCUIT_NSUPPORTS 6 /* rw1, idler, front roller, rear roller, sprocket, rw7 */

/* Names of the supports and spans (static strings). */
extern const char *const ts_circuit_support_names[TS_CIRCUIT_NSUPPORTS];
extern const char *const ts_circuit_span_names[TS_CIRCUIT_NSPANS];

typedef struct ts_circuit_params {
    ts_span_support support[TS_CIRCUIT_NSUPPORTS]; /* pitch-line circles, loop order */
    double inertia[TS_CIRCUIT_NSUPPORTS];          /* spin inertia [kg m^2] (ends unused: fixed) */
    double rho, ea, tension;                       /* track [kg/m], [N], [N] */
    double gravity;                                /* [m/s^2] */
    double speed;                                  /* track speed around the loop [m/s] */
    int translation_terms;                         /* gyroscopic terms of Eqs. 1–2 */
    int quasi_static_stretch; /* spans with uniform tension (n_long must be 0) */
    int n_long, n_trans;      /* modes per span */
} ts_circuit_params;

typedef struct ts_circuit {
    ts_circuit_params p;
    ts_span_geometry geom[TS_CIRCUIT_NSPANS];
    ts_span *span[TS_CIRCUIT_NSPANS];
    double wrap[TS_CIRCUIT_NSUPPORTS]; /* wrap angle on each support [rad] */
    int ndof;
    int span_dof0[TS_CIRCUIT_NSPANS]; /* global index of each span's first modal coordinate */
    double *M, *K, *G;                /* ndof x ndof, row-major */
    int gyroscopic;                   /* G != 0 */
} ts_circuit;

/* Circuit parameters from a run config: support circles from the /vehicle
 * layout (road wheels 1 and 7 = first and last /vehicle/road_wheel_x; pitch
 * line = rim + /vehicle/track_pitch_offset for road wheels, idler and rollers,
 * /vehicle/sprocket_radius as is), spin inertias from /vehicle (the vehicle
 * model's own: one layout for both), track data from /track,
 * modes per span /track/n_long, /track/n_trans (n_long = 0: quasi-static
 * uniform-tension stretch), track speed /track/modes_speed when
 * /track/translation_terms. TS_ERR_PARAM naming the field on bad input. */
TS_MUST_CHECK ts_rc ts_circuit_params_from_config(const ts_config *cfg, ts_circuit_params *p,
                                                  ts_err *err);

/* Parameters of the i-th single span of /track/span_length (chord angle
 * /track/span_inclination[i] above horizontal; track data and mode counts as
 * above). TS_ERR_PARAM naming /track/span_inclination when the counts differ. */
TS_MUST_CHECK ts_rc ts_span_params_from_config(const ts_config *cfg, int i, ts_span_params *p,
                                               ts_err *err);

ts_circuit *ts_circuit_make(const ts_circuit_params *p, ts_err *err);
void ts_circuit_free(ts_circuit *c);

/* Local coordinates x[sp->n] of span i from a global vector y[ndof]. */
void ts_circuit_span_state(const ts_circuit *c, int i, const double *y, double *x);

/* Result of an eigenanalysis. */
typedef struct ts_modes {
    int n;         /* modes found (ascending frequency) */
    int ndof;      /* length of each shape */
    double *freq;  /* [n] natural frequencies [Hz] */
    double *shape; /* [n * ndof] shapes: mass-normalised (y^T M y = 1) for the symmetric
                      problem; for gyroscopic the real part of the complex shape scaled to
                      max |z| = 1 (not mass-normalised) */
} ts_modes;
void ts_modes_free(ts_modes *m);

/* Generalised eigenproblem of (M, K[, G]) of size n (row-major). G may be NULL.
 * Returns up to nmax modes with positive frequency. NULL on failure
 * (TS_ERR_SOLVER naming the LAPACK routine, TS_ERR_NOMEM). */
ts_modes *ts_eig(int n, const double *M, const double *K, const double *G, int nmax, ts_err *err);

/* Modes of a span with both ends fixed (u0 = u1 = 0). family: 0 all modal
 * coordinates (coupled), 1 longitudinal block only, 2 transverse block only. */
ts_modes *ts_span_modes(const ts_span *sp, int family, int nmax, ts_err *err);

/* Modes of the circuit. */
ts_modes *ts_circuit_modes(const ts_circuit *c, int nmax, ts_err *err);

/* Kinetic-energy shares of one circuit mode (diagonal-mass estimate): per span
 * transverse and longitudinal (the span's sine modes only), and `wheels`: all
 * energy of the end coordinates u_w (wheel spin, wrapped track and the spans'
 * support-shape mass on them), counted as longitudinal. Sums to 1. */
typedef struct ts_mode_character {
    double trans[TS_CIRCUIT_NSPANS];
    double lon[TS_CIRCUIT_NSPANS];
    double wheels;
    int dominant_span; /* span with the largest share */
    int transverse;    /* 1 if transverse energy > longitudinal + wheels */
} ts_mode_character;
void ts_circuit_mode_character(const ts_circuit *c, const double *shape, ts_mode_character *ch);

#endif
