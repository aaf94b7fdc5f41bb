/*
 * test_render.c — the offscreen renderer (render/render.h) on hand-built M1
 * snapshots (m1_fixture.h: the vehicle.json layout): PNG validity and size,
 * not blank, the hull where the projection puts it, the track following the
 * span deflection (more with a larger exaggeration), tension colours, the
 * overlay, two renderers on two threads giving identical bytes, bad input.
 *
 * Geometric checks use TSR_SHADE_IDS images, where every part has one exact
 * colour (no lighting, no antialiasing), so pixels can be counted per part.
 */
#include "test_util.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "render/m1_fixture.h"
#include "render/render.h"
#include "render/scene.h" /* nv: how much a scene built */

/* ---- helpers ------------------------------------------------------------------ */

typedef struct {
    int n;                  /* pixels of the part */
    int x0, x1, y0, y1;     /* inclusive bounding box */
} part_px;

static int is_part(const tsr_image *img, int x, int y, int part)
{
    unsigned char rgb[3];
    tsr_part_color(part, rgb);
    const unsigned char *p = img->rgba + (size_t)y * img->stride + (size_t)x * 4;
    return p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
}

static part_px count_part(const tsr_image *img, int part)
{
    part_px r = {0, img->width, -1, img->height, -1};
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (is_part(img, x, y, part)) {
                r.n++;
                if (x < r.x0) r.x0 = x;
                if (x > r.x1) r.x1 = x;
                if (y < r.y0) r.y0 = y;
                if (y > r.y1) r.y1 = y;
            }
    return r;
}

/* A scene of g under v (for tsr_project, tsr_scene_hull_box, tsr_render). */
static tsr_scene *scene_or_fail(const ts_geom *g, const tsr_view *v)
{
    ts_err err;
    tsr_scene *sc = tsr_scene_make(&err);
    if (!sc) fail_msg("tsr_scene_make: %s", err.msg);
    assert_int_equal(tsr_scene_update(sc, g, v, &err), TS_OK);
    return sc;
}

/* Render scene sc with v into a malloc'd copy of the RGBA pixels (img->rgba). */
static unsigned char *render_scene_copy(tsr_ctx *c, const tsr_scene *sc, const tsr_view *v,
                                        tsr_image *img)
{
    ts_err err;
    assert_int_equal(tsr_render(c, sc, v, img, &err), TS_OK);
    size_t n = img->stride * (size_t)img->height;
    unsigned char *copy = malloc(n);
    assert_non_null(copy);
    memcpy(copy, img->rgba, n);
    img->rgba = copy;
    return copy;
}

/* Render g with v into a malloc'd copy of the RGBA pixels. */
static unsigned char *render_copy(tsr_ctx *c, const ts_geom *g, const tsr_view *v, tsr_image *img)
{
    tsr_scene *sc = scene_or_fail(g, v);
    unsigned char *copy = render_scene_copy(c, sc, v, img);
    tsr_scene_free(sc);
    return copy;
}

static void bump_state(m1_state *s)
{
    memset(s, 0, sizeof *s);
    /* the paper's large obstacle, 1 ft x 25 ft (II.D), under the front wheels */
    m1_set_terrain(&s->g, -60, 100, 10.0, 0.3048, 7.62);
    m1_pose(s, 8.6, 3.2, 2.2);
}

static tsr_ctx *ctx_or_fail(void)
{
    ts_err err;
    tsr_ctx *c = tsr_ctx_make(&err);
    if (!c) fail_msg("tsr_ctx_make: %s", err.msg);
    return c;
}

/* The default view with one exact colour per part (the geometric checks). */
static tsr_view ids_view(void)
{
    tsr_view v;
    tsr_view_default(&v);
    v.shading = TSR_SHADE_IDS;
    return v;
}

/* Pixel position of the hull-frame point (bx, bz) at world depth y: the
 * rigid-body rotation by the hull pitch (positive nose-down) about the hull
 * origin, written out here independently of scene.c, then tsr_project. */
