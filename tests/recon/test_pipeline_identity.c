/* Moving AAF behind the method interface changed no pixel: each bench scene and the default
 * scene, rendered through the pipeline (--filter auto, 48x36, seed 0, 2 threads), hashes to
 * the value the renderer gave before the move (build 3afa3de, `wedge render SCENE --res 48x36
 * --threads 2`, its EXR's R, G, B read back and hashed by this program:
 * `recon_test_pipeline_identity --hash-exr FILE...`). A change that is meant to alter the
 * images updates the table with the new hashes and says why in its commit. */
#include <inttypes.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
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

static const struct {
    const char *scene; /* under the source tree */
    uint64_t hash;
} EXPECTED[] = {
#include "pipeline_identity_hashes.inc"
};

static bool render_hash(const char *path, uint64_t *out)
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
        *out = hash_rgb(res->rgb, 3 * (size_t)res->width * (size_t)res->height);
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
    CHECK(src != NULL);
    if (!src) CHECK_DONE();
    for (size_t k = 0; k < sizeof EXPECTED / sizeof EXPECTED[0]; ++k) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", src, EXPECTED[k].scene);
        uint64_t h = 0;
        CHECK(render_hash(path, &h));
        if (h != EXPECTED[k].hash)
            fprintf(stderr, "%s: hash 0x%016" PRIx64 ", expected 0x%016" PRIx64 "\n", EXPECTED[k].scene, h,
                    EXPECTED[k].hash);
        CHECK(h == EXPECTED[k].hash);
    }
    CHECK_DONE();
}
