/*
 * test_scene.c — the scene builder (render/scene.c) without OpenGL: the
 * world-space triangles that tsr_scene_update makes from a hand-built M1
 * snapshot (m1_fixture.h), checked against rigid-body motion, the geometry.h
 * contract (deflection exaggerated along x and z, the loop in either
 * direction, one shoe per track pitch), the tension colour ramp of render.h,
 * the terrain held at its ends and its points kept, wheels that turn with
 * their spin angle, tsr_project's refusal of a point behind the camera and
 * tsr_view_check's inclusive limits.
 *
 * These are the survivors of a mutation pass over render/ (session 28): each
 * check here failed with its mutant applied (listed at each test).
 */
#include "test_util.h"

#include <stdlib.h>
#include <string.h>

#include "render/m1_fixture.h"
#include "render/render.h"
#include "render/scene.h"

/* ---- helpers ------------------------------------------------------------------ */

static tsr_scene *scene_of(const ts_geom *g, const tsr_view *v)
{
    ts_err err;
    tsr_scene *sc = tsr_scene_make(&err);
    if (!sc) fail_msg("tsr_scene_make: %s", err.msg);
    if (tsr_scene_update(sc, g, v, &err) != TS_OK) fail_msg("tsr_scene_update: %s", err.msg);
    return sc;
}

static tsr_view side_view(void)
{
    tsr_view v;
    tsr_view_default(&v);
    return v;
}

static int part_of(const tsr_vertex *v) { return v->rgba[3]; }

/* Largest distance [m] from a vertex of part in a to the nearest vertex of
 * part in b: 0 when b draws every point a draws (the drawing order and the
 * triangulation of a face left out). */
static double part_gap(const tsr_scene *a, const tsr_scene *b, int part)
{
    double worst = 0;
    for (int i = 0; i < a->nv; i++) {
        if (part_of(&a->v[i]) != part) continue;
        double best = INFINITY;
        for (int j = 0; j < b->nv && best > 0; j++) {
            if (part_of(&b->v[j]) != part) continue;
            double d = 0;
            for (int k = 0; k < 3; k++) d = fmax(d, fabs(a->v[i].pos[k] - b->v[j].pos[k]));
            best = fmin(best, d);
        }
        worst = fmax(worst, best);
    }
    return worst;
}

static int part_count(const tsr_scene *sc, int part)
{
    int n = 0;
    for (int i = 0; i < sc->nv; i++) n += part_of(&sc->v[i]) == part;
    return n;
}

/* Rotate (x, z) about (ox, oz) as the hull frame does for a pitch th
 * (positive nose-down, geometry.h): body +x goes to -z. */
static void pitch_point(double ox, double oz, double th, double *x, double *z)
{
    double bx = *x - ox, bz = *z - oz, c = cos(th), s = sin(th);
    *x = ox + bx * c + bz * s;
    *z = oz - bx * s + bz * c;
}

/* ---- tests -------------------------------------------------------------------- */

/* EVIDENCE: rigid-body motion. The hull, turret and gun are drawn in the hull
 * frame, placed by the snapshot's hull pose (geometry.h: pitch positive
 * nose-down). Pitching the whole snapshot (hull, wheels, pivots, track) by
 * 0.15 rad about the hull origin must pitch those parts' vertices by the same
 * rotation, vertex for vertex (float positions: 20 um). The mutant with
 * w[0] = ox + x c - z s (not a rotation) misplaced the deck by 0.1 m here;
 * test_render's pitched-hull check looks at points near the hull origin's
 * height, where it moves by less than its 2 px. */
