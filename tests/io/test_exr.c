/* EXR writer/reader: exact float32 round trips with several channels and attributes,
 * NaN/Inf replacement, every storage type and compression the reader must accept, error
 * messages, and the atomic-write guarantee (no stray temporary file after a failure). */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "io/image_io.h"

static char tmpdir[256];

static void path_in_tmp(char *buf, size_t size, const char *name)
{
    if (snprintf(buf, size, "%s/%s", tmpdir, name) >= (int)size) abort();
}

/* Number of entries in a folder besides "." and "..". */
static int count_entries(const char *folder)
{
    DIR *d = opendir(folder);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++n;
    closedir(d);
    return n;
}

/* Removes every file in tmpdir (the tests create only files at its top level). */
static void clean_tmp(void)
{
    DIR *d = opendir(tmpdir);
    if (!d) return;
    struct dirent *e;
    char p[512];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
        if (unlink(p) != 0) rmdir(p);
    }
    closedir(d);
}

/* A deterministic value that exercises sign, magnitude and fractional bits of float32. */
static float pattern(int x, int y, int c)
{
    int k = (y * 131 + x * 17 + c * 7) % 97;
    return (float)((k - 40) * 0.123456789) * (c == 5 ? 1e-30f : 1.0f) + (float)c * 1024.0f;
}

