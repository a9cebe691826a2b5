/* Robustness of the PLY reader: thousands of deterministic random mutations (byte flips,
 * truncations, digit edits) of valid files in all three encodings. Every read must either
 * succeed with a mesh whose indices are in range and whose values are finite (and agree
 * with ply_count_triangles), or fail with a "PATH..." message. Run under
 * -DWEDGE_SANITIZE=ON this also proves there is no out-of-bounds access. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "geometry/ply.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint32_t next_u32(void)
{
    /* xorshift64* */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (uint32_t)((rng_state * 0x2545f4914f6cdd1dull) >> 32);
}

static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc(*n + 64);
    if (fread(b, 1, *n, f) != *n) *n = 0;
    fclose(f);
    return b;
}

int main(void)
{
    char dir[64] = "/tmp/wedge-plymut-XXXXXX", base[128], path[128];
    if (!mkdtemp(dir)) { perror("mkdtemp"); return 1; }
    snprintf(base, sizeof base, "%s/base.ply", dir);
    snprintf(path, sizeof path, "%s/mut.ply", dir);

    vec3 P[6], N[6];
    vec2 UV[6];
    for (int i = 0; i < 6; i++) {
        P[i] = v3((float)i, (float)(i * i), -0.5f * i);
        N[i] = v3(0, 0, 1);
        UV[i] = v2(0.1f * i, 1 - 0.1f * i);
    }
    const uint8_t sizes[4] = {3, 4, 3, 5};
    const uint32_t idx[15] = {0, 1, 2, 1, 2, 3, 4, 4, 5, 0, 0, 1, 2, 3, 4};

    int successes = 0, failures = 0;
    for (int fmt = 0; fmt < 3; fmt++)
        for (int extra = 0; extra < 2; extra++) {
            PlyWriteDesc w = {6, P, N, extra ? UV : NULL, 4, sizes, idx, extra};
            Diag err = {0};
            CHECK(ply_write(base, (PlyFormat)fmt, &w, &err));
            size_t n = 0;
            unsigned char *orig = slurp(base, &n);
            unsigned char *buf = malloc(n + 64);
            for (int iter = 0; iter < 400; iter++) {
                memcpy(buf, orig, n);
                size_t len = n;
                int kind = (int)(next_u32() % 4);
                if (kind == 0) { /* flip 1-4 random bytes */
                    for (int k = 1 + (int)(next_u32() % 4); k > 0; k--) buf[next_u32() % len] ^= (unsigned char)(1 + next_u32() % 255);
                } else if (kind == 1) { /* truncate */
                    len = next_u32() % len;
                } else if (kind == 2) { /* replace a digit by another digit or a sign */
                    for (int k = 0; k < 8; k++) {
                        size_t at = next_u32() % len;
                        if (buf[at] >= '0' && buf[at] <= '9') {
                            buf[at] = (unsigned char)"0123456789-9+"[next_u32() % 13];
                            break;
                        }
                    }
                } else { /* set a random byte in the data section to 0xff (huge counts) */
                    size_t at = next_u32() % len;
                    buf[at] = 0xff;
                }
                FILE *f = fopen(path, "wb");
                fwrite(buf, 1, len, f);
                fclose(f);

                TriMesh m;
                Diag e = {0};
                if (ply_read(path, &m, NULL, NULL, &e)) {
                    successes++;
                    int bad = 0;
                    for (int t = 0; t < 3 * m.triangle_count; t++) bad += m.index[t] >= (uint32_t)m.vertex_count;
                    for (int i = 0; i < m.vertex_count; i++) {
                        bad += !isfinite(m.p[i].x) || !isfinite(m.p[i].y) || !isfinite(m.p[i].z);
                        if (m.n) bad += !isfinite(m.n[i].x) || !isfinite(m.n[i].y) || !isfinite(m.n[i].z);
                        if (m.uv) bad += !isfinite(m.uv[i].x) || !isfinite(m.uv[i].y);
                    }
                    CHECK(bad == 0);
                    CHECK(ply_count_triangles(path, &e) == m.triangle_count);
                    mesh_free(&m);
                } else {
                    failures++;
                    CHECK(strncmp(e.message, path, strlen(path)) == 0);
                    CHECK(strstr(e.message, ": error: ") != NULL);
                    CHECK(ply_count_triangles(path, &e) < 0 || e.message[0]); /* no crash either way */
                }
            }
            free(buf);
            free(orig);
        }
    printf("%d mutated files read, %d rejected\n", successes, failures);
    CHECK(successes > 0 && failures > 0);
    unlink(base);
    unlink(path);
    rmdir(dir);
    CHECK_DONE();
}
