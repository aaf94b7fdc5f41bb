/*
 * analyses.h — the daemon's analyses: computations that answer one question
 * about a configuration instead of advancing a session. The engine's
 * full-load map on a dynamometer (paper Section III.B.3, Fig. 18; the same
 * document as `tanksim engine-map`, api/analysis_json.h) and the IVS speed
 * controller's Ziegler–Nichols tuning with an optional gain schedule (Eqs.
 * 11-12, Figs. 26-27; `tanksim tune`).
 *
 * They take seconds to minutes (a crank-angle sweep ~3 s; a tune at the
 * crank-angle fidelity ~5 s per schedule point), so each runs as an
 * operation (operations.h): POST answers 202 with it, GET
 * /v1/operations/{id} shows parts done and, at the end, the document as its
 * response; :cancel stops it after the part in progress. An analysis holds a
 * worker thread from start to end, so at most max(1, threads - 1) run at
 * once: session runs always keep a worker when there are two. Results live
 * in the operation (memory), as run operations do.
 */
#ifndef TSD_ANALYSES_H
#define TSD_ANALYSES_H

#include <jansson.h>

#include "../api/analysis_json.h"
#include "../sim/config.h"
#include "../sim/errors.h"
#include "server.h"

typedef enum tsd_analysis_kind { TSD_ANALYSIS_ENGINE_MAP, TSD_ANALYSIS_TUNE } tsd_analysis_kind;

typedef struct tsd_analysis_req {
    tsd_analysis_kind kind;
    ts_config cfg;                     /* the loaded configuration */
    char var[8];                       /* tune: "mass" or "grade" when n > 0 */
    double x[TSA_TUNE_SCHEDULE_MAX];   /* tune: the schedule's values (kg or rad) */
    int n;                             /* tune: schedule points (0: none) */
} tsd_analysis_req;

/* Queue the analysis; *opdoc (new reference) is its operation document.
 * TS_ERR_LIMIT when the concurrent analyses are at their cap,
 * TSD_ERR_SHUTDOWN once shutdown began, TS_ERR_NOMEM. */
ts_rc tsd_analysis_start(tsd_server *srv, const tsd_analysis_req *req, json_t **opdoc,
                         ts_err *err);

#endif
