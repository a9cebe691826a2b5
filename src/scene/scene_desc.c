/* SceneDesc lifetime and warnings. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "scene/scene_desc.h"

/* A scene with thousands of broken shapes should not print thousands of lines. */
enum { WARNINGS_MAX = 200 };

void scene_desc_free(SceneDesc *scene)
{
    if (!scene) return;
    arena_free(&scene->arena);
    memset(scene, 0, sizeof *scene);
}

static void push_warning(SceneDesc *scene, const char *line)
{
    /* The array lives in the arena; grow by doubling at powers of two (old copies stay in
     * the arena until it is freed, which is bounded by WARNINGS_MAX). */
    int n = scene->warning_count;
    if (n == 0 || (n & (n - 1)) == 0) {
        int cap = n == 0 ? 8 : 2 * n;
        const char **w = arena_alloc(&scene->arena, (size_t)cap * sizeof *w);
        if (!w) return;
        if (n) memcpy(w, scene->warnings, (size_t)n * sizeof *w);
        scene->warnings = w;
    }
    const char *copy = arena_strdup(&scene->arena, line);
    if (!copy) return;
    scene->warnings[scene->warning_count++] = copy;
}

void scene_warn(SceneDesc *scene, SrcLoc loc, const char *fmt, ...)
{
    if (scene->warning_count > WARNINGS_MAX) return; /* already suppressed: skip the formatting */
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    diag_format(line, sizeof line, loc, "warning", fmt, ap);
    va_end(ap);
    for (int i = 0; i < scene->warning_count; ++i)
        if (!strcmp(scene->warnings[i], line)) return;
    if (scene->warning_count == WARNINGS_MAX) {
        push_warning(scene, "warning: too many warnings; further warnings suppressed");
        return;
    }
    if (scene->warning_count > WARNINGS_MAX) return;
    push_warning(scene, line);
}
