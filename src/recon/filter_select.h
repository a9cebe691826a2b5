/* Which reconstruction filter each distribution effect gets (DESIGN.md section 1: the
 * renderer chooses per effect). One policy, read by `wedge render` and `wedge info`. */
#ifndef WEDGE_RECON_FILTER_SELECT_H
#define WEDGE_RECON_FILTER_SELECT_H

#include <stdbool.h>
#include <stddef.h>

#include "scene/scene_desc.h"

/* Effects in the order of the scene's effect names: soft_shadows, defocus, motion, indirect. */
enum { RECON_SOFT_SHADOWS, RECON_DEFOCUS, RECON_MOTION, RECON_INDIRECT, RECON_EFFECT_COUNT };

const char *recon_effect_name(int effect);
bool recon_effect_present(const Effects *fx, int effect);
/* True for the --filter values the renderer accepts: "auto", "aaf", "none". */
bool recon_filter_known(const char *requested);
/* Those values as a phrase for messages, "auto, aaf or none", written to buf (truncated to
 * size - 1 characters); returns buf. */
const char *recon_filter_choices(char *buf, size_t size);
/* The filter the effect gets for a --filter request: "aaf" or "none". Until further filters
 * land, auto means axis-aligned filtering for soft shadows, defocus and indirect light, and
 * nothing for motion blur. Absent effects get "none". */
const char *recon_filter_for(const char *requested, const Effects *fx, int effect);

#endif
