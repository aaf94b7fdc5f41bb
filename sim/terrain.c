/*
 * terrain.c — ground profiles for the vehicle scenario (terrain.h): flat, a
 * list of 1-cos bumps (the shipped synthetic Aberdeen course "apg4-synth",
 * parameters in sim/data/terrain/apg4-synth.txt) or a user CSV profile.
 * Leaves out: soft soil, lateral profile (the model is planar).
 */
#include "terrain.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "constants.h"
#include "file_read.h"
#include "param.h"
#define PI TS_PI

struct ts_terrain {
    int kind;
    int n;             /* bumps or profile points */
    double *a, *b, *c; /* bumps: start, height, length; profile: x, z, (unused) */
    double length;
};

void ts_terrain_free(ts_terrain *t)
{
    if (!t) return;
    free(t->a);
    free(t->b);
    free(t->c);
    free(t);
}

static int alloc_arrays(ts_terrain *t, int n)
{
    size_t k = (size_t)(n > 0 ? n : 1);
    t->a = calloc(k, sizeof(double));
    t->b = calloc(k, sizeof(double));
    t->c = calloc(k, sizeof(double));
    return t->a && t->b && t->c;
}

/* Largest terrain file read (a resource limit, not physics): 64 MiB holds ~3
 * million "x,z" profile rows of ~20 bytes, a 30 km course at 1 cm spacing.
 * Without it a config naming /dev/zero or a growing file never returned. */
#define TERRAIN_FILE_MAX ((size_t)64 << 20)

/* Read a whole regular file (file_read.h; a config may name any path) of at
 * most TERRAIN_FILE_MAX into a NUL-terminated buffer (caller frees); errors
 * name the field. */
static char *slurp(const char *path, const char *pointer, ts_err *err)
{
    char *buf = ts_file_read(path, TERRAIN_FILE_MAX, TS_READ_REGULAR, NULL, err);
    if (!buf && err) {
        char why[sizeof err->msg];
        memcpy(why, err->msg, sizeof why);
        ts_err_set(err, err->code, pointer, "%s: %.300s", pointer, why);
    }
    return buf;
}

/* Ranges of what a terrain file may hold (input checks, not physics): a
 * course's bumps those of the inline /terrain/bump_* fields (their rows in
 * the parameter table, cfg_vehicle.c), a profile's points within 10,000 km
 * along and 10 km up or down. */
#define PROFILE_X_MAX     1e7
#define PROFILE_Z_MAX     1e4
#define LINE_MAX_CHARS    256

/* The next line of text at *p, ended by \n, \r or \r\n, copied into buf
 * (LINE_MAX_CHARS) with a '#' comment cut off; *p moves past it. Returns 0
 * at the end of the text, -1 for a line too long for buf, else 1. */
static int next_line(const char **p, char *buf)
{
    const char *s = *p;
    if (!*s) return 0;
    size_t len = strcspn(s, "\r\n");
    *p = s + len;
    if (**p == '\r') (*p)++;
    if (**p == '\n') (*p)++;
    if (len >= LINE_MAX_CHARS) return -1;
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *hash = strchr(buf, '#');
    if (hash) *hash = '\0';
    return 1;
}

static const char *skip_blanks(const char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    return s;
}

/* Length of the decimal number at s (sign, digits with at most one point,
 * exponent), 0 if none: strtod alone also reads hexadecimal ("0x10" as 16),
 * "inf" and "nan", which a distance or height column never means. */
static size_t decimal_length(const char *s)
{
    const char *p = s;
    int digits = 0;
    if (*p == '+' || *p == '-') p++;
    for (; isdigit((unsigned char)*p); p++) digits++;
    if (*p == '.')
        for (p++; isdigit((unsigned char)*p); p++) digits++;
    if (!digits) return 0;
    if (*p == 'e' || *p == 'E') {
        const char *e = p + 1;
        if (*e == '+' || *e == '-') e++;
        if (isdigit((unsigned char)*e)) {
            while (isdigit((unsigned char)*e)) e++;
            p = e;
        }
    }
    return (size_t)(p - s);
}

/* Exactly want finite decimal numbers from s, separated by blanks or one
 * comma, and nothing after them but blanks. Returns 0, or -1 (v partly
 * written). */
static int read_numbers(const char *s, double *v, int want)
{
    for (int i = 0; i < want; i++) {
        s = skip_blanks(s);
        if (i > 0 && *s == ',') s = skip_blanks(s + 1);
        char *end;
        size_t len = decimal_length(s);
        errno = 0;
        v[i] = strtod(s, &end);
        if (!len || end != s + len || errno == ERANGE || !isfinite(v[i])) return -1;
        s = end;
    }
    return *skip_blanks(s) ? -1 : 0;
}

