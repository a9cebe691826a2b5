/* fsf_irradiance_and_share_since against the full fsf_irradiance_and_share: r(x) and FSF's
 * light's share found once from guides A, then the guides changed at some pixels (a position,
 * a normal, the hit flag, or a position changed only in its sign of zero), and the outputs
 * brought up to date from A's must equal a full call on the new guides bit for bit. Two
 * triangle lights of different shapes, so that the share is neither 0 nor 1 everywhere. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_light.h"
#include "recon_test_util.h"
#include "scene/scene_desc.h"

enum { N = 1500 };

static uint32_t rng(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static float unit(uint32_t *s) { return (float)(rng(s) % 100001) * 1e-5f; }

/* a receiver on the floor (y = 0) or tilted, most facing up */
static void random_guide(uint32_t *s, unsigned char *hit, float *pos, float *nrm)
{
    *hit = rng(s) % 13 != 0;
    pos[0] = 8.0f * unit(s) - 4.0f, pos[1] = 0.5f * unit(s), pos[2] = 8.0f * unit(s) - 4.0f, pos[3] = 3.0f;
    float nx = 0.6f * unit(s) - 0.3f, nz = 0.6f * unit(s) - 0.3f, ny = rng(s) % 9 == 0 ? -1.0f : 1.0f;
    float len = sqrtf(nx * nx + ny * ny + nz * nz);
    nrm[0] = nx / len, nrm[1] = ny / len, nrm[2] = nz / len, nrm[3] = 0.0f;
}

int main(void)
{
    char text[4096];
    snprintf(text, sizeof text, "%s%s", SHADOW_SCENE,
             "AttributeBegin\n"
             "  AreaLightSource \"diffuse\" \"rgb L\" [ 3 3 3 ]\n"
             "  Shape \"trianglemesh\" \"point3 P\" [ 2 3 2  3 3 2  3 3 3  2 3 3 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
             "AttributeEnd\n");
    SceneDesc scene;
    Renderer *r;
    if (!recon_test_renderer(text, 1, 4, false, &scene, &r)) {
        CHECK(false);
        return 1;
    }
    FsfLight light;
    Diag d = {0};
    CHECK(fsf_light_from_renderer(r, &light, &d));
    unsigned char *hit = malloc(N);
    float *pos = malloc(sizeof(float) * 4 * N), *nrm = malloc(sizeof(float) * 4 * N);
    float *irr = malloc(sizeof(float) * N), *share = malloc(sizeof(float) * N);
    float *irr_full = malloc(sizeof(float) * N), *share_full = malloc(sizeof(float) * N);
    uint32_t s = 5;
    for (int i = 0; i < N; ++i) random_guide(&s, &hit[i], pos + 4 * i, nrm + 4 * i);
    fsf_irradiance_and_share(r, light.shape, N, hit, pos, nrm, irr, share);
    FsfShadeInputs before = {0};
    CHECK(fsf_shade_inputs_keep(&before, N, hit, pos, nrm));
    /* pass 2's refinement: a fifth of the pixels change, each in one of four ways */
    int changed = 0, partial = 0;
    for (int i = 0; i < N; i += 5) {
        switch (rng(&s) % 4) {
        case 0: pos[4 * i] += 0.01f; break;
        case 1: nrm[4 * i + 2] = -nrm[4 * i + 2] + 0.01f; break;
        case 2: hit[i] = !hit[i]; break;
        default: pos[4 * i + 1] = pos[4 * i + 1] == 0.0f ? -0.0f : -pos[4 * i + 1]; break;
        }
        ++changed;
    }
    fsf_irradiance_and_share(r, light.shape, N, hit, pos, nrm, irr_full, share_full);
    fsf_irradiance_and_share_since(r, light.shape, N, hit, pos, nrm, &before, irr, share);
    long differ = 0;
    for (int i = 0; i < N; ++i) {
        differ += memcmp(&irr[i], &irr_full[i], sizeof(float)) != 0 || memcmp(&share[i], &share_full[i], sizeof(float)) != 0;
        partial += share_full[i] > 0.0f && share_full[i] < 1.0f;
    }
    printf("%d of %d pixels changed; %ld differ from the full call; %d with a share strictly between 0 and 1\n", changed,
           N, differ, partial);
    CHECK(differ == 0);
    CHECK(partial > 0); /* the second light makes the share a real fraction somewhere */
    fsf_shade_inputs_free(&before);
    free(hit), free(pos), free(nrm), free(irr), free(share), free(irr_full), free(share_full);
    renderer_destroy(r);
    scene_desc_free(&scene);
    return check_failures ? 1 : 0;
}
