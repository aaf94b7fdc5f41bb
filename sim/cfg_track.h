/*
 * cfg_track.h — the "track" section of a run config: track material data and
 * the fidelity of the track model (paper Section II.C.2). Extended by the
 * track module as it grows.
 */
#ifndef TS_CFG_TRACK_H
#define TS_CFG_TRACK_H

typedef enum ts_track_fidelity {
    TS_TRACK_STATIC,       /* massless spring-damper chain (21 DOF in the paper) */
    TS_TRACK_LUMPED,       /* upper-span mass lumped into the support rollers */
    TS_TRACK_QUASI_STATIC, /* Guyan (static condensation) into the rollers */
    TS_TRACK_LONGITUDINAL, /* n_long longitudinal modes per span (26 DOF with 1) */
    TS_TRACK_TRANSVERSE,   /* n_trans transverse modes per span, quasi-static stretch */
    TS_TRACK_COUPLED,      /* n_long + n_trans per span (31 DOF with 1 + 1); n_long = 0:
                              uniform-tension stretch, as TS_TRACK_TRANSVERSE */
    TS_NTRACK_FIDELITY
} ts_track_fidelity;
extern const char *const ts_track_fidelity_names[];

#define TS_TRACK_MAX_SPANS 8 /* single-span analysis overrides (/track/span_length) */

typedef struct ts_track_config {
    int fidelity;             /* ts_track_fidelity */
    int n_long;               /* longitudinal modes per free span */
    int n_trans;              /* transverse modes per free span */
    double pitch;             /* track pitch [m] */
    double mass_per_length;   /* rho, mass per unit length [kg/m] */
    double ea;                /* axial stiffness EA [N] */
    double tension;           /* static track tension P0 [N] */
    double damping_ratio;     /* modal damping ratio of span modes [1] */
    int translation_terms;    /* keep the track-speed terms of Eqs. 1-2 [bool] */
    int no_compression;       /* modal spans go slack instead of pushing [bool] */
    double modes_speed;       /* track speed for eigenanalysis with translation_terms [m/s] */
    int modes_reported;       /* circuit modes reported by `tanksim modes` */
    int span_n;               /* single spans to analyse (0: the layout's five spans) */
    double span_length[TS_TRACK_MAX_SPANS];      /* their chord lengths [m] */
    int span_inclination_n;                      /* must equal span_n */
    double span_inclination[TS_TRACK_MAX_SPANS]; /* chord angle above horizontal [rad] */
} ts_track_config;

#endif
