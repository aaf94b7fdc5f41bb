/*
 * pool.h — the simulation worker pool: N threads taking jobs from one queue.
 *
 * Physics never runs on an HTTP thread: handlers submit a job and either
 * suspend their connection until it completes (step) or answer 202 at once
 * (run). A job may carry a "not before" time (monotonic seconds); a worker
 * takes the oldest job that is due and sleeps on a condition variable until
 * one is — no polling. Long runs re-submit themselves after each slice, so
 * sessions share the workers fairly and a short step is never stuck behind a
 * long run (see session.c).
 *
 * Shutdown (tsd_pool_stop): no new jobs are accepted, every queued job is
 * still run (jobs see tsd_server.stopping, set before, and finish quickly),
 * then the threads are joined. The pool itself stays valid until
 * tsd_pool_free — HTTP threads keep serving during shutdown and may still
 * call tsd_pool_submit (refused, -1) or tsd_pool_pending (0), so it is freed
 * only after libmicrohttpd has stopped. Jobs own their argument.
 */
#ifndef TSD_POOL_H
#define TSD_POOL_H

#include <stddef.h>

#include "../sim/errors.h"

typedef struct tsd_pool tsd_pool;
typedef void (*tsd_job_fn)(void *arg);

/* Start nthreads workers; NULL on failure. */
tsd_pool *tsd_pool_start(int nthreads);

/* Queue fn(arg) to run at or after monotonic time not_before (0 = now).
 * 0 on success, -1 when the pool is stopping (the job is not run). */
TS_MUST_CHECK int tsd_pool_submit(tsd_pool *p, tsd_job_fn fn, void *arg, double not_before);

/* Jobs queued or running (for /metrics). */
int tsd_pool_pending(tsd_pool *p);

/* Drain (run every queued job, ignoring not_before) and join; later submits
 * are refused. NULL is a no-op; calling it twice is harmless. */
void tsd_pool_stop(tsd_pool *p);

/* Free a pool (stopping it first if needed). NULL is a no-op. */
void tsd_pool_free(tsd_pool *p);

/* Monotonic clock [s]. */
double tsd_now(void);
/* Wall-clock time [s since 1970-01-01 UTC]: the stored "created" times. */
double tsd_unix_now(void);

/* Fresh random id: prefix + 16 hex digits (getrandom; the clock if that
 * fails) into out[n]. Sessions ("s...") and operations ("op...") use it. */
void tsd_random_id(char *out, size_t n, const char *prefix);

#endif