static void project_hull_point(const tsr_scene *sc, const tsr_view *v, const ts_geom *g,
                               double bx, double bz, double y, double *px, double *py)
{
    double cs = cos(g->hull_pitch), sn = sin(g->hull_pitch);
    double wx = g->hull_x + bx * cs + bz * sn;
    double wz = g->hull_z - bx * sn + bz * cs;
    ts_err err;
    assert_int_equal(tsr_project(sc, v, wx, y, wz, px, py, &err), TS_OK);
}

/* One frame of g under v with the scene it was drawn from (for tsr_project
 * and the hull box); shot_free releases all of it. */
typedef struct {
    tsr_ctx *c;
    tsr_scene *sc;
    tsr_image img; /* img.rgba = px */
    unsigned char *px; /* malloc'd copy of the pixels */
} shot;

static shot shot_take(const ts_geom *g, const tsr_view *v)
{
    shot sh;
    sh.c = ctx_or_fail();
    sh.sc = scene_or_fail(g, v);
    sh.px = render_scene_copy(sh.c, sh.sc, v, &sh.img);
    return sh;
}

static void shot_free(shot *sh)
{
    free(sh->px);
    tsr_scene_free(sh->sc);
    tsr_ctx_free(sh->c);
}

/* ---- tests -------------------------------------------------------------------- */

/* EVIDENCE: PNG spec (signature, IHDR) + png_io decode; the frame has the
 * requested size, is RGB (opaque: colour type 2) and decodes losslessly. */
