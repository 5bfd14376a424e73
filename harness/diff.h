/* pgt harness: element-by-element comparison of a backend's outputs with the reference's
 * (`pgt diff`, and the tests that run it). */
#ifndef PGT_DIFF_H
#define PGT_DIFF_H

#include <stdint.h>
#include <stdio.h>

#include "backend.h"
#include "tolerances.h"

/* Distance in units in the last place between two floats (0 for equal values, +0 vs -0 too;
 * UINT64_MAX when either is NaN). */
uint64_t pgt_ulp_distance(float a, float b);

/* Float outputs: the largest absolute error and ULP distance, and the worst element. */
typedef struct pgt_diff_floats {
    uint64_t count;   /* elements compared */
    uint64_t outside; /* elements outside the tolerance (beyond max_ulp and beyond max_abs) */
    double max_abs;
    uint64_t max_ulp;
    uint64_t worst; /* element with the largest ULP distance (first of equals) */
    float worst_ref, worst_got;
} pgt_diff_floats;

/* Compares n floats; abs_bound is the tolerance's absolute bound (already scaled). */
void pgt_diff_floats_run(pgt_diff_floats *d, const float *ref, const float *got, uint64_t n,
                         uint32_t max_ulp, double abs_bound);

/* One sqrt(3) case: reference vs backend on the same input and options. */
typedef struct pgt_diff_sqrt3 {
    int ref_failed, got_failed; /* the call returned an error (codes below) */
    pgt_result ref_code, got_code;
    char ref_message[PGT_ERROR_MESSAGE_SIZE], got_message[PGT_ERROR_MESSAGE_SIZE];
    uint32_t ref_vertices, got_vertices, ref_faces, got_faces;
    /* mismatching elements of integer outputs (0 expected) */
    uint64_t triangles, opposite, parents, protected_flags, labels;
    uint64_t first_triangle; /* first mismatching triangle (UINT64_MAX when none) */
    pgt_diff_floats positions;
    double diagonal; /* of the reference output */
    const pgt_tolerance *tolerance;
    uint32_t iterations; /* k of the run: the bounds grow past 3 (pgt_tolerance_sqrt3_bounds) */
    uint32_t max_ulp;    /* the bounds in force, set by pgt_diff_sqrt3_compare */
    double max_abs_rel;
    int pass; /* counts and integer outputs equal, positions within the tolerance; or both
                 refused the input with the same error code */
    double ref_ms, got_ms;
} pgt_diff_sqrt3;

/* One side's outputs: the mesh and the per-face arrays pgt_sqrt3_options fills (out_opposite,
 * out_face_parent, out_protected), face_count entries each (opposite: 3 per face). */
typedef struct pgt_diff_sqrt3_output {
    pgt_mesh out;
    uint32_t *opp, *parent;
    uint8_t *prot;
} pgt_diff_sqrt3_output;

/* Compares two sides' outputs into d's counts, positions and pass (d's run fields, ms and
 * error codes untouched; d->tolerance is the sqrt3 entry unless set). What pgt_diff_sqrt3_run
 * does after both calls succeed. */
void pgt_diff_sqrt3_compare(pgt_diff_sqrt3 *d, const pgt_diff_sqrt3_output *ref,
                            const pgt_diff_sqrt3_output *got);

/* Runs both and compares. Returns PGT_OK when the comparison could be made (a refusal by both
 * with the same code counts as a comparison); an error only for what stops it (out of memory). */
pgt_result pgt_diff_sqrt3_run(pgt_backend *b, const pgt_mesh *in, uint32_t iterations,
                              const uint8_t *protected_faces, pgt_diff_sqrt3 *d, pgt_error *err);

/* One line (or one JSON object) describing a case; `label` names the input and options. */
void pgt_diff_sqrt3_print(FILE *f, const char *label, const pgt_diff_sqrt3 *d, int json);

/* One march case: `walkers` seeded random walkers (pgt_march_random_starts) take up to `steps`
 * steps of `length` texels on the backend, which records every step; each step is then re-run
 * by the reference (pgt_march_step) from the backend's state before it and compared: discrete
 * outcomes must be equal, floats within the "march" tolerance. */
typedef struct pgt_diff_march {
    uint32_t walkers, steps_per_walker;
    uint64_t steps;     /* steps compared (a STOP counts; nothing after it) */
    uint64_t crossings; /* of those, steps that crossed a chart border */
    uint64_t stops;
    uint64_t discrete; /* steps whose event, stop, crossings, chart, from or bounces differ */
    uint64_t first_walker, first_step; /* the first such step (UINT64_MAX: none) */
    uint32_t ref_event, got_event;     /* its event words (PGT_MARCH_EVENT_WORD) */
    pgt_diff_floats state;             /* x, y, dx, dy, in_dx, in_dy of every compared step */
    const pgt_tolerance *tolerance;
    int pass;
    double ref_ms, got_ms;
} pgt_diff_march;

/* Runs a march case (seed: pgt_march_random_starts's). PGT_OK when the comparison was made; an
 * error when the backend fails or memory runs out. */
pgt_result pgt_diff_march_run(pgt_backend *b, const pgt_march_atlas *a, const pgt_march_options *o,
                              float length, uint32_t steps, uint32_t walkers, uint32_t seed,
                              pgt_diff_march *d, pgt_error *err);

/* The comparison of pgt_diff_march_run after the backend's run: walker i started at start[i];
 * rec and ev are its walkers x steps records (pgt_backend_march). Fills d (ms left 0). A record
 * the reference cannot start from (pgt_backend_march_record_valid: an unknown event, a position
 * off its chart's inner texels, a non-finite direction) is a discrete mismatch that ends the
 * comparison of its walker. */
pgt_result pgt_diff_march_compare(pgt_diff_march *d, const pgt_march_atlas *a,
                                  const pgt_march_options *o, float length, uint32_t steps,
                                  uint32_t walkers, const pgt_march_state *start,
                                  const pgt_march_state *rec, const uint32_t *ev, pgt_error *err);

/* One line (or one JSON object) describing a march case. */
void pgt_diff_march_print(FILE *f, const char *label, const pgt_diff_march *d, int json);

#endif
