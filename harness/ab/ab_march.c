/* pgt_ab_march: two builds of ref_cpu/src/march.c, loaded as shared objects into one process,
 * march the same walkers on the same atlas in alternation; prints each one's rate, the median
 * of the per-pair ratios of the rates (B over A), and whether both left every walker in the
 * same state after the same steps (and with the same position sums, with --position). On a shared
 * machine whose speed drifts by 1.5x within an hour, runs of two binaries minutes apart cannot show
 * a 5 % change; pairs taken a fraction of a second apart can (the same build against itself: ratios
 * 0.99-1.00). scripts/ab_march.sh builds the two objects from git revisions or files and runs this.
 *
 *   pgt_ab_march A.so B.so MESH [--runs N] [--walkers W] [--steps S] [--step L] [--res R]
 *                [--position] [--two-views]
 *
 * Both objects must export pgt_march_atlas_create and pgt_march_batch with march.h's
 * signatures; everything else they call (the thread pool, allocation, errors) comes from this
 * program. The atlas is built here and its marching view created once by A: both builds read
 * the same arrays at the same addresses. That needs A's pgt_march_atlas_create to fill every
 * field B's march.c reads. With --two-views each build creates its own view: needed when B
 * reads a field A does not fill (march.h's fields may only be added at the end; this program
 * seeds the walkers through A's view). A's view without ring masks (a march.c before 9033a2c)
 * is detected and gets a view per build with a note. Two views lie on pages of their own:
 * calibrate with A against itself first (0.96x measured once). */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pgt/atlas_build.h"
#include "pgt/march.h"
#include "pgt/mesh_io.h"

typedef void (*batch_fn)(const pgt_march_atlas *, const pgt_march_options *, float, uint32_t,
                         uint32_t, float *, float *, float *, float *, uint32_t *, uint32_t,
                         uint32_t *, double *);
typedef pgt_result (*create_fn)(pgt_march_atlas *, const pgt_image *, const char *, pgt_error *);

