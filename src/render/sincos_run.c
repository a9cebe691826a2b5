/* A run of sines and cosines (see sincos_run.h). */
#include "render/sincos_run.h"

#include "core/vectorise.h"

WEDGE_VECTORISED void sincos_run(int count, const float *restrict x, float *restrict s, float *restrict c)
{
    for (int k = 0; k < count; ++k) sincos_lane(x[k], &s[k], &c[k]);
}

void sincos_one(float x, float *s, float *c)
{
    sincos_lane(x, s, c);
}
