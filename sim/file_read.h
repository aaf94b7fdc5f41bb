/*
 * file_read.h — a whole file into memory, bounded.
 *
 * The terrain files (sim/terrain.c) and the CLI's config files
 * (api/config_json.c) are read whole and parsed from memory. One reader for
 * both: a size bound (a path may name /dev/zero or a growing file), read
 * errors reported rather than taken as the end, and, where a path comes from
 * a config that may name anything, non-regular files refused.
 */
#ifndef TANKSIM_FILE_READ_H
#define TANKSIM_FILE_READ_H

#include <stddef.h>

#include "errors.h"

enum { TS_READ_ANY = 0, TS_READ_REGULAR = 1 };

/* The bytes of path, NUL-terminated (the caller frees), their count in *len
 * (may be NULL); at most max bytes (a file of exactly max is read). NULL with
 * err filled (pointer ""; messages name the path): TS_ERR_NOTFOUND when it
 * cannot be opened, TS_ERR_PARAM when `kind` is TS_READ_REGULAR and it is
 * not a regular file (a directory, device or pipe), TS_ERR_LIMIT past max,
 * TS_ERR_IO on a read error, TS_ERR_NOMEM. */
char *ts_file_read(const char *path, size_t max, int kind, size_t *len, ts_err *err);

#endif
