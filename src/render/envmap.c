/* Image-based environment light with importance sampling; see envmap.h. */
#include "render/envmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"
#include "render/warp.h"

/* ---------------------------------------------------------------- parameterisations */

vec3 envmap_equal_area_to_dir(vec2 uv)
{
    /* Clarberg 2008: on the square [-1,1]^2 the diamond |u| + |v| <= 1 maps to the upper
     * hemisphere and the four corner triangles fold onto the lower one. r is the
     * "radius" (distance from the +z or -z pole in the diamond's L1 metric), z = +-(1 - r^2)
     * makes equal areas of the square cover equal solid angles (the area of a spherical
     * cap of height 1 - z is 2 pi (1 - z) = 2 pi r^2), and the azimuth is linear in the
     * position along the diamond's edge within the quadrant. */
    float u = 2.0f * uv.x - 1.0f, v = 2.0f * uv.y - 1.0f;
    float au = fabsf(u), av = fabsf(v);
    float signed_dist = 1.0f - (au + av); /* > 0 inside the diamond (upper hemisphere) */
    float r = 1.0f - fabsf(signed_dist);
    float phi = (r == 0.0f ? 1.0f : (av - au) / r + 1.0f) * (WEDGE_PI / 4.0f);
    float z = copysignf(1.0f - r * r, signed_dist);
    float ring = r * sqrtf(fmaxf(0.0f, 2.0f - r * r)); /* sqrt(1 - z^2) */
    return v3(copysignf(cosf(phi), u) * ring, copysignf(sinf(phi), v) * ring, z);
}

vec2 envmap_dir_to_equal_area(vec3 w)
{
    float ax = fabsf(w.x), ay = fabsf(w.y), az = fminf(fabsf(w.z), 1.0f);
    float r = sqrtf(1.0f - az);
    float t = (ax == 0.0f && ay == 0.0f) ? 0.0f : atan2f(ay, ax) * (2.0f / WEDGE_PI); /* azimuth in [0,1] */
    /* upper hemisphere: |u| + |v| = r split by the azimuth */
    float au = r * (1.0f - t), av = r * t;
    if (w.z < 0.0f) { /* fold into the corner triangle: reflect across the diamond's edge */
        float fu = 1.0f - av, fv = 1.0f - au;
        au = fu, av = fv;
    }
    float u = copysignf(au, w.x), v = copysignf(av, w.y);
    return v2(0.5f * (u + 1.0f), 0.5f * (v + 1.0f));
}

vec3 envmap_latlong_to_dir(vec2 uv)
{
    float theta = uv.y * WEDGE_PI, phi = uv.x * 2.0f * WEDGE_PI;
    float s = sinf(theta);
    return v3(s * cosf(phi), s * sinf(phi), cosf(theta));
}

vec2 envmap_dir_to_latlong(vec3 w)
{
    float theta = acosf(fminf(fmaxf(w.z, -1.0f), 1.0f));
    float phi = atan2f(w.y, w.x);
    if (phi < 0.0f) phi += 2.0f * WEDGE_PI;
    return v2(phi / (2.0f * WEDGE_PI), theta / WEDGE_PI);
}

/* ---------------------------------------------------------------- construction */

static float clean(float v) { return isfinite(v) && v > 0.0f ? v : 0.0f; }

/* sin(theta) at the centre of lat-long row y: the relative solid angle of its pixels. */
static float row_sin(const Envmap *e, int y) { return sinf(((float)y + 0.5f) / (float)e->height * WEDGE_PI); }

static bool build_distribution(Envmap *e)
{
    int w = e->width, h = e->height;
    e->pixel_weight = malloc((size_t)w * (size_t)h * sizeof(float));
    e->row_cdf = malloc((size_t)(h + 1) * sizeof(float));
    e->col_cdf = malloc((size_t)h * (size_t)(w + 1) * sizeof(float));
    if (!e->pixel_weight || !e->row_cdf || !e->col_cdf) return false;
    double total = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
        /* pass 0: weights proportional to the pixel's mean rgb (times its solid angle);
         * pass 1, only for an all-black map: proportional to solid angle (uniform). */
        total = 0.0;
        for (int y = 0; y < h; ++y) {
            float sa = e->layout == ENVMAP_LATLONG ? row_sin(e, y) : 1.0f;
            for (int x = 0; x < w; ++x) {
                const float *p = e->rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
                float lum = pass == 0 ? (p[0] + p[1] + p[2]) / 3.0f : 1.0f;
                float wt = lum * sa;
                e->pixel_weight[(size_t)y * (size_t)w + (size_t)x] = wt;
                total += wt;
            }
        }
        if (total > 0.0 && isfinite(total)) break;
    }
    e->weight_total = total;
    double acc_rows = 0.0;
    e->row_cdf[0] = 0.0f;
    for (int y = 0; y < h; ++y) {
        const float *pw = e->pixel_weight + (size_t)y * (size_t)w;
        float *cdf = e->col_cdf + (size_t)y * (size_t)(w + 1);
        double row = 0.0;
        for (int x = 0; x < w; ++x) row += pw[x];
        double acc = 0.0;
        cdf[0] = 0.0f;
        for (int x = 0; x < w; ++x) {
            acc += pw[x];
            cdf[x + 1] = row > 0.0 ? (float)(acc / row) : (float)(x + 1) / (float)w;
        }
        cdf[w] = 1.0f;
        acc_rows += row;
        e->row_cdf[y + 1] = (float)(acc_rows / total);
    }
    e->row_cdf[h] = 1.0f;
    return true;
}

