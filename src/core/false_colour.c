#include "core/false_colour.h"

#include <math.h>

void false_colour(float t, float rgb[3])
{
    /* Piecewise-linear ramp through five stops of increasing lightness. */
    static const float stops[5][3] = {
        {0.00f, 0.00f, 0.00f}, {0.15f, 0.10f, 0.55f}, {0.70f, 0.15f, 0.55f}, {0.98f, 0.55f, 0.15f}, {1.00f, 1.00f, 0.75f},
    };
    if (!(t > 0.0f)) t = 0.0f;
    if (t > 1.0f) t = 1.0f;
    float x = t * 4.0f;
    int i = (int)x;
    if (i > 3) i = 3;
    float f = x - (float)i;
    for (int k = 0; k < 3; ++k) rgb[k] = stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f;
}

float false_colour_image(const float *values, size_t n, float *rgb)
{
    float vmax = 0.0f;
    for (size_t i = 0; i < n; ++i)
        if (isfinite(values[i]) && values[i] > vmax) vmax = values[i];
    for (size_t i = 0; i < n; ++i) {
        float v = isfinite(values[i]) ? values[i] : 0.0f;
        false_colour(vmax > 0.0f ? v / vmax : 0.0f, rgb + 3 * i);
    }
    return vmax;
}