ts_rc ts_terrain_parse_course(const char *text, double *start, double *height, double *len, int cap,
                              int *n, double *length, ts_err *err)
{
    const char *ptr = "/terrain/course";
    *n = 0;
    *length = 0;
    int line = 0, got;
    char buf[LINE_MAX_CHARS];
    /* the ranges of the inline fields, from their rows in the parameter table */
    const ts_param *field[3] = {ts_param_find("/terrain/bump_start"),
                                ts_param_find("/terrain/bump_height"),
                                ts_param_find("/terrain/bump_length")};
    while ((got = next_line(&text, buf)) != 0) {
        line++;
        if (got < 0)
            return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: line %d: longer than %d characters", ptr,
                              line, LINE_MAX_CHARS - 1);
        const char *s = skip_blanks(buf);
        if (!*s) continue;
        double v[3];
        if (strncmp(s, "length", 6) == 0) {
            if (read_numbers(s + 6, v, 1) != 0 || !(v[0] > 0) ||
                ts_param_check_number(field[0], v[0], NULL) != TS_OK)
                return ts_err_set(err, TS_ERR_PARAM, ptr,
                                  "%s: line %d: want 'length METRES', METRES > 0 and within "
                                  "/terrain/bump_start's range",
                                  ptr, line);
            *length = v[0];
            continue;
        }
        if (read_numbers(s, v, 3) != 0)
            return ts_err_set(err, TS_ERR_PARAM, ptr,
                              "%s: line %d: want three numbers 'start_m height_m length_m'", ptr,
                              line);
        for (int k = 0; k < 3; k++) {
            ts_err range;
            if (ts_param_check_number(field[k], v[k], &range) != TS_OK)
                return ts_err_set(err, TS_ERR_PARAM, ptr, "%s: line %d: %s", ptr, line,
                                  range.msg);
        }
        if (*n >= cap)
            return ts_err_set(err, TS_ERR_LIMIT, ptr, "%s: more than %d bumps", ptr, cap);
        if (*n > 0 && v[0] < start[*n - 1] + len[*n - 1])
            return ts_err_set(err, TS_ERR_PARAM, ptr,
                              "%s: line %d: bumps must be in order, not overlapping", ptr, line);
        start[*n] = v[0];
        height[*n] = v[1];
        len[*n] = v[2];
        (*n)++;
    }
    return TS_OK;
}

static ts_rc load_profile(ts_terrain *t, const char *path, ts_err *err)
{
    const char *ptr = "/terrain/profile_csv";
    char *text = slurp(path, ptr, err);
    if (!text) return err ? err->code : TS_ERR_NOTFOUND;
    int cap = 1;
    for (const char *q = text; *q; q++)
        cap += *q == '\n' || *q == '\r';
    ts_rc rc = TS_OK;
    if (!alloc_arrays(t, cap)) {
        rc = ts_err_set(err, TS_ERR_NOMEM, ptr, "out of memory");
        goto done;
    }
    int line = 0, got;
    char buf[LINE_MAX_CHARS];
    const char *p = text;
    while ((got = next_line(&p, buf)) != 0) {
        line++;
        if (got < 0) {
            rc = ts_err_set(err, TS_ERR_PARAM, ptr, "%s: line %d: longer than %d characters", ptr,
                            line, LINE_MAX_CHARS - 1);
            goto done;
        }
        const char *s = skip_blanks(buf);
        if (!*s) continue;
        double v[2];
        if (read_numbers(s, v, 2) != 0) {
            char *end;
            (void)strtod(s, &end);
            if (line == 1 && end == s) continue; /* a header: it does not start with a number */
            rc =
                ts_err_set(err, TS_ERR_PARAM, ptr,
                           "%s: line %d: want two finite numbers 'distance_m,height_m'", ptr, line);
            goto done;
        }
        if (fabs(v[0]) > PROFILE_X_MAX || fabs(v[1]) > PROFILE_Z_MAX) {
            rc =
                ts_err_set(err, TS_ERR_PARAM, ptr,
                           "%s: line %d: distance_m in [%g, %g] and height_m in [%g, %g] "
                           "expected",
                           ptr, line, -PROFILE_X_MAX, PROFILE_X_MAX, -PROFILE_Z_MAX, PROFILE_Z_MAX);
            goto done;
        }
        if (t->n > 0 && !(v[0] > t->a[t->n - 1])) {
            rc = ts_err_set(err, TS_ERR_PARAM, ptr, "%s: line %d: distances must increase", ptr,
                            line);
            goto done;
        }
        t->a[t->n] = v[0];
        t->b[t->n] = v[1];
        t->n++;
    }
    if (t->n < 1)
        rc = ts_err_set(err, TS_ERR_PARAM, ptr, "%s: no rows in '%s'", ptr, path);
    else
        t->length = t->a[t->n - 1];
done:
    free(text);
    return rc;
}

