/* No unintended change to the images: each bench scene and the default scene, rendered
 * through the pipeline (--filter auto, 48x36, seed 0, 2 threads), must reproduce the image
 * stored in tests/recon/identity/ (written by this program: `recon_test_pipeline_identity
 * --write-reference DIR`). A change that is meant to alter the images rewrites them and says
 * why in its commit.
 *
 * Not bit for bit: Embree's traversal differs in the last bits between instruction sets (the
 * same build on one machine, Embree forced to sse4.2 or avx against avx2, gave relMSE
 * 4e-16 to 7e-14 between the images, and the stored hashes of an AVX-512 machine matched no
 * image here), so a bit hash pins the machine, not the code. The bound below is far above
 * that rounding and far below the smallest change that means anything: one colour channel of
 * one pixel off by 1% alone gives (0.01)^2 / (48 * 36 * 3) = 1.9e-8. */
#include <inttypes.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/image_metrics.h"
#include "io/image_io.h"
#include "recon/pipeline.h"
#include "render/renderer.h"
#include "scene/scene_desc.h"

/* FNV-1a over the float bit patterns: any changed bit changes the hash. */
static uint64_t hash_rgb(const float *rgb, size_t n3)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n3; ++i) {
        uint32_t bits;
        memcpy(&bits, &rgb[i], sizeof bits);
        for (int b = 0; b < 4; ++b) {
            h ^= (bits >> (8 * b)) & 0xffu;
            h *= 1099511628211ull;
        }
    }
    return h;
}

/* relMSE against the stored image above which the image has changed (see the top). */
#define IDENTITY_RELMSE_MAX 1e-10

static const char *const SCENES[] = {
    "scenes/bench/soft_shadows.pbrt", "scenes/bench/defocus.pbrt",  "scenes/bench/indirect.pbrt",
    "scenes/bench/motion.pbrt",       "scenes/bench/combined.pbrt", "scenes/default.pbrt",
};

/* The stored image of a scene: its file name without folders or extension, .exr. */
static void reference_path(const char *dir, const char *scene, char *out, size_t size)
{
    const char *base = strrchr(scene, '/');
    base = base ? base + 1 : scene;
    int n = snprintf(out, size, "%s/%.*s.exr", dir, (int)(strcspn(base, ".") & 0xff), base);
    if (n < 0 || (size_t)n >= size) out[0] = 0; /* too long: no file of that name is read */
}

/* Renders the scene as the table says; rgb (malloc'd, w x h x 3) on success. */
static bool render_rgb(const char *path, float **rgb, int *w, int *h)
{
    SceneDesc scene;
    Diag d = {0};
    if (!scene_parse_file(path, &scene, &d)) {
        fprintf(stderr, "%s\n", d.message);
        return false;
    }
    RenderOptions ro = {0};
    ro.width = 48, ro.height = 36, ro.threads = 2;
    Renderer *r = NULL;
    ReconPipeline *p = NULL;
    bool ok = renderer_create(&scene, &ro, &r, &d);
    ReconOptions o = {.filter = "auto"};
    ok = ok && recon_pipeline_create(r, &o, &p, &d) && recon_pipeline_render(p, &d);
    if (ok) {
        const ReconResult *res = recon_pipeline_result(p);
        size_t n3 = 3 * (size_t)res->width * (size_t)res->height;
        *w = res->width, *h = res->height;
        *rgb = malloc(n3 * sizeof **rgb);
        ok = *rgb != NULL;
        if (ok) memcpy(*rgb, res->rgb, n3 * sizeof **rgb);
    } else {
        fprintf(stderr, "%s\n", d.message);
    }
    recon_pipeline_destroy(p);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return ok;
}

int main(int argc, char **argv)
{
    /* auto's static choice: this test is about the filters' pipeline on a tiny frame, where
     * auto's fallback (recon/auto_fallback.h) would leave the shading effects to Monte Carlo */
    setenv("WEDGE_AUTO_FALLBACK", "0", 1);
    if (argc > 1 && !strcmp(argv[1], "--hash-exr")) {
        for (int i = 2; i < argc; ++i) {
            int w, h;
            float *rgb = NULL;
            Diag d = {0};
            if (!exr_read_rgb(argv[i], &w, &h, &rgb, &d)) {
                fprintf(stderr, "%s\n", d.message);
                return 2;
            }
            printf("0x%016" PRIx64 "  %s\n", hash_rgb(rgb, 3 * (size_t)w * (size_t)h), argv[i]);
            free(rgb);
        }
        return 0;
    }
    const char *src = getenv("WEDGE_SOURCE_DIR");
    const char *write_dir = argc > 2 && !strcmp(argv[1], "--write-reference") ? argv[2] : NULL;
    CHECK(src != NULL);
    if (!src) CHECK_DONE();
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/tests/recon/identity", src);
    for (size_t k = 0; k < sizeof SCENES / sizeof SCENES[0]; ++k) {
        char path[4096], ref_path[4096];
        snprintf(path, sizeof path, "%s/%s", src, SCENES[k]);
        float *rgb = NULL;
        int w = 0, h = 0;
        CHECK(render_rgb(path, &rgb, &w, &h));
        if (!rgb) continue;
        Diag d = {0};
        if (write_dir) {
            reference_path(write_dir, SCENES[k], ref_path, sizeof ref_path);
            ExrChannel ch[3] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
            CHECK(exr_write(ref_path, w, h, ch, 3, NULL, 0, &d));
            printf("wrote %s\n", ref_path);
        } else {
            reference_path(dir, SCENES[k], ref_path, sizeof ref_path);
            float *ref = NULL;
            int rw = 0, rh = 0;
            CHECK(exr_read_rgb(ref_path, &rw, &rh, &ref, &d));
            CHECK(ref != NULL && rw == w && rh == h);
            if (ref && rw == w && rh == h) {
                double e = metric_relmse(ref, rgb, w, h);
                printf("%s: relMSE %.3g against the stored image (hash here 0x%016" PRIx64 ")\n", SCENES[k], e,
                       hash_rgb(rgb, 3 * (size_t)w * (size_t)h));
                CHECK(e <= IDENTITY_RELMSE_MAX);
            }
            free(ref);
        }
        free(rgb);
    }
    CHECK_DONE();
}
