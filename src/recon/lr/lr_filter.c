/* LR eqs. 8-14 and Appendices B, C; derivation in docs/algorithms.md ("Layered
 * reconstruction", 8.2-8.4). All frequencies are angular (band limit 1/sigma, not the
 * paper's 1/(2 pi sigma); the paper's 2 pi factors cancel against that). */
#include "recon/lr/lr_filter.h"

#include <math.h>

LrFilterConfig lr_filter_config_default(void)
{
    LrFilterConfig c;
    c.sigma_pixel_px = 1.0f / 3.0f;
    /* LR uses 1/3 against a Gaussian-aperture reference; the renderer's lens is the uniform
     * unit disk, whose per-axis std is 1/2: matching it cut the error on a defocused scene
     * 4.4x (docs/algorithms.md 8.1) */
    c.sigma_pixel_still_px = c.sigma_pixel_px; /* the frame's count sets it (lr_still_sigma_pixel_px) */
    c.sigma_lens = 0.5f;
    c.sigma_shutter = 1.0f / 3.0f; /* LR's 2/3 on a shutter of length 2 */
    c.sigma_clamp_px = (32.0f - 16.0f) / 4.0f;
    /* The target is the pixel integrated over the renderer's lens disk and shutter box, which
     * its samples already cover uniformly; a Gaussian weight on a sample's own u, v, t turns
     * that into a Gaussian-tapered disk and shutter, a bias no sample count removes (the
     * screen filter keeps the Gaussians' blur: complete_bands). Flat weights: 17-25% lower
     * relMSE on the hard motion+defocus bench, 4-23% on the others (docs/algorithms.md 8.15). */
    c.flat_lens_time = true;
    /* The Gaussian's tails spread each layer where the disk and the box do not reach: 1.45x
     * (8 spp) to 1.9x (64 spp) lower relMSE on the hard motion+defocus bench (docs/algorithms.md
     * 8.18). */
    c.shaped_screen = true;
    c.round_screen = true;
    return c;
}

float lr_still_sigma_pixel_px(int spp)
{
    const float paper = 1.0f / 3.0f;
    if (!(spp > 0) || spp >= LR_PIXEL_BAND_SPP) return paper;
    /* between the smooth-light optimum's n^(-1/6) and the step edge's n^(-1/3) */
    return paper * powf((float)LR_PIXEL_BAND_SPP / (float)spp, 0.25f);
}

/* Smallest |slope| of a range; 0 when the range touches or straddles 0 (the spectrum then
 * reaches every Omega_x up to the other band limits). */
static double min_abs(double lo, double hi)
{
    if (lo <= 0.0 && hi >= 0.0) return 0.0;
    return fmin(fabs(lo), fabs(hi));
}

/* The Fourier warp in "roles": x, the clipping dimension a and the other extra dimension b.
 * Clip against a (LR Appendix B, case Omega_u): scale (s_x, s_a, s_b), then shear Omega_x by
 * alpha Omega_a, then Omega_b by beta Omega_x (eq. 8). Clip against x: scale then shear
 * Omega_a by beta_a Omega_x and Omega_b by beta_b Omega_x (already x-only). */
typedef struct {
    bool clip_x;
    double s_x, s_a, s_b;
    double alpha;          /* clip a: Omega_x shear by Omega_a */
    double beta_a, beta_b; /* clip a: beta_b only; clip x: both */
} RoleWarp;

/* The clipped double wedge of slopes (a in [a_lo, a_hi] clipped at |Omega_a| <= band_a,
 * b in [b_lo, b_hi]) as one scaled and sheared Gaussian. Spectral lines are
 * Omega_a = -a Omega_x, Omega_b = -b Omega_x (our signs, docs 8.2). */
static RoleWarp warp_clip_a(double a_lo, double a_hi, double band_a, double b_lo, double b_hi)
{
    RoleWarp w = {0};
    /* At Omega_a = band_a the lines sit at Omega_x = -band_a / a for a in [a_lo, a_hi]. */
    double inv_lo = 1.0 / a_lo, inv_hi = 1.0 / a_hi;
    w.s_a = band_a;
    w.s_x = band_a * fabs(inv_lo - inv_hi) * 0.5;
    w.alpha = -0.5 * (inv_lo + inv_hi);
    /* Omega_x reaches band_a / |a|min; there the b lines spread by |b_hi - b_lo| Omega_x. */
    double x_extent = band_a / min_abs(a_lo, a_hi);
    w.beta_b = -0.5 * (b_lo + b_hi);
    w.s_b = 0.5 * fabs(b_hi - b_lo) * x_extent;
    return w;
}