ts_terrain *ts_terrain_make(const ts_terrain_config *c, ts_err *err)
{
    ts_terrain *t = calloc(1, sizeof *t);
    if (!t) {
        ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        return NULL;
    }
    t->kind = c->kind;
    ts_rc rc = TS_OK;
    if (c->kind == TS_TERRAIN_BUMPS &&
        (c->bump_height_n != c->bump_n || c->bump_length_n != c->bump_n)) {
        /* heights without starts too: they would give way to the course unseen */
        rc = ts_err_set(err, TS_ERR_PARAM, "/terrain/bump_height",
                        "/terrain/bump_height: bump_start, bump_height and bump_length must have "
                        "the same length (%d, %d and %d given)",
                        c->bump_n, c->bump_height_n, c->bump_length_n);
    } else if (c->kind == TS_TERRAIN_BUMPS && c->bump_n > 0) {
        if (!alloc_arrays(t, c->bump_n)) {
            rc = ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
        } else {
            t->n = c->bump_n;
            for (int i = 0; i < t->n; i++) {
                t->a[i] = c->bump_start[i];
                t->b[i] = c->bump_height[i];
                t->c[i] = c->bump_length[i];
                if (i > 0 && t->a[i] < t->a[i - 1] + t->c[i - 1])
                    rc = ts_err_set(err, TS_ERR_PARAM, "/terrain/bump_start",
                                    "/terrain/bump_start: bumps must be in order, not overlapping");
                if (t->a[i] + t->c[i] > t->length) t->length = t->a[i] + t->c[i];
            }
        }
    } else if (c->kind == TS_TERRAIN_BUMPS) {
        char path[2 * TS_PATH_LEN];
        snprintf(path, sizeof path, "%s/%s.txt", c->course_dir, c->course);
        char *text = slurp(path, "/terrain/course", err);
        if (!text)
            rc = err ? err->code : TS_ERR_NOTFOUND;
        else {
            if (!alloc_arrays(t, TS_TERRAIN_BUMPS_MAX))
                rc = ts_err_set(err, TS_ERR_NOMEM, NULL, "out of memory");
            else
                rc = ts_terrain_parse_course(text, t->a, t->b, t->c, TS_TERRAIN_BUMPS_MAX, &t->n,
                                             &t->length, err);
            free(text);
        }
        if (rc == TS_OK && t->n > 0 && t->length < t->a[t->n - 1] + t->c[t->n - 1])
            t->length = t->a[t->n - 1] + t->c[t->n - 1];
    } else if (c->kind == TS_TERRAIN_PROFILE) {
        if (!c->profile_csv[0])
            rc = ts_err_set(err, TS_ERR_PARAM, "/terrain/profile_csv",
                            "/terrain/profile_csv: a profile terrain needs a CSV path");
        else
            rc = load_profile(t, c->profile_csv, err);
    }
    if (rc != TS_OK) {
        ts_terrain_free(t);
        return NULL;
    }
    return t;
}

double ts_terrain_length(const ts_terrain *t)
{
    return t->length;
}

/* Index of the last entry with key <= x, or -1. */
static int find_le(const double *key, int n, double x)
{
    if (n <= 0 || x < key[0]) return -1;
    int lo = 0, hi = n; /* key[lo] <= x < key[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (key[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double ts_terrain_height(const ts_terrain *t, double x, double *slope)
{
    double z = 0, dz = 0;
    if (t->kind == TS_TERRAIN_BUMPS) {
        int i = find_le(t->a, t->n, x);
        if (i >= 0 && x <= t->a[i] + t->c[i]) {
            double w = 2.0 * PI / t->c[i], u = x - t->a[i];
            z = 0.5 * t->b[i] * (1.0 - cos(w * u));
            dz = 0.5 * t->b[i] * w * sin(w * u);
        }
    } else if (t->kind == TS_TERRAIN_PROFILE && t->n > 0) {
        int i = find_le(t->a, t->n, x);
        if (i < 0)
            z = t->b[0];
        else if (i >= t->n - 1)
            z = t->b[t->n - 1];
        else {
            dz = (t->b[i + 1] - t->b[i]) / (t->a[i + 1] - t->a[i]);
            z = t->b[i] + dz * (x - t->a[i]);
        }
    }
    if (slope) *slope = dz;
    return z;
}
