/* LR's screen taps (see lr_taps.h; docs/algorithms.md 8.18). */
#include "recon/lr/lr_taps.h"

#include <math.h>
#include <string.h>

/* Half the window, at most the kernels' tables. */
static int radius_cap(const LrConfig *cfg) { return cfg->window_px / 2 < LR_MAX_RADIUS_PX ? cfg->window_px / 2 : LR_MAX_RADIUS_PX; }

int lr_filter_radius_px(float inv_sigma_px, const LrConfig *cfg)
{
    int cap = radius_cap(cfg);
    if (!(inv_sigma_px > 0.0f)) return cap;
    float r = ceilf(3.0f / inv_sigma_px);
    return r > (float)cap ? cap : (int)r;
}

#define LR_MIN_SHARE_PX 2.0

/* One axis of a partition's screen filter: total std, disk radius, box length (px). */
typedef struct {
    double sigma, disk, box;
} Axis;

static Axis axis_of(const LrFilter *f, const LrConfig *cfg, bool across)
{
    Axis a = {1.0 / (across ? f->inv_sigma_y_px : f->inv_sigma_x_px), across ? f->aperture_y_px : f->aperture_x_px,
              across ? 0.0 : f->shutter_x_px};
    /* Binned into pixels, a disk or box under 2 px no longer has its shape, only more
     * weight on the neighbours than its variance asks (a 1-px disk: 0.27 of the centre
     * against the Gaussian's 0.19); such a share stays in the Gaussian. On LR's pipeline
     * test scene (circles of confusion of about 1 px) keeping them cost 40% more error; on
     * the hard bench scene the threshold makes no difference from 1.5 to 3 px. */
    if (a.disk < LR_MIN_SHARE_PX) a.disk = 0.0;
    if (a.box < LR_MIN_SHARE_PX) a.box = 0.0;
    /* A tile's edge pixels find samples only (N_s - N) / 2 px beyond the tile (its window):
     * shares reaching further would be cut on one side there, a step at the tile border
     * (test_no_tile_seams); they shrink to fit, their variance going to the Gaussian. */
    double reach = a.disk + 0.5 * a.box, margin = 0.5 * (cfg->window_px - cfg->tile_px);
    if (reach > margin) a.disk *= margin / reach, a.box *= margin / reach;
    return a;
}

/* The Gaussian's share: what is left of the variance after the disk (R^2 / 4) and the box
 * (L^2 / 12); lr_filter_make keeps the shares inside the total. */
static double rest_sigma(const Axis *a)
{
    double v = a->sigma * a->sigma - a->disk * a->disk * 0.25 - a->box * a->box / 12.0;
    return v > 0.0 ? sqrt(v) : 0.0;
}

static int axis_radius(const Axis *a, const LrConfig *cfg)
{
    int cap = radius_cap(cfg);
    if (a->disk == 0.0 && a->box == 0.0) return lr_filter_radius_px((float)(1.0 / a->sigma), cfg);
    double r = ceil(a->disk + 0.5 * a->box + 3.0 * rest_sigma(a) + 0.5);
    return r > (double)cap ? cap : (int)r;
}

void lr_screen_radii_px(const LrFilter *f, const LrConfig *cfg, int *rx, int *ry)
{
    /* a layer without shears has no motion: its band is the still layers' (8.36) */
    float pixel = 1.0f / cfg->filter.sigma_pixel_still_px;
    bool neither = f->eta_px == 0.0f && f->xi_px == 0.0f && f->rho_px == 0.0f && f->inv_sigma_x_px >= pixel &&
                   f->inv_sigma_y_px >= pixel;
    Axis along = axis_of(f, cfg, false), across = axis_of(f, cfg, true);
    *rx = neither ? 0 : axis_radius(&along, cfg);
    *ry = neither ? 0 : axis_radius(&across, cfg);
}

static double phi(double z) { return 0.5 * erfc(-z * M_SQRT1_2); }

/* The semicircle's cumulative distribution at x (radius R > 0). */
static double semicircle_cdf(double x, double R)
{
    if (x <= -R) return 0.0;
    if (x >= R) return 1.0;
    double q = x / R;
    return 0.5 + (q * sqrt(1.0 - q * q) + asin(q)) / M_PI;
}

enum { SPAN = LR_MAX_RADIUS_PX, WIDTH = 2 * SPAN + 1 }; /* per-pixel tables over [-SPAN, SPAN] */