static void png_has_size_and_decodes(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    tsr_ctx *c = ctx_or_fail();
    tsr_view v;
    tsr_view_default(&v);
    v.width = 320;
    v.height = 200;
    unsigned char *png = NULL, *rgba = NULL;
    size_t len = 0;
    ts_err err;
    assert_int_equal(tsr_render_png(c, &s.g, &v, NULL, &png, &len, &err), TS_OK);
    assert_true(len > 33 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
    assert_memory_equal(png + 12, "IHDR", 4);
    assert_int_equal(png[25], 2); /* colour type RGB */
    int w, h;
    assert_int_equal(tsr_png_decode(png, len, &rgba, &w, &h, &err), TS_OK);
    assert_int_equal(w, 320);
    assert_int_equal(h, 200);
    /* the decoded pixels are the rendered ones */
    tsr_image img;
    unsigned char *ref = render_copy(c, &s.g, &v, &img);
    assert_memory_equal(rgba, ref, (size_t)w * h * 4);
    free(ref);
    free(rgba);
    free(png);
    tsr_ctx_free(c);
}

/* EVIDENCE: a lit frame of the M1 is a picture, not a clear colour: many
 * colours, and every part of the vehicle covers pixels in the id image. */
static void frame_is_not_blank(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    tsr_ctx *c = ctx_or_fail();
    tsr_view v;
    tsr_view_default(&v);
    v.width = 640;
    v.height = 360;
    tsr_image img;
    unsigned char *lit = render_copy(c, &s.g, &v, &img);
    /* distinct colours, and the sky (top-right pixel) does not fill the frame */
    static unsigned char seen[1 << 18];
    memset(seen, 0, sizeof seen);
    int ncol = 0, nsky = 0;
    const unsigned char *sky = lit + 4 * (size_t)(img.width - 1);
    for (int i = 0; i < img.width * img.height; i++) {
        const unsigned char *p = lit + 4 * (size_t)i;
        int key = (p[0] >> 2) << 12 | (p[1] >> 2) << 6 | (p[2] >> 2);
        if (!seen[key]) seen[key] = 1, ncol++;
        if (memcmp(p, sky, 3) == 0) nsky++;
    }
    print_message("%d colours, sky %.0f %% of the frame\n", ncol,
                  100.0 * nsky / (img.width * img.height));
    assert_true(ncol >= 10); /* flat shading: ~17 for this frame; a blank one has 1 */
    assert_true(nsky < img.width * img.height * 3 / 4);
    free(lit);
    v.shading = TSR_SHADE_IDS;
    unsigned char *ids = render_copy(c, &s.g, &v, &img);
    for (int part = TSR_PART_TERRAIN; part < TSR_NPART; part++) {
        part_px pp = count_part(&img, part);
        if (pp.n < 20) fail_msg("part %d covers only %d pixels", part, pp.n);
    }
    free(ids);
    tsr_ctx_free(c);
}

/* EVIDENCE: render.h placement rule + side-view projection (closed form):
 * for the flat, unpitched M1 the hull's pixels fill exactly the projected box
 * rear..front x belly..deck (deck = 0.52 of belly->roof, scene.c profile), and
 * the gun reaches TSR_GUN_REACH past the front; tolerance 1.5 px. tsr_project
 * agrees with the formula to 1e-6 px. */
static void hull_pixels_in_projected_box(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    tsr_view v = ids_view();
    const int W = v.width, H = v.height;
    /* layout of vehicle.json: sprocket (0, 0.70) r 0.327; idler (5.88, 0.60) r 0.3175 */
    double env_rear = 0.0 - 0.327, env_front = 5.88 + 0.3175;
    double rear = env_rear - 0.45 * (TSR_HULL_LENGTH - (env_front - env_rear));
    double front = rear + TSR_HULL_LENGTH;
    double belly = 0.60 - TSR_BELLY_BELOW_AXLES;
    double roof = belly + TSR_HULL_HEIGHT - TSR_GROUND_CLEARANCE;
    double deck = belly + 0.52 * (roof - belly);
    double cx = 0.5 * (rear + front), cz = 0.5 * (belly + roof), k = W / 13.0;
#define PX(x) (W / 2.0 + k * ((x) - cx))
#define PY(z) (H / 2.0 - k * ((z) - cz))
    ts_err err;
    shot sh = shot_take(&s.g, &v);
    double br, bf, bb, bt;
    tsr_scene_hull_box(sh.sc, &br, &bf, &bb, &bt);
    assert_close(br + s.g.hull_x, rear, 0, 1e-9);
    assert_close(bt + s.g.hull_z, roof, 0, 1e-9);
    double px, py;
    assert_int_equal(tsr_project(sh.sc, &v, front, -5.0, deck, &px, &py, &err), TS_OK);
    assert_close(px, PX(front), 0, 1e-6);
    assert_close(py, PY(deck), 0, 1e-6);
    part_px hull = count_part(&sh.img, TSR_PART_HULL);
    /* pixel i covers [i, i+1): an edge at e gives first/last covered pixel ~ e, e-1 */
    assert_close(hull.x0, PX(rear), 0, 1.5);
    assert_close(hull.x1 + 1, PX(front), 0, 1.5);
    assert_close(hull.y0, PY(deck), 0, 1.5);
    assert_close(hull.y1 + 1, PY(belly), 0, 1.5);
    part_px turret = count_part(&sh.img, TSR_PART_TURRET);
    assert_close(turret.y0, PY(roof + 0.16), 0, 1.5); /* weapon station on the roof */
    part_px gun = count_part(&sh.img, TSR_PART_GUN);
    assert_close(gun.x1 + 1, PX(front + TSR_GUN_REACH), 0, 1.5);
    shot_free(&sh);
#undef PX
#undef PY
}

/* EVIDENCE: rigid-body rotation of the placement box: on the bump the hull is
 * pitched nose-up; every hull pixel lies inside the projected box of the
 * rotated corners (1.5 px), the rightmost hull pixel is the rotated nose
 * (profile point (1.00, 0.30), scene.c) and the leftmost the rotated rear
 * face (0.00, 0.10..0.49), within 2 px. */
static void pitched_hull_inside_rotated_box(void **state)
{
    (void)state;
    static m1_state s;
    bump_state(&s);
    assert_true(s.g.hull_pitch < -0.01); /* climbing: nose up */
    tsr_view v = ids_view();
    shot sh = shot_take(&s.g, &v);
    double r, f, b, t;
    tsr_scene_hull_box(sh.sc, &r, &f, &b, &t);
    double deck = b + 0.52 * (t - b);
    double bx[4] = {r, f, f, r}, bz[4] = {b, b, deck, deck};
    double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
    for (int i = 0; i < 4; i++) {
        double px, py;
        project_hull_point(sh.sc, &v, &s.g, bx[i], bz[i], -5, &px, &py);
        xmin = fmin(xmin, px), xmax = fmax(xmax, px), ymin = fmin(ymin, py), ymax = fmax(ymax, py);
    }
    part_px hull = count_part(&sh.img, TSR_PART_HULL);
    assert_true(hull.n > 1000);
    assert_true(hull.x0 >= xmin - 1.5 && hull.x1 + 1 <= xmax + 1.5);
    assert_true(hull.y0 >= ymin - 1.5 && hull.y1 + 1 <= ymax + 1.5);
    double nose[2], rear_lo[2], rear_hi[2];
    double pts[3][2] = {{f, b + 0.30 * (t - b)}, {r, b + 0.10 * (t - b)}, {r, b + 0.49 * (t - b)}};
    double *outp[3] = {nose, rear_lo, rear_hi};
    for (int i = 0; i < 3; i++)
        project_hull_point(sh.sc, &v, &s.g, pts[i][0], pts[i][1], -5, &outp[i][0], &outp[i][1]);
    assert_close(hull.x1 + 1, nose[0], 0, 2.0);
    assert_close(hull.x0, fmin(rear_lo[0], rear_hi[0]), 0, 2.0);
    shot_free(&sh);
}

/* Pixels whose track/non-track status differs between two id images, and
 * their horizontal extent. */
static int track_diff(const tsr_image *a, const tsr_image *b, int *x0, int *x1, int *y1)
{
    int n = 0;
    *x0 = a->width, *x1 = -1, *y1 = -1;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++)
            if (is_part(a, x, y, TSR_PART_TRACK) != is_part(b, x, y, TSR_PART_TRACK)) {
                n++;
                if (x < *x0) *x0 = x;
                if (x > *x1) *x1 = x;
                if (y > *y1) *y1 = y;
            }
    return n;
}

