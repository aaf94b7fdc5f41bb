/*
 * bytebuf.h — a growable in-memory byte buffer, internal to render/: the sink
 * of libpng's write callback (png_io.c) and of the APNG chunk writer
 * (apng.c). Allocation failure sets oom and drops every later append, so the
 * writer checks oom once at the end; the owner frees p.
 */
#ifndef TSR_BYTEBUF_H
#define TSR_BYTEBUF_H

#include <stdlib.h>
#include <string.h>

typedef struct {
    unsigned char *p; /* malloc'd, n bytes used of cap */
    size_t n, cap;
    int oom;
} tsr_bytebuf;

static inline void tsr_bytebuf_put(tsr_bytebuf *b, const void *d, size_t n)
{
    if (b->oom || n == 0) return;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 65536;
        while (cap < b->n + n) cap *= 2;
        unsigned char *np = realloc(b->p, cap);
        if (!np) {
            b->oom = 1;
            return;
        }
        b->p = np;
        b->cap = cap;
    }
    memcpy(b->p + b->n, d, n);
    b->n += n;
}

#endif
