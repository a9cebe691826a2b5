/* PLY reader/writer: round trips in all three encodings (with and without normals, uv,
 * quads, and properties/elements the reader must skip), and one exact message per
 * malformed-file class. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "geometry/ply.h"

static char tmpdir[64];

static const char *tmp_path(const char *name)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    return path;
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) { perror(path); exit(1); }
    fwrite(data, 1, n, f);
    fclose(f);
}

static void write_text(const char *path, const char *text) { write_bytes(path, text, strlen(text)); }

/* Reads path expecting failure; returns the message (static buffer). */
static const char *read_error(const char *path)
{
    static Diag err;
    memset(&err, 0, sizeof err);
    TriMesh m;
    if (ply_read(path, &m, NULL, NULL, &err)) {
        mesh_free(&m);
        return "(no error)";
    }
    CHECK(err.exit_code == WEDGE_EXIT_INPUT);
    CHECK(m.p == NULL && m.index == NULL); /* nothing leaks out on failure */
    return err.message;
}

/* ---- round trips ---- */

/* A small mesh with a triangle, a quad and a triangle; awkward floats that must survive
 * ASCII (%.9g is exact for float) and both byte orders. */
static const vec3 P[5] = {{0.1f, -2.5f, 3e-7f}, {1.0f, 0.0f, -0.333333343f}, {-375000.25f, 7.0f, 1.5f},
                          {0.0f, 1e20f, -1e-20f}, {2.0f, 2.0f, 2.0f}};
static const vec3 N[5] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0.6f, 0.8f, 0}, {-0.6f, 0, -0.8f}};
static const vec2 UV[5] = {{0, 0}, {1, 0}, {0.5f, 1}, {0.25f, 0.125f}, {-3, 4}};
static const uint8_t FACE_SIZE[3] = {3, 4, 3};
static const uint32_t FACE_INDEX[10] = {0, 1, 2, 1, 3, 4, 2, 4, 3, 0};
/* quad v0 v1 v2 v3 -> (v0 v1 v2) (v0 v2 v3) */
static const uint32_t TRI_INDEX[12] = {0, 1, 2, 1, 3, 4, 1, 4, 2, 4, 3, 0};

static void round_trip(PlyFormat fmt, bool normals, bool uv, bool extra)
{
    const char *path = tmp_path("rt.ply");
    PlyWriteDesc w = {5, P, normals ? N : NULL, uv ? UV : NULL, 3, FACE_SIZE, FACE_INDEX, extra};
    Diag err = {0};
    CHECK(ply_write(path, fmt, &w, &err));

    PlyInfo info;
    CHECK(ply_read_info(path, &info, &err));
    CHECK(info.format == fmt);
    CHECK(info.vertex_count == 5 && info.face_count == 3);
    CHECK(info.has_normals == normals && info.has_uv == uv);
    CHECK(ply_count_triangles(path, &err) == 4);

    TriMesh m;
    bool ok = ply_read(path, &m, NULL, NULL, &err);
    CHECK(ok);
    if (!ok) {
        fprintf(stderr, "format %d normals %d uv %d extra %d: %s\n", fmt, normals, uv, extra, err.message);
        return;
    }
    CHECK(m.vertex_count == 5 && m.triangle_count == 4);
    CHECK((m.n != NULL) == normals && (m.uv != NULL) == uv);
    int bad = 0;
    for (int i = 0; i < 5; i++) {
        bad += memcmp(&m.p[i], &P[i], sizeof P[i]) != 0;
        if (normals) bad += memcmp(&m.n[i], &N[i], sizeof N[i]) != 0;
        if (uv) bad += memcmp(&m.uv[i], &UV[i], sizeof UV[i]) != 0;
    }
    bad += memcmp(m.index, TRI_INDEX, sizeof TRI_INDEX) != 0;
    CHECK(bad == 0);
    if (bad) fprintf(stderr, "  (format %d normals %d uv %d extra %d)\n", fmt, normals, uv, extra);
    mesh_free(&m);
}

/* All-triangle mesh written without face sizes. */
static void round_trip_triangles(PlyFormat fmt)
{
    const char *path = tmp_path("tris.ply");
    PlyWriteDesc w = {5, P, NULL, NULL, 4, NULL, TRI_INDEX, false};
    Diag err = {0};
    CHECK(ply_write(path, fmt, &w, &err));
    TriMesh m;
    CHECK(ply_read(path, &m, NULL, NULL, &err));
    CHECK(m.triangle_count == 4 && memcmp(m.index, TRI_INDEX, sizeof TRI_INDEX) == 0);
    mesh_free(&m);
}