static void hull_parts_pitch_with_the_hull(void **state)
{
    (void)state;
    static m1_state a, b;
    m1_flat(&a, 0);
    b = a;
    const double th = 0.15, ox = a.g.hull_x, oz = a.g.hull_z;
    b.g.hull_pitch = a.g.hull_pitch + th;
    for (int i = 0; i < b.g.nwheel; i++) {
        ts_geom_wheel *w = &b.g.wheel[i];
        pitch_point(ox, oz, th, &w->x, &w->z);
        pitch_point(ox, oz, th, &w->pivot_x, &w->pivot_z);
    }
    for (int i = 0; i < b.g.ntrack; i++) pitch_point(ox, oz, th, &b.g.track_x[i], &b.g.track_z[i]);
    tsr_view v = side_view();
    tsr_scene *sa = scene_of(&a.g, &v), *sb = scene_of(&b.g, &v);
    assert_int_equal(sa->nv, sb->nv);
    int checked = 0;
    for (int i = 0; i < sa->nv; i++) {
        int p = part_of(&sa->v[i]);
        if (p != TSR_PART_HULL && p != TSR_PART_TURRET && p != TSR_PART_GUN) continue;
        assert_int_equal(part_of(&sb->v[i]), p);
        double x = sa->v[i].pos[0], z = sa->v[i].pos[2];
        pitch_point(ox, oz, th, &x, &z);
        assert_close(sb->v[i].pos[0], x, 0, 2e-5);
        assert_close(sb->v[i].pos[1], sa->v[i].pos[1], 0, 2e-5);
        assert_close(sb->v[i].pos[2], z, 0, 2e-5);
        checked++;
    }
    print_message("      %d hull, turret and gun vertices pitched by %.2f rad\n", checked, th);
    assert_true(checked > 300);
    tsr_scene_free(sa);
    tsr_scene_free(sb);
}

/* EVIDENCE: geometry.h — the drawn centreline is track_x/z + exaggeration x
 * track_dx/dz, in both coordinates. A uniform 1 cm modal displacement along x
 * at exaggeration 3 moves every shoe vertex by 3 cm along x and nowhere else
 * (test_render checks the z deflection on a span; the mutant that dropped
 * the exaggeration on track_dx moved them 1 cm). */
static void track_deflection_exaggerated_along_x(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    tsr_view v = side_view();
    v.exaggeration = 0;
    tsr_scene *rest = scene_of(&s.g, &v);
    for (int i = 0; i < s.g.ntrack; i++) s.g.track_dx[i] = 0.01;
    v.exaggeration = 3;
    tsr_scene *moved = scene_of(&s.g, &v);
    assert_int_equal(rest->nv, moved->nv);
    int n = 0;
    for (int i = 0; i < rest->nv; i++) {
        if (part_of(&rest->v[i]) != TSR_PART_TRACK) continue;
        assert_close(moved->v[i].pos[0], rest->v[i].pos[0] + 0.03, 0, 2e-5);
        assert_close(moved->v[i].pos[1], rest->v[i].pos[1], 0, 2e-5);
        assert_close(moved->v[i].pos[2], rest->v[i].pos[2], 0, 2e-5);
        n++;
    }
    assert_true(n > 1000);
    tsr_scene_free(rest);
    tsr_scene_free(moved);
}

/* EVIDENCE: geometry.h — the track is a closed polyline; its direction is not
 * part of the contract. The same loop listed clockwise (from the same first
 * point) draws the same shoes at a sprocket angle of 0.1 rad: scene.c turns
 * the shoe phase with the loop's orientation so that forward spin moves the
 * top run forward either way. With the orientation fixed at
 * counter-clockwise, the clockwise listing put every shoe 2 x 0.1 x 0.327 m
 * off. */
static void track_loop_direction_does_not_matter(void **state)
{
    (void)state;
    static m1_state a, b;
    m1_flat(&a, 0);
    for (int i = 0; i < a.g.nwheel; i++) a.g.wheel[i].angle = 0.1; /* sprocket included */
    b = a;
    int n = a.g.ntrack;
    for (int i = 0; i < n; i++) {
        int j = (n - i) % n;
        b.g.track_x[i] = a.g.track_x[j];
        b.g.track_z[i] = a.g.track_z[j];
        b.g.track_tension[i] = a.g.track_tension[j];
    }
    tsr_view v = side_view();
    tsr_scene *sa = scene_of(&a.g, &v), *sb = scene_of(&b.g, &v);
    assert_true(part_count(sa, TSR_PART_TRACK) > 1000);
    assert_int_equal(part_count(sa, TSR_PART_TRACK), part_count(sb, TSR_PART_TRACK));
    double gap_ab = part_gap(sa, sb, TSR_PART_TRACK), gap_ba = part_gap(sb, sa, TSR_PART_TRACK);
    print_message("      shoe corners apart: %.2g / %.2g m\n", gap_ab, gap_ba);
    assert_true(gap_ab < 2e-5 && gap_ba < 2e-5);
    tsr_scene_free(sa);
    tsr_scene_free(sb);
}

