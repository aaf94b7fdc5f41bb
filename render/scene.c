/*
 * scene.c — from a ts_geom snapshot to world-space triangles (scene.h): the
 * ground strip, the hull and turret of the M1 silhouette, road arms, road
 * wheels, sprocket with teeth, idler, support rollers and the track as rigid
 * shoes following the deformed centreline; plus the cameras of the two views.
 *
 * The model is a pitch plane (Paper II.A): the snapshot gives x-z positions of
 * the running gear and the track pitch line of one side. This file extrudes
 * that to 3-D with the widths below and draws the same running gear and track
 * on both sides. The track centreline drawn is track_x/z (quasi-static:
 * supports' current positions + static sag) plus exaggeration times
 * track_dx/dz (the modal span vibration, Paper II.C.2 / Eqs. 1-2 solution),
 * cut into rigid shoes of about one track pitch each (78 shoes per side for the
 * M1 loop, Paper II.C.1), so the shoes' chords follow the deformed line.
 *
 * Drawing constants (metres; pictures, not model parameters — the model has no
 * width): M1 overall width 3.66 m and track (shoe) width 0.635 m are public
 * data; the hull side profile, turret, gun and wheel details are a low-poly
 * estimate of the M1 silhouette (hull 7.92 m, 2.44 m to the turret roof, sloped
 * upper glacis, turret with bustle, 120 mm gun reaching 1.91 m past the nose).
 * Leaves out: skirts (they would hide the upper spans the model is about),
 * track pins and pads, roll and yaw (pitch-plane model).
 */
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TSR_PI 3.14159265358979323846

/* ---- drawing constants ---------------------------------------------------- */

static const double OVERALL_WIDTH = 3.66;   /* [m] M1 width over the tracks */
static const double TRACK_WIDTH = 0.635;    /* [m] T-156/T-158 shoe width */
static const double LOWER_HULL_HALF = 1.05; /* [m] lower hull between the tracks */
static const double SHOE_INNER = 0.045;     /* [m] shoe body inside the pitch line, unless the
                                               geometry gives its pitch offset */
static const double SHOE_OUTER = 0.045;     /* [m] shoe body outside the pitch line */
static const double SHOE_GAP = 0.06;        /* fraction of a pitch left open at each end */
static const int SPROCKET_TEETH = 11;       /* unless the track's pitch fixes the count */
static const double GROUND_HALF = 6.0;      /* [m] ground strip half-width */
static const double GROUND_REACH = 40.0;    /* [m] ground drawn ahead of/behind the hull */
static const double GROUND_STEP = 0.25;     /* [m] ground sampling step (divides the stripes) */
static const double GROUND_STRIPE = 1.0;    /* [m] alternating ground bands (speed cue) */
static const double DEFAULT_SPAN = 13.0;    /* [m] side view width when tsr_view.span = 0 */
#define SIDE_SPAN(v) ((v)->span > 0 ? (v)->span : DEFAULT_SPAN)
static const double FOV_Y = 30.0 * TSR_PI / 180.0; /* three-quarter camera vertical field */

/* Hull side profile: (fraction of length from the rear, fraction of belly->roof
 * height), counter-clockwise. Deck at 0.52,
 * shallow upper glacis from the nose (1.00, 0.30) to the turret ring. */
static const double HULL_PROFILE[][2] = {{0.02, 0.00}, {0.80, 0.00}, {0.93, 0.17}, {1.00, 0.30},
                                         {0.99, 0.34}, {0.72, 0.52}, {0.03, 0.52}, {0.00, 0.49},
                                         {0.00, 0.10}};
static const double DECK = 0.52;
/* Turret side profile: (fraction of hull length, fraction of deck->roof). */
static const double TURRET_PROFILE[][2] = {{0.33, 0.00}, {0.66, 0.00}, {0.685, 0.45},
                                           {0.56, 1.00}, {0.28, 1.00}, {0.245, 0.80},
                                           {0.245, 0.25}, {0.30, 0.12}};
static const double TURRET_CENTRE[2] = {0.46, 0.50};
static const double TURRET_HALF_BOTTOM = 1.60, TURRET_HALF_TOP = 1.42; /* [m] */
static const double GUN_HEIGHT = 0.50;  /* fraction of deck->roof at the trunnion */
static const double GUN_ROOT = 0.675;   /* fraction of hull length where the barrel leaves */

#define NCOL 3
#define MAX_SHOES 2048 /* shoes drawn on one loop at most */
static const unsigned char COL_HULL[NCOL] = {184, 162, 112};     /* desert tan */
static const unsigned char COL_HULL_DARK[NCOL] = {150, 132, 92};
static const unsigned char COL_RUBBER[NCOL] = {46, 46, 44};
static const unsigned char COL_STEEL[NCOL] = {78, 76, 72};
static const unsigned char COL_TRACK[NCOL] = {64, 62, 58};
static const unsigned char COL_GROUND_A[NCOL] = {118, 128, 84};
static const unsigned char COL_GROUND_B[NCOL] = {104, 114, 74};
static const unsigned char COL_EARTH_A[NCOL] = {124, 100, 72};
static const unsigned char COL_EARTH_B[NCOL] = {114, 92, 66};

/* ---- mesh builder ---------------------------------------------------------- */

typedef struct {
    tsr_scene *s;
    int oom;
    int part;
    unsigned char col[NCOL];
    int body;              /* 1: coordinates are in the hull body frame */
    double ox, oz, c, sn;  /* body frame: origin, cos/sin of pitch */
} mb;

