/* The moving-light test scenes' common text (recon/test_moving_light_sweep,
 * recon/test_fsf_swept_light): a camera over a floor with an open shutter, then a 0.8 x 0.8 square
 * light 3 units up (its transform between the two: MOVING_LIGHT_HEAD, the motion, then
 * MOVING_LIGHT_AND_FLOOR). */
#ifndef WEDGE_TESTS_MOVING_LIGHT_SCENE_H
#define WEDGE_TESTS_MOVING_LIGHT_SCENE_H

#define MOVING_LIGHT_HEAD                                                                                           \
    "LookAt 0 6 -0.5   0 0 0   0 1 0\n"                                                                            \
    "Camera \"perspective\" \"float fov\" [ 70 ] \"float shutteropen\" [ 0 ] \"float shutterclose\" [ 1 ]\n"       \
    "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 24 ] \"string filename\" [ \"t.exr\" ]\n" \
    "Sampler \"stratified\" \"integer pixelsamples\" [ 16 ]\n"                                                      \
    "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"                                                              \
    "WorldBegin\n"                                                                                                  \
    "AttributeBegin\n"
#define MOVING_LIGHT_AND_FLOOR                                                                                            \
    "  AreaLightSource \"diffuse\" \"rgb L\" [ 5 5 5 ]\n"                                                                  \
    "  Shape \"trianglemesh\" \"point3 P\" [ -0.4 3 -0.4  0.4 3 -0.4  0.4 3 0.4  -0.4 3 0.4 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n" \
    "AttributeEnd\n"                                                                                                      \
    "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"                                                          \
    "Shape \"trianglemesh\" \"point3 P\" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ] \"integer indices\" [ 0 2 1 0 3 2 ]\n"

#endif
