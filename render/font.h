/*
 * font.h — a built-in 5x7 bitmap font and text drawing into RGBA8 images, for
 * the renderer's overlay (time, speed, gear, legends). Built in so frames need
 * no font files or font library; glyphs drawn for this project (printable
 * ASCII; characters without a glyph show as '?'). Internal to render/.
 */
#ifndef TSR_FONT_H
#define TSR_FONT_H

#include <stddef.h>

#define TSR_GLYPH_W 5 /* glyph cell without spacing [px at scale 1] */
#define TSR_GLYPH_H 7
#define TSR_ADVANCE 6 /* horizontal advance per character [px at scale 1] */

/* Width in pixels of s drawn at scale (integer magnification >= 1). */
int tsr_text_width(const char *s, int scale);

/* Draw s with its top-left corner at (x, y) in a top-down RGBA8 image,
 * clipped to the image; opaque colour rgb. */
void tsr_text_draw(unsigned char *rgba, int width, int height, size_t stride, int x, int y,
                   int scale, const char *s, const unsigned char rgb[3]);

/* Blend rectangle [x, x+w) x [y, y+h) towards rgb with weight alpha (0..1). */
void tsr_fill_rect(unsigned char *rgba, int width, int height, size_t stride, int x, int y, int w,
                   int h, const unsigned char rgb[3], double alpha);

#endif