static double thread_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, uint32_t n) { /* sorts v */
    qsort(v, n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int usage(void) {
    fputs("usage: pgt_ab_march A.so B.so MESH [--runs N] [--walkers W] [--steps S] [--step L]\n"
          "                    [--res R] [--position] [--two-views]\n",
          stderr);
    return 2;
}

static int load(const char *path, batch_fn *batch, create_fn *create) {
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        fprintf(stderr, "pgt_ab_march: %s\n", dlerror());
        return 0;
    }
    /* POSIX: a data pointer from dlsym converts to a function pointer */
    void *b = dlsym(h, "pgt_march_batch"), *c = dlsym(h, "pgt_march_atlas_create");
    if (!b || !c) {
        fprintf(stderr, "pgt_ab_march: %s: no pgt_march_batch or pgt_march_atlas_create\n", path);
        return 0;
    }
    memcpy(batch, &b, sizeof b);
    memcpy(create, &c, sizeof c);
    return 1;
}

static int parse_u32(const char *flag, const char *v, uint32_t lo, uint32_t hi, uint32_t *out) {
    char *end;
    const unsigned long x = v ? strtoul(v, &end, 10) : 0;
    if (!v || *end || end == v || x < lo || x > hi) {
        fprintf(stderr, "pgt_ab_march: %s wants a whole number from %u to %u\n", flag, lo, hi);
        return 0;
    }
    *out = (uint32_t)x;
    return 1;
}

int main(int argc, char **argv) {
    if (argc < 4) return usage();
    uint32_t runs = 20, walkers = 8192, steps = 500, res = 1024;
    float step = 2.0f;
    int position = 0, two_views = 0;
    for (int i = 4; i < argc; ++i) {
        const char *f = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(f, "--position")) {
            position = 1;
            continue;
        }
        if (!strcmp(f, "--two-views")) {
            two_views = 1;
            continue;
        }
        int ok;
        if (!strcmp(f, "--runs"))
            ok = parse_u32(f, v, 1, 10000, &runs);
        else if (!strcmp(f, "--walkers"))
            ok = parse_u32(f, v, 1, 1u << 20, &walkers);
        else if (!strcmp(f, "--steps"))
            ok = parse_u32(f, v, 1, 100000, &steps);
        else if (!strcmp(f, "--res"))
            ok = parse_u32(f, v, 16, 8192, &res);
        else if (!strcmp(f, "--step")) {
            char *end;
            step = v ? strtof(v, &end) : 0.0f;
            ok = v && !*end && end != v && step > 0.0f && step <= PGT_MARCH_MAX_LENGTH;
            if (!ok)
                fprintf(stderr, "pgt_ab_march: --step wants a length in (0, %g]\n",
                        (double)PGT_MARCH_MAX_LENGTH);
        } else {
            fprintf(stderr, "pgt_ab_march: unknown flag '%s'\n", f);
            return usage();
        }
        if (!ok) return 2;
        i++;
    }
    batch_fn batch[2];
    create_fn create[2];
    if (!load(argv[1], &batch[0], &create[0]) || !load(argv[2], &batch[1], &create[1])) return 2;

    pgt_error err = {0};
    pgt_mesh m;
    const pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
    if (pgt_mesh_read(&m, argv[3], &ro, &err) != PGT_OK) {
        fprintf(stderr, "pgt_ab_march: %s\n", err.message);
        return 2;
    }
    pgt_image img;
    pgt_atlas_options ao = {0};
    ao.width = ao.height = res, ao.threads = 2, ao.what = argv[3];
    /* zeroed: a build with an older, shorter layout leaves the fields it lacks alone */
    pgt_march_atlas view[2];
    memset(view, 0, sizeof view);
    if (pgt_atlas_build(&img, &m, &ao, NULL, &err) != PGT_OK ||
        create[0](&view[0], &img, argv[3], &err) != PGT_OK) {
        fprintf(stderr, "pgt_ab_march: %s\n", err.message);
        return 2;
    }
    if (!two_views && !view[0].rings) { /* B would read A's missing masks */
        fprintf(stderr, "pgt_ab_march: A's view has no ring masks (a march.c before 9033a2c): "
                        "a view per build, as --two-views\n");
        two_views = 1;
    }
    if (two_views && create[1](&view[1], &img, argv[3], &err) != PGT_OK) {
        fprintf(stderr, "pgt_ab_march: %s\n", err.message);
        return 2;
    }
    pgt_mesh_destroy(&m);
    const pgt_march_atlas *v[2] = {&view[0], two_views ? &view[1] : &view[0]}, *a = v[0];

    const size_t n = walkers;
    float *s0 = malloc(4 * n * sizeof(float));
    float *s[2] = {malloc(4 * n * sizeof(float)), malloc(4 * n * sizeof(float))};
    uint32_t *c0 = malloc(n * sizeof(uint32_t));
    uint32_t *c[2] = {malloc(n * sizeof(uint32_t)), malloc(n * sizeof(uint32_t))};
    uint32_t *taken[2] = {malloc(n * sizeof(uint32_t)), malloc(n * sizeof(uint32_t))};
    double *sum[2] = {malloc(n * sizeof(double)), malloc(n * sizeof(double))};
    double *ms[2] = {malloc(runs * sizeof(double)), malloc(runs * sizeof(double))};
    double *ratio = malloc(runs * sizeof(double));
    if (!s0 || !s[0] || !s[1] || !c0 || !c[0] || !c[1] || !taken[0] || !taken[1] || !sum[0] ||
        !sum[1] || !ms[0] || !ms[1] || !ratio) {
        fputs("pgt_ab_march: out of memory\n", stderr);
        return 2;
    }
    /* seeded random inner texels and headings, through A's view */
    if (pgt_march_random_starts(a, 5, walkers, s0, s0 + n, s0 + 2 * n, s0 + 3 * n, c0)) {
        fprintf(stderr, "pgt_ab_march: %s: no inner texel found\n", argv[3]);
        return 2;
    }
    uint64_t total[2] = {0, 0};
    for (int64_t r = -1; r < (int64_t)runs; ++r) { /* run -1: the warm-up */
        for (int j = 0; j < 2; ++j) {
            const int k = r & 1 ? 1 - j : j; /* A first in even runs, B first in odd ones */
            float *sk = s[k];
            memcpy(sk, s0, 4 * n * sizeof(float));
            memcpy(c[k], c0, n * sizeof(uint32_t));
            const double t0 = thread_ms();
            batch[k](v[k], NULL, step, steps, walkers, sk, sk + n, sk + 2 * n, sk + 3 * n, c[k], 1,
                     taken[k], position ? sum[k] : NULL);
            const double dt = thread_ms() - t0;
            if (r >= 0) ms[k][r] = dt;
        }
    }
    for (size_t i = 0; i < n; ++i) total[0] += taken[0][i], total[1] += taken[1][i];
    if (!total[0] || !total[1]) { /* a rate needs steps (a broken build takes none) */
        fprintf(stderr, "pgt_ab_march: build %s took no steps: no rate to compare\n",
                !total[0] ? "A" : "B");
        return 2;
    }
    /* rate B over rate A per pair: the ratio of the times only while both take as many steps */
    for (uint32_t r = 0; r < runs; ++r)
        ratio[r] = ((double)total[1] / ms[1][r]) / ((double)total[0] / ms[0][r]);
    /* every run starts from the same states, so the last run's ends stand for all */
    const int same = !memcmp(s[0], s[1], 4 * n * sizeof(float)) &&
                     !memcmp(c[0], c[1], n * sizeof(uint32_t)) &&
                     !memcmp(taken[0], taken[1], n * sizeof(uint32_t)) &&
                     (!position || !memcmp(sum[0], sum[1], n * sizeof(double)));
    const double ma = median(ms[0], runs), mb = median(ms[1], runs);
    const double mr = median(ratio, runs); /* sorts ratio */
    printf("A %.2f M steps/s, B %.2f M steps/s (medians); B/A %.3f (median of %u pairs, "
           "%.3f-%.3f); end states, steps taken%s the same: %s\n",
           (double)total[0] / ma * 1e-3, (double)total[1] / mb * 1e-3, mr, runs, ratio[0],
           ratio[runs - 1], position ? " and position sums" : "", same ? "yes" : "no");
    free(s0), free(s[0]), free(s[1]), free(c0), free(c[0]), free(c[1]), free(taken[0]),
        free(taken[1]), free(sum[0]);
    free(sum[1]), free(ms[0]), free(ms[1]), free(ratio);
    pgt_march_atlas_destroy(&view[0]);
    pgt_march_atlas_destroy(&view[1]);
    pgt_image_destroy(&img);
    return 0;
}
