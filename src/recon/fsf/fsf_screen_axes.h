/* FSF's gather directions (shared by the soft-shadow and the indirect parameters): for two
 * axes in a receiver's tangent plane, the screen direction along which one pixel step moves
 * the receiver point along each axis (FSF Fig. 5a).
 *
 * With J = [dP/dx dP/dy] the pixel's world Jacobian (from its neighbours' mean positions,
 * receiver metres per pixel step), the direction for a tangent axis u_t is the least-squares
 * solution a of J a = u_t, normalised to one pixel step; the receiver then moves by J a
 * (step_world) per step. */
#ifndef WEDGE_RECON_FSF_SCREEN_AXES_H
#define WEDGE_RECON_FSF_SCREEN_AXES_H

#include <stdbool.h>

#include "core/vec.h"
#include "recon/gbuffer.h"

/* dP per pixel step along screen x (jx) and y (jy) of pixel (x, y): central differences
 * over neighbours on the same surface (hit, not mixed, normals within ~25 deg), else one-sided;
 * false when a column has neither neighbour. */
bool fsf_pixel_jacobian(const GBuffer *g, int x, int y, vec3 *jx, vec3 *jy);

typedef struct {
    float dir[2][2];        /* unit screen direction per axis (pixel steps along x, y) */
    vec3 step_world[2];     /* receiver displacement per step along dir[a] (metres) */
    float step_m[2];        /* |step_world[a]| */
} FsfScreenAxes;

/* The gather directions of axes axis[0], axis[1] (world; projected onto the tangent plane of
 * normal n first). false where J is singular or an axis is normal to the surface. */
bool fsf_screen_axes(vec3 jx, vec3 jy, vec3 n, const vec3 axis[2], FsfScreenAxes *out);

/* fsf_screen_axes for up to FSF_AXES_BLOCK receivers at once, the same floats. The receivers
 * run side by side in vector lanes (the one-receiver form is a chain of dependent divisions and
 * square roots: 70 ns a pixel, 6 ms of the plan's and the filter's parameters at 256x256). */
enum { FSF_AXES_BLOCK = 64 };
typedef struct {
    float jx[3][FSF_AXES_BLOCK], jy[3][FSF_AXES_BLOCK], n[3][FSF_AXES_BLOCK];
    float axis[2][3][FSF_AXES_BLOCK]; /* axis[a] (the light's, or the pixel's own tangents) */
} FsfAxesIn;
/* A block of receivers: lane k holds pixel at[k]'s inputs (component c in [c][k]); after
 * fsf_screen_axes_block, ok[k] is what fsf_screen_axes returns, and out[k] what it writes where
 * it returns true. */
typedef struct {
    FsfAxesIn in;
    FsfScreenAxes out[FSF_AXES_BLOCK];
    bool ok[FSF_AXES_BLOCK];
    size_t at[FSF_AXES_BLOCK];
    int count;
} FsfAxesBlock;
void fsf_screen_axes_block(FsfAxesBlock *b);
/* Adds pixel i's inputs as the next lane (count < FSF_AXES_BLOCK). */
static inline void fsf_axes_lane(FsfAxesBlock *b, size_t i, vec3 jx, vec3 jy, vec3 n, const vec3 axis[2])
{
    const vec3 *v[5] = {&jx, &jy, &n, &axis[0], &axis[1]};
    float(*dst[5])[FSF_AXES_BLOCK] = {b->in.jx, b->in.jy, b->in.n, b->in.axis[0], b->in.axis[1]};
    for (int e = 0; e < 5; ++e) dst[e][0][b->count] = v[e]->x, dst[e][1][b->count] = v[e]->y, dst[e][2][b->count] = v[e]->z;
    b->at[b->count++] = i;
}

#endif