/* EVIDENCE: scene.c — shoes of about one track pitch each: round(L / pitch)
 * shoes round the loop (78 for the M1, Paper II.C.1). Each shoe is a box of
 * 12 triangles; the side view draws one side. At a pitch of L / 78.4 that is
 * 78 shoes (the mutant that rounded up drew 79), at L / 77.6 also 78; a pitch
 * of a third of the loop still draws 8 (scene.c's least, so that a coarse
 * pitch still reads as a loop of shoes). */
static void one_shoe_per_pitch(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    double L = 0;
    for (int i = 0; i < s.g.ntrack; i++) {
        int k = (i + 1) % s.g.ntrack;
        L += hypot(s.g.track_x[k] - s.g.track_x[i], s.g.track_z[k] - s.g.track_z[i]);
    }
    const double per[3] = {78.4, 77.6, 3.0};
    const int want[3] = {78, 78, 8};
    for (int c = 0; c < 3; c++) {
        s.g.track_pitch = L / per[c];
        tsr_view v = side_view();
        tsr_scene *sc = scene_of(&s.g, &v);
        assert_int_equal(part_count(sc, TSR_PART_TRACK), want[c] * 12 * 3);
        tsr_scene_free(sc);
    }
}

/* EVIDENCE: render.h colour ramp — blue when slack, grey at the static
 * tension, red at twice it and above; a non-finite ratio is drawn as static
 * (grey). End points are the ramp's own colours; 0.5 is halfway from blue to
 * grey. The mutants that clamped at 3 x static or drew NaN blue failed here. */
static void tension_colour_ramp(void **state)
{
    (void)state;
    unsigned char lo[3], mid[3], hi[3], c[3];
    tsr_tension_color(0.0, lo);
    tsr_tension_color(1.0, mid);
    tsr_tension_color(2.0, hi);
    assert_true(lo[2] > 200 && lo[0] < 60);                          /* blue */
    assert_true(mid[0] > 190 && mid[1] > 190 && mid[2] > 190);       /* light grey */
    assert_true(hi[0] > 200 && hi[1] < 60 && hi[2] < 60);            /* red */
    const double same_as_lo[] = {-1.0, -1e9}, same_as_hi[] = {2.5, 3.0, 1e9};
    for (int i = 0; i < 2; i++) {
        tsr_tension_color(same_as_lo[i], c);
        assert_memory_equal(c, lo, 3);
    }
    for (int i = 0; i < 3; i++) {
        tsr_tension_color(same_as_hi[i], c);
        assert_memory_equal(c, hi, 3);
    }
    tsr_tension_color(NAN, c);
    assert_memory_equal(c, mid, 3);
    tsr_tension_color(INFINITY, c);
    assert_memory_equal(c, mid, 3);
    tsr_tension_color(0.5, c);
    for (int k = 0; k < 3; k++) assert_true(abs(2 * c[k] - lo[k] - mid[k]) <= 1);
}

/* EVIDENCE: geometry.h track_static_tension — the colour scale's reference;
 * without one (0) the scene takes half the largest track tension, so the
 * tautest point is drawn red (2 x reference). A track with no tension at all
 * has no scale: its shoes keep the plain track colour, as with colours off.
 * The mutants that took the full largest tension, or started the search at
 * 1 N (all-zero tensions then drawn blue), failed here. */
static void tension_reference_without_a_static_tension(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    s.g.track_static_tension = 0;
    for (int i = 0; i < s.g.ntrack; i++) s.g.track_tension[i] = i == 5 ? 20000.0 : 8000.0;
    tsr_view v = side_view();
    v.color_by_tension = 1;
    tsr_scene *sc = scene_of(&s.g, &v);
    assert_close(sc->tension_ref, 10000.0, 1e-12, 0);
    tsr_scene_free(sc);

    for (int i = 0; i < s.g.ntrack; i++) s.g.track_tension[i] = 0;
    tsr_scene *on = scene_of(&s.g, &v);
    v.color_by_tension = 0;
    tsr_scene *off = scene_of(&s.g, &v);
    assert_true(on->tension_ref == 0);
    assert_int_equal(on->nv, off->nv);
    int n = 0;
    for (int i = 0; i < on->nv; i++)
        if (part_of(&on->v[i]) == TSR_PART_TRACK) {
            assert_memory_equal(on->v[i].rgba, off->v[i].rgba, 4);
            n++;
        }
    assert_true(n > 1000);
    tsr_scene_free(on);
    tsr_scene_free(off);
}

