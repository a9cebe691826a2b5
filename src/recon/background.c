/* What an escaped ray sees (see background.h). */
#include "recon/background.h"

bool recon_background_is_black(const Renderer *r)
{
    RenderLightInfo info;
    for (int l = 0; l < renderer_light_count(r); ++l)
        if (renderer_light_info(r, l, &info) && info.kind == RENDER_LIGHT_INFINITE) return false;
    return true;
}
