/*
 * store.h — the embedded default store: every file under sim/data/ (defaults,
 * presets, courses) and api/openapi.yaml, compiled into the binaries by
 * api/embed.sh so that a daemon or runner started anywhere finds them.
 * Paths are repository-relative ("sim/data/presets/NAME.json").
 */
#ifndef TSA_STORE_H
#define TSA_STORE_H

#include <stddef.h>

typedef struct tsa_file {
    const char *path;          /* repository-relative path */
    const unsigned char *data; /* contents, NUL-terminated for convenience */
    size_t size;               /* bytes, without the terminating NUL */
} tsa_file;

/* The generated table (build/gen/embedded_store.c). */
extern const tsa_file tsa_embedded_files[];
extern const int tsa_embedded_nfiles;

/* File at exactly this path, or NULL. Static data: never free. */
const tsa_file *tsa_store_find(const char *path);

/* The i-th file whose path starts with prefix and ends with suffix (either may
 * be ""), counting from 0; NULL past the last. */
const tsa_file *tsa_store_nth(const char *prefix, const char *suffix, int i);

#endif
