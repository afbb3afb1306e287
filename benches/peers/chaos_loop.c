/* A plain C chaos game writing nothing: the baseline of issue 11.
 *
 *   chaos_loop fern|gasket N      (prints the mean point, so nothing is optimised away)
 *
 * The maps are the affine maps of automata/fern.toml and automata/gasket.toml
 * (x' = a x + b y + e, y' = c x + d y + f), picked with the probabilities bcifs
 * gives them by default (|det|, with a floor of 1% of the mean for the fern's
 * singular stem) by a cumulative table; the generator is wyrand, as in bcifs. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct { double a, b, c, d, e, f; } Map;

static const Map FERN[] = {
    {0.85, 0.04, -0.04, 0.85, 0.0, 1.6},
    {-0.15, 0.28, 0.26, 0.24, 0.0, 0.44},
    {0.20, -0.26, 0.23, 0.22, 0.0, 1.6},
    {0.0, 0.0, 0.0, 0.16, 0.0, 0.0},
};
static const Map GASKET[] = {
    {0.5, 0.0, 0.0, 0.5, 0.0, 0.0},
    {0.5, 0.0, 0.0, 0.5, 0.5, 0.0},
    {0.5, 0.0, 0.0, 0.5, 0.25, 0.4330127018922193},
};

static uint64_t state = 0x9E3779B97F4A7C15ull;
static inline uint64_t wyrand(void) {
    state += 0xa0761d6478bd642full;
    __uint128_t t = (__uint128_t)state * (state ^ 0xe7037ed1a0b428dbull);
    return (uint64_t)(t >> 64) ^ (uint64_t)t;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: chaos_loop fern|gasket N\n");
        return 2;
    }
    const Map *maps = strcmp(argv[1], "fern") == 0 ? FERN : GASKET;
    int k = strcmp(argv[1], "fern") == 0 ? 4 : 3;
    long long n = atoll(argv[2]);
    uint64_t cumulative[4];
    double p[4], mean = 0, total = 0;
    for (int i = 0; i < k; i++) {
        p[i] = fabs(maps[i].a * maps[i].d - maps[i].b * maps[i].c);
        mean += p[i] / k;
    }
    for (int i = 0; i < k; i++) {
        if (p[i] < 0.01 * mean) p[i] = 0.01 * mean;
        total += p[i];
    }
    double run = 0;
    for (int i = 0; i < k; i++) {
        run += p[i] / total;
        cumulative[i] = i == k - 1 ? UINT64_MAX : (uint64_t)(run * 18446744073709551615.0);
    }
    double x = 0, y = 0, sx = 0, sy = 0;
    for (long long i = 0; i < n; i++) {
        uint64_t r = wyrand();
        int j = 0;
        while (j < k - 1 && r > cumulative[j]) j++;
        const Map *m = &maps[j];
        double nx = m->a * x + m->b * y + m->e;
        y = m->c * x + m->d * y + m->f;
        x = nx;
        sx += x;
        sy += y;
    }
    printf("%.6f %.6f\n", sx / n, sy / n);
    return 0;
}
