/* The reference cache: high-spp reference renders stored under a key that changes whenever
 * anything that could change the reference changes (issue 5, "References and sweeps"):
 * the text of every scene file read (main file, Include, Import), every data file a
 * parameter names (plymesh and imagemap "filename"), the resolution, spp, seed, the render
 * arguments of the reference method and the wedge version. A stale reference is therefore
 * never reused, and an unchanged one is never rendered twice. */
#ifndef WEDGE_APP_REF_CACHE_H
#define WEDGE_APP_REF_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/diag.h"
#include "scene/scene_desc.h"

/* 64-bit FNV-1a (Fowler, Noll, Vo): a small, well-specified hash that is enough to tell
 * apart the handful of scene versions a cache ever sees. The key runs two independent
 * FNV-1a streams (different offset bases) so that a 128-bit name is stored. */
typedef struct {
    uint64_t h[2];
} RefKeyHash;

#define FNV1A64_OFFSET 0xcbf29ce484222325ull
#define FNV1A64_PRIME 0x100000001b3ull

/* Plain 64-bit FNV-1a of a byte string (exposed for the tests' known vectors). */
uint64_t fnv1a64(const void *data, size_t size, uint64_t state);

void ref_key_init(RefKeyHash *k);
/* Adds a tagged, length-prefixed field, so that ("ab","c") and ("a","bc") hash differently. */
void ref_key_add_bytes(RefKeyHash *k, const char *tag, const void *data, size_t size);
void ref_key_add_string(RefKeyHash *k, const char *tag, const char *s);
void ref_key_add_int(RefKeyHash *k, const char *tag, long long v);
/* Adds the whole content of a file; false with err (exit 2) when it cannot be read. */
bool ref_key_add_file(RefKeyHash *k, const char *tag, const char *path, Diag *err);
/* 32 lowercase hex digits. */
void ref_key_hex(const RefKeyHash *k, char out[33]);

/* Everything the reference depends on apart from the scene files themselves. */
typedef struct {
    int width, height;              /* the resolution actually rendered */
    int spp;
    uint64_t seed;
    const char *const *render_args; /* the reference method's extra render arguments */
    int render_arg_count;
} RefParams;

/* Key of a reference of `scene`. embedded_text is the scene text when the scene was parsed
 * from memory (the default scene) and NULL when it came from files: then every file of
 * scene->source_files is hashed, plus the plymesh and imagemap data files.
 * Returns false with err (exit 2) when a file cannot be read. */
bool ref_key_for_scene(const SceneDesc *scene, const char *embedded_text, const RefParams *p,
                       char out_hex[33], Diag *err);

/* The cache folder: `override` when not NULL, else $XDG_CACHE_HOME/wedge, else
 * $HOME/.cache/wedge. Created (with parents) when missing. False with err (exit 3). */
bool ref_cache_dir(const char *override, char *out, size_t out_size, Diag *err);


#endif
