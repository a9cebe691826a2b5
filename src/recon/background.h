/* What a ray that escapes the scene sees: black unless an environment ("infinite") light is
 * there. A pixel whose samples all escaped over a black background holds no light at all, and
 * a lens filter that gathered its neighbours' light into it would draw a halo around every
 * bright defocused emitter (AAF: docs/algorithms.md 3.2; FSF: section 10). */
#ifndef WEDGE_RECON_BACKGROUND_H
#define WEDGE_RECON_BACKGROUND_H

#include <stdbool.h>

#include "render/renderer.h"

/* True when the renderer has no environment light. */
bool recon_background_is_black(const Renderer *r);

#endif
