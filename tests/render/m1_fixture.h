/*
 * m1_fixture.h — hand-built ts_geom snapshots of the M1 for the renderer's
 * tests and benchmark (no scenario provides geometry to render/ tests).
 *
 * Layout: sim/data/defaults/vehicle.json (sprocket at x = 0, z = 0.70, pitch
 * radius 0.327; support rollers at 1.83 / 4.55 m, z = 0.84, r = 0.125; idler at
 * 5.88 m, z = 0.60, r = 0.3175; road wheels at 0.80 + 0.725 k, z = 0.41,
 * r = 0.3175). Trailing road arms a = 0.45 m, 30 deg below horizontal at
 * static, pivot ahead of the hub; hull CG at (2.98, 1.05); track pitch line
 * 0.045 m outside the wheels' rims and on the sprocket's pitch circle — all as
 * the reference parameter set's nominal layout (estimates, [E] there).
 *
 * The track is the belt round those circles (outer common tangents and wraps,
 * counter-clockwise in x-z), with the three upper free spans sampled every
 * ~0.1 m so that a test can put a modal shape on them. A road wheel pushed up
 * by a bump makes a concave corner: the belt then just passes under the wheel.
 * Terrain: flat, optionally with the paper's large obstacle (1 ft x 25 ft,
 * Paper II.D) as a 1-cos bump.
 */
#ifndef TS_M1_FIXTURE_H
#define TS_M1_FIXTURE_H

#include <math.h>
#include <string.h>

#include "sim/geometry.h"

#define TSR_PI 3.14159265358979323846
#define M1_NROAD 7
#define M1_ARM 0.45
#define M1_WRAP 0.045

typedef struct m1_state {
    ts_geom g;
    int span[TS_GEOM_MAX_TRACK]; /* 1..3: upper free span (idler->front roller, front->rear
                                    roller, rear roller->sprocket); 0 elsewhere */
    double xi[TS_GEOM_MAX_TRACK]; /* position along that span, 0..1 */
} m1_state;

static inline double m1_terrain(const ts_geom *g, double x)
{
    int n = g->nterrain;
    if (n == 0) return 0;
    if (x <= g->terrain_x[0]) return g->terrain_z[0];
    if (x >= g->terrain_x[n - 1]) return g->terrain_z[n - 1];
    int i = 0;
    while (g->terrain_x[i + 1] < x) i++;
    double f = (x - g->terrain_x[i]) / (g->terrain_x[i + 1] - g->terrain_x[i]);
    return g->terrain_z[i] + f * (g->terrain_z[i + 1] - g->terrain_z[i]);
}

/* Flat ground from x0 to x1, with a 1-cos bump of height h, length l at xb (h = 0: none). */
static inline void m1_set_terrain(ts_geom *g, double x0, double x1, double xb, double h, double l)
{
    int n = 0;
    g->terrain_x[n] = x0, g->terrain_z[n++] = 0;
    if (h > 0) {
        for (int k = 0; k <= 40; k++) {
            double s = l * k / 40.0;
            g->terrain_x[n] = xb + s;
            g->terrain_z[n++] = 0.5 * h * (1 - cos(2 * TSR_PI * s / l));
        }
    }
    g->terrain_x[n] = x1, g->terrain_z[n++] = 0;
    g->nterrain = n;
}

typedef struct {
    double x, z, r;
} m1_circle;

static inline void m1_push(m1_state *s, double x, double z, int span, double xi)
{
    ts_geom *g = &s->g;
    if (g->ntrack >= TS_GEOM_MAX_TRACK) return;
    g->track_x[g->ntrack] = x;
    g->track_z[g->ntrack] = z;
    g->track_dx[g->ntrack] = 0;
    g->track_dz[g->ntrack] = 0;
    g->track_tension[g->ntrack] = g->track_static_tension;
    s->span[g->ntrack] = span;
    s->xi[g->ntrack] = xi;
    g->ntrack++;
}

/* Belt round circles c[0..n-1] in counter-clockwise order; spans[i] tags the
 * straight run from circle i to i+1 (0 = not a tagged span). */
