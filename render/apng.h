/*
 * apng.h — animated PNG (APNG, W3C PNG 3rd edition §11.3.3: acTL, fcTL, fdAT
 * chunks) assembled from frames already encoded as PNG by png_io.h.
 *
 * Why APNG: one self-contained file that every current browser animates in an
 * <img> and that any PNG reader shows as its first frame; it reuses the
 * renderer's own PNG encoder (no second codec), and frames stay lossless so
 * the track's deformation is not blurred by a video codec.
 *
 * Every frame must have the same IHDR (size, bit depth, colour type); frame 0's
 * image data becomes the default image (IDAT), later frames become fdAT chunks
 * with sequence numbers. Ownership: *out is malloc'd; the caller frees it.
 */
#ifndef TSR_APNG_H
#define TSR_APNG_H

#include <stddef.h>

#include "../sim/errors.h"

/* Assemble n >= 1 PNG frames (pngs[i], lens[i] bytes) into one APNG that loops
 * forever, each frame shown delay_num/delay_den seconds. */
TS_MUST_CHECK ts_rc tsr_apng_assemble(const unsigned char *const *pngs, const size_t *lens, int n,
                                      unsigned delay_num, unsigned delay_den, unsigned char **out,
                                      size_t *out_len, ts_err *err);

#endif