/* Each share binned into pixels (exact integrals over [k - 1/2, k + 1/2]). A pixel's lower
 * edge is its left neighbour's upper edge, the same double (k - 1/2 = (k - 1) + 1/2 exactly),
 * so each edge's cdf is taken once (WIDTH + 1 calls, not 2 WIDTH). */
static void bin_disk(double R, double *t)
{
    double lo = R > 0.0 ? semicircle_cdf(-SPAN - 0.5, R) : 0.0;
    for (int k = -SPAN; k <= SPAN; ++k) {
        double hi = R > 0.0 ? semicircle_cdf(k + 0.5, R) : 0.0;
        t[k + SPAN] = R > 0.0 ? hi - lo : (k == 0);
        lo = hi;
    }
}

static void bin_box(double L, double *t)
{
    for (int k = -SPAN; k <= SPAN; ++k) {
        double lo = fmax(k - 0.5, -0.5 * L), hi = fmin(k + 0.5, 0.5 * L);
        t[k + SPAN] = L > 0.0 ? fmax(0.0, hi - lo) / L : (k == 0);
    }
}

static void bin_gauss(double s, double *t)
{
    double lo = s > 0.0 ? phi((-SPAN - 0.5) / s) : 0.0;
    for (int k = -SPAN; k <= SPAN; ++k) {
        double hi = s > 0.0 ? phi((k + 0.5) / s) : 0.0;
        t[k + SPAN] = s > 0.0 ? hi - lo : (k == 0);
        lo = hi;
    }
}

/* Half-width of a symmetric per-pixel table: the largest |k| with a nonzero entry. */
static int reach_of(const double *t)
{
    int k = SPAN;
    while (k > 0 && t[k + SPAN] == 0.0) --k;
    return k;
}

/* out[k] = sum over j of a[j] b[k - j] for k in [k0, SPAN] (a and b within their reaches),
 * j ascending. Only the j whose k - j lies within b's reach are visited: the same terms in the
 * same order as testing every j of a's reach (the taps of a frame's partitions cost 2% of a
 * warm LR frame's CPU that way). */
static void convolve(const double *a, const double *b, int k0, double *out)
{
    int ra = reach_of(a), rb = reach_of(b);
    for (int k = k0; k <= SPAN; ++k) {
        double sum = 0.0;
        int j0 = k - rb > -ra ? k - rb : -ra, j1 = k + rb < ra ? k + rb : ra;
        for (int j = j0; j <= j1; ++j) sum += a[j + SPAN] * b[k - j + SPAN];
        out[k + SPAN] = sum;
    }
}

void lr_screen_taps(const LrFilter *f, const LrConfig *cfg, bool across, int r, float *w)
{
    Axis a = axis_of(f, cfg, across);
    if (a.disk == 0.0 && a.box == 0.0) {
        float inv = across ? f->inv_sigma_y_px : f->inv_sigma_x_px;
        for (int k = 0; k <= r; ++k) {
            float q = (float)k * inv;
            w[k] = expf(-0.5f * q * q);
        }
        return;
    }
    /* A share binned into pixels has its variance plus a pixel box's 1/12 px^2, and the
     * convolution of m binned shares adds m/12; the point-sampled Gaussian above has none.
     * So the shares give back m/12 of their variance, the Gaussian first: the taps' variance
     * stays sigma^2 (it matters for small blurs: a disk of radius 1.1 px came out with 1.5
     * times its variance). */
    double var_d = a.disk * a.disk * 0.25, var_b = a.box * a.box / 12.0, var_g = rest_sigma(&a);
    var_g *= var_g;
    double need = ((var_d > 0.0) + (var_b > 0.0) + (var_g > 0.0)) / 12.0;
    double take = fmin(var_g, need);
    var_g -= take, need -= take;
    if (var_g <= 0.0 && take > 0.0) need = fmax(0.0, need - 1.0 / 12.0); /* no Gaussian left to bin */
    if (need > 0.0) {
        double keep = fmax(0.0, (var_d + var_b - need) / (var_d + var_b));
        var_d *= keep, var_b *= keep;
    }
    double disk[WIDTH], box[WIDTH], gauss[WIDTH], both[WIDTH], all[WIDTH];
    bin_disk(sqrt(4.0 * var_d), disk);
    bin_box(sqrt(12.0 * var_b), box);
    bin_gauss(sqrt(var_g), gauss);
    convolve(disk, box, -SPAN, both);
    convolve(both, gauss, 0, all); /* the taps are its k >= 0 */
    for (int k = 0; k <= r; ++k) w[k] = (float)all[k + SPAN];
}