/* EVIDENCE: geometry.h contract — the drawn centreline is track_x/z +
 * exaggeration x track_dx/dz. A 2 cm half-sine on the front->rear roller span
 * (span 2) changes track pixels only over that span (between the roller
 * centres, give or take the one shoe pitch that a shoe with a pin in the span
 * reaches past them; above the rollers' centres), changes more than twice as
 * many pixels at exaggeration 5 as at 1, and none at exaggeration 0 (image
 * identical to the rest state). */
static void track_follows_span_deflection(void **state)
{
    (void)state;
    static m1_state rest, bent;
    m1_flat(&rest, 0);
    bent = rest;
    m1_span_mode(&bent, 2, 0.02);
    tsr_ctx *c = ctx_or_fail();
    tsr_view v = ids_view();
    tsr_image i_rest, i0, i1, i5;
    unsigned char *p_rest = render_copy(c, &rest.g, &v, &i_rest);
    v.exaggeration = 0;
    unsigned char *p0 = render_copy(c, &bent.g, &v, &i0);
    v.exaggeration = 1;
    unsigned char *p1 = render_copy(c, &bent.g, &v, &i1);
    v.exaggeration = 5;
    unsigned char *p5 = render_copy(c, &bent.g, &v, &i5);
    assert_memory_equal(p0, p_rest, i_rest.stride * (size_t)i_rest.height);
    int x0, x1, y1;
    int d1 = track_diff(&i_rest, &i1, &x0, &x1, &y1);
    int d5 = track_diff(&i_rest, &i5, &x0, &x1, &y1);
    print_message("track pixels changed: %d at exaggeration 1, %d at 5\n", d1, d5);
    assert_true(d1 > 0);
    assert_true(d5 > 2 * d1);
    /* where: between the rollers (world x 1.83 .. 4.55), above their centres */
    ts_err err;
    tsr_scene *sc = scene_or_fail(&rest.g, &v);
    double pa, pb, py, dummy;
    assert_int_equal(tsr_project(sc, &v, 1.83, -5, 0.84, &pa, &py, &err), TS_OK);
    assert_int_equal(tsr_project(sc, &v, 4.55, -5, 0.84, &pb, &dummy, &err), TS_OK);
    double shoe = 0.18 * v.width / 13.0 + 1;
    print_message("changed columns %d..%d, rollers at %.1f, %.1f px\n", x0, x1, pa, pb);
    assert_true(x0 >= pa - shoe && x1 <= pb + shoe);
    assert_true(y1 <= py);
    tsr_scene_free(sc);
    free(p_rest), free(p0), free(p1), free(p5);
    tsr_ctx_free(c);
}

