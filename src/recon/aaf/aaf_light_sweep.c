/* r(x)'s emitters for a light that moves during the shutter (see aaf_light_sweep.h). */
#include "recon/aaf/aaf_light_sweep.h"

#include <stdlib.h>
#include <string.h>

/* 8-point Gauss-Legendre on [-1, 1]: the positive abscissae and their weights (the rule is
 * symmetric). Exact for polynomials of degree 15 in time; r(x) is analytic in time but where the
 * light crosses the receiver's horizon (docs/algorithms.md 1.9 gives its error against a fine
 * midpoint mean: 4e-8 on the test's floor, 1.3e-3 where the motion is 5x the light's distance). */
static const double GL_X[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
static const double GL_W[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
_Static_assert(AAF_SWEEP_NODES == 8, "the abscissae above are the 8-point rule's");

double aaf_sweep_node(int k, double *weight)
{
    int i = k < 4 ? 3 - k : k - 4; /* nodes in increasing time */
    double x = k < 4 ? -GL_X[i] : GL_X[i];
    *weight = 0.5 * GL_W[i];
    return 0.5 * (1.0 + x);
}

int aaf_light_sweep(const Renderer *r, const AafLightGeom *lights, int count, AafLightGeom **out)
{
    *out = NULL;
    if (count <= 0) return 0;
    RenderLightInfo *info = calloc((size_t)count, sizeof *info);
    if (!info) return 0;
    int moving = 0;
    for (int l = 0; l < count; ++l) {
        if (!renderer_light_info(r, l, &info[l])) info[l].kind = RENDER_LIGHT_POINT;
        info[l].moving = info[l].moving && info[l].kind == RENDER_LIGHT_AREA && lights[l].emitter != AAF_EMITTER_NONE;
        moving += info[l].moving;
    }
    double *shape_area = moving ? aaf_shape_areas(info, count) : NULL;
    size_t total = (size_t)count + (size_t)moving * (AAF_SWEEP_NODES - 1);
    AafLightGeom *em = moving && shape_area ? malloc(total * sizeof *em) : NULL;
    int n = 0;
    for (int l = 0; l < count && em; ++l) {
        if (!info[l].moving) {
            em[n++] = lights[l];
            continue;
        }
        double area = info[l].shape >= 0 ? shape_area[info[l].shape] : 0.0;
        for (int k = 0; k < AAF_SWEEP_NODES; ++k) {
            double w, u = aaf_sweep_node(k, &w);
            RenderLightInfo at;
            if (!renderer_light_info_at(r, l, (float)u, &at)) at = info[l];
            aaf_light_geom_from_info(&at, area, &em[n]);
            em[n++].radiance_mean *= (float)w;
        }
    }
    free(shape_area);
    free(info);
    *out = em;
    return em ? n : 0;
}

