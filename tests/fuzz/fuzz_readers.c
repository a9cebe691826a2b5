/* libFuzzer harness for the file readers wedge takes from users besides the scene parser
 * (tools/fuzz-readers builds it, once per reader, with -DFUZZ_PLY, -DFUZZ_EXR or -DFUZZ_PNG):
 * the PLY mesh reader (plymesh shapes), the EXR reader (wedge compare, convert, image
 * textures and environment maps) and the PNG reader (compare, convert, textures). The readers
 * take a path, so each input is written to a file first. Any input must be read or refused
 * with a message: no crash, hang, leak or sanitizer report. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "core/diag.h"
#if defined(FUZZ_PLY)
#include "geometry/ply.h"
#else
#include "io/image_io.h"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#if defined(FUZZ_PLY)
/* geometry/mesh.c's, without the rest of that file (which needs OpenSubdiv) */
void mesh_free(TriMesh *mesh)
{
    free(mesh->p), free(mesh->n), free(mesh->uv), free(mesh->index);
    mesh->p = NULL, mesh->n = NULL, mesh->uv = NULL, mesh->index = NULL;
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    if (!path[0]) snprintf(path, sizeof path, "/tmp/wedge-fuzz-%d.bin", (int)getpid());
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fwrite(data, 1, size, f);
    fclose(f);
    Diag err = {0};
    bool ok;
#if defined(FUZZ_PLY)
    TriMesh mesh = {0};
    ok = ply_read(path, &mesh, NULL, NULL, &err);
    if (ok) mesh_free(&mesh);
#elif defined(FUZZ_EXR)
    ExrImage img;
    ok = exr_read(path, &img, &err);
    if (ok) exr_image_free(&img);
#else
    int w, h, c;
    float *px = NULL;
    ok = png_read(path, &w, &h, &c, &px, &err);
    free(px);
#endif
    unlink(path); /* a run leaves nothing behind in /tmp */
    if (!ok && err.message[0] == '\0') abort(); /* a refusal must always explain itself */
    return 0;
}