/* EVIDENCE: geometry.h track_tension -> colour ramp (render.h): with every
 * point at the static tension no track pixel is red; with span 2 at twice the
 * static tension its shoes turn red (r > 180, g, b < 90), and only with
 * color_by_tension on. */
static void tension_colours_follow_track_tension(void **state)
{
    (void)state;
    static m1_state s, taut;
    m1_flat(&s, 0);
    taut = s;
    for (int i = 0; i < taut.g.ntrack; i++)
        if (taut.span[i] == 2) taut.g.track_tension[i] = 2 * taut.g.track_static_tension;
    tsr_ctx *c = ctx_or_fail();
    tsr_view v;
    tsr_view_default(&v);
    v.overlay = 0;
    int red[3];
    const m1_state *st[3] = {&s, &taut, &taut};
    for (int k = 0; k < 3; k++) {
        v.color_by_tension = k < 2;
        tsr_image img;
        unsigned char *px = render_copy(c, &st[k]->g, &v, &img);
        red[k] = 0;
        for (int y = 0; y < img.height * 3 / 4; y++) /* above the legend */
            for (int x = 0; x < img.width; x++) {
                const unsigned char *p = px + (size_t)y * img.stride + 4 * (size_t)x;
                if (p[0] > 180 && p[1] < 90 && p[2] < 90) red[k]++;
            }
        free(px);
    }
    print_message("red pixels: static %d, taut span %d, taut without colours %d\n", red[0],
                  red[1], red[2]);
    assert_int_equal(red[0], 0);
    assert_true(red[1] > 100);
    assert_int_equal(red[2], 0);
    tsr_ctx_free(c);
}

/* Bounding box of the pixels where two images of one size differ; the count. */
typedef struct {
    int n, x0, x1, y1;
} diff_box;

static diff_box image_diff(const tsr_image *ia, const unsigned char *pa, const unsigned char *pb)
{
    diff_box d = {0, ia->width, -1, -1};
    for (int y = 0; y < ia->height; y++)
        for (int x = 0; x < ia->width; x++)
            if (memcmp(pa + (size_t)y * ia->stride + 4 * (size_t)x,
                       pb + (size_t)y * ia->stride + 4 * (size_t)x, 4) != 0) {
                d.n++;
                if (x < d.x0) d.x0 = x;
                if (x > d.x1) d.x1 = x;
                if (y > d.y1) d.y1 = y;
            }
    return d;
}

/* EVIDENCE: the overlay is the only thing that changes with the snapshot's
 * time: frames at t = 1 s and t = 2 s differ only inside the top-left text
 * box, and not at all with the overlay off. The gear (render.c draw_overlay)
 * is appended to that line: gear 1 against gear 0 changes only the top line
 * to the right of "t 1.00 s   v 7.2 km/h (4.5 mph)" (31 characters of 6 px
 * at scale 2 from x = 16, render/font.h). An absurd snapshot time (1e300 s:
 * a 300-digit first line) still draws: the line is cut at its buffer and
 * nothing is written past it (an ASan build checks that). */