static RoleWarp warp_clip_x(double band_x, double a_lo, double a_hi, double b_lo, double b_hi)
{
    RoleWarp w = {0};
    w.clip_x = true;
    w.s_x = band_x;
    w.beta_a = -0.5 * (a_lo + a_hi);
    w.s_a = 0.5 * fabs(a_hi - a_lo) * band_x;
    w.beta_b = -0.5 * (b_lo + b_hi);
    w.s_b = 0.5 * fabs(b_hi - b_lo) * band_x;
    return w;
}

/* Appendix C: widen the Fourier filter until the primal sigma_x is at most sigma_clamp. In
 * the clip-a case that means a larger s_x (gamma = 1/sigma_clamp); the spread s_b grows with
 * the Omega_x extent the filter now reaches. The shear alpha stays, so a layer's central
 * slope keeps exactly its blur (docs 8.4); only fewer samples are shared. */
static bool clamp_warp(RoleWarp *w, double sigma_clamp)
{
    double gamma2 = w->s_x * w->s_x + (w->clip_x ? 0.0 : w->alpha * w->alpha * w->s_a * w->s_a);
    double gamma_min = 1.0 / sigma_clamp;
    if (gamma2 >= gamma_min * gamma_min) return false;
    double gamma = sqrt(gamma2);
    double grow = gamma > 0.0 ? gamma_min / gamma : 1.0;
    if (w->clip_x) {
        w->s_x = gamma_min;
        w->s_a *= grow;
    } else {
        w->s_x = sqrt(gamma_min * gamma_min - w->alpha * w->alpha * w->s_a * w->s_a);
    }
    w->s_b *= grow;
    return true;
}

/* Eqs. 10-11: the same Gaussian with both shears functions of Omega_x only, then eq. 13's
 * primal scales. Outputs in roles: 1/sigma_x, shear of x by a and by b, 1/sigma_a, 1/sigma_b. */
static void x_only(const RoleWarp *w, double *inv_sx, double *eta_a, double *xi_b, double *inv_sa, double *inv_sb)
{
    if (w->clip_x) {
        *inv_sx = w->s_x;
        *eta_a = w->beta_a;
        *xi_b = w->beta_b;
        *inv_sa = w->s_a;
        *inv_sb = w->s_b;
        return;
    }
    double gamma = sqrt(w->s_x * w->s_x + w->alpha * w->alpha * w->s_a * w->s_a);
    *inv_sx = gamma;
    *eta_a = gamma > 0.0 ? w->alpha * w->s_a * w->s_a / (gamma * gamma) : 0.0;
    *inv_sa = gamma > 0.0 ? w->s_x * w->s_a / gamma : 0.0;
    *xi_b = w->beta_b;
    *inv_sb = w->s_b;
}

/* The xut subspace: which band clips first along the corner ray (smallest |c| and |d|). */
static RoleWarp warp_xut(const LrSlopes *s, const LrFilterConfig *cfg, LrClip *clip)
{
    double band_x = 1.0 / cfg->sigma_pixel_px, band_u = 1.0 / cfg->sigma_lens, band_t = 1.0 / cfg->sigma_shutter;
    double cmin = min_abs(s->c_min_px, s->c_max_px), dmin = min_abs(s->d_min_px, s->d_max_px);
    double ext_u = cmin > 0.0 ? band_u / cmin : INFINITY;
    double ext_t = dmin > 0.0 ? band_t / dmin : INFINITY;
    if (band_x <= ext_u && band_x <= ext_t) {
        *clip = LR_CLIP_X;
        return warp_clip_x(band_x, s->c_min_px, s->c_max_px, s->d_min_px, s->d_max_px);
    }
    if (ext_u <= ext_t) {
        *clip = LR_CLIP_U;
        return warp_clip_a(s->c_min_px, s->c_max_px, band_u, s->d_min_px, s->d_max_px);
    }
    *clip = LR_CLIP_T;
    return warp_clip_a(s->d_min_px, s->d_max_px, band_t, s->c_min_px, s->c_max_px);
}

/* The filter of a case contains the band limit it was clipped by (case U: s_u = 1/sigma_a, the
 * aperture; case T: the shutter) but not the other one: at the layer's central slopes its
 * output has the aperture's blur and none of the shutter's (case U), or the converse (docs
 * 8.3). We convolve the primal filter with the Gaussian of the missing aperture or shutter,
 * var_add, in the dimension with shear `shear` and weight variance *var (INFINITY: flat):
 * the covariance gains var_add in that dimension, which in x-only form is
 *     var' = var + var_add,  shear' = shear var / var',  sigma_x'^2 = sigma_x^2 + shear^2 var - shear'^2 var'
 * (flat: shear unchanged, sigma_x^2 += shear^2 var_add). The reductions are untouched: the
 * added dimension has shear 0 there. */