/* EVIDENCE: render.h — shoes coloured by track_tension: each shoe takes the
 * tension at its middle, interpolated along the polyline. One point of the
 * middle upper span at twice the static tension, every other point at it:
 * the shoes next to that point are drawn between grey and red, not only in
 * the two end colours (the mutant that took the segment's first point's
 * tension drew only grey and red). */
static void shoe_colour_interpolates_the_tension(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    int j = -1;
    for (int i = 0; i < s.g.ntrack && j < 0; i++)
        if (s.span[i] == 2 && s.xi[i] > 0.5) j = i;
    assert_true(j > 0);
    s.g.track_tension[j] = 2 * s.g.track_static_tension;
    tsr_view v = side_view();
    v.color_by_tension = 1;
    tsr_scene *sc = scene_of(&s.g, &v);
    unsigned char mid[3], hi[3];
    tsr_tension_color(1.0, mid);
    tsr_tension_color(2.0, hi);
    int between = 0, red = 0;
    for (int i = 0; i < sc->nv; i++) {
        const unsigned char *c = sc->v[i].rgba;
        if (part_of(&sc->v[i]) != TSR_PART_TRACK) continue;
        if (memcmp(c, hi, 3) == 0) red++;
        else if (memcmp(c, mid, 3) != 0 && c[0] >= mid[0] && c[0] <= hi[0] && c[1] < mid[1])
            between++;
    }
    print_message("      shoe vertices between grey and red: %d, red: %d\n", between, red);
    assert_true(between >= 36); /* at least one shoe */
    tsr_scene_free(sc);
}

/* EVIDENCE: the terrain profile is held flat beyond its ends, as the model's
 * (sim/terrain.c: a CSV profile's first height before its first point). A
 * profile that starts 3 m behind the hull at 0.2 m is drawn at 0.2 m behind
 * that point too (ground top face: the vertices at y = +6 m); the mutant drew
 * it at 0. */
static void ground_held_at_the_profile_start(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    double x0 = s.g.hull_x - 3.0;
    s.g.nterrain = 2;
    s.g.terrain_x[0] = x0, s.g.terrain_z[0] = 0.2;
    s.g.terrain_x[1] = x0 + 50, s.g.terrain_z[1] = 0.2;
    tsr_view v = side_view();
    tsr_scene *sc = scene_of(&s.g, &v);
    int n = 0;
    for (int i = 0; i < sc->nv; i++) {
        const tsr_vertex *p = &sc->v[i];
        if (part_of(p) != TSR_PART_TERRAIN || p->pos[1] < 5.9 || p->pos[0] >= x0) continue;
        assert_close(p->pos[2], 0.2, 0, 1e-6);
        n++;
    }
    assert_true(n > 10);
    tsr_scene_free(sc);
}

/* EVIDENCE: scene.c — the ground is sampled every 0.25 m plus the profile's
 * own points, so a bump's corners stay where the profile puts them. A
 * triangular 0.3-m spike whose apex lies between two samples is drawn up to
 * its apex height (the mutant that sampled the grid alone cut it to 0.21 m). */
static void ground_keeps_the_profile_points(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    double xp = s.g.hull_x + 1.137; /* off the 0.25-m grid */
    s.g.nterrain = 5;
    const double xs[5] = {-60, xp - 0.4, xp, xp + 0.4, 100}, zs[5] = {0, 0, 0.3, 0, 0};
    for (int i = 0; i < 5; i++) s.g.terrain_x[i] = xs[i], s.g.terrain_z[i] = zs[i];
    tsr_view v = side_view();
    tsr_scene *sc = scene_of(&s.g, &v);
    double top = -1;
    for (int i = 0; i < sc->nv; i++)
        if (part_of(&sc->v[i]) == TSR_PART_TERRAIN && sc->v[i].pos[1] > 5.9)
            top = fmax(top, sc->v[i].pos[2]);
    assert_close(top, 0.3, 0, 1e-6);
    tsr_scene_free(sc);
}