static void to_world(const mb *b, const double p[3], double w[3])
{
    if (!b->body) {
        memcpy(w, p, 3 * sizeof *w);
        return;
    }
    /* pitch positive nose-down: body +x goes to -z */
    w[0] = b->ox + p[0] * b->c + p[2] * b->sn;
    w[1] = p[1];
    w[2] = b->oz - p[0] * b->sn + p[2] * b->c;
}

static void set_paint(mb *b, int part, const unsigned char col[NCOL])
{
    b->part = part;
    memcpy(b->col, col, NCOL);
}

/* One triangle; the normal is turned to point away from centre (the solid's
 * interior point, same frame as the vertices). */
static void tri(mb *b, const double p0[3], const double p1[3], const double p2[3],
                const double centre[3])
{
    tsr_scene *s = b->s;
    if (b->oom) return;
    if (s->nv + 3 > s->cap) {
        int cap = s->cap ? 2 * s->cap : 16384;
        tsr_vertex *nv = realloc(s->v, (size_t)cap * sizeof *nv);
        if (!nv) {
            b->oom = 1;
            return;
        }
        s->v = nv;
        s->cap = cap;
    }
    double w[3][3], cw[3];
    to_world(b, p0, w[0]);
    to_world(b, p1, w[1]);
    to_world(b, p2, w[2]);
    to_world(b, centre, cw);
    double a[3], e[3], n[3];
    for (int k = 0; k < 3; k++) {
        a[k] = w[1][k] - w[0][k];
        e[k] = w[2][k] - w[0][k];
    }
    n[0] = a[1] * e[2] - a[2] * e[1];
    n[1] = a[2] * e[0] - a[0] * e[2];
    n[2] = a[0] * e[1] - a[1] * e[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 1e-12)) return; /* degenerate */
    double out = 0;
    for (int k = 0; k < 3; k++) out += n[k] * ((w[0][k] + w[1][k] + w[2][k]) / 3.0 - cw[k]);
    if (out < 0) len = -len;
    for (int i = 0; i < 3; i++) {
        tsr_vertex *v = &s->v[s->nv++];
        for (int k = 0; k < 3; k++) {
            v->pos[k] = (float)w[i][k];
            v->normal[k] = (float)(n[k] / len);
        }
        memcpy(v->rgba, b->col, NCOL);
        v->rgba[3] = (unsigned char)b->part;
    }
}

/* Prism of an x-z polygon (n points, star-shaped about (cx, cz)) between
 * y0 < y1; taper > 0 narrows both faces by taper*(z - zref) (sloped sides). */
static void extrude(mb *b, const double (*poly)[2], int n, double cx, double cz, double y0,
                    double y1, double taper, double zref)
{
    double centre[3] = {cx, 0.5 * (y0 + y1), cz};
    for (int i = 0; i < n; i++) {
        const double *p = poly[i], *q = poly[(i + 1) % n];
        double dp = taper * (p[1] - zref), dq = taper * (q[1] - zref), dc = taper * (cz - zref);
        double pf[3] = {p[0], y0 + dp, p[1]}, qf[3] = {q[0], y0 + dq, q[1]};
        double pb[3] = {p[0], y1 - dp, p[1]}, qb[3] = {q[0], y1 - dq, q[1]};
        double cf[3] = {cx, y0 + dc, cz}, cb[3] = {cx, y1 - dc, cz};
        if (n == 4) { /* convex quads (shoes, beams): two triangles per face */
            if (i < 2) {
                const double *r0 = poly[0], *r2 = poly[i + 1], *r3 = poly[i + 2];
                double d0 = taper * (r0[1] - zref), d2 = taper * (r2[1] - zref),
                       d3 = taper * (r3[1] - zref);
                double f0[3] = {r0[0], y0 + d0, r0[1]}, f2[3] = {r2[0], y0 + d2, r2[1]},
                       f3[3] = {r3[0], y0 + d3, r3[1]};
                double b0[3] = {r0[0], y1 - d0, r0[1]}, b2[3] = {r2[0], y1 - d2, r2[1]},
                       b3[3] = {r3[0], y1 - d3, r3[1]};
                tri(b, f0, f2, f3, centre);
                tri(b, b0, b3, b2, centre);
            }
        } else {
            tri(b, cf, pf, qf, centre);
            tri(b, cb, qb, pb, centre);
        }
        tri(b, pf, qf, qb, centre);
        tri(b, pf, qb, pb, centre);
    }
}

/* Disc (cylinder with its axis along y) at (x, z), radius r, between y0 < y1. */
#define DISC_MAX 64
static void disc(mb *b, double x, double z, double r, double y0, double y1, int nseg)
{
    double poly[DISC_MAX][2];
    if (nseg > DISC_MAX) nseg = DISC_MAX;
    for (int i = 0; i < nseg; i++) {
        double a = 2.0 * TSR_PI * i / nseg;
        poly[i][0] = x + r * cos(a);
        poly[i][1] = z + r * sin(a);
    }
    extrude(b, (const double(*)[2])poly, nseg, x, z, y0, y1, 0, 0);
}

/* Cylinder with its axis along x from x0 to x1 at (y, z), radius r. */
static void cylinder_x(mb *b, double x0, double x1, double y, double z, double r, int nseg)
{
    double centre[3] = {0.5 * (x0 + x1), y, z};
    for (int i = 0; i < nseg; i++) {
        double a0 = 2.0 * TSR_PI * i / nseg, a1 = 2.0 * TSR_PI * (i + 1) / nseg;
        double p00[3] = {x0, y + r * cos(a0), z + r * sin(a0)};
        double p01[3] = {x0, y + r * cos(a1), z + r * sin(a1)};
        double p10[3] = {x1, p00[1], p00[2]}, p11[3] = {x1, p01[1], p01[2]};
        double c0[3] = {x0, y, z}, c1[3] = {x1, y, z};
        tri(b, p00, p01, p11, centre);
        tri(b, p00, p11, p10, centre);
        tri(b, c0, p01, p00, centre);
        tri(b, c1, p10, p11, centre);
    }
}

