/*
 * terrain.h — the ground profile under the pitch-plane vehicle (paper Section
 * II.D: "arbitrary terrain profiles ... can be specified via data files").
 *
 * Three kinds (ts_terrain_config.kind):
 *   flat     z = 0 everywhere;
 *   bumps    a list of 1-cos bumps, z = (h/2)(1 - cos(2 pi (x - s)/l)) on [s, s + l],
 *            either inline (/terrain/bump_start, bump_height, bump_length) or read from
 *            the shipped course file COURSE_DIR/COURSE.txt (format in
 *            sim/data/terrain/apg4-synth.txt: '#' comments, "length L", rows
 *            "start_m height_m length_m");
 *   profile  a user CSV, one "distance_m,height_m" row per line (a header line that
 *            does not start with a number is skipped), joined by straight lines and
 *            continued flat beyond its ends.
 * x is the distance along the course [m] (world x of geometry.h); heights in m.
 * Ownership: ts_terrain_make / ts_terrain_free (NULL is a no-op). A terrain is
 * read-only after construction and may be shared.
 */
#ifndef TS_TERRAIN_H
#define TS_TERRAIN_H

#include "config.h"
#include "errors.h"

typedef struct ts_terrain ts_terrain;

/* Build from a config. Reads the course or profile file (stdio) for those kinds.
 * NULL with err filled (TS_ERR_NOTFOUND for a missing file, TS_ERR_PARAM for a
 * malformed one, naming the /terrain field). */
ts_terrain *ts_terrain_make(const ts_terrain_config *c, ts_err *err);
void ts_terrain_free(ts_terrain *t);

/* Height z(x) [m]; *slope (may be NULL) gets dz/dx [1]. */
double ts_terrain_height(const ts_terrain *t, double x, double *slope);

/* Course length [m] (0 for flat or an empty course). */
double ts_terrain_length(const ts_terrain *t);

/* Parse a course text (the .txt format above) into at most cap bumps.
 * *n gets the bump count, *length the course length (0 if not given). */
TS_MUST_CHECK ts_rc ts_terrain_parse_course(const char *text, double *start, double *height,
                                            double *len, int cap, int *n, double *length,
                                            ts_err *err);

#endif