/* Angles [rad] of the vertices of part about (xc, zc) at radius r (+- 1e-4 m),
 * sorted, taken from the first wheel within 0.7 r. */
static int angles_at_radius(const tsr_scene *sc, int part, double xc, double zc, double r,
                            double *out, int max)
{
    int n = 0;
    for (int i = 0; i < sc->nv && n < max; i++) {
        const tsr_vertex *p = &sc->v[i];
        if (part_of(p) != part) continue;
        double dx = p->pos[0] - xc, dz = p->pos[2] - zc;
        if (fabs(hypot(dx, dz) - r) < 1e-4) out[n++] = atan2(dz, dx);
    }
    return n;
}

/* Smallest difference between angle a and any of b[0..n-1] (mod 2 pi). */
static double nearest_angle(double a, const double *b, int n)
{
    double best = 10;
    for (int i = 0; i < n; i++) {
        double d = remainder(a - b[i], 2 * TSR_PI);
        if (fabs(d) < best) best = fabs(d);
    }
    return best;
}

/* EVIDENCE: geometry.h wheel angle — "spin positive = forward rolling =
 * clockwise seen from -y" (scene.c): the sprocket's tooth tips (radius
 * r + 0.075 m) and the road wheel's lightening holes (centres at 0.52 r) turn
 * by -0.1 rad about the wheel centre when its angle grows by 0.1 rad, so an
 * animation shows the wheels rolling. The mutants that drew the teeth fixed,
 * or turned the holes the other way, failed here. */
static void wheels_turn_with_their_spin(void **state)
{
    (void)state;
    static m1_state a, b;
    m1_flat(&a, 0);
    b = a;
    for (int i = 0; i < b.g.nwheel; i++) b.g.wheel[i].angle += 0.1;
    tsr_view v = side_view();
    tsr_scene *sa = scene_of(&a.g, &v), *sb = scene_of(&b.g, &v);
    int isp = -1, ird = -1;
    for (int i = 0; i < a.g.nwheel; i++) {
        if (a.g.wheel[i].role == TS_WHEEL_SPROCKET && isp < 0) isp = i;
        if (a.g.wheel[i].role == TS_WHEEL_ROAD && ird < 0) ird = i;
    }
    assert_true(isp >= 0 && ird >= 0);
    struct {
        int part, wheel;
        double radius;
    } probe[2] = {{TSR_PART_SPROCKET, isp, a.g.wheel[isp].radius + 0.075},
                  {TSR_PART_ROAD_WHEEL, ird, 0.52 * a.g.wheel[ird].radius}};
    for (int k = 0; k < 2; k++) {
        const ts_geom_wheel *w = &a.g.wheel[probe[k].wheel];
        double aa[512], ab[512];
        int na = angles_at_radius(sa, probe[k].part, w->x, w->z, probe[k].radius, aa, 512);
        int nb = angles_at_radius(sb, probe[k].part, w->x, w->z, probe[k].radius, ab, 512);
        assert_true(na > 5);
        assert_int_equal(na, nb);
        for (int i = 0; i < nb; i++) assert_true(nearest_angle(ab[i] + 0.1, aa, na) < 1e-4);
    }
    tsr_scene_free(sa);
    tsr_scene_free(sb);
}

/* EVIDENCE: geometry.h track_pitch_offset — the shoes ride on the wheels'
 * rims, so a shoe's body reaches the pitch offset inside the pitch line (on
 * the ground run: that far above it); and a sprocket of pitch radius r meshes
 * with shoes of pitch p with n = pi / asin(p / 2r) teeth (11 for the M1's
 * 0.180 m on 0.327 m). Until session 33 the drawing wrote 0.045 m and 11
 * teeth whatever the config said. */