/* Box between two x-z points (a beam such as a road arm), thickness th. */
static void beam(mb *b, double x0, double z0, double x1, double z1, double th, double y0,
                 double y1)
{
    double dx = x1 - x0, dz = z1 - z0, l = hypot(dx, dz);
    if (!(l > 1e-9)) return;
    double nx = -dz / l * th / 2, nz = dx / l * th / 2;
    double poly[4][2] = {{x0 + nx, z0 + nz}, {x0 - nx, z0 - nz}, {x1 - nx, z1 - nz},
                         {x1 + nx, z1 + nz}};
    extrude(b, (const double(*)[2])poly, 4, 0.5 * (x0 + x1), 0.5 * (z0 + z1), y0, y1, 0, 0);
}

/* ---- snapshot checks -------------------------------------------------------- */

static int finite_all(const double *a, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

static ts_rc check_geom(const ts_geom *g, int *isprocket, int *iidler, ts_err *err)
{
    if (g->nwheel < 0 || g->nwheel > TS_GEOM_MAX_WHEELS)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: nwheel %d outside 0..%d",
                          g->nwheel, TS_GEOM_MAX_WHEELS);
    if (g->ntrack < 3 || g->ntrack > TS_GEOM_MAX_TRACK)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: ntrack %d outside 3..%d",
                          g->ntrack, TS_GEOM_MAX_TRACK);
    if (g->nterrain < 0 || g->nterrain > TS_GEOM_MAX_TERRAIN)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: nterrain %d outside 0..%d",
                          g->nterrain, TS_GEOM_MAX_TERRAIN);
    double sc[] = {g->t, g->hull_x, g->hull_z, g->hull_pitch, g->hull_length, g->hull_height,
                   g->speed, g->track_static_tension};
    if (!finite_all(sc, (int)(sizeof sc / sizeof sc[0])) || g->hull_length < 0 ||
        g->hull_height < 0)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: non-finite or negative hull data");
    if (!isfinite(g->track_pitch) || g->track_pitch < 0) /* 0: a band without shoes */
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: track_pitch %g is not a length >= 0",
                          g->track_pitch);
    *isprocket = *iidler = -1;
    for (int i = 0; i < g->nwheel; i++) {
        const ts_geom_wheel *w = &g->wheel[i];
        double wv[] = {w->x, w->z, w->radius, w->angle, w->pivot_x, w->pivot_z};
        if (!finite_all(wv, 6) || !(w->radius > 0) || w->role < 0 || w->role >= TS_NWHEEL_ROLE)
            return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: wheel %d is invalid", i);
        if (w->role == TS_WHEEL_SPROCKET && *isprocket < 0) *isprocket = i;
        if (w->role == TS_WHEEL_IDLER && *iidler < 0) *iidler = i;
    }
    if (*isprocket < 0 || *iidler < 0)
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: needs a sprocket and an idler");
    if (!finite_all(g->track_x, g->ntrack) || !finite_all(g->track_z, g->ntrack) ||
        !finite_all(g->track_dx, g->ntrack) || !finite_all(g->track_dz, g->ntrack) ||
        !finite_all(g->track_tension, g->ntrack))
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: non-finite track point");
    if (!finite_all(g->terrain_x, g->nterrain) || !finite_all(g->terrain_z, g->nterrain))
        return ts_err_set(err, TS_ERR_PARAM, NULL, "geometry: non-finite terrain point");
    for (int i = 1; i < g->nterrain; i++)
        if (g->terrain_x[i] < g->terrain_x[i - 1])
            return ts_err_set(err, TS_ERR_PARAM, NULL,
                              "geometry: terrain_x must not decrease (point %d)", i);
    return TS_OK;
}

/* ---- the parts ------------------------------------------------------------- */

/* Shoe body inside the pitch line: the geometry's pitch offset (the shoes ride
 * on the wheels' rims), else the drawing's default. */
static double shoe_inner(const ts_geom *g)
{
    return g->track_pitch_offset > 0 ? g->track_pitch_offset : SHOE_INNER;
}

/* Teeth of a sprocket of pitch radius r meshing with shoes of this pitch:
 * r = pitch / (2 sin(pi / n)), the nearest whole n (the M1's 0.180 m pitch on
 * its 0.327 m radius: 11); the drawing's default without a pitch. */
static int sprocket_teeth(double pitch, double r)
{
    if (!(pitch > 0 && pitch < 2.0 * r)) return SPROCKET_TEETH;
    long n = lround(TSR_PI / asin(0.5 * pitch / r));
    return n < 6 ? 6 : n > 16 ? 16 : (int)n; /* the drawing holds at most 16 */
}

static double terrain_at(const ts_geom *g, double x)
{
    int n = g->nterrain;
    if (n == 0) return 0.0;
    if (x <= g->terrain_x[0]) return g->terrain_z[0];
    if (x >= g->terrain_x[n - 1]) return g->terrain_z[n - 1];
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (g->terrain_x[mid] <= x) lo = mid;
        else hi = mid;
    }
    double dx = g->terrain_x[hi] - g->terrain_x[lo];
    double f = dx > 0 ? (x - g->terrain_x[lo]) / dx : 0.0;
    return g->terrain_z[lo] + f * (g->terrain_z[hi] - g->terrain_z[lo]);
}