static void test_round_trip_exact(void)
{
    /* 37x21 with ZIP (16 scanlines per chunk) crosses a chunk boundary with a partial
     * last chunk; RGB come interleaved (stride 3), the AOVs planar (stride 1). */
    enum { W = 37, H = 21 };
    static float rgb[W * H * 3], albedo_r[W * H], depth[W * H], alpha[W * H];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) rgb[(y * W + x) * 3 + c] = pattern(x, y, c);
            albedo_r[y * W + x] = pattern(x, y, 3);
            depth[y * W + x] = pattern(x, y, 4);
            alpha[y * W + x] = pattern(x, y, 5); /* tiny values: denormal-adjacent */
        }
    /* Deliberately unsorted: the writer must sort them for the header. */
    ExrChannel ch[] = {
        {"R", rgb + 0, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3},
        {"albedo.R", albedo_r, 1}, {"Z", depth, 1}, {"A", alpha, 1},
    };
    ExrAttr attrs[] = {
        {"wedge.spp", EXR_ATTR_INT, NULL, 0.0, 64},
        {"wedge.seed", EXR_ATTR_INT, NULL, 0.0, -7},
        {"wedge.seconds", EXR_ATTR_FLOAT, NULL, 1.25, 0},
        {"wedge.version", EXR_ATTR_STRING, "0.1.0", 0.0, 0},
        {"wedge.scene", EXR_ATTR_STRING, "scenes/a scene with spaces.pbrt", 0.0, 0},
        {"wedge.a_rather_long_attribute_name_over_31_chars", EXR_ATTR_STRING, "long", 0.0, 0},
    };
    char path[512];
    path_in_tmp(path, sizeof path, "rt.exr");
    Diag err = {0};
    CHECK(exr_write(path, W, H, ch, 6, attrs, 6, &err));
    if (err.message[0]) fprintf(stderr, "%s\n", err.message);

    ExrImage img;
    CHECK(exr_read(path, &img, &err));
    CHECK(img.width == W && img.height == H);
    CHECK(img.channel_count == 6);
    if (img.channel_count == 6) {
        /* Alphabetical (byte order: capitals first), as the EXR header demands. */
        const char *expect[] = {"A", "B", "G", "R", "Z", "albedo.R"};
        for (int c = 0; c < 6; ++c) CHECK_STR(img.names[c], expect[c]);
    }
    const float *r = exr_image_channel(&img, "R"), *g = exr_image_channel(&img, "G"),
                *b = exr_image_channel(&img, "B"), *al = exr_image_channel(&img, "albedo.R"),
                *z = exr_image_channel(&img, "Z"), *a = exr_image_channel(&img, "A");
    CHECK(r && g && b && al && z && a);
    CHECK(exr_image_channel(&img, "nope") == NULL);
    int mismatches = 0;
    if (r && g && b && al && z && a)
        for (int i = 0; i < W * H; ++i) {
            mismatches += r[i] != rgb[3 * i] || g[i] != rgb[3 * i + 1] || b[i] != rgb[3 * i + 2];
            mismatches += al[i] != albedo_r[i] || z[i] != depth[i] || a[i] != alpha[i];
        }
    CHECK(mismatches == 0);

    const ExrAttr *at = exr_image_attr(&img, "wedge.spp");
    CHECK(at && at->type == EXR_ATTR_INT && at->i == 64);
    at = exr_image_attr(&img, "wedge.seed");
    CHECK(at && at->type == EXR_ATTR_INT && at->i == -7);
    at = exr_image_attr(&img, "wedge.seconds");
    CHECK(at && at->type == EXR_ATTR_FLOAT && at->f == 1.25);
    at = exr_image_attr(&img, "wedge.version");
    CHECK(at && at->type == EXR_ATTR_STRING && at->s && !strcmp(at->s, "0.1.0"));
    at = exr_image_attr(&img, "wedge.scene");
    CHECK(at && at->type == EXR_ATTR_STRING && at->s && !strcmp(at->s, "scenes/a scene with spaces.pbrt"));
    at = exr_image_attr(&img, "wedge.a_rather_long_attribute_name_over_31_chars");
    CHECK(at && at->s && !strcmp(at->s, "long"));
    exr_image_free(&img);

    /* exr_read_rgb interleaves R, G, B back exactly. */
    int w = 0, h = 0;
    float *back = NULL;
    CHECK(exr_read_rgb(path, &w, &h, &back, &err));
    CHECK(w == W && h == H && back && !memcmp(back, rgb, sizeof rgb));
    free(back);

    /* A named AOV channel on its own. */
    float *plane = NULL;
    CHECK(exr_read_channel(path, "albedo.R", &w, &h, &plane, &err));
    CHECK(plane && !memcmp(plane, albedo_r, sizeof albedo_r));
    free(plane);

    /* Missing channel: the error names the file, the channel and what the file has. */
    plane = NULL;
    CHECK(!exr_read_channel(path, "N.X", &w, &h, &plane, &err));
    char expect[1024];
    snprintf(expect, sizeof expect, "%s: error: no channel 'N.X' (the file has: A, B, G, R, Z, albedo.R)", path);
    CHECK_STR(err.message, expect);
    CHECK(err.exit_code == 2);
    CHECK(count_entries(tmpdir) == 1); /* only rt.exr: no temporary left behind */
    clean_tmp();
}

static void test_nonfinite_replaced(void)
{
    float px[4 * 3] = {1.0f, NAN, 2.0f, INFINITY, -INFINITY, 3.0f, 4.0f, 5.0f, 6.0f, -NAN, 7.0f, 8.0f};
    ExrChannel ch[] = {{"R", px, 3}, {"G", px + 1, 3}, {"B", px + 2, 3}};
    char path[512];
    path_in_tmp(path, sizeof path, "nan.exr");
    Diag err = {0};
    ExrWriteOptions opt = {EXR_STORE_FLOAT, EXRC_ZIP, 0, 0, -1};
    CHECK(exr_write_with(path, 2, 2, ch, 3, NULL, 0, &opt, &err));
    CHECK(opt.nonfinite_replaced == 4);
    int w, h;
    float *back = NULL;
    CHECK(exr_read_rgb(path, &w, &h, &back, &err));
    const float expect[12] = {1, 0, 2, 0, 0, 3, 4, 5, 6, 0, 7, 8};
    if (back)
        for (int i = 0; i < 12; ++i) CHECK(back[i] == expect[i]);
    free(back);
    clean_tmp();
}