static void shoes_ride_on_the_rims_and_the_teeth_follow_the_pitch(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    double zlo = INFINITY, xs = 0;
    int nlo = 0;
    for (int i = 0; i < s.g.ntrack; i++)
        zlo = fmin(zlo, s.g.track_z[i]);
    for (int i = 0; i < s.g.ntrack; i++)
        if (s.g.track_z[i] < zlo + 1e-9) xs += s.g.track_x[i], nlo++;
    assert_true(nlo >= 2);
    xs /= nlo; /* the middle of the ground run */
    const double offset[2] = {0.045, 0.08};
    for (int c = 0; c < 2; c++) {
        s.g.track_pitch_offset = offset[c];
        tsr_view v = side_view();
        tsr_scene *sc = scene_of(&s.g, &v);
        double top = -INFINITY;
        for (int i = 0; i < sc->nv; i++) {
            const tsr_vertex *p = &sc->v[i];
            if (part_of(p) == TSR_PART_TRACK && fabs(p->pos[0] - xs) < 0.3 && p->pos[2] < zlo + 0.2)
                top = fmax(top, p->pos[2]);
        }
        assert_close(top - zlo, offset[c], 0, 1e-5); /* vertices are floats */
        tsr_scene_free(sc);
    }
    int isp = -1;
    for (int i = 0; i < s.g.nwheel; i++)
        if (s.g.wheel[i].role == TS_WHEEL_SPROCKET && isp < 0) isp = i;
    assert_true(isp >= 0);
    const ts_geom_wheel *w = &s.g.wheel[isp];
    const double pitch[3] = {0.180, 2.0 * w->radius * sin(TSR_PI / 9), 0.0};
    const int teeth[3] = {11, 9, 11}; /* no pitch: the drawing's 11 */
    for (int c = 0; c < 3; c++) {
        s.g.track_pitch = pitch[c];
        tsr_view v = side_view();
        tsr_scene *sc = scene_of(&s.g, &v);
        double a[512];
        int n = angles_at_radius(sc, TSR_PART_SPROCKET, w->x, w->z, w->radius + 0.075, a, 512);
        double distinct[64];
        int nd = 0;
        for (int i = 0; i < n; i++)
            if (nearest_angle(a[i], distinct, nd) > 1e-6 && nd < 64) distinct[nd++] = a[i];
        assert_int_equal(nd, 2 * teeth[c]); /* each tooth's two tip corners */
        tsr_scene_free(sc);
    }
}

/* EVIDENCE: render.h tsr_project — a point behind the camera has no pixel:
 * TS_ERR_RANGE. The three-quarter camera sits on the line from the hull
 * centre towards (0.62, -0.72, 0.32); a point 1 km out along that line is
 * behind it. The mutant without the check returned a mirrored pixel. */
static void project_refuses_a_point_behind_the_camera(void **state)
{
    (void)state;
    static m1_state s;
    m1_flat(&s, 0);
    tsr_view v = side_view();
    v.kind = TSR_VIEW_THREE_QUARTER;
    tsr_scene *sc = scene_of(&s.g, &v);
    double dir[3] = {0.62, -0.72, 0.32}, l = sqrt(0.62 * 0.62 + 0.72 * 0.72 + 0.32 * 0.32);
    double px, py;
    ts_err err;
    assert_int_equal(tsr_project(sc, &v, sc->aim[0], sc->aim[1], sc->aim[2], &px, &py, &err),
                     TS_OK);
    assert_close(px, v.width / 2.0, 0, 1e-6); /* the aim is the image centre */
    assert_close(py, v.height / 2.0, 0, 1e-6);
    assert_int_equal(tsr_project(sc, &v, sc->aim[0] + 1000 * dir[0] / l,
                                 sc->aim[1] + 1000 * dir[1] / l, sc->aim[2] + 1000 * dir[2] / l,
                                 &px, &py, &err),
                     TS_ERR_RANGE);
    tsr_scene_free(sc);
}

/* EVIDENCE: render.h ranges — width and height in [TSR_MIN_SIZE,
 * TSR_MAX_SIZE] px, exaggeration and span in [0, 1000], the enumerations and
 * flags within their values, text printable ASCII (32-126) and at most
 * TSR_TEXT_LEN - 1 characters. Each limit is accepted and the value just past
 * it refused with the field's pointer; test_render checks one far value each
 * (every boundary mutant of tsr_view_check survived it). */