/* One ground segment [xa, xb]: top surface and the near cut face. */
static void ground_segment(mb *b, const ts_geom *g, double xa, double xb, double zbot)
{
    double za = terrain_at(g, xa), zb = terrain_at(g, xb);
    double xm = 0.5 * (xa + xb);
    int odd = (int)((long)floor(xm / GROUND_STRIPE) & 1);
    set_paint(b, TSR_PART_TERRAIN, odd ? COL_GROUND_A : COL_GROUND_B);
    double below[3] = {xm, 0.0, fmin(za, zb) - 1.0};
    double a0[3] = {xa, -GROUND_HALF, za}, b0[3] = {xb, -GROUND_HALF, zb};
    double a1[3] = {xa, GROUND_HALF, za}, b1[3] = {xb, GROUND_HALF, zb};
    tri(b, a0, b0, b1, below);
    tri(b, a0, b1, a1, below);
    set_paint(b, TSR_PART_TERRAIN, odd ? COL_EARTH_A : COL_EARTH_B);
    double inside[3] = {xm, 0.0, zbot};
    double ad[3] = {xa, -GROUND_HALF, zbot}, bd[3] = {xb, -GROUND_HALF, zbot};
    tri(b, a0, ad, bd, inside);
    tri(b, a0, bd, b0, inside);
}

static void build_ground(mb *b, const ts_geom *g, double xc, double reach)
{
    double x0 = xc - reach, x1 = xc + reach;
    double zmin = terrain_at(g, x0);
    for (int i = 0; i < g->nterrain; i++) zmin = fmin(zmin, g->terrain_z[i]);
    double zbot = zmin - 4.0;
    /* uniform samples, plus the profile's own points so bump corners stay sharp */
    double xa = floor(x0 / GROUND_STEP) * GROUND_STEP;
    int j = 0;
    while (j < g->nterrain && g->terrain_x[j] <= xa) j++;
    while (xa < x1) {
        double xb = (floor(xa / GROUND_STEP + 1e-9) + 1.0) * GROUND_STEP;
        if (j < g->nterrain && g->terrain_x[j] < xb - 1e-9) xb = g->terrain_x[j++];
        if (xb > xa + 1e-9) ground_segment(b, g, xa, xb, zbot);
        xa = xb;
    }
}

/* The track loop: arc length is measured on the quasi-static centreline
 * (track_x/z), so shoe pins are material points; each pin is then placed at the
 * same segment and fraction of the deformed line (centreline + exaggeration x
 * modal deflection). The modal deflection thus moves shoes across the line, not
 * along it, and shoes outside a vibrating span stay where they are. */
typedef struct {
    double px[TS_GEOM_MAX_TRACK], pz[TS_GEOM_MAX_TRACK]; /* deformed points */
    double cum[TS_GEOM_MAX_TRACK + 1];                   /* quasi-static arc length */
    int n;
} loop;

static void loop_point(const loop *lp, double s, double *x, double *z, double *seg_f)
{
    double L = lp->cum[lp->n];
    s = fmod(s, L);
    if (s < 0) s += L;
    int lo = 0, hi = lp->n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (lp->cum[mid] <= s) lo = mid;
        else hi = mid;
    }
    int a = lo, c = (lo + 1) % lp->n;
    double len = lp->cum[lo + 1] - lp->cum[lo];
    double f = len > 0 ? (s - lp->cum[lo]) / len : 0.0;
    *x = lp->px[a] + f * (lp->px[c] - lp->px[a]);
    *z = lp->pz[a] + f * (lp->pz[c] - lp->pz[a]);
    if (seg_f) *seg_f = lo + f;
}

