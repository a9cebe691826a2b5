/* sphere_packet_hits_float (src/render/sphere_packet_float.c) against the double test
 * sphere_packet_hits (which test_sphere_packet ties to tracer_quadric_hit bit for bit), on
 * random packets of 1, 4, 8 and 16 rays: every live lane the float test calls decided must have
 * the double test's hit exactly and its t within the lane's bound t_err; and the combined test
 * (sphere_packet_hits_fast) must give each lane what it gives that lane alone.
 *
 * The rays: from near and far (up to 1000 radii) towards the sphere, tangent ones (line
 * distance r (1 +- 10^-k), k = 1..8), rays leaving the surface outwards from just above it
 * (the offset a shadow or bounce ray gets, docs/design.md 12.2) and inwards from just below,
 * from on the surface give or take 10^-9..10^-5 r in any direction, from inside, and with
 * tnear / tfar near a root (10^-2..10^-7 of it, and 1..10^4 u (|o - c| + r) from it, the
 * other root in or out of range); directions of length 1/2 to 2. Spheres at every scale:
 * geom_from_tracer 2^-30..2^27 (test_robustness's scale sweep, 1e-9..1e8), radii 1e-6..1 of
 * the tracer's unit, centres near the origin and 1000 radii from it.
 *
 * What the bound must decide, so that the test notices a useless one (docs/algorithms.md,
 * "The packet sphere test in float"): every ray leaving the surface outwards at cos >= 1e-3
 * (a sure miss: no ray finds the sphere it leaves), and a ray from 2 to 10 radii whose line
 * passes within r sqrt(1 - 2^-7) of the centre, tnear 0 and tfar infinite. And the tangent
 * threshold caps a decided hit's t error at about 2^9 u (|o - c| + r) / |d| (u = 2^-24);
 * checked at 2^10. */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "core/rng.h"
#include "render/sphere_packet.h"
#include "render/sphere_packet_float.h"

enum { RAYN_ORG_X, RAYN_ORG_Y, RAYN_ORG_Z, RAYN_TNEAR, RAYN_DIR_X, RAYN_DIR_Y, RAYN_DIR_Z, RAYN_TIME, RAYN_TFAR };
enum { LANES = 16, PACKETS = 6000 };
enum { KIND_RANDOM, KIND_TANGENT, KIND_OUT, KIND_IN, KIND_INSIDE, KIND_CUT, KIND_SURFACE, KIND_NEAR_ROOT, KIND_COUNT };

