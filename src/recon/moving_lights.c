/* Whether a frame's area lights move (see moving_lights.h). */
#include "recon/moving_lights.h"

#include "render/integrator.h"
#include "render/light.h"
#include "render/tracer.h"

bool recon_area_light_moves(const Renderer *r)
{
    const IntegratorScene *isc = renderer_integrator_scene(r);
    if (!isc || !isc->lights || !isc->tracer) return false;
    for (int i = 0; i < isc->lights->count; ++i) {
        const Light *l = &isc->lights->lights[i];
        if (l->kind != LIGHT_AREA || l->instance < 0 || l->instance >= isc->tracer->instance_count) continue;
        if (isc->tracer->instances[l->instance].moving) return true;
    }
    return false;
}