static void build_track(mb *b, const ts_geom *g, const tsr_view *v, double phase_angle,
                        double phase_radius, double tension_ref, double yc_sign)
{
    loop *lp = malloc(sizeof *lp);
    if (!lp) {
        b->oom = 1;
        return;
    }
    int n = g->ntrack;
    lp->n = n;
    double area = 0;
    for (int i = 0; i < n; i++) {
        lp->px[i] = g->track_x[i] + v->exaggeration * g->track_dx[i];
        lp->pz[i] = g->track_z[i] + v->exaggeration * g->track_dz[i];
    }
    lp->cum[0] = 0;
    for (int i = 0; i < n; i++) {
        int k = (i + 1) % n;
        lp->cum[i + 1] = lp->cum[i] + hypot(g->track_x[k] - g->track_x[i],
                                            g->track_z[k] - g->track_z[i]);
        area += g->track_x[i] * g->track_z[k] - g->track_x[k] * g->track_z[i];
    }
    double L = lp->cum[n];
    if (!(L > 0) || !(g->track_pitch > 0)) { /* no loop, or no pitch to draw shoes at */
        free(lp);
        return;
    }
    double orient = area >= 0 ? 1.0 : -1.0; /* +1: counter-clockwise in (x right, z up) */
    /* at most MAX_SHOES (a pitch far below the loop's length would make
     * millions of boxes; the M1 has 78) */
    double shoes = L / g->track_pitch;
    int nshoe = shoes > MAX_SHOES ? MAX_SHOES : (int)lround(shoes);
    if (nshoe < 8) nshoe = 8;
    double p = L / nshoe;
    /* Forward rolling (positive sprocket spin) moves the top run forward, i.e.
     * clockwise round the loop: shoes advance by -orient * angle * radius. */
    double s0 = fmod(-orient * phase_angle * phase_radius, p);
    double yc = yc_sign * (OVERALL_WIDTH - TRACK_WIDTH) / 2;
    const double inner = shoe_inner(g);
    for (int i = 0; i < nshoe; i++) {
        double sa = s0 + i * p, ax, az, bx, bz, mx, mz, segf;
        loop_point(lp, sa, &ax, &az, NULL);
        loop_point(lp, sa + p, &bx, &bz, NULL);
        loop_point(lp, sa + 0.5 * p, &mx, &mz, &segf);
        double tx = bx - ax, tz = bz - az, l = hypot(tx, tz);
        if (!(l > 1e-9)) continue;
        tx /= l;
        tz /= l;
        double nx = orient * tz, nz = -orient * tx; /* outward */
        double gx = tx * SHOE_GAP * l, gz = tz * SHOE_GAP * l;
        double poly[4][2] = {
            {ax + gx - nx * inner, az + gz - nz * inner},
            {bx - gx - nx * inner, bz - gz - nz * inner},
            {bx - gx + nx * SHOE_OUTER, bz - gz + nz * SHOE_OUTER},
            {ax + gx + nx * SHOE_OUTER, az + gz + nz * SHOE_OUTER},
        };
        unsigned char col[NCOL];
        memcpy(col, COL_TRACK, NCOL);
        if (v->color_by_tension && tension_ref > 0) {
            int k0 = (int)segf, k1 = (k0 + 1) % n;
            double f = segf - k0;
            double T = (1 - f) * g->track_tension[k0] + f * g->track_tension[k1];
            tsr_tension_color(T / tension_ref, col);
        }
        set_paint(b, TSR_PART_TRACK, col);
        double cx = 0.25 * (poly[0][0] + poly[1][0] + poly[2][0] + poly[3][0]);
        double cz = 0.25 * (poly[0][1] + poly[1][1] + poly[2][1] + poly[3][1]);
        extrude(b, (const double(*)[2])poly, 4, cx, cz, yc - TRACK_WIDTH / 2,
                yc + TRACK_WIDTH / 2, 0, 0);
    }
    free(lp);
}

/* Flat disc (a lid facing direction out = -1 or +1 along y) at y: cheap
 * detail on the outer faces of wheels. */
static void lid(mb *b, double x, double z, double r, double y, double out, int nseg)
{
    double behind[3] = {x, y - out, z}, c[3] = {x, y, z};
    for (int i = 0; i < nseg; i++) {
        double a0 = 2.0 * TSR_PI * i / nseg, a1 = 2.0 * TSR_PI * (i + 1) / nseg;
        double p0[3] = {x + r * cos(a0), y, z + r * sin(a0)};
        double p1[3] = {x + r * cos(a1), y, z + r * sin(a1)};
        tri(b, c, p0, p1, behind);
    }
}

/* Spoked look for a wheel's outer face at y = yface: hub and lightening holes
 * that turn with the spin angle (so animations show rolling). */
static void wheel_face(mb *b, const ts_geom_wheel *w, double yface, double out, int nholes)
{
    double r = w->radius;
    set_paint(b, b->part, COL_HULL_DARK);
    for (int k = 0; k < nholes; k++) {
        /* spin positive = forward rolling = clockwise seen from -y (x right, z up) */
        double a = -w->angle + 2.0 * TSR_PI * k / nholes;
        lid(b, w->x + 0.52 * r * cos(a), w->z + 0.52 * r * sin(a), 0.13 * r, yface + 0.005 * out,
            out, 8);
    }
    set_paint(b, b->part, COL_STEEL);
    lid(b, w->x, w->z, 0.2 * r, yface + 0.01 * out, out, 10);
}

/* A dual wheel (road wheel, idler, roller) on the side whose track centre is yc. */
static void dual_wheel(mb *b, const ts_geom_wheel *w, int part, double yc, double half_w,
                       double out, int nholes)
{
    double r = w->radius, gap = 0.06;
    int nseg = r > 0.2 ? 22 : 14;
    set_paint(b, part, COL_RUBBER);
    disc(b, w->x, w->z, r, yc - half_w, yc - gap, nseg);
    disc(b, w->x, w->z, r, yc + gap, yc + half_w, nseg);
    set_paint(b, part, COL_HULL);
    double yo = yc + out * (half_w + 0.005); /* just outside the outer tyre face */
    lid(b, w->x, w->z, 0.8 * r, yo, out, nseg);
    wheel_face(b, w, yo, out, nholes);
}

static void sprocket(mb *b, const ts_geom_wheel *w, double pitch, double yc, double out)
{
    /* toothed rings just outboard of the track edge, hub disc inside */
    double r = w->radius, rt = r + 0.075, rr = r - 0.035;
    int nt = sprocket_teeth(pitch, r);
    double poly[4 * 16][2];
    int np = 0;
    for (int k = 0; k < nt && np + 4 <= 64; k++) {
        double a0 = -w->angle + 2.0 * TSR_PI * k / nt, da = 2.0 * TSR_PI / nt;
        double f[4] = {0.0, 0.30, 0.55, 0.85};
        double rad[4] = {rr, rt, rt, rr};
        for (int q = 0; q < 4; q++) {
            poly[np][0] = w->x + rad[q] * cos(a0 + f[q] * da);
            poly[np][1] = w->z + rad[q] * sin(a0 + f[q] * da);
            np++;
        }
    }
    double edge = yc + out * TRACK_WIDTH / 2;
    set_paint(b, TSR_PART_SPROCKET, COL_STEEL);
    double y0 = out < 0 ? edge - 0.10 : edge, y1 = out < 0 ? edge : edge + 0.10;
    extrude(b, (const double(*)[2])poly, np, w->x, w->z, y0, y1, 0, 0);
    set_paint(b, TSR_PART_SPROCKET, COL_HULL);
    disc(b, w->x, w->z, 0.7 * r, yc - TRACK_WIDTH / 2, yc + TRACK_WIDTH / 2, 16);
    wheel_face(b, w, out < 0 ? y0 : y1, out, 6);
}