static void add_band(double *var_x, double *shear, double *var, double var_add)
{
    if (!(var_add > 0.0) || *shear == 0.0) {
        if (isfinite(*var)) *var += var_add;
        return;
    }
    if (!isfinite(*var)) {
        *var_x += *shear * *shear * var_add;
        return;
    }
    double v1 = *var + var_add, sh1 = *shear * *var / v1;
    *var_x += *shear * *shear * *var - sh1 * sh1 * v1;
    *shear = sh1;
    *var = v1;
}

/* A filter wider than sigma_clamp after add_band: the excess blur E comes from reprojecting
 * along the added dimension and blurring back; reproject less instead, by the shear that
 * keeps the central slope's blur ((slope + shear')^2 var = E), with sigma_x at the clamp. */
static void clamp_added(double *var_x, double *shear, double var, double sigma_clamp)
{
    double e = *var_x - sigma_clamp * sigma_clamp;
    if (!(e > 0.0) || !isfinite(var) || !(var > 0.0) || *shear == 0.0) return;
    double back = sqrt(e / var); /* how far the samples stay from the centre, per unit */
    double mag = fabs(*shear);
    if (back >= mag) { /* no reprojection at all along it, sigma_x covers what is left */
        *var_x -= mag * mag * var;
        *shear = 0.0;
        return;
    }
    *shear = copysign(mag - back, *shear);
    *var_x = sigma_clamp * sigma_clamp;
}

static double var_of(float inv_sigma) { return inv_sigma > 0.0f ? 1.0 / ((double)inv_sigma * inv_sigma) : INFINITY; }
static float inv_of(double var) { return isfinite(var) && var > 0.0 ? (float)(1.0 / sqrt(var)) : 0.0f; }

static void complete_bands(LrFilter *f, const LrFilterConfig *cfg)
{
    double sa2 = (double)cfg->sigma_lens * cfg->sigma_lens, st2 = (double)cfg->sigma_shutter * cfg->sigma_shutter;
    double vx = 1.0 / ((double)f->inv_sigma_x_px * f->inv_sigma_x_px), vu = var_of(f->inv_sigma_u), vt = var_of(f->inv_sigma_t);
    double eta = f->eta_px, xi = f->xi_px;
    if (f->clip_x != LR_CLIP_U) add_band(&vx, &eta, &vu, sa2);
    if (f->clip_x != LR_CLIP_T) add_band(&vx, &xi, &vt, st2);
    /* the larger of the two added reprojections gives back first */
    if (f->clip_x != LR_CLIP_T) clamp_added(&vx, &xi, vt, cfg->sigma_clamp_px);
    if (f->clip_x != LR_CLIP_U) clamp_added(&vx, &eta, vu, cfg->sigma_clamp_px);
    f->inv_sigma_x_px = (float)(1.0 / sqrt(vx));
    f->eta_px = (float)eta, f->xi_px = (float)xi;
    f->inv_sigma_u = inv_of(vu), f->inv_sigma_t = inv_of(vt);
    if (f->clip_y != LR_CLIP_U) {
        double vy = 1.0 / ((double)f->inv_sigma_y_px * f->inv_sigma_y_px), vv = var_of(f->inv_sigma_v), rho = f->rho_px;
        add_band(&vy, &rho, &vv, sa2);
        clamp_added(&vy, &rho, vv, cfg->sigma_clamp_px);
        f->inv_sigma_y_px = (float)(1.0 / sqrt(vy));
        f->rho_px = (float)rho;
        f->inv_sigma_v = inv_of(vv);
    }
}