static inline void m1_belt(m1_state *s, const m1_circle *c, int n, const int *spans)
{
    double tin[16][2], tout[16][2]; /* tangent points: arriving at / leaving circle i */
    double ux[16], uz[16];          /* direction of the run from circle i to i+1 */
    for (int i = 0; i < n; i++) {
        const m1_circle *a = &c[i], *b = &c[(i + 1) % n];
        double dx = b->x - a->x, dz = b->z - a->z, D = hypot(dx, dz);
        dx /= D, dz /= D;
        double sb = (a->r - b->r) / D, cb = sqrt(1 - sb * sb);
        double nx = cb * dz + sb * dx, nz = cb * -dx + sb * dz; /* right of travel = outside */
        tout[i][0] = a->x + a->r * nx, tout[i][1] = a->z + a->r * nz;
        tin[(i + 1) % n][0] = b->x + b->r * nx, tin[(i + 1) % n][1] = b->z + b->r * nz;
        ux[i] = tin[(i + 1) % n][0] - tout[i][0], uz[i] = tin[(i + 1) % n][1] - tout[i][1];
        double l = hypot(ux[i], uz[i]);
        ux[i] /= l, uz[i] /= l;
    }
    for (int i = 0; i < n; i++) {
        const m1_circle *a = &c[i];
        int ip = (i + n - 1) % n;
        double cross = ux[ip] * uz[i] - uz[ip] * ux[i];
        if (cross > 1e-9) { /* convex corner: wrap counter-clockwise */
            double a0 = atan2(tin[i][1] - a->z, tin[i][0] - a->x);
            double a1 = atan2(tout[i][1] - a->z, tout[i][0] - a->x);
            while (a1 < a0) a1 += 2 * TSR_PI;
            int k = (int)ceil((a1 - a0) / (5 * TSR_PI / 180));
            for (int j = 0; j <= k; j++) {
                double t = a0 + (a1 - a0) * j / (k ? k : 1);
                m1_push(s, a->x + a->r * cos(t), a->z + a->r * sin(t), 0, 0);
            }
        } else { /* concave (wheel pushed up): one point under the wheel */
            double bx = -uz[ip] - uz[i], bz = ux[ip] + ux[i], l = hypot(bx, bz);
            m1_push(s, a->x - a->r * bx / l, a->z - a->r * bz / l, 0, 0);
        }
        if (spans[i]) { /* sample the free span */
            int ni = (i + 1) % n;
            double L = hypot(tin[ni][0] - tout[i][0], tin[ni][1] - tout[i][1]);
            int k = (int)ceil(L / 0.1);
            for (int j = 1; j < k; j++) {
                double f = (double)j / k;
                m1_push(s, tout[i][0] + f * (tin[ni][0] - tout[i][0]),
                        tout[i][1] + f * (tin[ni][1] - tout[i][1]), spans[i], f);
            }
        }
    }
}

/* The M1 with its sprocket layout origin at world x = X, on g's terrain
 * (set it first with m1_set_terrain), hull heave and pitch following the
 * ground under the road wheels, wheels rolled by X. */
