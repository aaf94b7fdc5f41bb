/*
 * main.c — tanksimd: parse flags, block SIGINT/SIGTERM in every thread, open
 * the database and reload stored sessions (runs that were in progress become
 * "interrupted"), start the worker pool and the HTTP server, wait for a
 * signal with sigwait, shut down cleanly.
 * Blocking the signals before any thread starts means no handler and no
 * global flag are needed: the main thread simply waits for one.
 *
 * Shutdown order: mark stopping (running jobs stop at their next sample and
 * store what they have; their sessions become "interrupted"; from here new
 * work — create, step, run, frames, modes — is answered 503 "shutting down"
 * with Retry-After, and /v1/health answers 503 "stopping"), wake streams,
 * drain and join the pool (deferred step replies are resumed by their jobs;
 * the pool stays allocated, refusing submissions, while HTTP threads run),
 * wake streams again, keep serving reads for --drain seconds (a second
 * signal ends that at once), wait (at most SETTLE_S, or until a further
 * signal) for requests in flight to complete — a step reply resumed by its
 * job is only queued by the next MHD call, and stopping MHD first lost it —
 * stop libmicrohttpd (no
 * connection is left suspended), then free the pool and sessions and close
 * the database.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../api/config_json.h"
#include "../sim/version.h"
#include "analyses.h"
#include "db.h"
#include "frames.h"
#include "operations.h"
#include "pool.h"
#include "server.h"
#include "session.h"
#include "static_files.h"

#define SETTLE_S 5.0 /* [s] at most, for requests in flight to complete at shutdown */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: tanksimd [OPTIONS]\n"
            "Simulation server for the M1 Abrams track/vehicle/powertrain model.\n\n"
            "  --bind ADDR      listen address (default 127.0.0.1)\n"
            "  --port N         TCP port (default 8080)\n"
            "  --data-dir DIR   sessions and results are kept here (default ./var)\n"
            "  --threads N      simulation worker threads (default: number of cores)\n"
            "  --max-body N     largest request body in bytes (default 1048576)\n"
            "  --timeout S      idle connection timeout in seconds (default 60)\n"
            "  --max-connections N  HTTP connections open at once; more wait in the listen\n"
            "                   queue (default 4096; the open-file limit is raised to fit\n"
            "                   2 N + 256, else N is lowered to fit under it, with a message)\n"
            "  --token T        require 'Authorization: Bearer T' (all but /v1/health and the\n"
            "                   dashboard's / and /static/ files); a command line is visible\n"
            "                   to every local user, so prefer:\n"
            "  --token-file F   the token from the first line of file F\n"
            "  (environment)    TANKSIM_TOKEN=T, when neither flag is given\n"
            "  --web-root DIR   dashboard files served at / (default: web_static/ beside the\n"
            "                   build directory of this binary, else ./web_static)\n"
            "  --max-sessions N sessions kept at once (default 1000; more -> 429)\n"
            "  --max-analyses N engine maps and tunings stored at once, running ones\n"
            "                   included (default 1000; more -> 429: DELETE /v1/analyses/ID)\n"
            "  --max-samples N  sample rows per series/FFT response (default 100000)\n"
            "  --max-rows N     sample rows one session may store: a config whose\n"
            "                   run.duration x run.sample_rate needs more gets 400\n"
            "                   (default 1000000, ~0.3 GB for the vehicle runs; 0: none)\n"
            "  --max-step S     longest synchronous step in simulated seconds (default 10)\n"
            "  --drain S        after SIGTERM/SIGINT keep answering S seconds (reads served,\n"
            "                   new work 503 with Retry-After) before closing; a second\n"
            "                   signal closes at once (default 0)\n"
            "  --max-run-wall S wall-clock budget of one run operation: past it the run pauses\n"
            "                   with an error naming this flag (default 0: none)\n"
            "  --client-files yes|no  let run configs name files on this machine for the daemon\n"
            "                   to read (/terrain/profile_csv, a course outside the shipped\n"
            "                   ones); default no: such configs get 400 naming the field\n"
            "  --routes         print the routing table and exit\n"
            "  --help           this text\n"
            "  --version        print the version\n");
}

