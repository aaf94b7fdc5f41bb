/*
 * render.h — offscreen frames of the tank: hull, running gear and the deformed
 * track circuit drawn from a geometry snapshot (sim/geometry.h) into RGBA8 and
 * PNG, with OSMesa (software OpenGL, 3.3+ core profile, GLSL 330 shaders).
 *
 * Why: the paper lists "animation sequences" among the outputs (II.C.2) and
 * shows the tank on the bump course (Figs. 9-10); the API, the dashboard and
 * CI need those pictures without a display or a GPU.
 *
 * Split as MuJoCo's mjv/mjr: tsr_scene_update turns a ts_geom snapshot (taken
 * under the session's lock by ts_geometry) into a scene of lit triangles; then
 * tsr_render draws a scene with a tsr_ctx, which owns the OpenGL context and
 * every buffer. Nothing here sees ts_model/ts_data, JSON or HTTP.
 *
 * Frame: as everywhere in tanksim, x forward, z up, y to the vehicle's left;
 * SI units. The model is a pitch plane (x-z): the renderer extrudes it to 3-D
 * (hull width, one track circuit on each side, both drawn from the same
 * snapshot). Proportions that are not in the snapshot (widths, hull profile,
 * turret, gun) are drawing constants of the M1 silhouette, documented in
 * render/scene.c; they are pictures, not model parameters.
 *
 * Hull placement (so tests and overlays can predict pixels): the hull is
 * drawn in the body frame attached to the hull reference point (hull_x,
 * hull_z) and pitched by hull_pitch (positive nose-down), located by the
 * hull-fixed running gear: its length is TSR_HULL_LENGTH, placed along x so
 * that its overhang beyond the track envelope (sprocket rear .. idler front)
 * is split 45 % rear, 55 % front; its belly is TSR_BELLY_BELOW_AXLES below the
 * lower of the sprocket and idler centres, and its turret roof is
 * TSR_HULL_HEIGHT - TSR_GROUND_CLEARANCE above the belly. The gun points
 * forward TSR_GUN_REACH metres beyond the hull front. The snapshot's
 * hull_length and hull_height are framing hints of the model (geometry.h) and
 * do not size the drawing.
 *
 * Threads: a tsr_ctx is used by one thread at a time (make one per render
 * thread); each call makes its OpenGL context current on the calling thread
 * and releases it before returning, so a ctx may move between threads of a
 * pool. Different ctx's render concurrently and give identical bytes for the
 * same scene and view. A tsr_scene is read-only during tsr_render.
 *
 * Errors: every call that can fail returns ts_rc and fills ts_err (pointer
 * names the tsr_view field at fault, e.g. "/width"); nothing prints or exits.
 * Ownership: *_make / *_free pairs; *_free(NULL) is a no-op. Buffers returned
 * through tsr_image belong to the ctx; PNG buffers are malloc'd for the caller.
 */
#ifndef TSR_RENDER_H
#define TSR_RENDER_H

#include <stddef.h>

#include "../sim/errors.h"
#include "../sim/geometry.h"
#include "png_io.h"

#define TSR_MIN_SIZE 16    /* smallest image side [px] */
#define TSR_MAX_SIZE 4096  /* largest image side [px] */
#define TSR_TEXT_LEN 96    /* capacity of tsr_view.text including the NUL */

/* Drawing constants of the hull placement rule above [m]. */
#define TSR_HULL_LENGTH 7.92          /* M1 hull length, gun excluded (public data) */
#define TSR_HULL_HEIGHT 2.44          /* M1 height to turret roof (public data) */
#define TSR_GROUND_CLEARANCE 0.48     /* M1 ground clearance (public data) */
#define TSR_BELLY_BELOW_AXLES 0.15    /* belly below the lower of sprocket/idler centres */
#define TSR_GUN_REACH 1.91            /* 9.83 m overall with gun forward - 7.92 m hull */

typedef enum tsr_view_kind {
    TSR_VIEW_SIDE,          /* orthographic, looking along +y at the vehicle's right side,
                               x to the right, centred on the hull box (follows the hull) */
    TSR_VIEW_THREE_QUARTER, /* perspective from front-right and above, aimed at the hull */
    TSR_NVIEW
} tsr_view_kind;

typedef enum tsr_shading {
    TSR_SHADE_LIT, /* lit colours, overlay text, optional multisampling (antialias) */
    TSR_SHADE_IDS, /* each part in its flat tsr_part_color, no AA, no overlay (tests, picking) */
    TSR_NSHADE
} tsr_shading;

/* Parts of the scene; in TSR_SHADE_IDS each is painted in tsr_part_color(part). */
typedef enum tsr_part {
    TSR_PART_BACKGROUND,
    TSR_PART_TERRAIN,
    TSR_PART_HULL,
    TSR_PART_TURRET,
    TSR_PART_GUN,
    TSR_PART_ROAD_ARM,
    TSR_PART_ROAD_WHEEL,
    TSR_PART_SPROCKET,
    TSR_PART_IDLER,
    TSR_PART_ROLLER,
    TSR_PART_TRACK,
    TSR_NPART
} tsr_part;

