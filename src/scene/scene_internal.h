/* Private helpers shared by the files of src/scene (not for other modules). */
#ifndef WEDGE_SCENE_INTERNAL_H
#define WEDGE_SCENE_INTERNAL_H

#include "scene/scene_desc.h"

/* The pbrt spelling of a parameter type ("float", "point3", ...). */
const char *param_type_name(ParamType t);

/* Which parameters an entity of a given kind and type understands (param_tables.c).
 * kind is "camera", "film", "sampler", "integrator", "filter", "shape", "material",
 * "texture", "light", "arealight" or "option". Returns false with err filled on a
 * parameter of a known name but the wrong type or value count; adds an "unused parameter"
 * warning for every parameter the kind/type does not know. Unknown types are not checked. */
bool params_check_known(SceneDesc *scene, const char *kind, const char *type, const ParamSet *ps, Diag *err);

/* Validates a shape's parameters (counts, index ranges, radii, PLY file present).
 * Returns false with err filled at the offending parameter. */
bool shape_validate(SceneDesc *scene, ShapeDesc *shape, Diag *err);

#endif
