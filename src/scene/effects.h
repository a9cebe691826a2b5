/* The distribution effects, one vocabulary for the whole renderer (DESIGN.md section 1):
 * this enum, in this order, and these names are used by `wedge info`, the run report, AOV
 * layer names, `wedge converge` and the docs. A set of effects is a bit mask. */
#ifndef WEDGE_SCENE_EFFECTS_H
#define WEDGE_SCENE_EFFECTS_H

#include <stdbool.h>

typedef enum {
    EFFECT_SOFT_SHADOWS, /* an area light with non-zero emission and area */
    EFFECT_DEFOCUS,      /* a thin lens: lensradius > 0 */
    EFFECT_MOTION,       /* shutter open < close and something moves (camera or shape) */
    EFFECT_INDIRECT,     /* the integrator's maxdepth >= 2 */
    EFFECT_COUNT
} Effect;

typedef unsigned EffectMask;
#define EFFECT_BIT(e) (1u << (unsigned)(e))
#define EFFECT_MASK_ALL ((1u << EFFECT_COUNT) - 1u)

static inline bool effect_in(EffectMask m, Effect e) { return (m & EFFECT_BIT(e)) != 0; }

/* "soft_shadows", "defocus", "motion", "indirect"; "?" out of range. */
const char *effect_name(Effect e);
/* The effect whose name is s; false when there is none. */
bool effect_from_name(const char *s, Effect *out);

#endif