bool envmap_init(Envmap *e, int width, int height, const float *rgb, float scale, Diag *err)
{
    *e = (Envmap){0};
    e->world_from_light = e->light_from_world = mat4_identity();
    if (width <= 0 || height <= 0 || (size_t)width * (size_t)height > ((size_t)1 << 28)) {
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0}, "environment map: bad size %dx%d", width, height);
        return false;
    }
    if (width == height) {
        e->layout = ENVMAP_EQUAL_AREA;
    } else if (width == 2 * height) {
        e->layout = ENVMAP_LATLONG;
    } else {
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){0},
                 "environment map is %dx%d: expected a square image (pbrt-v4's equal-area octahedral map) or a 2:1 "
                 "latitude-longitude image",
                 width, height);
        return false;
    }
    e->width = width, e->height = height;
    size_t n = (size_t)width * (size_t)height * 3;
    e->rgb = malloc(n * sizeof(float));
    if (!e->rgb) goto oom;
    float s = clean(scale);
    for (size_t i = 0; i < n; ++i) e->rgb[i] = clean(clean(rgb[i]) * s);
    if (!build_distribution(e)) goto oom;
    return true;
oom:
    envmap_free(e);
    diag_set(err, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for a %dx%d environment map", width, height);
    return false;
}

bool envmap_load(Envmap *e, const char *path, float scale, Diag *err)
{
    *e = (Envmap){0};
    int w = 0, h = 0;
    float *rgb = NULL;
    if (!image_read_linear_rgb(path, &w, &h, &rgb, err)) return false;
    bool ok = envmap_init(e, w, h, rgb, scale, err);
    if (!ok && err->exit_code == WEDGE_EXIT_INPUT) {
        /* name the file in the message */
        Diag inner = *err;
        diag_set(err, WEDGE_EXIT_INPUT, (SrcLoc){path, 0, 0}, "%s",
                 strstr(inner.message, "environment map") ? strstr(inner.message, "environment map") : inner.message);
        size_t len = strlen(err->message);
        if (len && err->message[len - 1] == '\n') err->message[len - 1] = '\0';
    }
    free(rgb);
    return ok;
}

void envmap_free(Envmap *e)
{
    free(e->rgb);
    free(e->row_cdf);
    free(e->col_cdf);
    free(e->pixel_weight);
    *e = (Envmap){0};
}

void envmap_set_transform(Envmap *e, const Mat4 *world_from_light)
{
    e->world_from_light = *world_from_light;
    if (!mat4_inverse(world_from_light, &e->light_from_world)) {
        e->world_from_light = e->light_from_world = mat4_identity();
    }
}

/* ---------------------------------------------------------------- lookups */

static vec3 to_light(const Envmap *e, vec3 w) { return v3_normalize(mat4_apply_vector(&e->light_from_world, w)); }
static vec3 to_world(const Envmap *e, vec3 w) { return v3_normalize(mat4_apply_vector(&e->world_from_light, w)); }

static vec2 dir_to_uv(const Envmap *e, vec3 w_light)
{
    return e->layout == ENVMAP_EQUAL_AREA ? envmap_dir_to_equal_area(w_light) : envmap_dir_to_latlong(w_light);
}

static int clampi(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }

static void uv_to_pixel(const Envmap *e, vec2 uv, int *x, int *y)
{
    float fx = uv.x * (float)e->width, fy = uv.y * (float)e->height;
    *x = clampi(isfinite(fx) ? (int)floorf(fx) : 0, 0, e->width - 1);
    *y = clampi(isfinite(fy) ? (int)floorf(fy) : 0, 0, e->height - 1);
}

static vec3 pixel_rgb(const Envmap *e, int x, int y)
{
    const float *p = e->rgb + 3 * ((size_t)y * (size_t)e->width + (size_t)x);
    return v3(p[0], p[1], p[2]);
}

