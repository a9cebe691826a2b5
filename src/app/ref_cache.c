/* Reference cache keys and folder (see ref_cache.h). */
#include "app/ref_cache.h"

#include "core/cache_home.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

uint64_t fnv1a64(const void *data, size_t size, uint64_t state)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; ++i) {
        state ^= p[i];
        state *= FNV1A64_PRIME;
    }
    return state;
}

void ref_key_init(RefKeyHash *k)
{
    /* The second stream starts from the offset basis of a hash of a fixed string, which makes
     * it a different function of the same input (a 128-bit name, not a repeated 64-bit one). */
    k->h[0] = FNV1A64_OFFSET;
    k->h[1] = fnv1a64("wedge reference cache", 21, FNV1A64_OFFSET);
}

static void key_feed(RefKeyHash *k, const void *data, size_t size)
{
    k->h[0] = fnv1a64(data, size, k->h[0]);
    k->h[1] = fnv1a64(data, size, k->h[1]);
}

static void key_feed_u64(RefKeyHash *k, uint64_t v)
{
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = (unsigned char)(v >> (8 * i)); /* fixed byte order */
    key_feed(k, b, sizeof b);
}

void ref_key_add_bytes(RefKeyHash *k, const char *tag, const void *data, size_t size)
{
    size_t tag_len = strlen(tag);
    key_feed_u64(k, tag_len);
    key_feed(k, tag, tag_len);
    key_feed_u64(k, size);
    key_feed(k, data, size);
}

void ref_key_add_string(RefKeyHash *k, const char *tag, const char *s)
{
    ref_key_add_bytes(k, tag, s ? s : "", s ? strlen(s) : 0);
}

void ref_key_add_int(RefKeyHash *k, const char *tag, long long v)
{
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = (unsigned char)((unsigned long long)v >> (8 * i));
    ref_key_add_bytes(k, tag, b, sizeof b);
}

bool ref_key_add_file(RefKeyHash *k, const char *tag, const char *path, Diag *err)
{
    SrcLoc none = {0};
    FILE *f = fopen(path, "rb");
    if (!f) {
        diag_set(err, WEDGE_EXIT_INPUT, none, "cannot read '%s' for the reference key: %s", path,
                 strerror(errno));
        return false;
    }
    /* Stream the file: data files (PLY meshes, textures) can be large. The length goes in
     * after the content here, which is as unambiguous as a prefix. */
    size_t tag_len = strlen(tag);
    key_feed_u64(k, tag_len);
    key_feed(k, tag, tag_len);
    unsigned char buf[1 << 16];
    uint64_t total = 0;
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) {
        key_feed(k, buf, n);
        total += n;
    }
    bool ok = !ferror(f);
    fclose(f);
    if (!ok) {
        diag_set(err, WEDGE_EXIT_INPUT, none, "cannot read '%s' for the reference key", path);
        return false;
    }
    key_feed_u64(k, total);
    return true;
}

void ref_key_hex(const RefKeyHash *k, char out[33])
{
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)k->h[0], (unsigned long long)k->h[1]);
}

/* The string value of parameter `name`, read without marking it used (the key must not
 * change what the renderer later reports as unused). */
static const char *param_string_raw(const ParamSet *ps, const char *name)
{
    for (int i = 0; i < ps->count; ++i) {
        const Param *p = &ps->items[i];
        if (p->type == PARAM_STRING && p->count >= 1 && p->strings && !strcmp(p->name, name))
            return p->strings[0];
    }
    return NULL;
}

static bool add_data_file(RefKeyHash *k, const char *base_dir, const char *filename, Diag *err)
{
    char path[4096];
    int n = filename[0] == '/' || !base_dir || !base_dir[0]
                ? snprintf(path, sizeof path, "%s", filename)
                : snprintf(path, sizeof path, "%s/%s", base_dir, filename);
    if (n < 0 || (size_t)n >= sizeof path) {
        SrcLoc none = {0};
        diag_set(err, WEDGE_EXIT_INPUT, none, "data file path too long: '%s'", filename);
        return false;
    }
    ref_key_add_string(k, "data-name", filename);
    return ref_key_add_file(k, "data", path, err);
}

bool ref_key_for_scene(const SceneDesc *scene, const char *embedded_text, const RefParams *p,
                       char out_hex[33], Diag *err)
{
    RefKeyHash k;
    ref_key_init(&k);
    ref_key_add_string(&k, "version", WEDGE_VERSION);
    if (embedded_text) {
        ref_key_add_string(&k, "embedded-scene", embedded_text);
    } else {
        for (int i = 0; i < scene->source_file_count; ++i)
            if (!ref_key_add_file(&k, "scene", scene->source_files[i], err)) return false;
    }
    for (int i = 0; i < scene->shape_count; ++i) {
        const ShapeDesc *s = &scene->shapes[i];
        const char *fn = s->type && !strcmp(s->type, "plymesh") ? param_string_raw(&s->params, "filename") : NULL;
        if (fn && !add_data_file(&k, s->base_dir, fn, err)) return false;
    }
    for (int i = 0; i < scene->texture_count; ++i) {
        const TextureDesc *t = &scene->textures[i];
        const char *fn = t->tex_class && !strcmp(t->tex_class, "imagemap") ? param_string_raw(&t->params, "filename") : NULL;
        if (fn && !add_data_file(&k, t->base_dir, fn, err)) return false;
    }
    /* An environment map ("infinite" light with a filename) changes the picture as much as a
     * texture does. */
    for (int i = 0; i < scene->light_count; ++i) {
        const LightDesc *l = &scene->lights[i];
        const char *fn = param_string_raw(&l->params, "filename");
        if (fn && !add_data_file(&k, l->base_dir, fn, err)) return false;
    }
    ref_key_add_int(&k, "width", p->width);
    ref_key_add_int(&k, "height", p->height);
    ref_key_add_int(&k, "spp", p->spp);
    ref_key_add_int(&k, "seed", (long long)p->seed);
    for (int i = 0; i < p->render_arg_count; ++i) ref_key_add_string(&k, "arg", p->render_args[i]);
    ref_key_hex(&k, out_hex);
    return true;
}


bool ref_cache_dir(const char *override, char *out, size_t out_size, Diag *err)
{
    SrcLoc none = {0};
    const char *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    int n;
    if (override)
        n = snprintf(out, out_size, "%s", override);
    else if (xdg && xdg[0] == '/') /* XDG base-dir spec: relative values are ignored */
        n = snprintf(out, out_size, "%s/wedge", xdg);
    else if (home && home[0])
        n = snprintf(out, out_size, "%s/.cache/wedge", home);
    else {
        diag_set(err, WEDGE_EXIT_RUNTIME, none, "no cache folder: set HOME or XDG_CACHE_HOME, or pass --cache DIR");
        return false;
    }
    if (n < 0 || (size_t)n >= out_size) {
        diag_set(err, WEDGE_EXIT_RUNTIME, none, "cache folder path too long");
        return false;
    }
    if (!make_dirs(out)) {
        diag_set(err, WEDGE_EXIT_RUNTIME, none, "cannot create cache folder '%s': %s", out, strerror(errno));
        return false;
    }
    return true;
}
