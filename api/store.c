/*
 * store.c — look-ups in the embedded default store (store.h).
 */
#include "store.h"

#include <string.h>

const tsa_file *tsa_store_find(const char *path)
{
    if (!path) return NULL;
    for (int i = 0; i < tsa_embedded_nfiles; i++)
        if (strcmp(tsa_embedded_files[i].path, path) == 0) return &tsa_embedded_files[i];
    return NULL;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

const tsa_file *tsa_store_nth(const char *prefix, const char *suffix, int i)
{
    for (int f = 0; f < tsa_embedded_nfiles; f++) {
        const char *p = tsa_embedded_files[f].path;
        if (strncmp(p, prefix, strlen(prefix)) == 0 && ends_with(p, suffix) && i-- == 0)
            return &tsa_embedded_files[f];
    }
    return NULL;
}
