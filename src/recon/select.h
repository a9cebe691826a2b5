/* Which reconstruction method each distribution effect gets (DESIGN.md section 1: the
 * renderer chooses per effect). The one policy, read by `wedge render` (through the
 * pipeline) and `wedge info`, so the two always agree. */
#ifndef WEDGE_RECON_SELECT_H
#define WEDGE_RECON_SELECT_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/method.h"
#include "scene/effects.h"

typedef struct {
    const ReconMethodClass *method[EFFECT_COUNT]; /* NULL: the effect is absent or not filtered */
    const char *reason[EFFECT_COUNT];             /* one line: why (NULL for absent effects) */
} ReconChoice;

/* The choice for the effects present and a --filter request: "auto" (the measured best per
 * effect), "none" (plain Monte Carlo), a method's name (that method for every effect it can
 * filter, nothing for the others), or a method per effect, "EFFECT=METHOD[,...]" with METHOD
 * a method's name, auto or none (effects not named: auto's choice), e.g. "motion=lr,defocus=lr"
 * for layered reconstruction of the camera effects beside auto's shading filters. An unknown
 * request chooses nothing. */
void recon_select(EffectMask present, const char *request, ReconChoice *out);

/* "aaf", or "none" when the effect is not filtered. */
const char *recon_choice_name(const ReconChoice *c, Effect e);
/* Whether any effect is filtered. */
bool recon_choice_any(const ReconChoice *c);

/* True for the --filter values the renderer accepts: "auto", "none", every method's name and
 * the per-effect form. */
bool recon_filter_known(const char *request);
/* The same, and for a per-effect request that is not valid, what is wrong in why ("lr cannot
 * filter soft_shadows"); why may be NULL. */
bool recon_filter_problem(const char *request, char *why, size_t why_size);
/* Those values as a phrase for messages, "auto, aaf or none", written to buf (truncated to
 * size - 1 characters); returns buf. */
const char *recon_filter_choices(char *buf, size_t size);

#endif
