/*
 * metrics.c — request counting and the Prometheus text page (metrics.h).
 * The page itself is built in routes.c's handler from these counters plus
 * gauges read at request time (sessions by status, queued jobs).
 */
#include "metrics.h"

const char *const tsd_run_result_names[TSD_NRUN_RESULTS] = {"done", "paused", "cancelled", "failed",
                                                            "interrupted"};

void tsd_metrics_request(tsd_metrics *m, unsigned status)
{
    if (status < 100 || status > 599) return;
    atomic_fetch_add(&m->requests[status / 100][status % 100], 1);
}
