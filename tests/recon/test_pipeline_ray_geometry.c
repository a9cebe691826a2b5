/* The ray geometry a filtered frame records is what its methods declared they read
 * (ReconMethodClass.shadow_geometry, .bounce_geometry; pipeline.c frame_ray_geometry).
 *  - Lambert receivers without a sky sample no last ray at all (light sampling alone at the
 *    last vertex), filtered or not; the checks below use glossy receivers.
 *  - A maxdepth-1 frame has no indirect light, so AAF, MAAF and FSF read no bounce geometry
 *    and pass 1 records only the shadow rays: the first hit's last BSDF rays keep the
 *    emitter-box test in every pass. The share of last rays the filtered frame traces is
 *    then a plain render's (the same box, the same kind of rays), not pass 1's every ray:
 *    on this scene plain Monte Carlo traces about 4% of them, and a frame whose pass 1
 *    traced all of them would trace at least pass 1's share of the frame's samples.
 *  - With indirect light (maxdepth 2) the methods read the bounce rays: the box test runs
 *    only at the last vertex (depth 2), and the frame's last rays are not all skipped.
 * Small images, so that the test stays fast under the sanitizers. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon_test_util.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* The share of the frame's last rays traced (the rest skipped by the box test), and the
 * frame's pass-1 share of its samples (-1 on failure or without last rays), and the number of
 * last rays (traced or skipped) when last_rays is not NULL. */
static double traced_share_count(const char *text, const char *filter, double *pass1_share, long long *last_rays)
{
    SceneDesc scene;
    Renderer *r;
    *pass1_share = 0.0;
    if (last_rays) *last_rays = -1;
    if (!recon_test_renderer(text, 3, 0, false, &scene, &r)) return -1.0;
    ReconOptions o;
    memset(&o, 0, sizeof o);
    o.filter = filter;
    ReconPipeline *p = NULL;
    Diag d = {0};
    double share = -1.0;
    if (recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d)) {
        const ReconResult *res = recon_pipeline_result(p);
        RenderStats st = renderer_stats(r);
        long long last = st.rays_bsdf + st.rays_bsdf_skipped;
        if (last_rays) *last_rays = last;
        share = last > 0 ? (double)st.rays_bsdf / (double)last : -1.0;
        *pass1_share = res->spp_avg > 0.0 ? res->pass1_spp / res->spp_avg : 0.0;
        printf("%-5s traced %lld of %lld last rays (%.3f), pass 1 %d of %.1f spp\n", filter, st.rays_bsdf, last, share,
               res->pass1_spp, res->spp_avg);
    } else {
        fprintf(stderr, "%s\n", d.message);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return share;
}

static double traced_share(const char *text, const char *filter, double *pass1_share)
{
    return traced_share_count(text, filter, pass1_share, NULL);
}

/* text with its first occurrence of `from` replaced by `to` (malloc'd; NULL if absent). */
static char *replaced(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    if (!at) return NULL;
    size_t head = (size_t)(at - text), n = strlen(text) - strlen(from) + strlen(to);
    char *out = malloc(n + 1);
    if (!out) return NULL;
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + strlen(from));
    return out;
}

int main(void)
{
    double pass1;
    /* Lambert receivers without a sky: the last vertex takes light sampling alone
     * (integrator.c, lambert_light_only) and samples no last ray, filtered or not */
    const char *all[] = {"none", "aaf", "maaf", "fsf"};
    for (int m = 0; m < 4; ++m) {
        long long last = -1;
        traced_share_count(SHADOW_SCENE, all[m], &pass1, &last);
        CHECK(last == 0);
    }
    /* the same scene with glossy surfaces (the emitter's too: at maxdepth 2 the last rays
     * that pass the box leave the light's own surface), whose last rays take the box test */
    char *part = replaced(SHADOW_SCENE, "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]",
                          "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"float roughness\" [ 0.3 ]");
    char *glossy = part ? replaced(part, "WorldBegin\n", "WorldBegin\nMaterial \"coateddiffuse\" \"float roughness\" [ 0.3 ]\n") : NULL;
    free(part);
    CHECK(glossy != NULL);
    if (!glossy) return 1;
    double plain = traced_share(glossy, "none", &pass1);
    CHECK(plain > 0.0 && plain < 0.1);
    const char *methods[] = {"aaf", "maaf", "fsf"};
    for (int m = 0; m < 3; ++m) {
        double share = traced_share(glossy, methods[m], &pass1);
        CHECK(share > 0.0);
        /* the same box test in every pass: the plain share up to the sampling noise (the
         * frames' samples differ), far below pass 1's share of the samples */
        CHECK(share < 1.5 * plain && share > plain / 1.5);
        CHECK(pass1 > 3.0 * plain);
    }

    /* one bounce: the bounce geometry is read, the first hit's bounce rays are traced
     * (they carry the paths on) and only the second vertex's last rays are tested */
    size_t len = strlen(glossy);
    char *gi = malloc(len + 1);
    CHECK(gi != NULL);
    if (gi) {
        memcpy(gi, glossy, len + 1);
        char *depth = strstr(gi, "\"integer maxdepth\" [ 1 ]");
        CHECK(depth != NULL);
        if (depth) depth[strlen("\"integer maxdepth\" [ ")] = '2';
        for (int m = 0; depth && m < 3; ++m) CHECK(traced_share(gi, methods[m], &pass1) > 0.0);
        free(gi);
    }
    free(glossy);
    CHECK_DONE();
}