/* Every pixel type and compression the reader must accept. The writer produces them, and
 * the values are exactly representable where the format is lossless: multiples of 1/8
 * up to 64 fit a half's 11-bit significand; uint gets integers. */
static void test_types_and_compressions(void)
{
    enum { W = 45, H = 35 };
    static float rgb[W * H * 3];
    static float flat[W * H * 3];
    for (int i = 0; i < W * H * 3; ++i) {
        rgb[i] = (float)((i * 37) % 512) / 8.0f;
        flat[i] = 0.5f * (float)(i % 3 + 1); /* constant per channel */
    }
    ExrChannel noisy[] = {{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
    ExrChannel smooth[] = {{"R", flat, 3}, {"G", flat + 1, 3}, {"B", flat + 2, 3}};
    struct {
        ExrStoreType store;
        ExrCompression comp;
        int tile;
        double tol; /* 0: lossless; lossy codecs get a relative tolerance */
    } cases[] = {
        {EXR_STORE_FLOAT, EXRC_NONE, 0, 0}, {EXR_STORE_FLOAT, EXRC_RLE, 0, 0},
        {EXR_STORE_FLOAT, EXRC_ZIPS, 0, 0}, {EXR_STORE_FLOAT, EXRC_PIZ, 0, 0},
        {EXR_STORE_HALF, EXRC_ZIP, 0, 0},   {EXR_STORE_HALF, EXRC_PIZ, 0, 0},
        {EXR_STORE_HALF, EXRC_NONE, 0, 0},  {EXR_STORE_UINT, EXRC_ZIP, 0, 0},
        {EXR_STORE_UINT, EXRC_NONE, 0, 0},  {EXR_STORE_FLOAT, EXRC_ZIP, 16, 0},
        {EXR_STORE_HALF, EXRC_PIZ, 8, 0},   {EXR_STORE_FLOAT, EXRC_NONE, 32, 0},
        /* Lossy: PXR24 keeps 24 bits of a float (rel. error <= 2^-16); B44 packs 4x4
         * blocks of half as 6-bit differences, exact for a flat block, which is why
         * the lossy cases use the smooth image below. (DWAA/DWAB cannot be written by
         * the OpenEXR 3.1 C API.) */
        {EXR_STORE_FLOAT, EXRC_PXR24, 0, 1.0 / 65536}, {EXR_STORE_HALF, EXRC_B44, 0, 0},
        {EXR_STORE_HALF, EXRC_B44A, 0, 0},
    };
    char path[512];
    path_in_tmp(path, sizeof path, "types.exr");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        Diag err = {0};
        ExrWriteOptions opt = {cases[k].store, cases[k].comp, cases[k].tile, 0, 0};
        bool lossy = cases[k].comp >= EXRC_PXR24;
        const float *src = lossy && cases[k].comp != EXRC_PXR24 ? flat : rgb;
        bool ok = exr_write_with(path, W, H, src == flat ? smooth : noisy, 3, NULL, 0, &opt, &err);
        CHECK(ok);
        if (!ok) {
            fprintf(stderr, "case %zu: %s\n", k, err.message);
            continue;
        }
        int w = 0, h = 0;
        float *back = NULL;
        ok = exr_read_rgb(path, &w, &h, &back, &err);
        CHECK(ok && w == W && h == H);
        if (!ok) {
            fprintf(stderr, "case %zu: %s\n", k, err.message);
            continue;
        }
        int bad = 0;
        double worst = 0.0;
        for (int i = 0; i < W * H * 3; ++i) {
            double want = cases[k].store == EXR_STORE_UINT ? floor(src[i] + 0.5) : src[i];
            double diff = fabs(back[i] - want);
            if (diff > worst) worst = diff;
            bad += diff > cases[k].tol * (1.0 + fabs(want));
        }
        if (bad) fprintf(stderr, "case %zu: %d values off, worst %g\n", k, bad, worst);
        CHECK(bad == 0);
        free(back);
    }
    clean_tmp();
}

/* Tiny chunks where compression cannot win: the writer must store them raw (a 2x1 RGB
 * image whose ZIP stream is exactly as long as the 24 raw bytes was once misread). */
static void test_tiny_chunks(void)
{
    const float px[2][6] = {{0.25f, 2.0f, 0.5f, 0.125f, 0.0f, 7.0f}, {1, 2, 3, 4, 5, 6}};
    const float alpha[2] = {1.0f, 0.5f};
    const ExrCompression comps[] = {EXRC_NONE, EXRC_RLE, EXRC_ZIPS, EXRC_ZIP, EXRC_PIZ};
    const ExrStoreType stores[] = {EXR_STORE_FLOAT, EXR_STORE_HALF};
    char path[512];
    path_in_tmp(path, sizeof path, "tiny.exr");
    for (int p = 0; p < 2; ++p)
        for (int nc = 3; nc <= 4; ++nc)
            for (size_t k = 0; k < sizeof comps / sizeof comps[0]; ++k)
                for (int st = 0; st < 2; ++st)
                    for (int w = 1; w <= 2; ++w) {
                        ExrChannel ch[] = {{"R", px[p], 3}, {"G", px[p] + 1, 3}, {"B", px[p] + 2, 3}, {"A", alpha, 1}};
                        ExrWriteOptions opt = {stores[st], comps[k], 0, 0, 0};
                        Diag err = {0};
                        bool ok = exr_write_with(path, w, 1, ch, nc, NULL, 0, &opt, &err);
                        ExrImage img;
                        ok = ok && exr_read(path, &img, &err);
                        CHECK(ok);
                        if (!ok) {
                            fprintf(stderr, "%s\n", err.message);
                            continue;
                        }
                        const float *r = exr_image_channel(&img, "R"), *b = exr_image_channel(&img, "B"),
                                    *a = exr_image_channel(&img, "A");
                        bool same = r && b && r[0] == px[p][0] && b[w - 1] == px[p][3 * (w - 1) + 2];
                        if (nc == 4) same = same && a && a[w - 1] == alpha[w - 1];
                        if (!same) fprintf(stderr, "tiny: pattern %d, %d channels, compression %d, store %d, w %d\n", p,
                                           nc, (int)comps[k], st, w);
                        CHECK(same);
                        exr_image_free(&img);
                    }
    clean_tmp();
}

/* Incompressible data (random float bits): every chunk must still read back exactly. */
static void test_incompressible(void)
{
    enum { W = 40, H = 40 };
    static float px[W * H * 3];
    unsigned s = 2463534242u;
    for (int i = 0; i < W * H * 3; ++i) {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        unsigned bits = (s & 0x807fffffu) | 0x3f000000u; /* random sign and mantissa, finite */
        memcpy(&px[i], &bits, sizeof bits);
    }
    ExrChannel ch[] = {{"R", px, 3}, {"G", px + 1, 3}, {"B", px + 2, 3}};
    const ExrCompression comps[] = {EXRC_RLE, EXRC_ZIPS, EXRC_ZIP, EXRC_PIZ};
    char path[512];
    path_in_tmp(path, sizeof path, "noise.exr");
    for (size_t k = 0; k < sizeof comps / sizeof comps[0]; ++k) {
        ExrWriteOptions opt = {EXR_STORE_FLOAT, comps[k], 0, 0, 0};
        Diag err = {0};
        int w, h;
        float *back = NULL;
        bool ok = exr_write_with(path, W, H, ch, 3, NULL, 0, &opt, &err) && exr_read_rgb(path, &w, &h, &back, &err);
        CHECK(ok);
        if (!ok) fprintf(stderr, "noise, compression %d: %s\n", (int)comps[k], err.message);
        CHECK(back && !memcmp(back, px, sizeof px));
        free(back);
    }
    clean_tmp();
}

static long read_whole(const char *path, unsigned char *buf, long cap)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    long n = (long)fread(buf, 1, (size_t)cap, f);
    fclose(f);
    return n;
}