/* Make room for --max-connections under the open-file limit: two
 * descriptors per connection (its socket, and a dashboard file it may be
 * sending: static_files.c answers from the file's descriptor) plus FD_RESERVE
 * for the store, the snapshots and the renderer. Raise the soft limit (up to
 * the hard one) if it is too low, else lower max_connections to fit, and say
 * so. With the limit too tight the connections took every descriptor: the
 * daemon stopped answering, and the store could not open its files. 0, or
 * -1 when not even MIN_CONNECTIONS fit. */
#define FD_RESERVE      256
#define FD_PER_CONN     2
#define MIN_CONNECTIONS 16
static int fit_open_files(tsd_options *o)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0) return 0; /* leave it to accept() */
    rlim_t want = (rlim_t)o->max_connections * FD_PER_CONN + FD_RESERVE;
    if (rl.rlim_cur != RLIM_INFINITY && rl.rlim_cur < want) {
        rlim_t cur = rl.rlim_cur;
        rl.rlim_cur = rl.rlim_max == RLIM_INFINITY || rl.rlim_max > want ? want : rl.rlim_max;
        if (setrlimit(RLIMIT_NOFILE, &rl) != 0) rl.rlim_cur = cur;
    }
    if (rl.rlim_cur != RLIM_INFINITY && rl.rlim_cur < want) {
        int n = (int)((rl.rlim_cur - (rl.rlim_cur > FD_RESERVE ? FD_RESERVE : rl.rlim_cur)) /
                      FD_PER_CONN);
        if (n < MIN_CONNECTIONS) {
            fprintf(stderr, "tanksimd: open-file limit %ld: at least %d needed\n",
                    (long)rl.rlim_cur, MIN_CONNECTIONS * FD_PER_CONN + FD_RESERVE);
            return -1;
        }
        fprintf(stderr,
                "tanksimd: open-file limit %ld (hard limit %ld): at most %d connections, not "
                "%d (--max-connections; raise the limit, e.g. LimitNOFILE=)\n",
                (long)rl.rlim_cur, (long)rl.rlim_max, n, o->max_connections);
        o->max_connections = n;
    }
    return 0;
}

/* Seconds in [lo, hi], or (lo, hi] when lo_open, written as a plain decimal
 * number (tsa_is_decimal: no blanks, hex, inf or nan): 0 and *out set, else -1
 * with a message naming the flag. */
static int parse_seconds(const char *flag, const char *s, double lo, int lo_open, double hi,
                         double *out)
{
    double x;
    if (tsa_parse_number(s, lo, hi, &x) != 0 || (lo_open && x == lo)) {
        fprintf(stderr, "tanksimd: %s: seconds in %c%g, %g] expected, got '%s'\n", flag,
                lo_open ? '(' : '[', lo, hi, s);
        return -1;
    }
    *out = x;
    return 0;
}

/* A plain decimal integer in [lo, hi] (tsa_parse_integer: "", " 2", "2.5",
 * "0x10" refused, as the CLI's and the query's integers). */
static int parse_int(const char *flag, const char *s, long lo, long hi, long *out)
{
    if (tsa_parse_integer(s, lo, hi, out) == 0) return 0;
    fprintf(stderr, "tanksimd: %s: integer in [%ld, %ld] expected, got '%s'\n", flag, lo, hi, s);
    return -1;
}

/* The bearer token from a flag, the environment or a file's first line: 0, or
 * 1 after a message (empty, too long for the options' buffer, or with bytes a
 * header value cannot carry). */