/* ---- warnings ---- */

static int warn_count;
static char warn_text[512];
static void on_warn(void *ctx, SrcLoc loc, const char *text)
{
    (void)ctx;
    warn_count++;
    snprintf(warn_text, sizeof warn_text, "%s: %s", loc.path, text);
}

static void polygon_skipped(void)
{
    const char *path = tmp_path("pent.ply");
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 3\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 0\n"
                     "5 0 1 2 4 3\n3 0 1 2\n2 0 1\n");
    TriMesh m;
    Diag err = {0};
    warn_count = 0;
    CHECK(ply_read(path, &m, on_warn, NULL, &err));
    CHECK(m.triangle_count == 1);
    CHECK(warn_count == 1);
    char expected[512];
    snprintf(expected, sizeof expected,
             "%s: ignored 2 faces with other than 3 or 4 vertices (only triangles and quads are "
             "supported)", path);
    CHECK_STR(warn_text, expected);
    mesh_free(&m);
    CHECK(ply_count_triangles(path, &err) == 1);
}

/* ---- malformed files: one exact message each ---- */

static const char *HEADER3 = "ply\nformat %s 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
                             "end_header\n";

/* A binary little-endian file with 3 vertices and the given triangles. */
static size_t make_binary(unsigned char *buf, int faces)
{
    size_t n = (size_t)sprintf((char *)buf, HEADER3, "binary_little_endian", faces);
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(buf + n, v, sizeof v); /* the test machine is little-endian (x86-64) */
    n += sizeof v;
    for (int f = 0; f < faces; f++) {
        buf[n++] = 3;
        int32_t idx[3] = {0, f % 2 ? 2 : 1, f % 2 ? 1 : 2};
        memcpy(buf + n, idx, sizeof idx);
        n += sizeof idx;
    }
    return n;
}