/* The ZIP level: level 0 (the default) must write exactly the bytes of level
 * EXR_ZIP_LEVEL_DEFAULT, not OpenEXR's own default (zlib's 6, the writer's old behaviour), and
 * every level must read back bit for bit through OpenEXR's reader, ZIP and ZIPS, scanline
 * and tiled. The image is a render's kind of float plane: a ramp with a little noise. */
static void test_zip_level(void)
{
    enum { W = 96, H = 64, CAP = 1 << 17 };
    static float px[W * H * 3];
    static unsigned char bytes[3][CAP];
    unsigned s = 88172645u;
    for (int i = 0; i < W * H * 3; ++i) {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        px[i] = 0.25f + (float)(i % (3 * W) / 3) / 64.0f + (float)(s & 3u) / 1024.0f;
    }
    ExrChannel ch[] = {{"R", px, 3}, {"G", px + 1, 3}, {"B", px + 2, 3}};
    const struct {
        ExrCompression comp;
        int tile;
    } cases[] = {{EXRC_ZIP, 0}, {EXRC_ZIPS, 0}, {EXRC_ZIP, 32}};
    const int levels[3] = {0, EXR_ZIP_LEVEL_DEFAULT, 6};
    char path[512];
    path_in_tmp(path, sizeof path, "zip.exr");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        long size[3] = {-1, -1, -1};
        for (int l = 0; l < 3; ++l) {
            ExrWriteOptions opt = {EXR_STORE_FLOAT, cases[k].comp, cases[k].tile, levels[l], 0};
            Diag err = {0};
            int w = 0, h = 0;
            float *back = NULL;
            bool ok = exr_write_with(path, W, H, ch, 3, NULL, 0, &opt, &err);
            size[l] = ok ? read_whole(path, bytes[l], CAP) : -1;
            ok = ok && exr_read_rgb(path, &w, &h, &back, &err);
            CHECK(ok && w == W && h == H && back && !memcmp(back, px, sizeof px));
            if (!ok) fprintf(stderr, "zip level %d, case %zu: %s\n", levels[l], k, err.message);
            free(back);
        }
        CHECK(size[0] > 0 && size[0] < CAP);
        /* the default is level 1 byte for byte, and level 6 deflates differently */
        CHECK(size[0] == size[1] && !memcmp(bytes[0], bytes[1], (size_t)size[0]));
        CHECK(size[2] > 0 && (size[2] != size[0] || memcmp(bytes[0], bytes[2], (size_t)size[0])));
    }
    clean_tmp();
}

