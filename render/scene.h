/*
 * scene.h — the renderer's scene: world-space triangles built from a ts_geom
 * snapshot by tsr_scene_update (scene.c), consumed by the OpenGL side
 * (render.c). Internal to render/: the public API is render.h.
 *
 * Every vertex carries its position [m], a flat face normal, a colour and the
 * tsr_part it belongs to; no model matrices — the scene is small (a few
 * thousand triangles) and is rebuilt for every frame.
 */
#ifndef TSR_SCENE_H
#define TSR_SCENE_H

#include "render.h"

typedef struct tsr_vertex {
    float pos[3];          /* world position [m] */
    float normal[3];       /* unit face normal, outward */
    unsigned char rgba[4]; /* lit colour; rgba[3] holds the tsr_part */
} tsr_vertex;

struct tsr_scene {
    tsr_vertex *v; /* nv vertices, three per triangle */
    int nv, cap;
    /* what the overlay prints */
    double t, speed;
    int gear;
    int color_by_tension;
    double tension_ref;  /* [N] tension mapped to the neutral colour */
    /* drawn hull box, in the hull body frame */
    double x_rear, x_front, z_belly, z_roof;
    /* camera aim (world): centre of the hull box, and a radius that bounds the
     * vehicle with its gun */
    double aim[3], radius;
};

/* Model-view-projection matrix (column-major, OpenGL order) of view v. */
void tsr_scene_mvp(const struct tsr_scene *s, const tsr_view *v, float mvp[16]);

/* Colour of tension ratio u = T / T_ref on the slack-neutral-taut ramp. */
void tsr_tension_color(double u, unsigned char rgb[3]);

#endif