LrFilter lr_filter_make_paper(const LrSlopes *s, const LrFilterConfig *cfg)
{
    LrFilter f = {0};
    double sx, sh_a, sh_b, sa, sb;
    RoleWarp w = warp_xut(s, cfg, &f.clip_x);
    f.clamped = clamp_warp(&w, cfg->sigma_clamp_px);
    x_only(&w, &sx, &sh_a, &sh_b, &sa, &sb);
    f.inv_sigma_x_px = (float)sx;
    if (f.clip_x == LR_CLIP_T) { /* roles: a = t, b = u */
        f.xi_px = (float)sh_a;
        f.inv_sigma_t = (float)sa;
        f.eta_px = (float)sh_b;
        f.inv_sigma_u = (float)sb;
    } else {
        f.eta_px = (float)sh_a;
        f.inv_sigma_u = (float)sa;
        f.xi_px = (float)sh_b;
        f.inv_sigma_t = (float)sb;
    }
    /* The yv subspace is the same design without time (VMCS13's sheared defocus filter). */
    LrSlopes yv = *s;
    yv.d_min_px = yv.d_max_px = 0.0f;
    LrClip clip_y;
    RoleWarp wy = warp_xut(&yv, cfg, &clip_y);
    f.clip_y = clip_y;
    f.clamped = clamp_warp(&wy, cfg->sigma_clamp_px) || f.clamped;
    double dummy_b;
    x_only(&wy, &sx, &sh_a, &sh_b, &sa, &dummy_b);
    f.inv_sigma_y_px = (float)sx;
    f.rho_px = (float)sh_a;
    f.inv_sigma_v = (float)sa;
    return f;
}

/* The renderer's lens is the uniform unit disk and its shutter a box over [0, 1]: the
 * variance of a sample's u (or v) and t. */
#define LR_DISK_VAR (1.0 / 4.0)
#define LR_BOX_VAR (1.0 / 12.0)

/* With flat sample weights a layer at slopes (c, d) is seen through
 *     Gauss(sigma) (x) disk projected on the axis, radius |c + shear_u| (x) box of length |d + shear_t|
 * (every sample lands at its own lens position's and time's residual offset, then the screen
 * Gaussian), so its blur variance is sigma^2 + (c + shear_u)^2 / 4 + (d + shear_t)^2 / 12. */
static double flat_blur_var(double var_x, double c, double shear_u, double d, double shear_t)
{
    double a = c + shear_u, b = d + shear_t;
    return var_x + a * a * LR_DISK_VAR + b * b * LR_BOX_VAR;
}

/* With flat weights the Gaussian design's blur at the layer's central slopes (c0, d0) is no
 * longer the renderer's: the design counted its own sample weights (8.3: a clamped layer's
 * sigma_u exceeds the aperture's), so a strongly defocused layer came out sharper than the
 * reference (back wall of the hard bench, c = 20.5 px: std 9.6 px against 10.25), with the
 * Gaussian's tails where the disk has none. Restore the true variance c0^2/4 + d0^2/12: first
 * widen sigma up to the clamp (more sharing), then reproject less (the residual disk and box
 * carry the rest, in their own shape), scaling both shears by the same mu in [0, 1]; B(mu) is
 * continuous with B(0) >= target, so bisection finds it. A layer already blurred more (the
 * design covering a wide slope range) is left alone. docs/algorithms.md 8.18. */
static void match_true_blur(double *var_x, float *shear_u, float *shear_t, double c0, double d0, double sigma_clamp)
{
    double want = c0 * c0 * LR_DISK_VAR + d0 * d0 * LR_BOX_VAR;
    double su = *shear_u, st = *shear_t;
    double have = flat_blur_var(*var_x, c0, su, d0, st);
    if (!(have < want) || !isfinite(want)) return;
    double room = sigma_clamp * sigma_clamp - *var_x;
    if (room > 0.0) {
        double grow = fmin(room, want - have);
        *var_x += grow;
        have += grow;
        if (!(have < want)) return;
    }
    double lo = 0.0, hi = 1.0; /* B(lo) >= want > B(hi) */
    for (int i = 0; i < 40; ++i) {
        double mid = 0.5 * (lo + hi);
        if (flat_blur_var(*var_x, c0, mid * su, d0, mid * st) >= want) lo = mid;
        else hi = mid;
    }
    *shear_u = (float)(lo * su), *shear_t = (float)(lo * st);
}

/* What the screen filter stands in for at the central slopes (c0, d0): the reprojection took
 * the disk's variance from c0^2/4 down to (c0 + shear_u)^2/4 and the box's from d0^2/12 to
 * (d0 + shear_t)^2/12; the screen filter puts the difference back. Given in the shapes that
 * were taken, a disk of radius sqrt(c0^2 - (c0 + shear_u)^2) and a box of length
 * sqrt(d0^2 - (d0 + shear_t)^2), instead of inside the Gaussian: a full reprojection then
 * blurs a layer exactly by the lens disk's projection and the shutter's box, without the
 * Gaussian's tails where the disk has none (docs/algorithms.md 8.18). The shares never exceed
 * the screen variance var_x; what is left of it stays Gaussian. */
