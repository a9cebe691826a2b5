/* The per-sample store (sample_store.c): the bytes it needs are known before rendering (and
 * are what it allocates), it refuses a store over the memory limit with a message that names
 * the need, the limit and the way out, it keeps exactly the declared fields of each sample
 * in order, and counts samples past a pixel's capacity instead of writing them. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/sample_store.h"

static SampleRecord record(float x, float depth)
{
    SampleRecord r = {0};
    r.px_raster = x, r.py_raster = 0.5f;
    r.lens_u = -0.25f, r.lens_v = 0.75f;
    r.time = 0.125f;
    r.hit = true;
    r.depth_cam = depth;
    r.L = v3(1, 2, 3);
    r.shadow_count = 1;
    r.shadow[0].light_p_world = v3(4, 5, 6);
    r.shadow[0].d_light_world = 7.0f;
    r.shadow[0].d_occluder_world = INFINITY;
    return r;
}

int main(void)
{
    /* sizes: film 2 + lens 2 + radiance 3 floats per sample, plus one int per pixel */
    unsigned fields = SAMPLE_FIELD_FILM | SAMPLE_FIELD_LENS | SAMPLE_FIELD_RADIANCE;
    CHECK(sample_field_components(SAMPLE_FIELD_LIGHT) == 5);
    CHECK(sample_field_components(SAMPLE_FIELD_FILM | SAMPLE_FIELD_LENS) == 0);
    CHECK(sample_store_bytes(fields, 4, 3, 8) == 12 * sizeof(int) + 12 * 8 * 7 * sizeof(float));
    CHECK(sample_store_bytes(fields, 65536, 65536, 1 << 30) == SIZE_MAX); /* overflow is "too big" */
    CHECK(sample_store_default_limit() > 0);

    /* over the limit: refused with the numbers and what to do */
    SampleStore *s = NULL;
    Diag d = {0};
    CHECK(!sample_store_create(fields, 1024, 1024, 64, (size_t)1 << 20, &s, &d));
    CHECK(s == NULL && d.exit_code == WEDGE_EXIT_RUNTIME);
    CHECK(strstr(d.message, "1024x1024 pixels at 64 samples per pixel needs 1.75 GiB") != NULL);
    CHECK(strstr(d.message, "limit of 0.00 GiB") != NULL && strstr(d.message, "--mem-limit") != NULL);

    /* the fields of each sample, in order; capacity 2: the third sample is counted, not kept */
    unsigned f2 = SAMPLE_FIELD_FILM | SAMPLE_FIELD_TIME | SAMPLE_FIELD_DEPTH | SAMPLE_FIELD_LIGHT;
    CHECK(sample_store_create(f2, 2, 1, 2, (size_t)1 << 20, &s, &d));
    if (s) {
        SampleRecord a = record(1.25f, 3.0f), b = record(1.75f, 4.0f), miss = record(1.5f, 9.0f);
        miss.hit = false;
        sample_store_add(s, 1, 0, &a);
        sample_store_add(s, 1, 0, &b);
        sample_store_add(s, 1, 0, &miss);
        sample_store_add(s, 0, 0, &miss);
        sample_store_add(s, 9, 9, &a); /* outside: ignored */
        CHECK(sample_store_count(s, 0) == 1 && sample_store_count(s, 1) == 2);
        CHECK(sample_store_dropped(s) == 1);
        CHECK(sample_store_field(s, SAMPLE_FIELD_LENS) == NULL);
        const float *film = sample_store_field(s, SAMPLE_FIELD_FILM), *depth = sample_store_field(s, SAMPLE_FIELD_DEPTH);
        const float *light = sample_store_field(s, SAMPLE_FIELD_LIGHT), *time = sample_store_field(s, SAMPLE_FIELD_TIME);
        /* pixel 1 holds samples at (1 * 2 + 0) and (1 * 2 + 1) */
        CHECK(film[2 * 2] == 1.25f && film[2 * 3] == 1.75f && film[2 * 3 + 1] == 0.5f);
        CHECK(depth[2] == 3.0f && depth[3] == 4.0f && isinf(depth[0])); /* a miss has no depth */
        CHECK(time[2] == 0.125f);
        CHECK(light[5 * 2 + 1] == 5.0f && light[5 * 2 + 3] == 7.0f && isinf(light[5 * 2 + 4]));
        sample_store_destroy(s);
    }

    /* LR's two records: the same values as the plain fields (lens v flipped), the reader's
     * slots left as the reader wrote them by a later sample of another pixel */
    unsigned f3 = SAMPLE_FIELD_LR_PLACE | SAMPLE_FIELD_LR_KEY | SAMPLE_FIELD_FILM | SAMPLE_FIELD_LENS |
                  SAMPLE_FIELD_TIME | SAMPLE_FIELD_DEPTH | SAMPLE_FIELD_MOTION;
    CHECK(sample_field_components(SAMPLE_FIELD_LR_PLACE) == 8 && sample_field_components(SAMPLE_FIELD_LR_KEY) == 4);
    CHECK(sample_store_bytes(SAMPLE_FIELD_LR_PLACE | SAMPLE_FIELD_LR_KEY, 4, 3, 8) ==
          12 * sizeof(int) + 12 * 8 * 12 * sizeof(float));
    CHECK(sample_store_create(f3, 2, 1, 2, (size_t)1 << 20, &s, &d));
    if (s) {
        SampleRecord a = record(1.25f, 3.0f), miss = record(1.5f, 9.0f);
        a.motion_px[0] = 2.5f, a.motion_px[1] = -1.5f;
        miss.hit = false;
        sample_store_add(s, 1, 0, &a);
        float *place = sample_store_field_mut(s, SAMPLE_FIELD_LR_PLACE), *key = sample_store_field_mut(s, SAMPLE_FIELD_LR_KEY);
        CHECK(place && key && place == sample_store_field(s, SAMPLE_FIELD_LR_PLACE));
        if (place && key) {
            place[8 * 2 + 5] = 11.0f, key[4 * 2 + 1] = 12.0f; /* the reader's slots of sample 2 */
            sample_store_add(s, 0, 0, &miss);
            const float *film = sample_store_field(s, SAMPLE_FIELD_FILM), *lens = sample_store_field(s, SAMPLE_FIELD_LENS);
            const float *time = sample_store_field(s, SAMPLE_FIELD_TIME), *depth = sample_store_field(s, SAMPLE_FIELD_DEPTH);
            const float *motion = sample_store_field(s, SAMPLE_FIELD_MOTION);
            for (int q = 0; q < 3; q += 2) { /* pixel 0's first sample (the miss), pixel 1's */
                const float *pl = place + 8 * q, *ky = key + 4 * q;
                CHECK(pl[0] == film[2 * q] && pl[1] == film[2 * q + 1] && pl[2] == lens[2 * q] && pl[3] == -lens[2 * q + 1]);
                CHECK(pl[4] == time[q] && ky[0] == depth[q] && ky[2] == motion[2 * q] && ky[3] == motion[2 * q + 1]);
            }
            CHECK(isinf(key[0]) && key[4 * 2 + 2] == 2.5f && key[4 * 2 + 3] == -1.5f && place[8 * 2 + 3] == -0.75f);
            CHECK(place[8 * 2 + 5] == 11.0f && key[4 * 2 + 1] == 12.0f);
        }
        sample_store_destroy(s);
    }
    CHECK_DONE();
}
