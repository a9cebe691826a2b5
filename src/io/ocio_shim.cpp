// The only C++ in src/io: a thin extern "C" wrapper around OpenColorIO 2.1 (which has no
// C API). Every entry point catches all exceptions and reports through a Diag.
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <OpenColorIO/OpenColorIO.h>

extern "C" {
#include "core/diag.h"
}
#include "io/ocio.h"

namespace OCIO = OCIO_NAMESPACE;

namespace {

// The config text, compiled in so that the binary finds it from any folder.
const char kEmbeddedConfig[] =
#include "io/ocio/wedge_config.ocio.inc"
    ;

struct LoadedConfig {
    OCIO::ConstConfigRcPtr config;
    std::string source;  // "built-in" or the $OCIO path
};

// $OCIO wins when set and non-empty (the OpenColorIO convention); otherwise the built-in.
bool load_config(LoadedConfig &out, Diag *err)
{
    const char *env = std::getenv("OCIO");
    try {
        if (env && *env) {
            out.source = env;
            out.config = OCIO::Config::CreateFromFile(env);
        } else {
            out.source = "built-in";
            std::istringstream text(kEmbeddedConfig);
            out.config = OCIO::Config::CreateFromStream(text);
        }
        out.config->validate();
        return true;
    } catch (const std::exception &e) {
        SrcLoc loc = {env && *env ? env : nullptr, 0, 0};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot load OpenColorIO config%s: %s",
                 env && *env ? " ($OCIO)" : " (built-in)", e.what());
        return false;
    }
}

std::string view_list(const OCIO::ConstConfigRcPtr &config, const char *display)
{
    std::string list;
    int n = config->getNumViews(display);
    for (int i = 0; i < n; ++i) {
        if (i) list += ", ";
        list += config->getView(display, i);
    }
    return list;
}

}  // namespace

struct OcioView {
    OCIO::ConstCPUProcessorRcPtr cpu;
    std::string view, display, source;
};

extern "C" {

const char *ocio_embedded_config(void)
{
    return kEmbeddedConfig;
}

bool ocio_view_open(const char *view, OcioView **out, Diag *err)
{
    *out = nullptr;
    LoadedConfig lc;
    if (!load_config(lc, err)) return false;
    try {
        const char *display = lc.config->getDefaultDisplay();
        if (!display || !*display) {
            SrcLoc loc = {lc.source.c_str(), 0, 0};
            diag_set(err, WEDGE_EXIT_INPUT, loc, "the OpenColorIO config has no display");
            return false;
        }
        std::string chosen = (view && *view) ? view : lc.config->getDefaultView(display);
        bool known = false;
        for (int i = 0; i < lc.config->getNumViews(display); ++i)
            known |= chosen == lc.config->getView(display, i);
        if (!known) {
            SrcLoc loc = {nullptr, 0, 0};
            diag_set(err, WEDGE_EXIT_USAGE, loc, "unknown view '%s' (display '%s' has views: %s)", chosen.c_str(),
                     display, view_list(lc.config, display).c_str());
            return false;
        }
        if (!lc.config->getColorSpace(OCIO::ROLE_SCENE_LINEAR)) {
            SrcLoc loc = {lc.source.c_str(), 0, 0};
            diag_set(err, WEDGE_EXIT_INPUT, loc, "the OpenColorIO config has no scene_linear role");
            return false;
        }
        OCIO::ConstProcessorRcPtr proc = lc.config->getProcessor(OCIO::ROLE_SCENE_LINEAR, display, chosen.c_str(),
                                                                 OCIO::TRANSFORM_DIR_FORWARD);
        // Full-precision CPU path: the tests compare against exact sRGB values.
        OCIO::ConstCPUProcessorRcPtr cpu = proc->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_LOSSLESS);
        OcioView *v = new OcioView;
        v->cpu = cpu;
        v->view = chosen;
        v->display = display;
        v->source = lc.source;
        *out = v;
        return true;
    } catch (const std::exception &e) {
        SrcLoc loc = {lc.source.c_str(), 0, 0};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "OpenColorIO: %s", e.what());
        return false;
    }
}

void ocio_view_apply(const OcioView *v, float *rgb, size_t pixel_count)
{
    for (size_t i = 0; i < 3 * pixel_count; ++i)
        if (!std::isfinite(rgb[i])) rgb[i] = 0.0f;
    // Rows of at most 2^20 pixels keep the image description's long sizes small.
    const size_t row = size_t(1) << 20;
    for (size_t start = 0; start < pixel_count; start += row) {
        size_t n = pixel_count - start < row ? pixel_count - start : row;
        try {
            OCIO::PackedImageDesc desc(rgb + 3 * start, long(n), 1, 3);
            v->cpu->apply(desc);
        } catch (const std::exception &) {
            // A processor that was built cannot fail on plain float rgb; be safe anyway.
            std::memset(rgb + 3 * start, 0, 3 * n * sizeof(float));
        }
    }
    for (size_t i = 0; i < 3 * pixel_count; ++i)
        if (!std::isfinite(rgb[i])) rgb[i] = 0.0f;
}

const char *ocio_view_name(const OcioView *v)
{
    return v->view.c_str();
}

const char *ocio_view_display(const OcioView *v)
{
    return v->display.c_str();
}

const char *ocio_view_config_source(const OcioView *v)
{
    return v->source.c_str();
}

void ocio_view_close(OcioView *v)
{
    delete v;
}

bool ocio_list_views(char *buf, size_t size, Diag *err)
{
    if (size) buf[0] = '\0';
    LoadedConfig lc;
    if (!load_config(lc, err)) return false;
    try {
        std::string list = view_list(lc.config, lc.config->getDefaultDisplay());
        std::snprintf(buf, size, "%s", list.c_str());
        return true;
    } catch (const std::exception &e) {
        SrcLoc loc = {lc.source.c_str(), 0, 0};
        diag_set(err, WEDGE_EXIT_INPUT, loc, "OpenColorIO: %s", e.what());
        return false;
    }
}

}  // extern "C"
