/* The plain Monte Carlo image of a scene given as text (references and baselines of the
 * pipeline tests). */
#ifndef WEDGE_TESTS_RECON_MC_RENDER_H
#define WEDGE_TESTS_RECON_MC_RENDER_H

#include "recon_test_util.h"

/* spp samples per pixel with seed; 3 floats per pixel (free it), their count in *n3; NULL on
 * failure (the message on stderr). */
static inline float *recon_test_mc_image(const char *text, unsigned seed, int spp, size_t *n3)
{
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, seed, spp, false, &scene, &r)) return NULL;
    int w = renderer_width(r), h = renderer_height(r);
    Frame f;
    frame_init(&f, w, h);
    render_pass(r, 0, NULL, spp, &f, NULL);
    *n3 = 3 * (size_t)w * (size_t)h;
    float *rgb = malloc(*n3 * sizeof(float));
    if (rgb) frame_resolve3(&f, f.color, rgb);
    frame_free(&f);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return rgb;
}

#endif
