/*
 * metrics.h — counters behind GET /metrics (Prometheus text format 0.0.4).
 * Lock-free C11 atomics, updated by HTTP threads and workers; gauges that
 * describe current state (sessions by status, queued jobs) are computed when
 * the page is rendered.
 */
#ifndef TSD_METRICS_H
#define TSD_METRICS_H

#include <stdatomic.h>

#define TSD_NRUN_RESULTS 5 /* done, paused, cancelled, failed, interrupted */

typedef struct tsd_metrics {
    atomic_long requests[6][100]; /* by status class (1xx..5xx) and last two digits */
    atomic_long runs_started;
    atomic_long runs_ended[TSD_NRUN_RESULTS];
    atomic_long steps;
    atomic_long sessions_created;
    atomic_long samples_stored;
    atomic_llong sim_microseconds;  /* simulated time advanced [us] */
    atomic_llong wall_microseconds; /* wall time spent advancing [us] */
    atomic_long replies_busy;       /* answers refused 503 /problems/busy (tsd_reply_busy) */
    atomic_long store_writes_refused; /* best-effort status and removal writes the store
                                         refused (session.c store_status, store_delete) */
    atomic_long answers_cut;          /* answers whose client closed before they were sent
                                         (libmicrohttpd's send errors, server.c mhd_log) */
} tsd_metrics;

extern const char *const tsd_run_result_names[TSD_NRUN_RESULTS];

void tsd_metrics_request(tsd_metrics *m, unsigned status);

#endif