/* Hull, turret, gun in the body frame; sets the scene's hull box. */
static void build_hull(mb *b, tsr_scene *s, const ts_geom *g, int isp, int iid)
{
    const ts_geom_wheel *sp = &g->wheel[isp], *id = &g->wheel[iid];
    double c = cos(g->hull_pitch), sn = sin(g->hull_pitch);
    /* world -> body (inverse of to_world) for hull-fixed points */
#define BX(x, z) (((x) - g->hull_x) * c - ((z) - g->hull_z) * sn)
#define BZ(x, z) (((x) - g->hull_x) * sn + ((z) - g->hull_z) * c)
    /* the M1 silhouette's own size: the snapshot's hull_length/height are
     * framing hints of the model (e.g. the track envelope), not a drawing */
    const double L = TSR_HULL_LENGTH, H = TSR_HULL_HEIGHT;
    double spx = BX(sp->x, sp->z), spz = BZ(sp->x, sp->z);
    double idx = BX(id->x, id->z), idz = BZ(id->x, id->z);
    double rear = fmin(spx - sp->radius, idx - id->radius);
    double front = fmax(spx + sp->radius, idx + id->radius);
    double x0 = rear - 0.45 * (L - (front - rear));
    double zb = fmin(spz, idz) - TSR_BELLY_BELOW_AXLES;
    double Hh = H - TSR_GROUND_CLEARANCE;
    if (Hh < 0.5) Hh = 0.5;
    /* fender line: above the highest support (sprocket, idler, rollers) + track */
    double zf = fmax(spz + sp->radius, idz + id->radius);
    for (int i = 0; i < g->nwheel; i++)
        if (g->wheel[i].role == TS_WHEEL_ROLLER)
            zf = fmax(zf, BZ(g->wheel[i].x, g->wheel[i].z) + g->wheel[i].radius);
    zf += shoe_inner(g) + SHOE_OUTER + 0.06;
    if (zf > zb + DECK * Hh - 0.05) zf = zb + DECK * Hh - 0.05;
    if (zf < zb + 0.1) zf = zb + 0.1;
#undef BX
#undef BZ
    s->x_rear = x0;
    s->x_front = x0 + L;
    s->z_belly = zb;
    s->z_roof = zb + Hh;

    b->body = 1;
    b->ox = g->hull_x;
    b->oz = g->hull_z;
    b->c = c;
    b->sn = sn;
    int nh = (int)(sizeof HULL_PROFILE / sizeof HULL_PROFILE[0]);
    double prof[16][2];
    for (int i = 0; i < nh; i++) {
        prof[i][0] = x0 + HULL_PROFILE[i][0] * L;
        prof[i][1] = zb + HULL_PROFILE[i][1] * Hh;
    }
    /* split the profile at the fender line: narrow below, full width above */
    double lower[20][2], upper[20][2];
    int nl = 0, nu = 0;
    for (int i = 0; i < nh; i++) {
        const double *p = prof[i], *q = prof[(i + 1) % nh];
        int pin = p[1] <= zf, qin = q[1] <= zf;
        if (pin) memcpy(lower[nl++], p, sizeof lower[0]);
        else memcpy(upper[nu++], p, sizeof upper[0]);
        if (pin != qin) {
            double f = (zf - p[1]) / (q[1] - p[1]);
            double xcut[2] = {p[0] + f * (q[0] - p[0]), zf};
            memcpy(lower[nl++], xcut, sizeof xcut);
            memcpy(upper[nu++], xcut, sizeof xcut);
        }
    }
    set_paint(b, TSR_PART_HULL, COL_HULL_DARK);
    if (nl >= 3) {
        double lcx = 0, lcz = 0;
        for (int i = 0; i < nl; i++) lcx += lower[i][0] / nl, lcz += lower[i][1] / nl;
        extrude(b, (const double(*)[2])lower, nl, lcx, lcz, -LOWER_HULL_HALF, LOWER_HULL_HALF,
                0, 0);
    }
    set_paint(b, TSR_PART_HULL, COL_HULL);
    if (nu >= 3) {
        double ucx = 0, ucz = 0;
        for (int i = 0; i < nu; i++) ucx += upper[i][0] / nu, ucz += upper[i][1] / nu;
        extrude(b, (const double(*)[2])upper, nu, ucx, ucz, -OVERALL_WIDTH / 2, OVERALL_WIDTH / 2,
                0, 0);
    }
    /* turret with sloped sides */
    double zd = zb + DECK * Hh, ht = zb + Hh - zd;
    int nt = (int)(sizeof TURRET_PROFILE / sizeof TURRET_PROFILE[0]);
    double tp[16][2];
    for (int i = 0; i < nt; i++) {
        tp[i][0] = x0 + TURRET_PROFILE[i][0] * L;
        tp[i][1] = zd + TURRET_PROFILE[i][1] * ht;
    }
    set_paint(b, TSR_PART_TURRET, COL_HULL);
    double taper = (TURRET_HALF_BOTTOM - TURRET_HALF_TOP) / ht;
    extrude(b, (const double(*)[2])tp, nt, x0 + TURRET_CENTRE[0] * L, zd + TURRET_CENTRE[1] * ht,
            -TURRET_HALF_BOTTOM, TURRET_HALF_BOTTOM, taper, zd);
    /* commander's weapon station on the roof (right side) */
    set_paint(b, TSR_PART_TURRET, COL_HULL_DARK);
    double cup[4][2] = {{x0 + 0.36 * L, zd + ht - 0.01}, {x0 + 0.43 * L, zd + ht - 0.01},
                        {x0 + 0.42 * L, zd + ht + 0.16}, {x0 + 0.37 * L, zd + ht + 0.16}};
    extrude(b, (const double(*)[2])cup, 4, x0 + 0.395 * L, zd + ht + 0.07, -0.95, -0.35, 0, 0);
    /* gun: mantlet, barrel, bore evacuator */
    double gz = zd + GUN_HEIGHT * ht, gx0 = x0 + GUN_ROOT * L, gx1 = x0 + L + TSR_GUN_REACH;
    set_paint(b, TSR_PART_GUN, COL_HULL_DARK);
    double mant[4][2] = {{gx0 - 0.25, gz - 0.28}, {gx0 + 0.12, gz - 0.22},
                         {gx0 + 0.12, gz + 0.22}, {gx0 - 0.25, gz + 0.28}};
    extrude(b, (const double(*)[2])mant, 4, gx0 - 0.05, gz, -0.45, 0.45, 0, 0);
    set_paint(b, TSR_PART_GUN, COL_HULL);
    double gl = gx1 - gx0;
    cylinder_x(b, gx0, gx0 + 0.55 * gl, 0.0, gz, 0.10, 12);
    cylinder_x(b, gx0 + 0.55 * gl, gx1, 0.0, gz, 0.08, 12);
    cylinder_x(b, gx0 + 0.62 * gl, gx0 + 0.74 * gl, 0.0, gz, 0.125, 12);
    /* camera aim (world): the centre of the hull box */
    const double box_centre[3] = {x0 + 0.5 * L, 0.0, zb + 0.5 * Hh};
    to_world(b, box_centre, s->aim);
    b->body = 0;
    double reach = 0.5 * L + TSR_GUN_REACH;
    s->radius = sqrt(reach * reach + 0.25 * Hh * Hh + 0.25 * OVERALL_WIDTH * OVERALL_WIDTH);
}

