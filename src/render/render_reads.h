/* What the users of a render read of it beyond the image, declared by those users so that the
 * renderer can skip the rest (issue 22; docs/design.md section 2, "Declared reads").
 *
 * Every user reads the radiance: the frame's colour sums and its sample counts, and a
 * record's radiance (L, emission, direct, indirect) and film, lens and time coordinates.
 * Beyond that:
 *
 *   RENDER_READS_FIRST_HIT     the record's fields the methods read: the first-hit fields
 *                              (albedo and its diffuse / glossy split, phong_exponent,
 *                              unfilterable, p_world, n_shading, depth_cam, object_id, and on a
 *                              miss their miss values), the unfiltered parts (unfiltered,
 *                              unfiltered_direct) and the cleared motion and ray geometry
 *                              entries: the G-buffer sink, the sample store and the methods'
 *                              sinks read them
 *   RENDER_READS_FRAME_GUIDES  the frame's albedo, normal, depth and hits sums (made from the
 *                              first-hit fields): the AOV layers, the preview, the composite
 *   RENDER_READS_FRAME_PARTS   the frame's direct, indirect and emission sums: the AOV
 *                              layers, the composite, the methods
 *
 * A declaration is RENDER_READS_RADIANCE plus the bits above that some user needs; 0 means
 * "not declared" and keeps everything, so a user that says nothing gets every field. A pass
 * declared with neither bit, without a sink and recording neither motion nor ray geometry
 * keeps the radiance alone, in 52-byte RadianceRecords instead of SampleRecords
 * (integrate_wave_radiance, integrator_radiance_only); a frame made for it
 * (render_reads_frame_planes) holds the colour and the counts alone. */
#ifndef WEDGE_RENDER_RENDER_READS_H
#define WEDGE_RENDER_RENDER_READS_H

#include "render/frame.h"

enum {
    RENDER_READS_RADIANCE = 1u << 0,
    RENDER_READS_FIRST_HIT = 1u << 1,
    RENDER_READS_FRAME_GUIDES = 1u << 2,
    RENDER_READS_FRAME_PARTS = 1u << 3,
    RENDER_READS_ALL = RENDER_READS_RADIANCE | RENDER_READS_FIRST_HIT | RENDER_READS_FRAME_GUIDES |
                       RENDER_READS_FRAME_PARTS,
};

/* Whether a declaration (0: none, everything) asks for the first-hit record fields; the
 * frame's guide sums are made from them. */
static inline int render_reads_first_hit(unsigned reads)
{
    return reads == 0 || (reads & (RENDER_READS_FIRST_HIT | RENDER_READS_FRAME_GUIDES)) != 0;
}
static inline int render_reads_frame_guides(unsigned reads)
{
    return reads == 0 || (reads & RENDER_READS_FRAME_GUIDES) != 0;
}
static inline int render_reads_frame_parts(unsigned reads)
{
    return reads == 0 || (reads & RENDER_READS_FRAME_PARTS) != 0;
}

/* The planes of a frame that a declaration reads (frame_init_planes). */
static inline unsigned render_reads_frame_planes(unsigned reads)
{
    return (render_reads_frame_parts(reads) ? FRAME_PLANES_PARTS : 0u) |
           (render_reads_frame_guides(reads) ? FRAME_PLANES_GUIDES : 0u);
}

#endif
