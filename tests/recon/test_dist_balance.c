/* The tile assignment of MPI ranks after pass 1 (dist_balance, dist_reassign, issue 21):
 * every tile goes to exactly one rank, the same on every call, each rank's predicted cost
 * within one tile's cost of the ideal (total / ranks), Graham's largest-first bound against
 * the brute-force optimum, and tiles stay with their owner where that keeps the balance.
 * No MPI is needed: the assignment is computed alike by every rank, without messages. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/dist.h"

/* A reproducible cost map like an adaptive pass 2: most tiles cheap or empty, patches
 * (penumbrae, out-of-focus edges) up to 40x dearer. */
static void cost_map(double *cost, int tiles_x, int tiles_y, unsigned seed)
{
    unsigned s = seed;
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            s = s * 1664525u + 1013904223u;
            double noise = (double)(s >> 8) / 16777216.0;
            bool patch = (tx - tiles_x / 3) * (tx - tiles_x / 3) + (ty - tiles_y / 2) * (ty - tiles_y / 2) < 20;
            double c = patch ? 64.0 * (20.0 + 20.0 * noise) : (noise < 0.3 ? 0.0 : 64.0 * noise);
            cost[ty * tiles_x + tx] = floor(c);
        }
}

/* Each rank's sum, the largest tile, the ideal; checks every owner is a rank. */
static void loads(const double *cost, const int *owner, int n, int ranks, double *load, double *largest,
                  double *ideal)
{
    double total = 0.0;
    *largest = 0.0;
    memset(load, 0, (size_t)ranks * sizeof(double));
    for (int t = 0; t < n; ++t) {
        CHECK(owner[t] >= 0 && owner[t] < ranks);
        if (owner[t] < 0 || owner[t] >= ranks) continue;
        load[owner[t]] += cost[t];
        total += cost[t];
        if (cost[t] > *largest) *largest = cost[t];
    }
    *ideal = total / ranks;
}

static void test_bound_and_determinism(void)
{
    enum { TX = 32, TY = 24, N = TX * TY };
    static double cost[N];
    static int owner[N], again[N], before[N];
    for (unsigned seed = 1; seed <= 4; ++seed) {
        cost_map(cost, TX, TY, seed);
        for (int ranks = 2; ranks <= 7; ++ranks) {
            for (int keep = 0; keep < 3; ++keep) {
                /* no preference; the interleave before; everything on rank 0 before (the
                 * keep rule must not break the bound however uneven the old owners were) */
                for (int t = 0; t < N; ++t) before[t] = keep == 1 ? t % ranks : 0;
                const int *b = keep ? before : NULL;
                dist_balance(cost, b, N, ranks, owner);
                dist_balance(cost, b, N, ranks, again);
                CHECK(memcmp(owner, again, sizeof owner) == 0);
                double load[8], largest, ideal;
                loads(cost, owner, N, ranks, load, &largest, &ideal);
                double lo = INFINITY, hi = 0.0;
                for (int r = 0; r < ranks; ++r) lo = fmin(lo, load[r]), hi = fmax(hi, load[r]);
                CHECK(hi <= ideal + largest);
                /* the sums add up to the total, so no rank falls far below the ideal either */
                CHECK(lo >= ideal - (ranks - 1) * largest);
                /* the map is uneven: an interleave alone is off by more than one tile */
                if (seed == 1 && ranks == 2 && keep == 1) {
                    double il[2] = {0, 0};
                    for (int t = 0; t < N; ++t) il[t % 2] += cost[t];
                    CHECK(fabs(il[0] - il[1]) > largest);
                    CHECK(hi - lo <= largest);
                }
            }
        }
    }
}

/* Graham (1969): largest-first is within 4/3 - 1/(3 ranks) of the best possible largest
 * sum; checked against every assignment of a small set. */
static void test_against_brute_force(void)
{
    enum { N = 11 };
    double cost[N];
    int owner[N];
    for (unsigned seed = 1; seed <= 20; ++seed) {
        unsigned s = seed * 2654435761u;
        for (int t = 0; t < N; ++t) {
            s = s * 1664525u + 1013904223u;
            cost[t] = 1.0 + (double)(s >> 24);
        }
        for (int ranks = 2; ranks <= 3; ++ranks) {
            double best = INFINITY;
            int combos = 1;
            for (int t = 0; t < N; ++t) combos *= ranks;
            for (int c = 0; c < combos; ++c) {
                double load[3] = {0, 0, 0};
                for (int t = 0, k = c; t < N; ++t, k /= ranks) load[k % ranks] += cost[t];
                double hi = fmax(load[0], fmax(load[1], load[2]));
                if (hi < best) best = hi;
            }
            dist_balance(cost, NULL, N, ranks, owner);
            double load[3], largest, ideal;
            loads(cost, owner, N, ranks, load, &largest, &ideal);
            double hi = fmax(load[0], fmax(load[1], ranks > 2 ? load[2] : 0.0));
            CHECK(hi >= best);
            CHECK(hi <= (4.0 / 3.0 - 1.0 / (3.0 * ranks)) * best + 1e-9);
        }
    }
}

/* Owners are kept where the balance allows: even costs after the interleave move nothing,
 * free tiles never move, and a single dear tile moves only what it must. */
static void test_keeps_owners(void)
{
    enum { N = 60 };
    double cost[N];
    int before[N], owner[N];
    for (int ranks = 2; ranks <= 5; ++ranks) {
        for (int t = 0; t < N; ++t) cost[t] = 10.0, before[t] = t % ranks;
        dist_balance(cost, before, N, ranks, owner);
        CHECK(memcmp(owner, before, sizeof owner) == 0);
        for (int t = 0; t < N; ++t) cost[t] = t % 7 == 0 ? 0.0 : 10.0 + t;
        for (int t = 0; t < N; ++t) before[t] = (t * 7) % ranks;
        dist_balance(cost, before, N, ranks, owner);
        for (int t = 0; t < N; ++t)
            if (cost[t] == 0.0) CHECK(owner[t] == before[t]);
    }
}

