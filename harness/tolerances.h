/* pgt: THE tolerance table of `pgt diff` (one file; every bound says why it is that bound).
 *
 * Integer and topological outputs (counts, triangles, adjacency, parents, flags, labels) have
 * no entry: they must be equal, always. A float element passes when it is within max_ulp units
 * in the last place of the reference's value OR within max_abs_rel x the reference output's
 * bounding-box diagonal (ULPs mean nothing for a coordinate that happens to sit near 0, where a
 * float is far denser than the data's own precision). */
#ifndef PGT_TOLERANCES_H
#define PGT_TOLERANCES_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct pgt_tolerance {
    const char *algorithm;
    const char *output;
    uint32_t max_ulp;
    double max_abs_rel; /* x bounding-box diagonal of the reference output */
    const char *why;
} pgt_tolerance;

static const pgt_tolerance pgt_tolerances[] = {
    /* sqrt(3) positions. The backends run the reference's float operations in its order with
     * contraction off, so an IEEE device (PoCL and lavapipe are) gives the same bits. The bound
     * leaves room for what the APIs allow a real GPU: OpenCL C and Vulkan let x / y be 2.5 ulp
     * off (the centroid's / 3, the masks' / 27, alpha_n / n), i.e. ~3 ulp per operation; a
     * vertex sees at most one division-rounded weight per iteration and the relaxations are
     * convex combinations (they do not amplify an error), so k <= 3 iterations stay within
     * 3 x 3 ulp of cancellation-free data; 16 ulp adds margin for the sums' reordering a
     * compiler may not do but a driver might. 1e-6 x diagonal is 8x float epsilon over a unit
     * model: the absolute floor for coordinates near zero. An element fails only beyond both,
     * so the bound in force is max(16 ulp, 1e-6 x diagonal): the absolute one for coordinates
     * below about half the diagonal (16 ulp of 0.5 is 9.5e-7), the ulp one beyond. For k > 3
     * both grow (pgt_tolerance_sqrt3_bounds). */
    {"sqrt3", "positions", 16u, 1e-6,
     "division may be 2.5 ulp on OpenCL/Vulkan devices; k <= 3 convex relaxations do not "
     "amplify; 1e-6 x diagonal floors coordinates near 0"},
    /* Marching: the state after each step (x, y, dx, dy and the no-bounce memory's in_dx,
     * in_dy), compared step by step from the backend's own state before it, so errors do not
     * carry from step to step. The kernel runs the reference's float operations in its order
     * with contraction off, and the rot's cosine and sine come from the host's cosf and sinf, so
     * an IEEE device gives the same bits. A step holds at most PGT_MARCH_MAX_JUMPS jumps, each a
     * few divisions and square roots (the remaining length, the Jacobian rotation's solve, the
     * direction's normalisation) that the APIs let a real GPU round 2.5-3 ulp off; 16 ulp covers
     * a jump's chain of them. 1e-6 is the absolute floor for a direction component near 0 (a
     * unit vector: 8x float epsilon) and, in texels, for a position (far below the 1/256 texel
     * that decides which texel a point lies in). Discrete outcomes (event, stop, crossings,
     * chart, the no-bounce memory's texel and count) have no entry: they must be equal. */
    {"march", "state", 16u, 1e-6,
     "a jump's divisions and square roots may be 2.5-3 ulp each on OpenCL/Vulkan devices; "
     "1e-6 floors direction components and texel coordinates near 0"},
};

/* Each sqrt(3) iteration past the 3 the table's entry covers adds one division-rounded weight per
 * vertex (about 3 ulp, not amplified by the convex relaxations): 4 ulp and 1/3 of the absolute
 * floor more per iteration. */
#define PGT_TOLERANCE_SQRT3_COVERED_ITERATIONS 3u
#define PGT_TOLERANCE_SQRT3_ULP_PER_ITERATION 4u

/* The sqrt(3) position bounds in force for k iterations (k <= 3: the table's entry). */
static inline void pgt_tolerance_sqrt3_bounds(const pgt_tolerance *t, uint32_t k, uint32_t *max_ulp,
                                              double *max_abs_rel) {
    const uint32_t c = PGT_TOLERANCE_SQRT3_COVERED_ITERATIONS, more = k > c ? k - c : 0u;
    *max_ulp = t->max_ulp + PGT_TOLERANCE_SQRT3_ULP_PER_ITERATION * more;
    *max_abs_rel = t->max_abs_rel * (double)(c + more) / (double)c;
}

static inline const pgt_tolerance *pgt_tolerance_find(const char *algorithm, const char *output) {
    for (size_t i = 0; i < sizeof pgt_tolerances / sizeof *pgt_tolerances; ++i)
        if (!strcmp(pgt_tolerances[i].algorithm, algorithm) &&
            !strcmp(pgt_tolerances[i].output, output))
            return &pgt_tolerances[i];
    return NULL;
}

#endif
