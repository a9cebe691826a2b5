// The only C++ in src/geometry: a thin extern "C" bridge to OpenSubdiv 3.5 Far
// (uniform refinement, then limit positions and tangents). See subdiv.h.
#include "geometry/subdiv.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

using namespace OpenSubdiv;

namespace {

// A primvar in double precision: OpenSubdiv only needs Clear and AddWithWeight.
struct Point {
    double x, y, z;
    void Clear(void * = nullptr) { x = y = z = 0.0; }
    void AddWithWeight(Point const &s, double w)
    {
        x += w * s.x;
        y += w * s.y;
        z += w * s.z;
    }
};

Point sub(Point a, Point b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Point add(Point a, Point b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Point cross(Point a, Point b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Point a, Point b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Far reports topology errors through a process-wide callback; keep the first message
// of the current call (per thread).
thread_local std::string far_error;
void on_far_error(Far::ErrorType, const char *message)
{
    if (far_error.empty()) far_error = message ? message : "unknown OpenSubdiv error";
}
void on_far_warning(const char *) {}

bool refine(const SubdivInput *in, SubdivOutput *out, std::string &msg)
{
    std::vector<int> sizes;
    if (!in->face_size) sizes.assign((size_t)in->face_count, 3);
    const int *face_size = in->face_size ? in->face_size : sizes.data();

    Sdc::Options options;
    // Boundary edges are infinitely sharp creases (cubic B-spline boundary curves) and
    // corner vertices follow the crease rule too: pbrt-v4's boundary rule.
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    Sdc::SchemeType type = in->scheme == SUBDIV_LOOP ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;

    Far::TopologyDescriptor desc;
    desc.numVertices = in->vertex_count;
    desc.numFaces = in->face_count;
    desc.numVertsPerFace = face_size;
    desc.vertIndicesPerFace = in->index;

    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(type, options));
    if (!refiner) {
        msg = far_error.empty() ? "OpenSubdiv rejected the topology" : far_error;
        return false;
    }
    struct Owner {
        Far::TopologyRefiner *r;
        ~Owner() { delete r; }
    } owner{refiner};

    if (in->levels > 0) {
        Far::TopologyRefiner::UniformOptions uniform(in->levels);
        uniform.fullTopologyInLastLevel = true; // Limit() needs the last level's edges
        refiner->RefineUniform(uniform);
    }
    if (!far_error.empty()) {
        msg = far_error;
        return false;
    }

    // Interpolate level by level into one buffer (the usual Far pattern).
    std::vector<Point> verts((size_t)refiner->GetNumVerticesTotal());
    for (int i = 0; i < in->vertex_count; i++)
        verts[(size_t)i] = {in->p[3 * i], in->p[3 * i + 1], in->p[3 * i + 2]};
    Far::PrimvarRefiner primvar(*refiner);
    Point *src = verts.data();
    for (int level = 1; level <= in->levels; level++) {
        Point *dst = src + refiner->GetLevel(level - 1).GetNumVertices();
        primvar.Interpolate(level, src, dst);
        src = dst;
    }

    Far::TopologyLevel const &last = refiner->GetLevel(in->levels);
    const int nv = last.GetNumVertices();
    std::vector<Point> pos((size_t)nv), du((size_t)nv), dv((size_t)nv);
    Point *pos_p = pos.data(), *du_p = du.data(), *dv_p = dv.data();
    primvar.Limit(src, pos_p, du_p, dv_p);
    if (!far_error.empty()) {
        msg = far_error;
        return false;
    }

    // Fan-triangulate the last level's faces (triangles for Loop, quads for Catmull-Clark
    // after one level) and accumulate their counter-clockwise area normals per vertex.
    long tri_count = 0;
    for (int f = 0; f < last.GetNumFaces(); f++) tri_count += last.GetFaceVertices(f).size() - 2;
    std::vector<Point> face_normal((size_t)nv, Point{0, 0, 0});
    out->vertex_count = nv;
    out->triangle_count = (int)tri_count;
    out->p = (float *)malloc(3 * (size_t)nv * sizeof(float));
    out->n = (float *)malloc(3 * (size_t)nv * sizeof(float));
    out->index = (uint32_t *)malloc(3 * (size_t)tri_count * sizeof(uint32_t));
    if (!out->p || !out->n || (tri_count && !out->index)) throw std::bad_alloc();
    uint32_t *t = out->index;
    for (int f = 0; f < last.GetNumFaces(); f++) {
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int k = 1; k + 1 < fv.size(); k++) {
            int a = fv[0], b = fv[k], c = fv[k + 1];
            Point n = cross(sub(pos[(size_t)b], pos[(size_t)a]), sub(pos[(size_t)c], pos[(size_t)a]));
            face_normal[(size_t)a] = add(face_normal[(size_t)a], n);
            face_normal[(size_t)b] = add(face_normal[(size_t)b], n);
            face_normal[(size_t)c] = add(face_normal[(size_t)c], n);
            // reversed winding: see the orientation note in subdiv.h
            *t++ = (uint32_t)a;
            *t++ = (uint32_t)c;
            *t++ = (uint32_t)b;
        }
    }

    for (int i = 0; i < nv; i++) {
        Point p = pos[(size_t)i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
            std::fabs(p.x) > 3.0e38 || std::fabs(p.y) > 3.0e38 || std::fabs(p.z) > 3.0e38) {
            msg = "a limit position is not finite";
            return false;
        }
        out->p[3 * i] = (float)p.x;
        out->p[3 * i + 1] = (float)p.y;
        out->p[3 * i + 2] = (float)p.z;

        // Limit normal = du x dv; tangents can be parallel at degenerate configurations,
        // then the averaged face normal stands in. Orient it with the counter-clockwise
        // face normals, then flip both (pbrt-v4's convention, subdiv.h).
        Point n = cross(du[(size_t)i], dv[(size_t)i]);
        Point fn = face_normal[(size_t)i];
        double n2 = dot(n, n), t2 = dot(du[(size_t)i], du[(size_t)i]) * dot(dv[(size_t)i], dv[(size_t)i]);
        if (!(n2 > 1e-12 * t2) || !std::isfinite(n2)) n = fn;
        else if (dot(n, fn) < 0) n = {-n.x, -n.y, -n.z};
        double len = std::sqrt(dot(n, n));
        if (!(len > 0) || !std::isfinite(len)) n = {0, 0, -1}, len = 1; // vertex in no face
        out->n[3 * i] = (float)(-n.x / len);
        out->n[3 * i + 1] = (float)(-n.y / len);
        out->n[3 * i + 2] = (float)(-n.z / len);
    }
    return true;
}

} // namespace

extern "C" long subdiv_triangle_count(SubdivScheme scheme, int levels, int face_count, const int *face_size)
{
    if (levels < 0 || face_count < 0) return -1;
    // Loop: every triangle splits into 4. Catmull-Clark: an n-gon becomes n quads at the
    // first level, every quad 4 quads after that; each quad is 2 triangles.
    long base = 0;
    if (scheme == SUBDIV_LOOP || levels == 0) {
        for (int f = 0; f < face_count; f++) base += (face_size ? face_size[f] : 3) - 2;
    } else {
        for (int f = 0; f < face_count; f++) base += 2L * (face_size ? face_size[f] : 3);
        levels -= 1;
    }
    for (int l = 0; l < levels; l++) {
        if (base > (1L << 40)) return -1;
        base *= 4;
    }
    return base;
}

extern "C" bool subdiv_refine(const SubdivInput *in, SubdivOutput *out, char *msg, size_t msg_size)
{
    memset(out, 0, sizeof *out);
    std::string error;
    far_error.clear();
    // The callbacks are process-wide: install them once, so that concurrent calls from
    // several threads do not race on them (messages go to a per-thread string).
    static std::once_flag callbacks_installed;
    std::call_once(callbacks_installed, [] {
        Far::SetErrorCallback(on_far_error);
        Far::SetWarningCallback(on_far_warning);
    });
    bool ok = false;
    try {
        ok = refine(in, out, error);
    } catch (const std::bad_alloc &) {
        error = "out of memory";
    } catch (...) {
        error = "OpenSubdiv failed";
    }
    if (!ok) {
        subdiv_output_free(out);
        if (msg && msg_size) snprintf(msg, msg_size, "%s", error.c_str());
    }
    return ok;
}

extern "C" void subdiv_output_free(SubdivOutput *out)
{
    free(out->p);
    free(out->n);
    free(out->index);
    memset(out, 0, sizeof *out);
}