static int set_token(tsd_options *o, const char *from, const char *v, size_t n)
{
    if (n == 0 || n >= sizeof o->token) {
        fprintf(stderr, "tanksimd: %s: a token of 1 to %zu characters expected, got %zu\n", from,
                sizeof o->token - 1, n);
        return 1;
    }
    for (size_t i = 0; i < n; i++)
        if ((unsigned char)v[i] <= ' ' || (unsigned char)v[i] >= 127) {
            fprintf(stderr, "tanksimd: %s: the token must be printable ASCII without blanks\n",
                    from);
            return 1;
        }
    memcpy(o->token, v, n);
    o->token[n] = '\0';
    return 0;
}

static int read_token_file(tsd_options *o, const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "tanksimd: --token-file %s: %s\n", path, strerror(errno));
        return 1;
    }
    char line[256];
    size_t n = fgets(line, sizeof line, f) ? strcspn(line, "\r\n") : 0;
    fclose(f);
    return set_token(o, "--token-file", line, n);
}

/* One daemon per data directory: a second one would mark the first one's
 * running sessions interrupted and advance them too. An exclusive flock on
 * DIR/tanksimd.lock, which holds the owner's pid for the message. 0, or -1
 * after a message. */
static int lock_data_dir(const char *dir)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/tanksimd.lock", dir);
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
        fprintf(stderr, "tanksimd: cannot open %s: %s\n", path, strerror(errno));
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        int e = errno;
        if (e == EWOULDBLOCK) {
            char pid[32] = "";
            ssize_t k = pread(fd, pid, sizeof pid - 1, 0);
            pid[k > 0 ? strcspn(pid, "\n") : 0] = '\0';
            fprintf(stderr,
                    "tanksimd: data dir %s is in use by another tanksimd%s%s%s; give each "
                    "daemon its own --data-dir\n",
                    dir, pid[0] ? " (pid " : "", pid, pid[0] ? ")" : "");
        } else {
            fprintf(stderr, "tanksimd: cannot lock %s: %s\n", path, strerror(e));
        }
        close(fd);
        return -1;
    }
    char pid[32];
    int len = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) != 0 || pwrite(fd, pid, (size_t)len, 0) != len)
        fprintf(stderr, "tanksimd: note: cannot write the pid to %s\n", path);
    return fd;
}

static int make_dirs(const char *path)
{
    char buf[PATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(buf, 0755) != 0 && errno != EEXIST) return -1;
        *p = '/';
    }
    return (mkdir(buf, 0755) != 0 && errno != EEXIST) ? -1 : 0;
}