static void overlay_shows_time(void **state)
{
    (void)state;
    static m1_state a, b;
    m1_flat(&a, 0);
    assert_int_equal(a.g.gear, 1);
    b = a;
    b.g.t = 2.0;
    tsr_ctx *c = ctx_or_fail();
    tsr_view v;
    tsr_view_default(&v);
    tsr_image ia, ib;
    unsigned char *pa = render_copy(c, &a.g, &v, &ia);
    unsigned char *pb = render_copy(c, &b.g, &v, &ib);
    diff_box d = image_diff(&ia, pa, pb);
    assert_true(d.n > 10);
    assert_true(d.y1 < 48 && d.x1 < 640);
    free(pb);
    b = a;
    b.g.gear = 0;
    pb = render_copy(c, &b.g, &v, &ib);
    d = image_diff(&ia, pa, pb);
    assert_true(d.n > 10);
    assert_true(d.y1 < 48);
    assert_true(d.x0 >= 16 + 31 * 6 * 2 - 2);
    free(pa), free(pb);
    b = a;
    b.g.t = 1e300;
    pb = render_copy(c, &b.g, &v, &ib);
    free(pb);
    v.overlay = 0;
    pa = render_copy(c, &a.g, &v, &ia);
    b = a;
    b.g.t = 2.0;
    pb = render_copy(c, &b.g, &v, &ib);
    assert_memory_equal(pa, pb, ia.stride * (size_t)ia.height);
    free(pa), free(pb);
    tsr_ctx_free(c);
}

/* EVIDENCE: the snapshot's terrain and track are drawn in one frame: on the
 * bump, in the column under each road wheel the lowest track pixel sits on the
 * terrain's top pixel (gap <= 2 px; the fixture puts the shoes' outer face
 * 2.5 mm above the ground). */
static void track_rests_on_terrain(void **state)
{
    (void)state;
    static m1_state s;
    bump_state(&s);
    tsr_view v = ids_view();
    shot sh = shot_take(&s.g, &v);
    const tsr_image *img = &sh.img;
    ts_err err;
    int on_bump = 0;
    for (int i = 0; i < s.g.nwheel; i++) {
        const ts_geom_wheel *w = &s.g.wheel[i];
        if (w->role != TS_WHEEL_ROAD) continue;
        double fx, fy;
        assert_int_equal(tsr_project(sh.sc, &v, w->x, -5, w->z, &fx, &fy, &err), TS_OK);
        int x = (int)fx, low_track = -1, top_terrain = -1;
        for (int y = 0; y < img->height; y++) {
            if (is_part(img, x, y, TSR_PART_TRACK)) low_track = y;
            if (top_terrain < 0 && is_part(img, x, y, TSR_PART_TERRAIN)) top_terrain = y;
        }
        assert_true(low_track >= 0 && top_terrain >= 0);
        assert_true(top_terrain - low_track >= 1 && top_terrain - low_track <= 3);
        if (m1_terrain(&s.g, w->x) > 0.05) on_bump++;
    }
    assert_true(on_bump >= 2); /* the check covered wheels up on the bump */
    shot_free(&sh);
}

/* EVIDENCE: perspective camera aimed at the hull (render.h): the three-quarter
 * view shows hull, turret, track and road wheels, and a point inside the
 * turret projects onto a turret (or hull) pixel. */
static void three_quarter_view_shows_the_tank(void **state)
{
    (void)state;
    static m1_state s;
    bump_state(&s);
    tsr_view v = ids_view();
    v.kind = TSR_VIEW_THREE_QUARTER;
    v.width = 640;
    v.height = 360;
    shot sh = shot_take(&s.g, &v);
    int parts[] = {TSR_PART_HULL, TSR_PART_TURRET, TSR_PART_TRACK, TSR_PART_ROAD_WHEEL,
                   TSR_PART_TERRAIN};
    for (int i = 0; i < 5; i++) assert_true(count_part(&sh.img, parts[i]).n > 50);
    double r, f, b, t, fx, fy;
    tsr_scene_hull_box(sh.sc, &r, &f, &b, &t);
    /* inside the turret */
    project_hull_point(sh.sc, &v, &s.g, r + 0.40 * (f - r), b + 0.85 * (t - b), 0, &fx, &fy);
    assert_true(fx > 0 && fx < v.width && fy > 0 && fy < v.height);
    int x = (int)fx, y = (int)fy;
    assert_true(is_part(&sh.img, x, y, TSR_PART_HULL) || is_part(&sh.img, x, y, TSR_PART_TURRET));
    shot_free(&sh);
}