/* Per-axis variance of a round table of radius r (the cells with d2 <= r^2). */
static double round_variance(const double *t, int r, double *sum)
{
    double s = 0.0, m2 = 0.0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            int d2 = dx * dx + dy * dy;
            if (d2 > r * r) continue;
            s += t[d2], m2 += t[d2] * dx * dx;
        }
    *sum = s;
    return s > 0.0 ? m2 / s : 0.0;
}

/* The table at the squared offsets of the cells within r (dx^2 + dy^2 <= r^2, the only entries
 * read: round_variance, the kernels, lr_round_sum); 0 at the others (3, 6, 7, 11, ...: 54% of
 * the entries up to 8^2, 62% up to 16^2), which were an erfc each, five times a table. */
static void round_fill(double R, double s, int r, double *t)
{
    for (int d2 = 0; d2 <= r * r; ++d2) t[d2] = 0.0;
    for (int dy = 0; dy <= r; ++dy)
        for (int dx = 0; dx <= dy && dx * dx + dy * dy <= r * r; ++dx) t[dx * dx + dy * dy] = 1.0;
    for (int d2 = 0; d2 <= r * r; ++d2)
        if (t[d2] != 0.0) t[d2] = 0.5 * erfc((sqrt((double)d2) - R) / (s * M_SQRT2));
}

bool lr_screen_round(const LrFilter *f, const LrConfig *cfg, float cos_psi, float sin_psi, int *r, float *table)
{
    if (!cfg->filter.round_screen || !cfg->filter.shaped_screen || sin_psi != 0.0f || cos_psi != 1.0f || f->xi_px != 0.0f ||
        f->shutter_x_px != 0.0f)
        return false;
    Axis a = axis_of(f, cfg, false), b = axis_of(f, cfg, true);
    if (a.disk == 0.0 || b.disk == 0.0) return false;
    int rx = axis_radius(&a, cfg), ry = axis_radius(&b, cfg);
    int rr = rx > ry ? rx : ry;
    if (rr > LR_ROUND_MAX_PX) return false;
    /* the target: the larger of the two axes' screen variances (they differ only through the
     * clamp's rounding); the rim's softness: the Gaussian rest, at least half a pixel so that
     * the table is not a bare step sampled at whole pixels */
    double var = fmax(a.sigma * a.sigma, b.sigma * b.sigma);
    double R = fmin(a.disk, b.disk), s = fmax(0.5, rest_sigma(&a));
    double t[LR_ROUND_TABLE], sum = 0.0;
    for (int it = 0; it < 4; ++it) { /* R^2 / 4 is the disk's part of the variance: move it by the miss */
        round_fill(R, s, rr, t);
        double v = round_variance(t, rr, &sum);
        R = sqrt(fmax(0.0, R * R + 4.0 * (var - v)));
    }
    round_fill(R, s, rr, t);
    round_variance(t, rr, &sum);
    for (int d2 = 0; d2 <= rr * rr; ++d2) table[d2] = (float)(t[d2] / sum);
    *r = rr;
    return true;
}

void lr_screen_make(const LrFilter *f, const LrConfig *cfg, float cos_psi, float sin_psi, LrScreen *s)
{
    memset(s, 0, sizeof *s);
    int rr;
    if (lr_screen_round(f, cfg, cos_psi, sin_psi, &rr, s->table)) {
        s->round = true, s->rx = s->ry = rr;
        return;
    }
    lr_screen_radii_px(f, cfg, &s->rx, &s->ry);
    lr_screen_taps(f, cfg, false, s->rx, s->taps_x);
    lr_screen_taps(f, cfg, true, s->ry, s->taps_y);
}

bool lr_screen_same(const LrScreen *a, const LrScreen *b)
{
    return a->rx == b->rx && a->ry == b->ry && a->round == b->round && !memcmp(a->taps_x, b->taps_x, sizeof a->taps_x) &&
           !memcmp(a->taps_y, b->taps_y, sizeof a->taps_y) && !memcmp(a->table, b->table, sizeof a->table);
}