/* A unit vector, uniform on the sphere. */
static void random_dir(Pcg32 *rng, double v[3])
{
    double z = 1.0 - 2.0 * pcg32_float(rng), phi = 2.0 * M_PI * pcg32_float(rng), s = sqrt(fmax(0.0, 1.0 - z * z));
    v[0] = s * cos(phi), v[1] = s * sin(phi), v[2] = z;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* A unit vector perpendicular to unit n. */
static void perpendicular(Pcg32 *rng, const double n[3], double v[3])
{
    double x[3];
    random_dir(rng, x);
    double k = dot3(x, n);
    for (int j = 0; j < 3; ++j) x[j] -= k * n[j];
    double l = sqrt(dot3(x, x));
    for (int j = 0; j < 3; ++j) v[j] = x[j] / l;
}

/* One lane's ray in tracer units, relative to the sphere of centre c and radius r; what the
 * test promises about it in *must_decide (see the header). */
typedef struct {
    int kind;
    bool must_decide, must_miss;
} LaneInfo;

static void make_lane(float *rays, unsigned n, unsigned i, Pcg32 *rng, const double c[3], double r, LaneInfo *info)
{
    int kind = (int)pcg32_below(rng, KIND_COUNT);
    double o[3], d[3], u[3], side[3];
    double tnear = 0.0, tfar = INFINITY;
    random_dir(rng, u);
    info->kind = kind, info->must_decide = false, info->must_miss = false;
    if (kind == KIND_SURFACE) {
        /* on the surface give or take 10^-9..10^-5 r (either side: the origin's c may round
         * either way), in any direction */
        double lift = (pcg32_float(rng) < 0.5 ? -1.0 : 1.0) * r * pow(10.0, -9.0 + 4.0 * pcg32_float(rng));
        for (int j = 0; j < 3; ++j) o[j] = c[j] + (r + lift) * u[j];
        random_dir(rng, d);
    } else if (kind == KIND_OUT || kind == KIND_IN) {
        /* the offset of a ray leaving a hit: 1e-5 of the point's largest coordinate plus r */
        double mag = fmax(fmax(fabs(c[0] + r * u[0]), fabs(c[1] + r * u[1])), fabs(c[2] + r * u[2])) + r;
        double lift = kind == KIND_OUT ? 1e-5 * mag : -1e-5 * mag;
        for (int j = 0; j < 3; ++j) o[j] = c[j] + (r * u[j] + lift * u[j]);
        double cosine = pcg32_float(rng), sine = sqrt(1.0 - cosine * cosine);
        perpendicular(rng, u, side);
        double sign = kind == KIND_OUT ? 1.0 : -1.0;
        for (int j = 0; j < 3; ++j) d[j] = sign * cosine * u[j] + sine * side[j];
        info->must_miss = kind == KIND_OUT;
        info->must_decide = kind == KIND_OUT && cosine >= 1e-3;
    } else {
        double dist = kind == KIND_INSIDE ? 0.9 * r * pcg32_float(rng) : r * (1.0 + pow(10.0, 3.0 * pcg32_float(rng)));
        if (kind == KIND_TANGENT) dist = fmax(dist, 2.0 * r);
        for (int j = 0; j < 3; ++j) o[j] = c[j] + dist * u[j];
        perpendicular(rng, u, side);
        if (kind == KIND_TANGENT) {
            /* a line at distance r (1 +- 10^-k) from the centre, k = 1..8 (dist >= 2 r) */
            double line = r * (1.0 + (pcg32_float(rng) < 0.5 ? -1.0 : 1.0) * pow(10.0, -1.0 - 7.0 * pcg32_float(rng)));
            double sine = line / dist, cosine = sqrt(1.0 - sine * sine);
            for (int j = 0; j < 3; ++j) d[j] = -cosine * u[j] + sine * side[j];
        } else {
            /* at a point within 1.2 r of the centre */
            double aim[3], a_dir[3], lateral = 1.2 * r * pcg32_float(rng);
            for (int j = 0; j < 3; ++j) aim[j] = c[j] + lateral * side[j];
            for (int j = 0; j < 3; ++j) a_dir[j] = aim[j] - o[j];
            double l = sqrt(dot3(a_dir, a_dir));
            for (int j = 0; j < 3; ++j) d[j] = a_dir[j] / l;
        }
        if (kind == KIND_NEAR_ROOT) {
            /* tnear or tfar at 1..10^4 u (|o - c| + r) from a root: where the bounds decide */
            double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
            double b = dot3(d, oc), cc = dot3(oc, oc) - r * r, disc = b * b - cc;
            if (disc > 0.0) {
                double root = -b + (pcg32_float(rng) < 0.5 ? -1.0 : 1.0) * sqrt(disc);
                double gap = 0x1p-24 * (sqrt(dot3(oc, oc)) + r) * pow(10.0, 4.0 * pcg32_float(rng));
                double cut = root + (pcg32_float(rng) < 0.5 ? -gap : gap), other = -b - (root + b);
                if (cut > 0.0) {
                    /* with the other root outside [tnear, tfar] half of the time, so that this
                     * root alone decides the hit */
                    bool alone = pcg32_float(rng) < 0.5;
                    if (pcg32_float(rng) < 0.5) tfar = cut, tnear = alone && other < root ? fmax(0.0, 0.5 * (other + root)) : 0.0;
                    else tnear = cut, tfar = alone && other > root ? 0.5 * (other + root) : INFINITY;
                }
            }
        }
        if (kind == KIND_CUT) {
            /* tnear or tfar within 10^-2..10^-7 of a root (the double test's) */
            double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
            double b = dot3(d, oc), cc = dot3(oc, oc) - r * r, disc = b * b - cc;
            if (disc > 0.0) {
                double root = -b + (pcg32_float(rng) < 0.5 ? -1.0 : 1.0) * sqrt(disc);
                double cut = root * (1.0 + (pcg32_float(rng) < 0.5 ? -1.0 : 1.0) * pow(10.0, -2.0 - 5.0 * pcg32_float(rng)));
                if (cut > 0.0) {
                    if (pcg32_float(rng) < 0.5) tfar = cut;
                    else tnear = cut;
                }
            }
        }
        if (kind == KIND_RANDOM && dist >= 2.0 * r && dist <= 10.0 * r) {
            double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
            double b = dot3(d, oc), line2 = dot3(oc, oc) - b * b;
            info->must_decide = line2 <= r * r * (1.0 - 0x1p-7);
        }
    }
    /* direction lengths 1/2..2 (t scales by the inverse) */
    double len = pow(2.0, 2.0 * pcg32_float(rng) - 1.0);
    for (int j = 0; j < 3; ++j) d[j] *= len;
    tnear /= len, tfar /= len;
    rays[RAYN_ORG_X * n + i] = (float)o[0], rays[RAYN_ORG_Y * n + i] = (float)o[1], rays[RAYN_ORG_Z * n + i] = (float)o[2];
    rays[RAYN_DIR_X * n + i] = (float)d[0], rays[RAYN_DIR_Y * n + i] = (float)d[1], rays[RAYN_DIR_Z * n + i] = (float)d[2];
    rays[RAYN_TNEAR * n + i] = (float)tnear, rays[RAYN_TFAR * n + i] = (float)tfar;
    rays[RAYN_TIME * n + i] = 0.0f;
}

/* One sphere: centre c_tracer and radius r_tracer in tracer units, geometry space = tracer
 * space times w (a power of two). */
static void check_sphere(double w, const double c_tracer[3], double r_tracer, uint64_t seed)
{
    const double translation[3] = {-w * c_tracer[0], -w * c_tracer[1], -w * c_tracer[2]};
    double r = w * r_tracer;
    Pcg32 rng;
    pcg32_seed(&rng, seed, 3);
    static const unsigned sizes[4] = {1, 4, 8, 16};
    long lanes = 0, decided_lanes = 0, hits = 0, wrong_hit = 0, wrong_t = 0, promised = 0, promise_broken = 0;
    long out_lanes = 0, out_hits = 0, fast_differs = 0;
    double worst_rel = 0.0; /* |t_f - t_d| in units of u (|o - c| + r) / |d| */
    float rays[12 * LANES + 8 * LANES], one[12 + 8];
    for (int p = 0; p < PACKETS; ++p) {
        unsigned n = sizes[p % 4];
        int valid[LANES], hit[LANES], hit_d[LANES], hit_fast[LANES], decided[LANES];
        double t[LANES], t_d[LANES], t_fast[LANES];
        float t_err[LANES];
        LaneInfo info[LANES];
        for (unsigned i = 0; i < n; ++i) {
            make_lane(rays, n, i, &rng, c_tracer, r_tracer, &info[i]);
            valid[i] = pcg32_float(&rng) < 0.85f ? -1 : 0;
        }
        sphere_packet_hits_float(rays, valid, n, w, translation, r, hit, t, t_err, decided);
        sphere_packet_hits(rays, valid, n, w, translation, r, hit_d, t_d);
        sphere_packet_hits_fast(rays, valid, n, w, translation, r, hit_fast, t_fast);
        for (unsigned i = 0; i < n; ++i) {
            if (valid[i] != -1) continue;
            ++lanes;
            hits += hit_d[i];
            if (info[i].kind == KIND_OUT) ++out_lanes, out_hits += hit_d[i];
            if (info[i].must_miss && hit_d[i]) ++promise_broken;
            if (info[i].must_decide) ++promised, promise_broken += !decided[i];
            /* sphere_packet_hits_fast: the lane's answer is the one it gets alone, bit for bit
             * (the float test's where decided, the double test's where not) */
            for (int f = 0; f < 9; ++f) one[f] = rays[f * n + i];
            int valid_one = -1, hit_one;
            double t_one;
            sphere_packet_hits_fast(one, &valid_one, 1, w, translation, r, &hit_one, &t_one);
            fast_differs += hit_fast[i] != hit_one || (hit_one && memcmp(&t_fast[i], &t_one, sizeof t_one) != 0) ||
                            hit_fast[i] != (decided[i] ? hit[i] : hit_d[i]) ||
                            (hit_one && memcmp(&t_one, decided[i] ? &t[i] : &t_d[i], sizeof t_one) != 0);
            if (!decided[i]) continue;
            ++decided_lanes;
            if ((hit[i] != 0) != (hit_d[i] != 0)) {
                ++wrong_hit;
                continue;
            }
            if (!hit_d[i]) continue;
            double err = fabs(t[i] - t_d[i]);
            wrong_t += !(err <= (double)t_err[i]);
            double o[3], dd[3];
            for (int j = 0; j < 3; ++j) o[j] = rays[(RAYN_ORG_X + j) * n + i] - c_tracer[j];
            for (int j = 0; j < 3; ++j) dd[j] = rays[(RAYN_DIR_X + j) * n + i];
            double scale = 0x1p-24 * (sqrt(dot3(o, o)) + r_tracer) / sqrt(dot3(dd, dd));
            worst_rel = fmax(worst_rel, err / scale);
        }
    }
    printf("w 2^%d r %g |c| %g: %ld live lanes, %ld hits, %ld decided (%ld wrong hits, %ld t beyond the bound), worst "
           "t error %.3g u (|o - c| + r) / |d|; %ld of %ld promised lanes broken; %ld of %ld outward rays hit; %ld "
           "lanes of the combined test differ from alone\n",
           (int)log2(w), r_tracer, sqrt(dot3(c_tracer, c_tracer)), lanes, hits, decided_lanes, wrong_hit, wrong_t,
           worst_rel, promise_broken, promised, out_hits, out_lanes, fast_differs);
    CHECK(fast_differs == 0);
    CHECK(wrong_hit == 0);
    CHECK(wrong_t == 0);
    CHECK(promise_broken == 0);
    CHECK(promised > 100);
    CHECK(out_hits == 0);
    CHECK(hits > lanes / 10);
    /* the tangent threshold caps the error: within 2^10 u (|o - c| + r) / |d| (see the header) */
    CHECK(worst_rel <= 1024.0);
}

int main(void)
{
    /* dead lanes (NaN: Embree leaves them as they are) decide nothing and do not send a
     * packet to the double test */
    {
        float rays[12 * LANES + 8 * LANES];
        int valid[LANES], hit[LANES];
        double t[LANES];
        float t_err[LANES];
        int decided[LANES];
        const double translation[3] = {0.0, 0.0, 0.0};
        for (size_t i = 0; i < sizeof rays / sizeof rays[0]; ++i) rays[i] = NAN;
        for (int i = 0; i < LANES; ++i) valid[i] = 0;
        CHECK(sphere_packet_hits_float(rays, valid, LANES, 1.0, translation, 1.0, hit, t, t_err, decided) == 1);
        for (int i = 0; i < LANES; ++i) CHECK(hit[i] == 0);
        valid[3] = -1; /* and a live NaN lane is not decided */
        CHECK(sphere_packet_hits_float(rays, valid, LANES, 1.0, translation, 1.0, hit, t, t_err, decided) == 0);
        CHECK(decided[3] == 0 && decided[2] == 1);
    }
    static const double scales[] = {0x1p-30, 0x1p-10, 1.0, 0x1p10, 0x1p27};
    static const double radii[] = {1e-6, 1e-3, 0.3, 1.0};
    uint64_t seed = 1;
    for (size_t s = 0; s < sizeof scales / sizeof scales[0]; ++s)
        for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k) {
            double r = radii[k];
            /* near the origin of tracer space, and 1000 radii from it (a centre that is
             * not a float) */
            const double near[3] = {0.1 * r, -0.2 * r, 0.05 * r}, far[3] = {700.3 * r, -500.7 * r, 300.1 * r};
            check_sphere(scales[s], near, r, seed++);
            check_sphere(scales[s], far, r, seed++);
        }
    CHECK_DONE();
}