static void test_grey_and_missing_rgb(void)
{
    float y[6] = {0.5f, 1.5f, 2.5f, 3.5f, 4.5f, 5.5f};
    ExrChannel ch = {"Y", y, 1};
    char path[512];
    path_in_tmp(path, sizeof path, "grey.exr");
    Diag err = {0};
    CHECK(exr_write(path, 3, 2, &ch, 1, NULL, 0, &err));
    int w, h;
    float *rgb = NULL;
    CHECK(exr_read_rgb(path, &w, &h, &rgb, &err));
    if (rgb)
        for (int i = 0; i < 6; ++i) CHECK(rgb[3 * i] == y[i] && rgb[3 * i + 1] == y[i] && rgb[3 * i + 2] == y[i]);
    free(rgb);

    ExrChannel zc = {"Z", y, 1};
    CHECK(exr_write(path, 3, 2, &zc, 1, NULL, 0, &err));
    rgb = NULL;
    CHECK(!exr_read_rgb(path, &w, &h, &rgb, &err));
    char expect[1024];
    snprintf(expect, sizeof expect, "%s: error: no R, G, B or Y channels (the file has: Z)", path);
    CHECK_STR(err.message, expect);
    CHECK(err.exit_code == 2);
    clean_tmp();
}

static void test_bad_inputs(void)
{
    char path[512];
    Diag err = {0};
    int w, h;
    float *rgb = NULL;
    path_in_tmp(path, sizeof path, "missing.exr");
    CHECK(!exr_read_rgb(path, &w, &h, &rgb, &err));
    char expect[1024];
    snprintf(expect, sizeof expect, "%s: error: cannot open: No such file or directory", path);
    CHECK_STR(err.message, expect);
    CHECK(err.exit_code == 2);

    path_in_tmp(path, sizeof path, "text.exr");
    FILE *f = fopen(path, "w");
    fputs("this is not an image\n", f);
    fclose(f);
    CHECK(!exr_read_rgb(path, &w, &h, &rgb, &err));
    CHECK(err.exit_code == 2 && strstr(err.message, "cannot read EXR") && strstr(err.message, path));

    /* A truncated file must fail cleanly (the sanitizer build checks no bad access). */
    float px[64 * 64 * 3];
    for (int i = 0; i < 64 * 64 * 3; ++i) px[i] = (float)(i % 13);
    ExrChannel ch[] = {{"R", px, 3}, {"G", px + 1, 3}, {"B", px + 2, 3}};
    path_in_tmp(path, sizeof path, "trunc.exr");
    CHECK(exr_write(path, 64, 64, ch, 3, NULL, 0, &err));
    struct stat st;
    CHECK(stat(path, &st) == 0);
    CHECK(truncate(path, st.st_size / 2) == 0);
    rgb = NULL;
    CHECK(!exr_read_rgb(path, &w, &h, &rgb, &err));
    CHECK(rgb == NULL && err.exit_code == 2 && strstr(err.message, path));

    /* Bad write arguments. */
    CHECK(!exr_write(path, 0, 4, ch, 3, NULL, 0, &err));
    CHECK(err.exit_code == 3);
    ExrChannel twice[] = {{"R", px, 3}, {"R", px, 3}};
    CHECK(!exr_write(path, 4, 4, twice, 2, NULL, 0, &err));
    CHECK(strstr(err.message, "channel 'R' given twice") != NULL);
    clean_tmp();
}