/* Image-space density (over [0,1]^2) of pixel (x, y). */
static float pixel_pdf_uv(const Envmap *e, int x, int y)
{
    double wt = e->pixel_weight[(size_t)y * (size_t)e->width + (size_t)x];
    return (float)(wt * (double)e->width * (double)e->height / e->weight_total);
}

/* Solid angle per unit image area at a light-space direction. */
static float uv_to_solid_angle_jacobian(const Envmap *e, vec3 w_light)
{
    if (e->layout == ENVMAP_EQUAL_AREA) return 4.0f * WEDGE_PI;
    float sin_theta = sqrtf(fmaxf(0.0f, 1.0f - w_light.z * w_light.z));
    return 2.0f * WEDGE_PI * WEDGE_PI * sin_theta; /* dw = sin(theta) (pi dv) (2 pi du) */
}

vec3 envmap_Le(const Envmap *e, vec3 w_world)
{
    if (!e->rgb) return v3s(0.0f);
    int x, y;
    uv_to_pixel(e, dir_to_uv(e, to_light(e, w_world)), &x, &y);
    return pixel_rgb(e, x, y);
}

float envmap_pdf(const Envmap *e, vec3 w_world)
{
    if (!e->rgb) return 0.0f;
    vec3 wl = to_light(e, w_world);
    int x, y;
    uv_to_pixel(e, dir_to_uv(e, wl), &x, &y);
    float jac = uv_to_solid_angle_jacobian(e, wl);
    if (!(jac > 0.0f)) return 0.0f;
    float pdf = pixel_pdf_uv(e, x, y) / jac;
    return isfinite(pdf) ? pdf : 0.0f;
}

/* Index i with cdf[i] <= u < cdf[i+1] (cdf has n + 1 entries, cdf[n] = 1, u < 1); entries
 * with zero mass are never returned. */
static int cdf_find(const float *cdf, int n, float u)
{
    int lo = 1, hi = n; /* first index in [1, n] with cdf[idx] > u */
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (cdf[mid] > u) hi = mid;
        else lo = mid + 1;
    }
    return lo - 1;
}

bool envmap_sample(const Envmap *e, vec2 u, vec3 *w_world, vec3 *Le, float *pdf)
{
    if (!e->rgb) return false;
    float uy = fminf(fmaxf(u.y, 0.0f), 0x1.fffffep-1f), ux = fminf(fmaxf(u.x, 0.0f), 0x1.fffffep-1f);
    int y = cdf_find(e->row_cdf, e->height, uy);
    const float *cc = e->col_cdf + (size_t)y * (size_t)(e->width + 1);
    int x = cdf_find(cc, e->width, ux);
    /* continuous offsets inside the pixel, reusing what is left of u */
    float dy = e->row_cdf[y + 1] > e->row_cdf[y] ? (uy - e->row_cdf[y]) / (e->row_cdf[y + 1] - e->row_cdf[y]) : 0.5f;
    float dx = cc[x + 1] > cc[x] ? (ux - cc[x]) / (cc[x + 1] - cc[x]) : 0.5f;
    dx = fminf(fmaxf(dx, 0.0f), 0x1.fffffep-1f), dy = fminf(fmaxf(dy, 0.0f), 0x1.fffffep-1f);
    vec2 uv = v2(((float)x + dx) / (float)e->width, ((float)y + dy) / (float)e->height);
    vec3 wl = e->layout == ENVMAP_EQUAL_AREA ? envmap_equal_area_to_dir(uv) : envmap_latlong_to_dir(uv);
    float jac = uv_to_solid_angle_jacobian(e, wl);
    if (!(jac > 0.0f)) return false;
    /* pdf and radiance of the pixel the direction maps back to (rounding at pixel edges
     * can move it to a neighbour; evaluating there keeps sample and pdf consistent) */
    int px, py;
    uv_to_pixel(e, dir_to_uv(e, wl), &px, &py);
    float p = pixel_pdf_uv(e, px, py) / jac;
    if (!(p > 0.0f) || !isfinite(p)) return false;
    *w_world = to_world(e, wl);
    *Le = pixel_rgb(e, px, py);
    *pdf = p;
    return true;
}

vec3 envmap_mean_radiance(const Envmap *e)
{
    if (!e->rgb) return v3s(0.0f);
    double s[3] = {0, 0, 0}, wsum = 0.0;
    for (int y = 0; y < e->height; ++y) {
        double sa = e->layout == ENVMAP_LATLONG ? row_sin(e, y) : 1.0;
        for (int x = 0; x < e->width; ++x) {
            vec3 c = pixel_rgb(e, x, y);
            s[0] += c.x * sa, s[1] += c.y * sa, s[2] += c.z * sa;
            wsum += sa;
        }
    }
    return wsum > 0 ? v3((float)(s[0] / wsum), (float)(s[1] / wsum), (float)(s[2] / wsum)) : v3s(0.0f);
}