static void build_running_gear(mb *b, const ts_geom *g, int side)
{
    double out = side < 0 ? -1.0 : 1.0; /* side < 0: right (y < 0) */
    double yc = out * (OVERALL_WIDTH - TRACK_WIDTH) / 2;
    double wheel_half = 0.275; /* dual road wheels inside the guide horns */
    for (int i = 0; i < g->nwheel; i++) {
        const ts_geom_wheel *w = &g->wheel[i];
        switch (w->role) {
        case TS_WHEEL_ROAD: {
            /* road arm inboard of the wheel, from the hull pivot to the hub */
            set_paint(b, TSR_PART_ROAD_ARM, COL_STEEL);
            double yi = yc - out * wheel_half; /* inner face of the wheel */
            double ya = yi - out * 0.02, yb = yi - out * 0.16;
            beam(b, w->pivot_x, w->pivot_z, w->x, w->z, 0.14, fmin(ya, yb), fmax(ya, yb));
            double hub_a = yi, hub_b = yi - out * 0.2;
            disc(b, w->pivot_x, w->pivot_z, 0.09, fmin(hub_a, hub_b), fmax(hub_a, hub_b), 10);
            dual_wheel(b, w, TSR_PART_ROAD_WHEEL, yc, wheel_half, out, 6);
            break;
        }
        case TS_WHEEL_IDLER: dual_wheel(b, w, TSR_PART_IDLER, yc, wheel_half, out, 6); break;
        case TS_WHEEL_ROLLER: dual_wheel(b, w, TSR_PART_ROLLER, yc, 0.2, out, 3); break;
        case TS_WHEEL_SPROCKET:
            sprocket(b, w, g->track_pitch, yc, out);
            break;
        default: break;
        }
    }
}

/* ---- public ---------------------------------------------------------------- */

tsr_scene *tsr_scene_make(ts_err *err)
{
    tsr_scene *s = calloc(1, sizeof *s);
    if (!s) ts_err_set(err, TS_ERR_NOMEM, NULL, "render: out of memory");
    return s;
}

void tsr_scene_free(tsr_scene *s)
{
    if (!s) return;
    free(s->v);
    free(s);
}

void tsr_tension_color(double u, unsigned char rgb[3])
{
    /* slack (blue) -> static (light grey) -> twice static and above (red) */
    static const double lo[3] = {40, 90, 220}, mid[3] = {205, 205, 200}, hi[3] = {215, 40, 30};
    if (!isfinite(u)) u = 1.0;
    double f = fmin(fmax(u, 0.0), 2.0);
    for (int k = 0; k < 3; k++) {
        double val = f < 1 ? lo[k] + f * (mid[k] - lo[k]) : mid[k] + (f - 1) * (hi[k] - mid[k]);
        rgb[k] = (unsigned char)lround(val);
    }
}