/* The atomic write: a failed write leaves neither the destination nor a temporary. */
static void test_atomic_failures(void)
{
    float px[3] = {1, 2, 3};
    ExrChannel ch[] = {{"R", px, 3}, {"G", px + 1, 3}, {"B", px + 2, 3}};
    Diag err = {0};
    char path[512];

    /* Missing folder: nothing can be created at all. */
    path_in_tmp(path, sizeof path, "no/such/folder/out.exr");
    CHECK(!exr_write(path, 1, 1, ch, 3, NULL, 0, &err));
    CHECK(err.exit_code == 3);
    char expect[1024];
    snprintf(expect, sizeof expect, "%s: error: cannot create a file in folder '%s/no/such/folder': No such file or directory",
             path, tmpdir);
    CHECK_STR(err.message, expect);
    CHECK(count_entries(tmpdir) == 0);

    /* The destination is a folder: the temporary is written in full, the rename fails,
     * and the temporary must be removed. */
    path_in_tmp(path, sizeof path, "a_folder.exr");
    CHECK(mkdir(path, 0755) == 0);
    CHECK(!exr_write(path, 1, 1, ch, 3, NULL, 0, &err));
    CHECK(err.exit_code == 3 && strstr(err.message, "cannot rename"));
    CHECK(count_entries(tmpdir) == 1); /* just the folder */
    CHECK(!png_write_srgb(path, 1, 1, px, &err));
    CHECK(count_entries(tmpdir) == 1);
    rmdir(path);

    /* Read-only folder (permissions do not bind root, so only checked as a user). */
    if (geteuid() != 0) {
        char ro[256];
        path_in_tmp(ro, sizeof ro, "ro");
        CHECK(mkdir(ro, 0555) == 0);
        snprintf(path, sizeof path, "%s/out.exr", ro);
        CHECK(!exr_write(path, 1, 1, ch, 3, NULL, 0, &err));
        CHECK(strstr(err.message, "Permission denied") != NULL);
        CHECK(count_entries(ro) == 0);
        chmod(ro, 0755);
        rmdir(ro);
    }

    /* Success replaces an existing file in place. */
    path_in_tmp(path, sizeof path, "replace.exr");
    FILE *f = fopen(path, "w");
    fputs("old", f);
    fclose(f);
    CHECK(exr_write(path, 1, 1, ch, 3, NULL, 0, &err));
    int w, h;
    float *rgb = NULL;
    CHECK(exr_read_rgb(path, &w, &h, &rgb, &err));
    CHECK(rgb && rgb[0] == 1 && rgb[1] == 2 && rgb[2] == 3);
    free(rgb);
    CHECK(count_entries(tmpdir) == 1);
    clean_tmp();
}