static void view_limits_are_inclusive(void **state)
{
    (void)state;
    typedef struct {
        const char *ptr;
        int field; /* 0 width 1 height 2 exaggeration 3 span 4 kind 5 shading 6 colour 7 overlay
                      8 antialias */
        double ok, bad;
    } lim;
    static const lim L[] = {
        {"/width", 0, TSR_MIN_SIZE, TSR_MIN_SIZE - 1},
        {"/width", 0, TSR_MAX_SIZE, TSR_MAX_SIZE + 1},
        {"/height", 1, TSR_MIN_SIZE, TSR_MIN_SIZE - 1},
        {"/height", 1, TSR_MAX_SIZE, TSR_MAX_SIZE + 1},
        {"/exaggeration", 2, 0.0, -1e-9},
        {"/exaggeration", 2, 1000.0, 1000.001},
        {"/span", 3, 0.0, -1e-9},
        {"/span", 3, 1000.0, 1000.001},
        {"/view", 4, 0, -1},
        {"/view", 4, TSR_NVIEW - 1, TSR_NVIEW},
        {"/shading", 5, 0, -1},
        {"/shading", 5, TSR_NSHADE - 1, TSR_NSHADE},
        {"/color_by_tension", 6, 1, 2},
        {"/overlay", 7, 1, 2},
        {"/antialias", 8, 1, -1},
    };
    for (size_t i = 0; i < sizeof L / sizeof L[0]; i++)
        for (int k = 0; k < 2; k++) {
            tsr_view v = side_view();
            double x = k ? L[i].bad : L[i].ok;
            switch (L[i].field) {
            case 0: v.width = (int)x; break;
            case 1: v.height = (int)x; break;
            case 2: v.exaggeration = x; break;
            case 3: v.span = x; break;
            case 4: v.kind = (int)x; break;
            case 5: v.shading = (int)x; break;
            case 6: v.color_by_tension = (int)x; break;
            case 7: v.overlay = (int)x; break;
            default: v.antialias = (int)x; break;
            }
            ts_err err;
            ts_rc rc = tsr_view_check(&v, &err);
            if (k == 0 && rc != TS_OK) fail_msg("%s = %g refused: %s", L[i].ptr, x, err.msg);
            if (k == 1 && rc != TS_ERR_RANGE) fail_msg("%s = %g accepted", L[i].ptr, x);
            if (k == 1) assert_string_equal(err.pointer, L[i].ptr);
        }
    /* text: 32 and 126 are printable, 31 and 127 are not */
    const char codes[4] = {32, 126, 31, 127};
    for (int k = 0; k < 4; k++) {
        tsr_view v = side_view();
        ts_err err;
        v.text[0] = 'a', v.text[1] = codes[k], v.text[2] = 0;
        assert_int_equal(tsr_view_check(&v, &err), k < 2 ? TS_OK : TS_ERR_PARAM);
    }
    char text[TSR_TEXT_LEN + 1];
    memset(text, 'x', sizeof text);
    text[TSR_TEXT_LEN - 1] = 0; /* TSR_TEXT_LEN - 1 characters: fits */
    tsr_view v = side_view();
    ts_err err;
    assert_int_equal(tsr_view_set_text(&v, text, &err), TS_OK);
    assert_int_equal(tsr_view_check(&v, &err), TS_OK);
    text[TSR_TEXT_LEN - 1] = 'x', text[TSR_TEXT_LEN] = 0; /* one more */
    assert_int_equal(tsr_view_set_text(&v, text, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/text");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hull_parts_pitch_with_the_hull),
        cmocka_unit_test(track_deflection_exaggerated_along_x),
        cmocka_unit_test(track_loop_direction_does_not_matter),
        cmocka_unit_test(one_shoe_per_pitch),
        cmocka_unit_test(tension_colour_ramp),
        cmocka_unit_test(tension_reference_without_a_static_tension),
        cmocka_unit_test(shoe_colour_interpolates_the_tension),
        cmocka_unit_test(ground_held_at_the_profile_start),
        cmocka_unit_test(ground_keeps_the_profile_points),
        cmocka_unit_test(wheels_turn_with_their_spin),
        cmocka_unit_test(shoes_ride_on_the_rims_and_the_teeth_follow_the_pitch),
        cmocka_unit_test(project_refuses_a_point_behind_the_camera),
        cmocka_unit_test(view_limits_are_inclusive),
    };
    return cmocka_run_group_tests_name("render/scene", tests, NULL, NULL);
}