/* What to draw and how. Start from tsr_view_default and change fields. */
typedef struct tsr_view {
    int width, height;       /* image size [px], TSR_MIN_SIZE..TSR_MAX_SIZE */
    int kind;                /* tsr_view_kind */
    double exaggeration;     /* factor on the modal deflection track_dx/dz, 0..1000 (1 = true) */
    int color_by_tension;    /* 1: colour track shoes by track_tension (blue slack, grey at
                                track_static_tension, red at twice it) and draw a legend */
    int overlay;             /* 1: draw "t, speed, gear" (and text) in the top-left corner */
    char text[TSR_TEXT_LEN]; /* extra overlay line, printable ASCII, may be empty */
    double span;             /* side view: metres across the image width; 0 = 13 m */
    int shading;             /* tsr_shading */
    int antialias;           /* 1: 4x multisampled edges (lit only; about 2.5x the draw time
                                on llvmpipe, so off by default for streamed frames) */
} tsr_view;

/* 1280 x 720, side view, exaggeration 1, no tension colours, overlay on, lit,
 * no antialiasing. */
void tsr_view_default(tsr_view *v);

/* TS_OK, or TS_ERR_RANGE / TS_ERR_PARAM naming the bad field ("/width", ...). */
TS_MUST_CHECK ts_rc tsr_view_check(const tsr_view *v, ts_err *err);

/* Copy text into v->text: TS_OK, or TS_ERR_RANGE naming "/text" when it does
 * not fit (it is not cut: a cut text would pass tsr_view_check's length). */
TS_MUST_CHECK ts_rc tsr_view_set_text(tsr_view *v, const char *text, ts_err *err);

/* "side" / "three_quarter" -> tsr_view_kind, -1 if unknown; and back (never NULL). */
int tsr_view_kind_parse(const char *name);
const char *tsr_view_kind_name(int kind);

/* Flat colour of a part in TSR_SHADE_IDS images (distinct for every part). */
void tsr_part_color(int part, unsigned char rgb[3]);

/* ---- scene: triangles built from a snapshot (no OpenGL) ------------------ */

typedef struct tsr_scene tsr_scene;

tsr_scene *tsr_scene_make(ts_err *err);
void tsr_scene_free(tsr_scene *s);

/* Build the scene of snapshot g for view v (exaggeration and tension colours
 * shape the track). TS_ERR_PARAM if g is inconsistent (counts out of range,
 * non-finite values, fewer than 3 track points, no sprocket or idler);
 * TS_ERR_RANGE from tsr_view_check. The scene keeps no pointer to g. */
TS_MUST_CHECK ts_rc tsr_scene_update(tsr_scene *s, const ts_geom *g, const tsr_view *v,
                                     ts_err *err);

/* Pixel coordinates (x right, y down, pixel i covers [i, i+1)) of world point
 * (x, y, z) [m] in the image of scene s seen with view v, as tsr_render draws
 * it. TS_ERR_RANGE if the point is behind a perspective camera.
 * Side view: with (cx, cz) the world position of the hull box centre and
 * k = width / span (span 13 m when 0): px = width/2 + k (x - cx),
 * py = height/2 - k (z - cz), whatever y. */
TS_MUST_CHECK ts_rc tsr_project(const tsr_scene *s, const tsr_view *v, double x, double y, double z,
                                double *px, double *py, ts_err *err);

/* Box of the drawn hull (placement rule above) in the body frame: x forward,
 * z up, relative to the hull reference point (hull_x, hull_z) before pitch
 * [m]: rear, front (gun excluded), belly, turret roof. */
void tsr_scene_hull_box(const tsr_scene *s, double *x_rear, double *x_front, double *z_belly,
                        double *z_roof);

/* ---- context: OpenGL + buffers, one per render thread -------------------- */

typedef struct tsr_ctx tsr_ctx;

/* Create an OSMesa core-profile context with 24-bit depth, compile the
 * shaders. TS_ERR_UNSUPPORTED if OSMesa cannot give a 3.3+ core context. */
tsr_ctx *tsr_ctx_make(ts_err *err);
void tsr_ctx_free(tsr_ctx *c);

/* GL_RENDERER and GL_VERSION strings of the context ("llvmpipe ...", "4.5 ..."). */
const char *tsr_ctx_gl_renderer(const tsr_ctx *c);
const char *tsr_ctx_gl_version(const tsr_ctx *c);

/* An RGBA8 image, rows top-down, stride bytes apart; pixels owned by the ctx,
 * valid until the next tsr_render on that ctx or tsr_ctx_free. */
typedef struct tsr_image {
    int width, height;
    size_t stride;
    const unsigned char *rgba;
} tsr_image;

/* Draw scene s with view v. The scene depends on v's kind, exaggeration,
 * tension colours (and, for the side view, span and aspect: it leaves out what
 * that view cannot see); size at the same aspect, shading, overlay, text and
 * antialias may differ from the view the scene was updated with. */
TS_MUST_CHECK ts_rc tsr_render(tsr_ctx *c, const tsr_scene *s, const tsr_view *v, tsr_image *out,
                               ts_err *err);

/* Snapshot -> PNG in one call, using a scene owned by the ctx: update, render,
 * encode with png (NULL: tsr_png_fast). *png is malloc'd; the caller frees it. */
TS_MUST_CHECK ts_rc tsr_render_png(tsr_ctx *c, const ts_geom *g, const tsr_view *v,
                                   const tsr_png_opts *png, unsigned char **out, size_t *out_len,
                                   ts_err *err);

/* The PNG settings frames use (see render.c for the measurement behind the
 * choice); tsr_render_png writes opaque RGB PNGs (tsr_png_encode_opaque). */
tsr_png_opts tsr_png_fast(void);

#endif