/* A 1.2 KB file found by tools/fuzz-readers exr whose chunk claims to unpack to 1.3 GB: refused
 * before anything that large is allocated (the fuzz smoke run, which seeds from this folder,
 * would also stop at its 1 GB memory limit). Its header's image is already more than 1.2 KB
 * could unpack to, so the whole-file bound refuses it first (read_chunk's own bound, the
 * first to catch it, stays for chunks that lie within a plausible header). */
static void test_chunk_claiming_too_much(void)
{
    ExrImage img;
    Diag err = {0};
    CHECK(!exr_read("data/fuzz-oom-chunk.exr", &img, &err));
    CHECK(strstr(err.message, "larger than the file's data could hold") != NULL);
    CHECK(err.exit_code == WEDGE_EXIT_INPUT);
}

/* A valid 2x2 file whose data window is then rewritten to 4096 x 4096: the header asks for
 * more pixels than the file's bytes could unpack to, and the reader says so before it
 * allocates the planes (the message is only this check's; without it the read fails later,
 * as corrupt chunk data, after allocating 16.8M pixels per channel). */
static void test_header_larger_than_file(void)
{
    char path[512];
    path_in_tmp(path, sizeof path, "huge_window.exr");
    float px[4] = {1, 2, 3, 4};
    ExrChannel ch[1] = {{"Y", px, 1}};
    Diag err = {0};
    CHECK(exr_write(path, 2, 2, ch, 1, NULL, 0, &err));
    FILE *f = fopen(path, "r+b");
    CHECK(f != NULL);
    if (!f) return;
    char buf[4096];
    size_t n = fread(buf, 1, sizeof buf, f);
    const char key[] = "dataWindow\0box2i";
    size_t at = 0;
    for (size_t i = 0; i + sizeof key + 24 < n && !at; ++i)
        if (!memcmp(buf + i, key, sizeof key)) at = i + sizeof key + 4; /* past the type and the size */
    CHECK(at > 0);
    int32_t box[4] = {0, 0, 4095, 4095}; /* min x, min y, max x, max y (little-endian, as EXR) */
    if (at) {
        fseek(f, (long)at, SEEK_SET);
        fwrite(box, sizeof box, 1, f);
    }
    fclose(f);
    ExrImage img;
    CHECK(!exr_read(path, &img, &err));
    CHECK(strstr(err.message, "larger than the file's data could hold") != NULL);
    CHECK(err.exit_code == WEDGE_EXIT_INPUT);
}

int main(void)
{
    test_chunk_claiming_too_much();
    snprintf(tmpdir, sizeof tmpdir, "/tmp/wedge_test_exr_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_round_trip_exact();
    test_nonfinite_replaced();
    test_types_and_compressions();
    test_tiny_chunks();
    test_incompressible();
    test_zip_level();
    test_grey_and_missing_rgb();
    test_bad_inputs();
    test_atomic_failures();
    test_header_larger_than_file();
    clean_tmp();
    rmdir(tmpdir);
    CHECK_DONE();
}