static void malformed(void)
{
    char expected[1024];
    unsigned char buf[4096];
    const char *path = tmp_path("bad.ply");

    /* a valid file first, so the failures below are the edits' doing */
    size_t full = make_binary(buf, 2);
    write_bytes(path, buf, full);
    CHECK_STR(read_error(path), "(no error)");

    /* truncated binary: the second face is missing entirely -> end of file at its count */
    write_bytes(path, buf, full - 13);
    snprintf(expected, sizeof expected,
             "%s: error: unexpected end of file in element \"face\" (row index 1, 2 rows declared)", path);
    CHECK_STR(read_error(path), expected);

    /* truncated binary inside a list: the list cannot fit in what is left */
    write_bytes(path, buf, full - 5);
    snprintf(expected, sizeof expected,
             "%s: error: list length 3 runs past the end of the file (element \"face\", row index 1)", path);
    CHECK_STR(read_error(path), expected);

    /* truncated inside the vertex rows: caught from the header before any allocation */
    size_t header = (size_t)snprintf(NULL, 0, HEADER3, "binary_little_endian", 2);
    write_bytes(path, buf, header + 20);
    snprintf(expected, sizeof expected,
             "%s:3:1: error: element \"vertex\" declares 3 rows, more than the 20 bytes of data left "
             "in the file can hold", path);
    CHECK_STR(read_error(path), expected);

    /* bad magic */
    write_text(path, "plyx\nformat ascii 1.0\nend_header\n");
    snprintf(expected, sizeof expected, "%s:1:1: error: not a PLY file (the first line must be \"ply\")", path);
    CHECK_STR(read_error(path), expected);
    write_bytes(path, "\x89PNG\r\n\x1a\n", 8);
    CHECK_STR(read_error(path), expected);

    /* count overflow: a huge row count with a few bytes of data */
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\n"
                     "property float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 0\n");
    snprintf(expected, sizeof expected,
             "%s:3:1: error: element \"vertex\" declares 2000000000 rows, more than the 14 bytes of "
             "data left in the file can hold", path);
    CHECK_STR(read_error(path), expected);
    write_text(path, "ply\nformat binary_big_endian 1.0\nelement vertex 99999999999\nend_header\n");
    snprintf(expected, sizeof expected,
             "%s:3:16: error: bad element count \"99999999999\" (expected an integer from 0 to 2147483647)", path);
    CHECK_STR(read_error(path), expected);

    /* index out of range (ASCII: with line and column of the index) */
    char text[1024];
    snprintf(text, sizeof text, HEADER3, "ascii", 2);
    strcat(text, "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 7 1\n");
    write_text(path, text);
    snprintf(expected, sizeof expected,
             "%s:14:5: error: face 1 has vertex index 7, out of range for 3 vertices", path);
    CHECK_STR(read_error(path), expected);
    /* ... and in binary (no lines there); negative indices too */
    full = make_binary(buf, 2);
    int32_t neg = -1;
    memcpy(buf + full - 4, &neg, 4);
    write_bytes(path, buf, full);
    snprintf(expected, sizeof expected, "%s: error: face 1 has vertex index -1, out of range for 3 vertices", path);
    CHECK_STR(read_error(path), expected);

    /* unknown format */
    write_text(path, "ply\nformat binary_middle_endian 1.0\nend_header\n");
    snprintf(expected, sizeof expected,
             "%s:2:8: error: unknown PLY format \"binary_middle_endian\" (expected ascii, "
             "binary_little_endian or binary_big_endian)", path);
    CHECK_STR(read_error(path), expected);

    /* more classes */
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
    snprintf(expected, sizeof expected,
             "%s:5:1: error: unexpected end of file in the header (no \"end_header\")", path);
    CHECK_STR(read_error(path), expected);

    write_text(path, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n3 0 0 0\n");
    snprintf(expected, sizeof expected, "%s:3:1: error: element \"vertex\" has no property \"z\"", path);
    CHECK_STR(read_error(path), expected);

    snprintf(text, sizeof text, HEADER3, "ascii", 1);
    strcat(text, "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
    write_text(path, text);
    snprintf(expected, sizeof expected,
             "%s:11:3: error: expected a finite number but found \"nan\" (element \"vertex\", row index 1)", path);
    CHECK_STR(read_error(path), expected);

    snprintf(text, sizeof text, HEADER3, "ascii", 1);
    strcat(text, "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n");
    write_text(path, text);
    snprintf(expected, sizeof expected,
             "%s:13:7: error: expected an integer of type int but found \"2.5\" (element \"face\", row index 0)", path);
    CHECK_STR(read_error(path), expected);

    write_text(path, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n");
    snprintf(expected, sizeof expected,
             "%s:8:15: error: list count type \"float\" is not an integer type", path);
    CHECK_STR(read_error(path), expected);

    snprintf(text, sizeof text, HEADER3, "ascii", 1);
    strcat(text, "0 0 0\n1 0 0\n0 1 0\n3 0 1\n");
    write_text(path, text);
    snprintf(expected, sizeof expected,
             "%s:14:1: error: unexpected end of file in element \"face\" (row index 0, 1 rows declared)", path);
    CHECK_STR(read_error(path), expected);

    /* binary float overflow to infinity is caught too */
    full = make_binary(buf, 1);
    size_t hdr1 = (size_t)snprintf(NULL, 0, HEADER3, "binary_little_endian", 1);
    float inf = 1e30f;
    inf *= 1e30f;
    memcpy(buf + hdr1 + 4, &inf, 4);
    write_bytes(path, buf, full);
    snprintf(expected, sizeof expected, "%s: error: vertex 0 has a non-finite value for \"y\"", path);
    CHECK_STR(read_error(path), expected);

    snprintf(expected, sizeof expected, "%s/missing.ply: error: cannot read PLY file: No such file or directory", tmpdir);
    CHECK_STR(read_error(tmp_path("missing.ply")), expected);
}

int main(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/wedge-ply-XXXXXX");
    if (!mkdtemp(tmpdir)) { perror("mkdtemp"); return 1; }

    for (int fmt = 0; fmt < 3; fmt++) {
        for (int mask = 0; mask < 8; mask++) round_trip((PlyFormat)fmt, mask & 1, mask & 2, mask & 4);
        round_trip_triangles((PlyFormat)fmt);
    }
    polygon_skipped();
    malformed();

    const char *names[] = {"rt.ply", "tris.ply", "pent.ply", "bad.ply"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) unlink(tmp_path(names[i]));
    rmdir(tmpdir);
    CHECK_DONE();
}
