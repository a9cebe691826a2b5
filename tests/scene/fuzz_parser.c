/* libFuzzer harness for the scene parser (built by tools/fuzz-parser, not a ctest test).
 * Any input must parse or fail with a message: no crash, hang, leak or sanitizer report. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_desc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* Include and PLY names resolve against the test data folder, so the fuzzer can reach
     * real include chains (cycles, nested files) through the seed corpus. */
    const char *base = getenv("WEDGE_FUZZ_BASE_DIR");
    SceneDesc scene;
    Diag err;
    if (scene_parse_string((const char *)data, size, "fuzz.pbrt", base ? base : ".", &scene, &err)) {
        /* Exercise the consumers' getters on everything that was kept. */
        float rgb[3];
        for (int i = 0; i < scene.material_count; ++i)
            for (int k = 0; k < scene.materials[i].params.count; ++k)
                params_rgb(&scene.materials[i].params, scene.materials[i].params.items[k].name, rgb);
        for (int i = 0; i < scene.light_count; ++i)
            for (int k = 0; k < scene.lights[i].params.count; ++k)
                params_illuminant_rgb(&scene.lights[i].params, scene.lights[i].params.items[k].name, rgb);
        scene_analyze_effects(&scene);
        scene_desc_free(&scene);
    } else if (err.message[0] == '\0') {
        abort(); /* a failure must always explain itself */
    }
    return 0;
}