static void screen_shares(double var_x, double c0, float shear_u, double d0, float shear_t, float *disk_px, float *box_px)
{
    double a = c0 + shear_u, b = d0 + shear_t;
    double disk2 = fmax(0.0, c0 * c0 - a * a), box2 = fmax(0.0, d0 * d0 - b * b);
    double used = disk2 * LR_DISK_VAR + box2 * LR_BOX_VAR;
    if (used > var_x && used > 0.0) disk2 *= var_x / used, box2 *= var_x / used;
    *disk_px = (float)sqrt(disk2), *box_px = (float)sqrt(box2);
}

LrFilter lr_filter_make(const LrSlopes *s, const LrFilterConfig *cfg_in)
{
    LrFilterConfig band = *cfg_in;
    if (s->d_min_px == 0.0f && s->d_max_px == 0.0f) band.sigma_pixel_px = cfg_in->sigma_pixel_still_px;
    const LrFilterConfig *cfg = &band;
    LrFilter f = lr_filter_make_paper(s, cfg);
    complete_bands(&f, cfg);
    if (!cfg->flat_lens_time) return f;
    f.inv_sigma_u = f.inv_sigma_v = f.inv_sigma_t = 0.0f;
    double c0 = 0.5 * ((double)s->c_min_px + s->c_max_px), d0 = 0.5 * ((double)s->d_min_px + s->d_max_px);
    double vx = 1.0 / ((double)f.inv_sigma_x_px * f.inv_sigma_x_px), vy = 1.0 / ((double)f.inv_sigma_y_px * f.inv_sigma_y_px);
    match_true_blur(&vx, &f.eta_px, &f.xi_px, c0, d0, cfg->sigma_clamp_px);
    float no_time = 0.0f;
    match_true_blur(&vy, &f.rho_px, &no_time, c0, 0.0, cfg->sigma_clamp_px);
    f.inv_sigma_x_px = (float)(1.0 / sqrt(vx)), f.inv_sigma_y_px = (float)(1.0 / sqrt(vy));
    if (!cfg->shaped_screen) return f;
    screen_shares(vx, c0, f.eta_px, d0, f.xi_px, &f.aperture_x_px, &f.shutter_x_px);
    float no_box;
    screen_shares(vy, c0, f.rho_px, 0.0, 0.0f, &f.aperture_y_px, &no_box);
    return f;
}

void lr_filter_warp(const LrSlopes *s, const LrFilterConfig *cfg, double S[3][3])
{
    LrClip clip;
    RoleWarp w = warp_xut(s, cfg, &clip);
    clamp_warp(&w, cfg->sigma_clamp_px);
    /* In roles (x, a, b): clip a: [[1, alpha, 0], [0, 1, 0], [beta, alpha beta, 1]] diag(s);
     * clip x: [[1, 0, 0], [beta_a, 1, 0], [beta_b, 0, 1]] diag(s). */
    double R[3][3] = {{0}};
    if (w.clip_x) {
        R[0][0] = w.s_x;
        R[1][0] = w.beta_a * w.s_x;
        R[1][1] = w.s_a;
        R[2][0] = w.beta_b * w.s_x;
        R[2][2] = w.s_b;
    } else {
        R[0][0] = w.s_x;
        R[0][1] = w.alpha * w.s_a;
        R[1][1] = w.s_a;
        R[2][0] = w.beta_b * w.s_x;
        R[2][1] = w.alpha * w.beta_b * w.s_a;
        R[2][2] = w.s_b;
    }
    /* Roles to (x, u, t): swap a and b (rows and columns) when the clip is against t. */
    int map[3] = {0, 1, 2};
    if (clip == LR_CLIP_T) map[1] = 2, map[2] = 1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) S[map[i]][map[j]] = R[i][j];
}

double lr_filter_weight_xut(const LrFilter *f, double dx_px, double du, double dt)
{
    double ax = f->inv_sigma_x_px * (dx_px + f->eta_px * du + f->xi_px * dt);
    double au = f->inv_sigma_u * du, at = f->inv_sigma_t * dt;
    return exp(-0.5 * (ax * ax + au * au + at * at));
}

bool lr_blur_within_band(const LrSlopes *s, const LrFilterConfig *cfg)
{
    float c_px = fmaxf(fabsf(s->c_min_px), fabsf(s->c_max_px));
    return s->d_min_px == 0.0f && s->d_max_px == 0.0f && 0.5f * c_px <= cfg->sigma_pixel_still_px;
}