/* ---- threads -------------------------------------------------------------------- */

typedef struct {
    const ts_geom *g;
    const tsr_view *v;
    unsigned char *png[3];
    size_t len[3];
    ts_rc rc;
} job;

static void *render_thread(void *arg)
{
    job *j = arg;
    ts_err err;
    tsr_ctx *c = tsr_ctx_make(&err);
    j->rc = c ? TS_OK : err.code;
    for (int k = 0; c && k < 3 && j->rc == TS_OK; k++)
        j->rc = tsr_render_png(c, j->g, j->v, NULL, &j->png[k], &j->len[k], &err);
    tsr_ctx_free(c);
    return NULL;
}

/* EVIDENCE: render.h thread contract — one ctx per thread; two contexts
 * rendering concurrently on two threads give byte-identical PNGs (three
 * frames each), equal to the main thread's. */
static void two_threads_identical_bytes(void **state)
{
    (void)state;
    static m1_state s;
    bump_state(&s);
    m1_span_mode(&s, 2, 0.01);
    tsr_view v;
    tsr_view_default(&v);
    v.width = 480;
    v.height = 270;
    v.exaggeration = 3;
    v.color_by_tension = 1;
    job j[2] = {{.g = &s.g, .v = &v}, {.g = &s.g, .v = &v}};
    pthread_t th[2];
    for (int i = 0; i < 2; i++) assert_int_equal(pthread_create(&th[i], NULL, render_thread, &j[i]), 0);
    for (int i = 0; i < 2; i++) pthread_join(th[i], NULL);
    tsr_ctx *c = ctx_or_fail();
    unsigned char *ref;
    size_t len;
    ts_err err;
    assert_int_equal(tsr_render_png(c, &s.g, &v, NULL, &ref, &len, &err), TS_OK);
    for (int i = 0; i < 2; i++) {
        assert_int_equal(j[i].rc, TS_OK);
        for (int k = 0; k < 3; k++) {
            assert_int_equal(j[i].len[k], len);
            assert_memory_equal(j[i].png[k], ref, len);
            free(j[i].png[k]);
        }
    }
    free(ref);
    tsr_ctx_free(c);
}

/* EVIDENCE: render.h error contract — bad views name the field, inconsistent
 * snapshots are TS_ERR_PARAM, nothing is drawn from them. */
