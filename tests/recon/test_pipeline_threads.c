/* Filtered renders are deterministic across thread counts: the default scene (soft shadows,
 * defocus, motion and indirect light: every effect, every stage of the pipeline) through
 * --filter auto with 1, 2 and 3 render threads gives the same image bit for bit, and so do
 * two runs with the same count. Each pixel's samples are seeded from (seed, pixel, pass), a
 * pixel's samples of a round are summed by one thread in order, and the host-side
 * reconstruction splits pixels, never sums, between cores. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* The filtered image of the default scene at 40x30 (malloc'd rgb), or NULL. */
static float *render_with_threads(const char *path, int threads, EffectMask *effects)
{
    SceneDesc scene;
    Diag d = {0};
    if (!scene_parse_file(path, &scene, &d)) {
        fprintf(stderr, "%s\n", d.message);
        return NULL;
    }
    RenderOptions ro = {0};
    ro.width = 40, ro.height = 30, ro.threads = threads, ro.seed = 5;
    Renderer *r = NULL;
    ReconPipeline *p = NULL;
    float *rgb = NULL;
    ReconOptions o = {.filter = "auto"};
    if (renderer_create(&scene, &ro, &r, &d) && recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d)) {
        const ReconResult *res = recon_pipeline_result(p);
        size_t bytes = 3 * sizeof(float) * (size_t)res->width * (size_t)res->height;
        rgb = malloc(bytes);
        if (rgb) memcpy(rgb, res->rgb, bytes);
        *effects = renderer_effects(r);
        CHECK(recon_choice_any(&res->choice));
    } else {
        fprintf(stderr, "%s\n", d.message);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return rgb;
}

int main(void)
{
    const char *src = getenv("WEDGE_SOURCE_DIR");
    CHECK(src != NULL);
    if (!src) CHECK_DONE();
    char path[4096];
    snprintf(path, sizeof path, "%s/scenes/default.pbrt", src);
    size_t bytes = 3 * sizeof(float) * 40 * 30;
    EffectMask fx = 0;
    float *one = render_with_threads(path, 1, &fx);
    CHECK(one != NULL);
    CHECK(fx == EFFECT_MASK_ALL); /* the scene exercises every effect */
    const int counts[3] = {2, 3, 1};
    for (int k = 0; k < 3 && one; ++k) {
        float *other = render_with_threads(path, counts[k], &fx);
        CHECK(other != NULL);
        if (other && memcmp(one, other, bytes) != 0) {
            fprintf(stderr, "%d threads: the image differs from 1 thread's\n", counts[k]);
            CHECK(false);
        }
        free(other);
    }
    free(one);
    CHECK_DONE();
}