int main(int argc, char **argv)
{
    tsd_server srv;
    memset(&srv, 0, sizeof srv);
    srv.listen_fd = -1;
    tsd_options *o = &srv.opt;
    snprintf(o->bind, sizeof o->bind, "127.0.0.1");
    o->port = 8080;
    snprintf(o->data_dir, sizeof o->data_dir, "./var");
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    o->threads = ncpu > 0 ? (int)ncpu : 2;
    o->http_threads = 4;
    o->max_body = 1 << 20;
    o->conn_timeout = 60;
    o->max_connections = 4096;
    o->max_sessions = 1000;
    o->max_analyses = 1000;
    o->max_samples = 100000;
    o->max_step = 10.0;
    o->max_rows = 1000000;
    tsd_static_default_root(o->web_root, sizeof o->web_root);

    int token_given = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--routes") == 0) {
            tsd_routes_print();
            return 0;
        } else if (strcmp(a, "--version") == 0) {
            printf("tanksimd %s\n", TS_VERSION);
            return 0;
        } else if (!v) {
            fprintf(stderr, "tanksimd: unknown option or missing value: %s\n", a);
            usage(stderr);
            return 2;
        } else if (strcmp(a, "--bind") == 0) {
            snprintf(o->bind, sizeof o->bind, "%s", v);
        } else if (strcmp(a, "--port") == 0) {
            if (parse_int(a, v, 0, 65535, &n)) return 2;
            o->port = (int)n;
        } else if (strcmp(a, "--data-dir") == 0) {
            snprintf(o->data_dir, sizeof o->data_dir, "%s", v);
        } else if (strcmp(a, "--threads") == 0) {
            if (parse_int(a, v, 1, 256, &n)) return 2;
            o->threads = (int)n;
        } else if (strcmp(a, "--max-body") == 0) {
            if (parse_int(a, v, 1024, 1L << 30, &n)) return 2;
            o->max_body = (size_t)n;
        } else if (strcmp(a, "--timeout") == 0) {
            if (parse_int(a, v, 1, 86400, &n)) return 2;
            o->conn_timeout = (unsigned)n;
        } else if (strcmp(a, "--max-connections") == 0) {
            if (parse_int(a, v, 1, 1000000, &n)) return 2;
            o->max_connections = (int)n;
        } else if (strcmp(a, "--max-sessions") == 0) {
            if (parse_int(a, v, 1, 1000000, &n)) return 2;
            o->max_sessions = (int)n;
        } else if (strcmp(a, "--max-analyses") == 0) {
            if (parse_int(a, v, 1, 1000000, &n)) return 2;
            o->max_analyses = (int)n;
        } else if (strcmp(a, "--max-samples") == 0) {
            if (parse_int(a, v, 10, 100000000, &n)) return 2;
            o->max_samples = n;
        } else if (strcmp(a, "--max-rows") == 0) {
            if (parse_int(a, v, 0, 1L << 40, &n)) return 2;
            o->max_rows = n;
        } else if (strcmp(a, "--max-step") == 0) {
            if (parse_seconds(a, v, 0, 1, 1e6, &o->max_step)) return 2;
        } else if (strcmp(a, "--drain") == 0) {
            if (parse_seconds(a, v, 0, 0, 86400, &o->drain)) return 2;
        } else if (strcmp(a, "--max-run-wall") == 0) {
            if (parse_seconds(a, v, 0, 0, 1e7, &o->max_run_wall)) return 2;
        } else if (strcmp(a, "--client-files") == 0) {
            if (strcmp(v, "yes") != 0 && strcmp(v, "no") != 0) {
                fprintf(stderr, "tanksimd: %s: 'yes' or 'no' expected, got '%s'\n", a, v);
                return 2;
            }
            o->client_files = strcmp(v, "yes") == 0;
        } else if (strcmp(a, "--token") == 0) {
            if (set_token(o, a, v, strlen(v))) return 2;
            token_given = 1;
        } else if (strcmp(a, "--token-file") == 0) {
            if (read_token_file(o, v)) return 2;
            token_given = 1;
        } else if (strcmp(a, "--web-root") == 0) {
            snprintf(o->web_root, sizeof o->web_root, "%s", v);
        } else {
            fprintf(stderr, "tanksimd: unknown option: %s\n", a);
            usage(stderr);
            return 2;
        }
        i++;
    }
    const char *env_token = getenv("TANKSIM_TOKEN");
    if (!token_given && env_token && env_token[0] &&
        set_token(o, "TANKSIM_TOKEN", env_token, strlen(env_token)))
        return 2;
    /* The socket first: a --bind that is no address, a port in use or one
     * not ours to bind fails here, before the store is created or locked, so
     * a start that fails leaves no tanksimd.db or tanksimd.lock behind (nor
     * the directories; removing them after a failure could remove what
     * another process was creating). Bound, not listening: connections are
     * refused until the store is open and tsd_server_start listens. */
    char err[1024]; /* a start-up error names paths and what to do */
    if (tsd_server_bind(&srv, err, sizeof err) != 0) {
        fprintf(stderr, "tanksimd: %s\n", err);
        return 1;
    }
    if (make_dirs(o->data_dir) != 0) {
        fprintf(stderr, "tanksimd: cannot create data dir %s: %s\n", o->data_dir, strerror(errno));
        tsd_server_unbind(&srv);
        return 1;
    }
    /* held (never closed) while the process lives: released by the kernel at exit */
    if (fit_open_files(o) != 0 || lock_data_dir(o->data_dir) < 0) {
        tsd_server_unbind(&srv);
        return 1;
    }

    sigset_t stop;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    sigaddset(&stop, SIGHUP); /* the terminal of `make run` closed: the same clean stop */
    pthread_sigmask(SIG_BLOCK, &stop, NULL);
    signal(SIGPIPE, SIG_IGN);

    srv.db = tsd_db_open(o->data_dir, err, sizeof err);
    if (!srv.db) {
        fprintf(stderr, "tanksimd: %s\n", err);
        tsd_server_unbind(&srv);
        return 1;
    }
    pthread_mutex_init(&srv.fft_lock, NULL);
    pthread_mutex_init(&srv.analyses_lock, NULL);
    snprintf(err, sizeof err, "out of memory");
    if (tsd_ops_init(&srv) != 0 || tsd_renderers_init(&srv) != 0 ||
        tsd_sessions_init(&srv, err, sizeof err) != 0) {
        fprintf(stderr, "tanksimd: %s\n", err);
        tsd_renderers_free(&srv);
        tsd_sessions_free(&srv);
        tsd_ops_free(&srv);
        tsd_db_close(srv.db);
        tsd_server_unbind(&srv);
        return 1;
    }
    /* analyses a killed daemon left running: stored as failed, not lost */
    if (tsd_analyses_recover(&srv) < 0)
        fprintf(stderr, "tanksimd: warning: could not mark the stored analyses of the last run "
                        "that did not finish (see the messages above)\n");
    srv.pool = tsd_pool_start(o->threads);
    if (!srv.pool || tsd_server_start(&srv, err, sizeof err) != 0) {
        fprintf(stderr, "tanksimd: %s\n", srv.pool ? err : "cannot start worker threads");
        tsd_pool_free(srv.pool);
        tsd_renderers_free(&srv);
        tsd_sessions_free(&srv);
        tsd_ops_free(&srv);
        tsd_db_close(srv.db);
        tsd_server_unbind(&srv);
        return 1;
    }
    const char *host = strchr(o->bind, ':') ? "[::1]" : o->bind;
    fprintf(stderr, "tanksimd %s listening on %s port %d, data in %s, %d workers\n", TS_VERSION,
            o->bind, o->port, o->data_dir, o->threads);
    printf("tanksimd: open http://%s:%d/ (health: http://%s:%d/v1/health)\n", host, o->port, host,
           o->port);
    fflush(stdout);

    int sig = 0;
    sigwait(&stop, &sig);
    fprintf(stderr, "tanksimd: %s received, shutting down\n",
            sig == SIGINT   ? "SIGINT"
            : sig == SIGHUP ? "SIGHUP"
                            : "SIGTERM");
    atomic_store(&srv.stopping, 1);
    tsd_sessions_wake_all(&srv);
    tsd_pool_stop(srv.pool); /* still allocated: handlers may call it until MHD stops */
    tsd_sessions_wake_all(&srv);
    if (o->drain > 0) {
        fprintf(stderr, "tanksimd: draining for %g s (a second signal stops at once)\n",
                o->drain);
        struct timespec ts = {(time_t)o->drain,
                              (long)((o->drain - (double)(time_t)o->drain) * 1e9)};
        while (sigtimedwait(&stop, NULL, &ts) < 0 && errno == EINTR)
            ;
    }
    /* resumed replies go out before MHD stops; a further signal cuts it short */
    tsd_server_settle(&srv, SETTLE_S, &stop);
    tsd_server_stop(&srv);
    tsd_pool_free(srv.pool);
    srv.pool = NULL;
    tsd_renderers_free(&srv);
    tsd_sessions_free(&srv);
    tsd_ops_free(&srv);
    tsd_db_close(srv.db);
    pthread_mutex_destroy(&srv.fft_lock);
    pthread_mutex_destroy(&srv.analyses_lock);
    fprintf(stderr, "tanksimd: stopped\n");
    return 0;
}