static void bad_input_is_rejected(void **state)
{
    (void)state;
    static m1_state s, bad;
    m1_flat(&s, 0);
    tsr_view v;
    tsr_view_default(&v);
    ts_err err;
    v.width = 8;
    assert_int_equal(tsr_view_check(&v, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/width");
    tsr_view_default(&v);
    v.exaggeration = NAN;
    assert_int_equal(tsr_view_check(&v, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/exaggeration");
    tsr_view_default(&v);
    v.kind = 7;
    assert_int_equal(tsr_view_check(&v, &err), TS_ERR_RANGE);
    tsr_view_default(&v);
    v.text[0] = '\n';
    assert_int_equal(tsr_view_check(&v, &err), TS_ERR_PARAM);
    assert_int_equal(tsr_view_kind_parse("three_quarter"), TSR_VIEW_THREE_QUARTER);
    assert_int_equal(tsr_view_kind_parse("top"), -1);
    tsr_view_default(&v);
    tsr_scene *sc = tsr_scene_make(&err);
    bad = s;
    bad.g.ntrack = 2;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    bad = s;
    bad.g.track_dz[5] = NAN;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    bad = s;
    for (int i = 0; i < bad.g.nwheel; i++)
        if (bad.g.wheel[i].role == TS_WHEEL_SPROCKET) bad.g.wheel[i].role = TS_WHEEL_ROAD;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    bad = s;
    bad.g.terrain_x[1] = bad.g.terrain_x[0] - 1;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    bad = s;
    bad.g.nwheel = TS_GEOM_MAX_WHEELS + 1;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    /* the shoe pitch: NaN or negative refused (both silently dropped the whole
     * track until session 20); 0 draws the band without shoes; a pitch far
     * below the loop's length draws at most MAX_SHOES, not millions */
    bad = s;
    bad.g.track_pitch = NAN;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    assert_non_null(strstr(err.msg, "track_pitch"));
    bad.g.track_pitch = -0.18;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_ERR_PARAM);
    bad.g.track_pitch = 0;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_OK);
    assert_int_equal(tsr_scene_update(sc, &s.g, &v, &err), TS_OK);
    int nv_m1 = sc->nv;       /* 78 shoes */
    bad.g.track_pitch = 1e-5; /* ~1.4 million shoes uncapped */
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_OK);
    int nv_capped = sc->nv;
    bad.g.track_pitch = 1e-6;
    assert_int_equal(tsr_scene_update(sc, &bad.g, &v, &err), TS_OK);
    assert_int_equal(sc->nv, nv_capped);                      /* the cap, not the pitch */
    assert_true(nv_capped > nv_m1 && nv_capped < 40 * nv_m1); /* 2048 of them */
    assert_int_equal(tsr_scene_update(sc, &s.g, &v, &err), TS_OK);
    tsr_scene_free(sc);
    tsr_scene_free(NULL);
    tsr_ctx_free(NULL);
}

/* EVIDENCE: none numeric — writes the M1 on the paper's large obstacle (side
 * and three-quarter, lit, antialiased, tension colours on the second) to
 * tests/out/render_m1_bump_*.png for a person to look at (Figs. 9-10's
 * situation); checks only that the PNGs are written and decode to the size. */
static void writes_bump_frames_for_review(void **state)
{
    (void)state;
    static m1_state s;
    bump_state(&s);
    m1_span_mode(&s, 2, 0.01);
    for (int i = 0; i < s.g.ntrack; i++) /* a taut upper run for the colour map */
        if (s.span[i]) s.g.track_tension[i] = 1.6 * s.g.track_static_tension;
    tsr_ctx *c = ctx_or_fail();
    char names[2][64];
    test_out_path(names[0], sizeof names[0], "render_m1_bump_side.png");
    test_out_path(names[1], sizeof names[1], "render_m1_bump_three_quarter.png");
    for (int k = 0; k < 2; k++) {
        tsr_view v;
        tsr_view_default(&v);
        v.kind = k ? TSR_VIEW_THREE_QUARTER : TSR_VIEW_SIDE;
        v.antialias = 1;
        v.exaggeration = 5;
        v.color_by_tension = k;
        snprintf(v.text, sizeof v.text, "M1 on the 1 ft x 25 ft bump (hand-built state), "
                                        "span deflection x5");
        unsigned char *png, *rgba;
        size_t len;
        int w, h;
        ts_err err;
        assert_int_equal(tsr_render_png(c, &s.g, &v, NULL, &png, &len, &err), TS_OK);
        FILE *f = fopen(names[k], "wb");
        assert_non_null(f);
        assert_int_equal(fwrite(png, 1, len, f), len);
        assert_int_equal(fclose(f), 0);
        assert_int_equal(tsr_png_decode(png, len, &rgba, &w, &h, &err), TS_OK);
        assert_int_equal(w, v.width);
        assert_int_equal(h, v.height);
        free(rgba);
        free(png);
    }
    tsr_ctx_free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(png_has_size_and_decodes),
        cmocka_unit_test(frame_is_not_blank),
        cmocka_unit_test(hull_pixels_in_projected_box),
        cmocka_unit_test(pitched_hull_inside_rotated_box),
        cmocka_unit_test(track_follows_span_deflection),
        cmocka_unit_test(tension_colours_follow_track_tension),
        cmocka_unit_test(overlay_shows_time),
        cmocka_unit_test(track_rests_on_terrain),
        cmocka_unit_test(three_quarter_view_shows_the_tank),
        cmocka_unit_test(two_threads_identical_bytes),
        cmocka_unit_test(bad_input_is_rejected),
        cmocka_unit_test(writes_bump_frames_for_review),
    };
    return cmocka_run_group_tests_name("render/render", tests, NULL, NULL);
}
