/*
 * pool.c — worker threads over one job list (pool.h).
 *
 * The list is kept in submission order; a worker scans it for the first job
 * whose not_before has passed (O(jobs), fine for the hundreds a daemon has)
 * and otherwise waits until the earliest due time or a new submission.
 * Also the two small helpers the daemon's modules share: the monotonic clock
 * (tsd_now) and random ids of sessions and operations (tsd_random_id).
 */
#define _GNU_SOURCE
#include "pool.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>

typedef struct job {
    tsd_job_fn fn;
    void *arg;
    double not_before;
    struct job *next;
} job;

struct tsd_pool {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    job *head, *tail;
    int stopping;
    int joined;  /* tsd_pool_stop has run (it joins once) */
    int njobs;   /* queued */
    int running; /* being run */
    int nthreads;
    pthread_t *threads;
};

double tsd_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double tsd_unix_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void tsd_random_id(char *out, size_t n, const char *prefix)
{
    unsigned char rnd[8] = {0};
    if (getrandom(rnd, sizeof rnd, 0) != (ssize_t)sizeof rnd) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        double x = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
        memcpy(rnd, &x, sizeof rnd);
    }
    snprintf(out, n, "%s%02x%02x%02x%02x%02x%02x%02x%02x", prefix, rnd[0], rnd[1], rnd[2], rnd[3],
             rnd[4], rnd[5], rnd[6], rnd[7]);
}

/* Take the first due job (all jobs are due while stopping); NULL if none. */
static job *take_due(tsd_pool *p, double now, double *earliest)
{
    job *prev = NULL;
    *earliest = INFINITY;
    for (job *j = p->head; j; prev = j, j = j->next) {
        if (p->stopping || j->not_before <= now) {
            if (prev)
                prev->next = j->next;
            else
                p->head = j->next;
            if (p->tail == j) p->tail = prev;
            p->njobs--;
            return j;
        }
        if (j->not_before < *earliest) *earliest = j->not_before;
    }
    return NULL;
}

static void *worker(void *arg)
{
    tsd_pool *p = arg;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        double earliest;
        job *j = take_due(p, tsd_now(), &earliest);
        if (!j) {
            if (p->stopping && !p->head) break;
            if (isfinite(earliest)) {
                struct timespec ts;
                double wake = earliest;
                ts.tv_sec = (time_t)wake;
                ts.tv_nsec = (long)((wake - (double)ts.tv_sec) * 1e9);
                pthread_cond_timedwait(&p->cv, &p->mu, &ts);
            } else {
                pthread_cond_wait(&p->cv, &p->mu);
            }
            continue;
        }
        p->running++;
        pthread_mutex_unlock(&p->mu);
        j->fn(j->arg);
        free(j);
        pthread_mutex_lock(&p->mu);
        p->running--;
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

tsd_pool *tsd_pool_start(int nthreads)
{
    tsd_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->cv, &ca);
    pthread_condattr_destroy(&ca);
    p->threads = calloc((size_t)nthreads, sizeof *p->threads);
    if (!p->threads) {
        free(p);
        return NULL;
    }
    for (int i = 0; i < nthreads; i++) {
        if (pthread_create(&p->threads[i], NULL, worker, p) != 0) break;
        p->nthreads++;
    }
    if (p->nthreads == 0) {
        free(p->threads);
        free(p);
        return NULL;
    }
    return p;
}

int tsd_pool_submit(tsd_pool *p, tsd_job_fn fn, void *arg, double not_before)
{
    job *j = calloc(1, sizeof *j);
    if (!j) return -1;
    j->fn = fn;
    j->arg = arg;
    j->not_before = not_before;
    pthread_mutex_lock(&p->mu);
    if (p->stopping) {
        pthread_mutex_unlock(&p->mu);
        free(j);
        return -1;
    }
    if (p->tail)
        p->tail->next = j;
    else
        p->head = j;
    p->tail = j;
    p->njobs++;
    pthread_cond_broadcast(&p->cv);
    pthread_mutex_unlock(&p->mu);
    return 0;
}

int tsd_pool_pending(tsd_pool *p)
{
    pthread_mutex_lock(&p->mu);
    int n = p->njobs + p->running;
    pthread_mutex_unlock(&p->mu);
    return n;
}

void tsd_pool_stop(tsd_pool *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    int joined = p->joined;
    p->stopping = 1;
    p->joined = 1;
    pthread_cond_broadcast(&p->cv);
    pthread_mutex_unlock(&p->mu);
    if (joined) return;
    for (int i = 0; i < p->nthreads; i++)
        pthread_join(p->threads[i], NULL);
}

void tsd_pool_free(tsd_pool *p)
{
    if (!p) return;
    tsd_pool_stop(p);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->cv);
    free(p->threads);
    free(p);
}
