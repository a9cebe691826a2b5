/* Helpers for the scene tests: parse text held in a string, get the scene or the message. */
#ifndef WEDGE_TESTS_SCENE_UTIL_H
#define WEDGE_TESTS_SCENE_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene/scene_desc.h"

/* The directory of the test data, absolute when ctest provides WEDGE_SOURCE_DIR. */
static inline const char *data_dir(void)
{
    static char buf[4096];
    const char *src = getenv("WEDGE_SOURCE_DIR");
    if (src) snprintf(buf, sizeof buf, "%s/tests/scene/data", src);
    else snprintf(buf, sizeof buf, "data");
    return buf;
}

/* Parses text as the file "t.pbrt" (Include and PLY paths relative to the data folder).
 * Returns true on success; the scene must then be freed by the caller. */
static inline bool parse_ok(const char *text, SceneDesc *s)
{
    Diag d;
    bool ok = scene_parse_string(text, strlen(text), "t.pbrt", data_dir(), s, &d);
    if (!ok) fprintf(stderr, "unexpected parse error: %s\n", d.message);
    return ok;
}

/* Parses text that must fail; returns the message (static buffer) or "(parsed)". */
static inline const char *parse_err(const char *text)
{
    static Diag d;
    SceneDesc s;
    if (scene_parse_string(text, strlen(text), "t.pbrt", data_dir(), &s, &d)) {
        scene_desc_free(&s);
        return "(parsed)";
    }
    if (d.exit_code != WEDGE_EXIT_INPUT) return "(wrong exit code)";
    return d.message;
}

/* True when some warning of the scene contains text. */
static inline bool has_warning(const SceneDesc *s, const char *text)
{
    for (int i = 0; i < s->warning_count; ++i)
        if (strstr(s->warnings[i], text)) return true;
    return false;
}

#endif
