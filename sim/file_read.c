/*
 * file_read.c — a whole file into memory, bounded (file_read.h).
 */
#include "file_read.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

char *ts_file_read(const char *path, size_t max, int kind, size_t *len, ts_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        ts_err_set(err, TS_ERR_NOTFOUND, NULL, "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (kind == TS_READ_REGULAR && (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode))) {
        fclose(f);
        ts_err_set(err, TS_ERR_PARAM, NULL, "'%s' is not a regular file", path);
        return NULL;
    }
    size_t cap = max < 4095 ? max + 1 : 4096, n = 0; /* room for cap - 1 bytes and the NUL */
    char *buf = malloc(cap);
    ts_rc rc = buf ? TS_OK : TS_ERR_NOMEM;
    while (rc == TS_OK) {
        if (n + 1 == cap) { /* full but for the terminator */
            if (n >= max) {
                if (fgetc(f) != EOF) rc = TS_ERR_LIMIT; /* exactly max bytes is fine */
                break;
            }
            size_t grow = cap - 1 > max / 2 ? max + 1 : 2 * cap;
            char *nb = realloc(buf, grow);
            if (!nb) {
                rc = TS_ERR_NOMEM;
                break;
            }
            buf = nb;
            cap = grow;
        }
        size_t r = fread(buf + n, 1, cap - 1 - n, f);
        n += r;
        if (r == 0) break;
    }
    if (rc == TS_OK && ferror(f)) rc = TS_ERR_IO;
    fclose(f);
    if (rc != TS_OK) {
        free(buf);
        if (rc == TS_ERR_LIMIT)
            ts_err_set(err, rc, NULL, "'%s' is larger than %zu MiB", path, max >> 20);
        else if (rc == TS_ERR_IO)
            ts_err_set(err, rc, NULL, "cannot read '%s'", path);
        else
            ts_err_set(err, rc, NULL, "out of memory reading '%s'", path);
        return NULL;
    }
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}
