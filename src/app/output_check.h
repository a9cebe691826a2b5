/* Before anything is rendered: can every output be written, and is none of them one of the
 * scene's own files? A typo in a directory must not cost a whole render, and
 * `wedge render s.pbrt -o s.pbrt` must not replace the scene with an image. */
#ifndef WEDGE_APP_OUTPUT_CHECK_H
#define WEDGE_APP_OUTPUT_CHECK_H

#include <stdbool.h>

#include "core/diag.h"
#include "scene/scene_desc.h"

/* False with err set (exit 3 for an unwritable place, exit 1 for an output that is an input:
 * the scene file, an included file, a PLY mesh, an image texture or environment map). what
 * names the output in the message ("output image", "report"). */
bool output_check(const char *path, const char *what, const SceneDesc *scene, Diag *err);

#endif