static inline void m1_pose(m1_state *s, double X, double t, double speed)
{
    ts_geom *g = &s->g;
    static const double road_x[M1_NROAD] = {0.800, 1.525, 2.250, 2.975, 3.700, 4.425, 5.150};
    const double cg_x = 2.98, cg_z = 1.05, r_road = 0.3175, r_sp = 0.327;
    g->t = t;
    g->speed = speed;
    g->gear = 1;
    g->hull_length = 7.92;
    g->hull_height = 2.44;
    g->track_static_tension = 66700.0;
    g->track_pitch = 0.180; /* sim/data/defaults/track.json */
    /* least-squares line through the ground under the road wheels */
    double sx = 0, sz = 0, sxx = 0, sxz = 0;
    for (int i = 0; i < M1_NROAD; i++) {
        double x = road_x[i], z = m1_terrain(g, X + x);
        sx += x, sz += z, sxx += x * x, sxz += x * z;
    }
    double b = (M1_NROAD * sxz - sx * sz) / (M1_NROAD * sxx - sx * sx);
    double a = (sz - b * sx) / M1_NROAD;
    double pitch = -atan(b); /* nose up when climbing: negative */
    g->hull_x = X + cg_x;
    g->hull_z = cg_z + a + b * cg_x;
    g->hull_pitch = pitch;
    double c = cos(pitch), sn = sin(pitch);
#define WX(bx, bz) (g->hull_x + ((bx) - cg_x) * c + ((bz) - cg_z) * sn)
#define WZ(bx, bz) (g->hull_z - ((bx) - cg_x) * sn + ((bz) - cg_z) * c)
    g->nwheel = 0;
    ts_geom_wheel *w;
    m1_circle circ[16];
    int nc = 0;
    /* road wheels on trailing arms: hub = pivot - a (cos phi, sin phi) */
    for (int i = 0; i < M1_NROAD; i++) {
        double px = road_x[i] + M1_ARM * cos(TSR_PI / 6), pz = 0.41 + M1_ARM * sin(TSR_PI / 6);
        double Px = WX(px, pz), Pz = WZ(px, pz);
        double lo = -0.1, hi = 1.2; /* arm angle below horizontal, bump stop .. rebound */
        for (int it = 0; it < 60; it++) {
            double phi = 0.5 * (lo + hi);
            double cx = Px - M1_ARM * cos(phi), cz = Pz - M1_ARM * sin(phi);
            if (cz - m1_terrain(g, cx) > 0.41)
                lo = phi; /* hub too high above the ground: swing down */
            else
                hi = phi;
        }
        double phi = 0.5 * (lo + hi);
        w = &g->wheel[g->nwheel++];
        w->role = TS_WHEEL_ROAD;
        w->x = Px - M1_ARM * cos(phi);
        w->z = Pz - M1_ARM * sin(phi);
        w->radius = r_road;
        w->angle = X / r_road;
        w->pivot_x = Px;
        w->pivot_z = Pz;
        circ[nc++] = (m1_circle){w->x, w->z, r_road + M1_WRAP};
    }
    w = &g->wheel[g->nwheel++];
    *w = (ts_geom_wheel){TS_WHEEL_IDLER, WX(5.88, 0.60), WZ(5.88, 0.60), 0.3175, X / 0.3175, 0, 0};
    w->pivot_x = w->x, w->pivot_z = w->z;
    circ[nc++] = (m1_circle){w->x, w->z, 0.3175 + M1_WRAP};
    w = &g->wheel[g->nwheel++];
    *w = (ts_geom_wheel){TS_WHEEL_ROLLER, WX(4.55, 0.84), WZ(4.55, 0.84), 0.125, X / 0.125, 0, 0};
    w->pivot_x = w->x, w->pivot_z = w->z;
    circ[nc++] = (m1_circle){w->x, w->z, 0.125 + M1_WRAP};
    w = &g->wheel[g->nwheel++];
    *w = (ts_geom_wheel){TS_WHEEL_ROLLER, WX(1.83, 0.84), WZ(1.83, 0.84), 0.125, X / 0.125, 0, 0};
    w->pivot_x = w->x, w->pivot_z = w->z;
    circ[nc++] = (m1_circle){w->x, w->z, 0.125 + M1_WRAP};
    w = &g->wheel[g->nwheel++];
    *w = (ts_geom_wheel){TS_WHEEL_SPROCKET, WX(0.0, 0.70), WZ(0.0, 0.70), r_sp, X / r_sp, 0, 0};
    w->pivot_x = w->x, w->pivot_z = w->z;
    circ[nc++] = (m1_circle){w->x, w->z, r_sp};
#undef WX
#undef WZ
    /* runs: RW7..RW1 (bottom), RW1->idler, idler->front roller (span 1),
     * front->rear roller (2), rear roller->sprocket (3), sprocket->RW7 */
    int spans[16] = {0};
    spans[M1_NROAD + 0] = 1;
    spans[M1_NROAD + 1] = 2;
    spans[M1_NROAD + 2] = 3;
    g->ntrack = 0;
    m1_belt(s, circ, nc, spans);
}

/* Put a half-sine transverse (vertical) deflection of amplitude amp [m] on
 * upper span `span` (1..3) as the modal part track_dz. */
static inline void m1_span_mode(m1_state *s, int span, double amp)
{
    for (int i = 0; i < s->g.ntrack; i++)
        if (s->span[i] == span) s->g.track_dz[i] = amp * sin(TSR_PI * s->xi[i]);
}

/* The M1 at rest on flat ground (x from -60 to 100 m) with its sprocket
 * layout origin at x = X; t = 1 s, speed 2 m/s for the overlay. */
static inline void m1_flat(m1_state *s, double X)
{
    memset(s, 0, sizeof *s);
    m1_set_terrain(&s->g, -60, 100, 0, 0, 1);
    m1_pose(s, X, 1.0, 2.0);
}

#endif