ts_rc tsr_scene_update(tsr_scene *s, const ts_geom *g, const tsr_view *v, ts_err *err)
{
    ts_rc rc = tsr_view_check(v, err);
    if (rc != TS_OK) return rc;
    int isp = -1, iid = -1;
    rc = check_geom(g, &isp, &iid, err);
    if (rc != TS_OK) return rc;
    s->nv = 0;
    s->t = g->t;
    s->speed = g->speed;
    s->gear = g->gear;
    s->color_by_tension = v->color_by_tension;
    double tref = g->track_static_tension;
    if (!(tref > 0)) {
        tref = 0;
        for (int i = 0; i < g->ntrack; i++) tref = fmax(tref, 0.5 * g->track_tension[i]);
    }
    s->tension_ref = tref;
    mb b = {.s = s};
    build_hull(&b, s, g, isp, iid);
    /* The side view is orthographic along y: it shows the ground only within
     * its span, and the left (y > 0) running gear and track lie exactly behind
     * the right ones (same x-z outline, farther away), so they are left out. */
    int side_view = v->kind == TSR_VIEW_SIDE;
    double span = SIDE_SPAN(v);
    double aspect = (double)v->width / v->height;
    double reach = side_view ? 0.5 * span * fmax(1.0, 1.0 / aspect) + 2.0 : GROUND_REACH;
    build_ground(&b, g, s->aim[0], reach);
    for (int side = -1; side <= (side_view ? -1 : 1); side += 2) {
        build_running_gear(&b, g, side);
        build_track(&b, g, v, g->wheel[isp].angle, g->wheel[isp].radius, tref, side);
    }
    if (b.oom) {
        s->nv = 0;
        return ts_err_set(err, TS_ERR_NOMEM, NULL, "render: out of memory building the scene");
    }
    return TS_OK;
}

void tsr_scene_hull_box(const tsr_scene *s, double *x_rear, double *x_front, double *z_belly,
                        double *z_roof)
{
    *x_rear = s->x_rear;
    *x_front = s->x_front;
    *z_belly = s->z_belly;
    *z_roof = s->z_roof;
}

/* ---- cameras ----------------------------------------------------------------- */

static void mat_mul(const double a[16], const double b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double acc = 0;
            for (int k = 0; k < 4; k++) acc += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = acc;
        }
}

static void look_at(const double eye[3], const double at[3], const double up[3], double m[16])
{
    double f[3], r[3], u[3], l;
    for (int k = 0; k < 3; k++) f[k] = at[k] - eye[k];
    l = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int k = 0; k < 3; k++) f[k] /= l;
    r[0] = f[1] * up[2] - f[2] * up[1];
    r[1] = f[2] * up[0] - f[0] * up[2];
    r[2] = f[0] * up[1] - f[1] * up[0];
    l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int k = 0; k < 3; k++) r[k] /= l;
    u[0] = r[1] * f[2] - r[2] * f[1];
    u[1] = r[2] * f[0] - r[0] * f[2];
    u[2] = r[0] * f[1] - r[1] * f[0];
    double t[16] = {r[0], u[0], -f[0], 0, r[1], u[1], -f[1], 0, r[2], u[2], -f[2], 0,
                    -(r[0] * eye[0] + r[1] * eye[1] + r[2] * eye[2]),
                    -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]),
                    f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2], 1};
    memcpy(m, t, sizeof t);
}

static void mvp_d(const tsr_scene *s, const tsr_view *v, double m[16])
{
    double aspect = (double)v->width / v->height, view[16], proj[16] = {0};
    if (v->kind == TSR_VIEW_THREE_QUARTER) {
        /* from front-right, above: direction (0.62, -0.72, 0.32) */
        double dir[3] = {0.62, -0.72, 0.32}, l = sqrt(0.62 * 0.62 + 0.72 * 0.72 + 0.32 * 0.32);
        double fovx = 2 * atan(tan(FOV_Y / 2) * aspect);
        double half = fmin(FOV_Y, fovx) / 2;
        double dist = 0.8 * s->radius / sin(half); /* sphere round hull + gun, a bit cropped */
        double eye[3], up[3] = {0, 0, 1};
        for (int k = 0; k < 3; k++) eye[k] = s->aim[k] + dist * dir[k] / l;
        look_at(eye, s->aim, up, view);
        double n = 0.5, f = dist + 4 * s->radius + 2 * GROUND_REACH, t = 1 / tan(FOV_Y / 2);
        proj[0] = t / aspect;
        proj[5] = t;
        proj[10] = -(f + n) / (f - n);
        proj[11] = -1;
        proj[14] = -2 * f * n / (f - n);
    } else {
        double eye[3] = {s->aim[0], s->aim[1] - 50.0, s->aim[2]}, up[3] = {0, 0, 1};
        look_at(eye, s->aim, up, view);
        double hw = SIDE_SPAN(v) / 2, hh = hw / aspect;
        double n = 1.0, f = 100.0;
        proj[0] = 1 / hw;
        proj[5] = 1 / hh;
        proj[10] = -2 / (f - n);
        proj[14] = -(f + n) / (f - n);
        proj[15] = 1;
    }
    mat_mul(proj, view, m);
}

void tsr_scene_mvp(const tsr_scene *s, const tsr_view *v, float mvp[16])
{
    double m[16];
    mvp_d(s, v, m);
    for (int i = 0; i < 16; i++) mvp[i] = (float)m[i];
}

ts_rc tsr_project(const tsr_scene *s, const tsr_view *v, double x, double y, double z,
                  double *px, double *py, ts_err *err)
{
    ts_rc rc = tsr_view_check(v, err);
    if (rc != TS_OK) return rc;
    double m[16], p[4] = {x, y, z, 1}, c[4];
    mvp_d(s, v, m);
    for (int r = 0; r < 4; r++) {
        c[r] = 0;
        for (int k = 0; k < 4; k++) c[r] += m[k * 4 + r] * p[k];
    }
    if (!(c[3] > 1e-9)) return ts_err_set(err, TS_ERR_RANGE, NULL, "point behind the camera");
    *px = (c[0] / c[3] + 1) / 2 * v->width;
    *py = (1 - c[1] / c[3]) / 2 * v->height;
    return TS_OK;
}