/* dist_reassign on a frame whose sides are not multiples of a tile: a tile's cost is the
 * samples of its pixels, every pixel's owner is its tile's, the moves are counted. */
static void test_reassign_frame(void)
{
    enum { W = 37, H = 21 };
    ReconDist d;
    memset(&d, 0, sizeof d);
    d.ranks = 3;
    Diag e = {0};
    CHECK(dist_tiles_reset(&d, W, H, &e));
    CHECK(d.tiles_x == 5 && d.tile_count == 15);
    /* pass 1: the interleave */
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) CHECK(dist_owner(&d, x, y) == ((y / 8) * 5 + x / 8) % 3);
    /* pass 2: all the samples in the first tile column (tiles 0, 5, 10: interleave owners
     * 0, 2, 1, already one each), then all in tile 0 and its right neighbour */
    static int spp[W * H];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) spp[y * W + x] = x < 8 ? 5 : 0;
    CHECK(dist_reassign(&d, spp, &e));
    CHECK(d.tiles_moved == 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) spp[y * W + x] = y < 8 && x < 16 ? 5 : 0;
    CHECK(dist_reassign(&d, spp, &e));
    /* tiles 0 and 1 (owners 0 and 1 before) cost alike: both stay, nothing else costs */
    CHECK(d.owner[0] == 0 && d.owner[1] == 1 && d.tiles_moved == 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) spp[y * W + x] = y < 8 && (x < 8 || (x >= 24 && x < 32)) ? 5 : 0;
    CHECK(dist_reassign(&d, spp, &e));
    /* tiles 0 and 3 had owners 0 and 0: one of them moves */
    CHECK(d.owner[0] != d.owner[3] && (d.owner[0] == 0 || d.owner[3] == 0) && d.tiles_moved == 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) CHECK(dist_owner(&d, x, y) == d.owner[(y / 8) * 5 + x / 8]);
    free(d.owner);
    free(d.owner_before);
    free(d.tile_seconds);
    free(d.tile_samples);
}

/* Measured seconds per sample weigh the planned samples: four tiles of equal counts, owned
 * (the interleave) by ranks 0, 1, 0, 1, with tiles 0 and 2 measured 3x dearer
 * per sample: one of them moves (counts alone move nothing). A tile not measured yet costs
 * the frame's mean rate. */
static void test_reassign_measured(void)
{
    enum { W = 32, H = 8 };
    ReconDist d;
    memset(&d, 0, sizeof d);
    d.ranks = 2;
    Diag e = {0};
    CHECK(dist_tiles_reset(&d, W, H, &e));
    CHECK(d.tile_count == 4 && d.owner[0] == 0 && d.owner[1] == 1 && d.owner[2] == 0 && d.owner[3] == 1);
    static int spp[W * H];
    for (int i = 0; i < W * H; ++i) spp[i] = 4;
    /* counts alone (no measurement yet): the interleave is balanced, nothing moves */
    CHECK(dist_reassign(&d, spp, &e));
    CHECK(d.tiles_moved == 0 && d.owner[0] == 0 && d.owner[1] == 1 && d.owner[2] == 0 && d.owner[3] == 1);
    for (int t = 0; t < 4; ++t) d.tile_samples[t] = 64.0, d.tile_seconds[t] = t % 2 == 0 ? 0.3 : 0.1;
    CHECK(dist_reassign(&d, spp, &e));
    /* one of the dear tiles moves: 1.2 against 0.4 + 0.4 + 1.2 (the best split with one
     * move; two moves would make 1.6 and 1.6) */
    CHECK(d.tiles_moved == 1 && d.owner[0] != d.owner[2]);
    /* tile 3 not measured: the mean rate of the others, (0.3 + 0.1 + 0.3) s per 192
     * samples; the sums are within one tile of the ideal with those costs */
    for (int t = 0; t < 4; ++t) {
        d.tile_samples[t] = t == 3 ? 0.0 : 64.0;
        d.tile_seconds[t] = t == 3 ? 0.0 : t == 1 ? 0.1 : 0.3;
    }
    CHECK(dist_reassign(&d, spp, &e));
    double mean = 0.7 / 192.0, cost[4] = {256 * 0.3 / 64, 256 * 0.1 / 64, 256 * 0.3 / 64, 256 * mean}, load[2] = {0, 0};
    for (int t = 0; t < 4; ++t) load[d.owner[t]] += cost[t];
    double ideal = (cost[0] + cost[1] + cost[2] + cost[3]) / 2;
    CHECK(load[0] <= ideal + cost[0] + 1e-12 && load[1] <= ideal + cost[0] + 1e-12);
    /* and the unmeasured tile counts: at a rate of 0 it would stay, at the mean rate rank 1
     * (tiles 0, 1, 3: 1.2 + 0.4 + 0.93) is over the ideal and gives tile 0 back */
    CHECK(d.owner[0] == 0 && d.owner[2] == 0 && d.owner[1] == 1 && d.owner[3] == 1);
    free(d.owner);
    free(d.owner_before);
    free(d.tile_seconds);
    free(d.tile_samples);
}

int main(void)
{
    test_bound_and_determinism();
    test_against_brute_force();
    test_keeps_owners();
    test_reassign_frame();
    test_reassign_measured();
    CHECK_DONE();
}
