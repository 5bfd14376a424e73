/* pgt harness: element-by-element diff of backend outputs against the reference. */
#include "diff.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static int64_t ordered_bits(float x) {
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    /* map the sign-magnitude float order onto the integers: -0 and +0 both to 0 */
    return (u & 0x80000000u) ? -(int64_t)(u & 0x7FFFFFFFu) : (int64_t)u;
}

uint64_t pgt_ulp_distance(float a, float b) {
    if (isnan(a) || isnan(b)) return UINT64_MAX;
    const int64_t d = ordered_bits(a) - ordered_bits(b);
    return (uint64_t)(d < 0 ? -d : d);
}

void pgt_diff_floats_run(pgt_diff_floats *d, const float *ref, const float *got, uint64_t n,
                         uint32_t max_ulp, double abs_bound) {
    memset(d, 0, sizeof(*d));
    d->count = n;
    for (uint64_t i = 0; i < n; ++i) {
        const uint64_t u = pgt_ulp_distance(ref[i], got[i]);
        const double e = fabs((double)ref[i] - (double)got[i]);
        if (i == 0 || u > d->max_ulp) {
            d->max_ulp = u;
            d->worst = i, d->worst_ref = ref[i], d->worst_got = got[i];
        }
        if (e > d->max_abs || isnan(e)) d->max_abs = isnan(e) ? INFINITY : e;
        if (u > max_ulp && !(e <= abs_bound)) d->outside++;
    }
}

static uint64_t count_u32(const uint32_t *a, const uint32_t *b, uint64_t n, uint64_t *first) {
    uint64_t c = 0;
    for (uint64_t i = 0; i < n; ++i)
        if (a[i] != b[i]) {
            if (c++ == 0 && first) *first = i;
        }
    return c;
}

void pgt_diff_sqrt3_compare(pgt_diff_sqrt3 *d, const pgt_diff_sqrt3_output *ref,
                            const pgt_diff_sqrt3_output *got) {
    const pgt_mesh *ro = &ref->out, *go = &got->out;
    if (!d->tolerance) d->tolerance = pgt_tolerance_find("sqrt3", "positions");
    pgt_tolerance_sqrt3_bounds(d->tolerance, d->iterations, &d->max_ulp, &d->max_abs_rel);
    d->first_triangle = UINT64_MAX;
    d->ref_vertices = ro->vertex_count, d->got_vertices = go->vertex_count;
    d->ref_faces = ro->face_count, d->got_faces = go->face_count;
    d->diagonal = pgt_mesh_bbox_diagonal(ro);
    const int same_counts = d->ref_vertices == d->got_vertices && d->ref_faces == d->got_faces;
    if (same_counts) {
        const uint64_t F = ro->face_count, V = ro->vertex_count;
        d->triangles = count_u32(ro->indices, go->indices, 3 * F, &d->first_triangle);
        if (d->first_triangle != UINT64_MAX) d->first_triangle /= 3;
        d->opposite = count_u32(ref->opp, got->opp, 3 * F, NULL);
        d->parents = count_u32(ref->parent, got->parent, F, NULL);
        for (uint64_t f = 0; f < F; ++f) d->protected_flags += ref->prot[f] != got->prot[f];
        if (ro->labels || go->labels) {
            if (!ro->labels || !go->labels)
                d->labels = F;
            else
                d->labels =
                    count_u32((const uint32_t *)ro->labels, (const uint32_t *)go->labels, F, NULL);
        }
        pgt_diff_floats_run(&d->positions, ro->positions, go->positions, 3 * V, d->max_ulp,
                            d->max_abs_rel * d->diagonal);
    }
    d->pass = same_counts && d->triangles == 0 && d->opposite == 0 && d->parents == 0 &&
              d->protected_flags == 0 && d->labels == 0 && d->positions.outside == 0;
}

static void output_free(pgt_diff_sqrt3_output *r) {
    pgt_mesh_destroy(&r->out);
    free(r->opp), free(r->parent), free(r->prot);
    memset(r, 0, sizeof(*r));
}

pgt_result pgt_diff_sqrt3_run(pgt_backend *b, const pgt_mesh *in, uint32_t iterations,
                              const uint8_t *protected_faces, pgt_diff_sqrt3 *d, pgt_error *err) {
    memset(d, 0, sizeof(*d));
    d->first_triangle = UINT64_MAX;
    d->tolerance = pgt_tolerance_find("sqrt3", "positions");
    d->iterations = iterations;
    uint32_t vb = 0, fb = 0;
    pgt_sqrt3_bound(in->vertex_count, in->face_count, 0, iterations, &vb, &fb, NULL);
    pgt_diff_sqrt3_output runs[2];
    memset(runs, 0, sizeof runs);
    pgt_backend cpu;
    pgt_backend_open(&cpu, PGT_BACKEND_CPU, 0, 0, NULL);
    for (int i = 0; i < 2; ++i) {
        pgt_diff_sqrt3_output *r = &runs[i];
        r->opp = malloc(((size_t)fb * 3 + 1) * sizeof(uint32_t));
        r->parent = malloc(((size_t)fb + 1) * sizeof(uint32_t));
        r->prot = malloc((size_t)fb + 1);
        if (!r->opp || !r->parent || !r->prot) {
            output_free(&runs[0]), output_free(&runs[1]);
            return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "diff: out of memory (%u faces)",
                                 fb);
        }
        pgt_sqrt3_options o = {
            iterations, pgt_cli_cpu_count(), protected_faces, r->prot, r->parent, r->opp, NULL};
        pgt_error e = {0};
        const double t0 = pgt_cli_now_ms();
        pgt_result res = pgt_backend_sqrt3(i == 0 ? &cpu : b, &r->out, in, &o, NULL, &e);
        const double ms = pgt_cli_now_ms() - t0;
        if (i == 0) {
            d->ref_ms = ms, d->ref_failed = res != PGT_OK, d->ref_code = res;
            snprintf(d->ref_message, sizeof d->ref_message, "%s", e.message);
        } else {
            d->got_ms = ms, d->got_failed = res != PGT_OK, d->got_code = res;
            snprintf(d->got_message, sizeof d->got_message, "%s", e.message);
        }
    }
    pgt_backend_close(&cpu);
    if (d->ref_failed || d->got_failed) {
        d->pass = d->ref_failed && d->got_failed && d->ref_code == d->got_code;
        output_free(&runs[0]), output_free(&runs[1]);
        return PGT_OK;
    }
    pgt_diff_sqrt3_compare(d, &runs[0], &runs[1]);
    output_free(&runs[0]), output_free(&runs[1]);
    return PGT_OK;
}

/* A JSON number, or null for NaN and infinities (JSON has neither). */
static void json_number(FILE *f, double x) {
    if (isfinite(x))
        fprintf(f, "%.9g", x);
    else
        fputs("null", f);
}

void pgt_diff_sqrt3_print(FILE *f, const char *label, const pgt_diff_sqrt3 *d, int json) {
    const char *verdict = d->pass ? "ok" : "FAIL";
    if (json) {
        fprintf(f, "{\"algorithm\":\"sqrt3\",\"case\":");
        pgt_cli_json_string(f, label);
        fprintf(f, ",\"pass\":%s", d->pass ? "true" : "false");
        if (d->ref_failed || d->got_failed) {
            fprintf(f, ",\"refused_by_both\":%s",
                    d->ref_failed && d->got_failed ? "true" : "false");
            fprintf(f, ",\"reference_error\":");
            pgt_cli_json_string(f, d->ref_failed ? pgt_result_name(d->ref_code) : "");
            fprintf(f, ",\"backend_error\":");
            pgt_cli_json_string(f, d->got_failed ? pgt_result_name(d->got_code) : "");
            fprintf(f, ",\"message\":");
            pgt_cli_json_string(f, d->got_failed ? d->got_message : d->ref_message);
            fprintf(f, "}\n");
            return;
        }
        fprintf(f,
                ",\"vertices\":[%u,%u],\"faces\":[%u,%u],\"mismatches\":{\"triangles\":%llu,"
                "\"opposite\":%llu,\"parents\":%llu,\"protected\":%llu,\"labels\":%llu},"
                "\"positions\":{\"max_abs\":",
                d->ref_vertices, d->got_vertices, d->ref_faces, d->got_faces,
                (unsigned long long)d->triangles, (unsigned long long)d->opposite,
                (unsigned long long)d->parents, (unsigned long long)d->protected_flags,
                (unsigned long long)d->labels);
        /* a NaN or infinite output is what a diff exists to show: JSON null, not 'nan' */
        json_number(f, d->positions.max_abs);
        fputs(",\"max_abs_over_diagonal\":", f);
        json_number(f, d->diagonal > 0 ? d->positions.max_abs / d->diagonal : 0.0);
        fprintf(f, ",\"max_ulp\":%llu,\"worst\":%llu,\"worst_ref\":",
                (unsigned long long)d->positions.max_ulp, (unsigned long long)d->positions.worst);
        json_number(f, d->positions.worst_ref);
        fputs(",\"worst_got\":", f);
        json_number(f, d->positions.worst_got);
        fprintf(f,
                ",\"outside\":%llu},\"tolerance\":{\"max_ulp\":%u,\"max_abs_rel\":%g},"
                "\"reference_ms\":%.3f,\"backend_ms\":%.3f}\n",
                (unsigned long long)d->positions.outside, d->max_ulp, d->max_abs_rel, d->ref_ms,
                d->got_ms);
        return;
    }
    if (d->ref_failed || d->got_failed) {
        if (d->pass)
            fprintf(f, "sqrt3 %s: both refuse (%s): %s: agree, nothing compared\n", label,
                    pgt_result_name(d->ref_code), d->ref_message);
        else
            fprintf(f, "sqrt3 %s: reference %s, backend %s: %s: FAIL\n", label,
                    d->ref_failed ? pgt_result_name(d->ref_code) : "ok",
                    d->got_failed ? pgt_result_name(d->got_code) : "ok",
                    d->got_failed ? d->got_message : d->ref_message);
        return;
    }
    if (d->ref_vertices != d->got_vertices || d->ref_faces != d->got_faces) {
        fprintf(f, "sqrt3 %s: counts differ: reference %u v %u f, backend %u v %u f: FAIL\n", label,
                d->ref_vertices, d->ref_faces, d->got_vertices, d->got_faces);
        return;
    }
    const uint64_t w = d->positions.worst;
    fprintf(f,
            "sqrt3 %s: %u v %u f; mismatches: triangles %llu, opposite %llu, parents %llu, "
            "protected %llu, labels %llu; positions: max abs %.3g (%.2g x diag), max ulp %llu "
            "(v%llu.%c ref %.9g got %.9g), %llu outside %u ulp / %.0e x diag; %.1f vs %.1f ms: "
            "%s\n",
            label, d->ref_vertices, d->ref_faces, (unsigned long long)d->triangles,
            (unsigned long long)d->opposite, (unsigned long long)d->parents,
            (unsigned long long)d->protected_flags, (unsigned long long)d->labels,
            d->positions.max_abs, d->diagonal > 0 ? d->positions.max_abs / d->diagonal : 0.0,
            (unsigned long long)d->positions.max_ulp, (unsigned long long)(w / 3), "xyz"[w % 3],
            d -> positions.worst_ref, d->positions.worst_got,
            (unsigned long long)d->positions.outside, d->max_ulp, d->max_abs_rel, d->ref_ms,
            d->got_ms, verdict);
}

/* ---- march ---------------------------------------------------------------------------------- */

/* The float fields of a state the diff compares, in this order. */
#define DIFF_MARCH_FLOATS 6u
static void march_floats(const pgt_march_state *s, float *out) {
    out[0] = s->x, out[1] = s->y, out[2] = s->dx, out[3] = s->dy, out[4] = s->in_dx;
    out[5] = s->in_dy;
}

pgt_result pgt_diff_march_run(pgt_backend *b, const pgt_march_atlas *a, const pgt_march_options *o,
                              float length, uint32_t steps, uint32_t walkers, uint32_t seed,
                              pgt_diff_march *d, pgt_error *err) {
    memset(d, 0, sizeof(*d));
    const uint64_t records = (uint64_t)walkers * steps;
    if (records > UINT32_MAX)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "march diff: %u walkers x %u steps is too many",
                             walkers, steps);
    pgt_march_state *start = calloc(walkers ? walkers : 1, sizeof *start),
                    *got = calloc(walkers ? walkers : 1, sizeof *got),
                    *rec = malloc((size_t)(records ? records : 1) * sizeof *rec);
    uint32_t *ev = malloc((size_t)(records ? records : 1) * 4);
    float *x = malloc((size_t)(walkers ? walkers : 1) * 4 * sizeof(float));
    uint32_t *chart = malloc((size_t)(walkers ? walkers : 1) * 4);
    pgt_result r = PGT_OK;
    if (!start || !got || !rec || !ev || !x || !chart) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "march diff: out of memory");
        goto done;
    }
    float *y = x + walkers, *dx = y + walkers, *dy = dx + walkers;
    if (pgt_march_random_starts(a, seed, walkers, x, y, dx, dy, chart) != 0) {
        r = pgt_error_set(err, PGT_ERROR_EMPTY, "march diff: no inner texel to start from");
        goto done;
    }
    for (uint32_t i = 0; i < walkers; ++i) {
        pgt_march_state s = {x[i], y[i], dx[i], dy[i], chart[i], 0u, 0.0f, 0.0f, 0u};
        start[i] = got[i] = s;
    }
    const double t0 = pgt_cli_now_ms();
    r = pgt_backend_march(b, a, o, length, steps, walkers, got, rec, ev, NULL, NULL, err);
    const double t1 = pgt_cli_now_ms();
    if (r != PGT_OK) goto done;
    r = pgt_diff_march_compare(d, a, o, length, steps, walkers, start, rec, ev, err);
    d->got_ms = t1 - t0, d->ref_ms = pgt_cli_now_ms() - t1;
done:
    free(start), free(got), free(rec), free(ev), free(x), free(chart);
    return r;
}

pgt_result pgt_diff_march_compare(pgt_diff_march *d, const pgt_march_atlas *a,
                                  const pgt_march_options *o, float length, uint32_t steps,
                                  uint32_t walkers, const pgt_march_state *start,
                                  const pgt_march_state *rec, const uint32_t *ev, pgt_error *err) {
    memset(d, 0, sizeof(*d));
    d->walkers = walkers, d->steps_per_walker = steps;
    d->first_walker = d->first_step = UINT64_MAX;
    d->tolerance = pgt_tolerance_find("march", "state");
    const uint64_t records = (uint64_t)walkers * steps;
    float *fr = malloc((size_t)(records ? records : 1) * DIFF_MARCH_FLOATS * sizeof(float)),
          *fg = malloc((size_t)(records ? records : 1) * DIFF_MARCH_FLOATS * sizeof(float));
    if (!fr || !fg) {
        free(fr), free(fg);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "march diff: out of memory");
    }
    /* every recorded step, re-run by the reference from the backend's state before it */
    uint64_t n = 0;
    for (uint32_t i = 0; i < walkers; ++i)
        for (uint32_t k = 0; k < steps; ++k) {
            const size_t at = (size_t)i * steps + k;
            pgt_march_state s = k ? rec[at - 1] : start[i];
            pgt_march_info info;
            const pgt_march_event e = pgt_march_step(a, o, &s, length, 0.0f, &info);
            const uint32_t want = PGT_MARCH_EVENT_WORD(e, info.stop, info.jumps);
            const pgt_march_state *g = &rec[at];
            const int valid = pgt_backend_march_record_valid(a, g, ev[at]);
            if (!valid || want != ev[at] || s.chart != g->chart || s.from != g->from ||
                s.bounces != g->bounces) {
                if (!d->discrete) {
                    d->first_walker = i, d->first_step = k;
                    d->ref_event = want, d->got_event = ev[at];
                }
                d->discrete++;
            }
            if (!valid) break; /* nothing to re-run the next step from */
            march_floats(&s, fr + n * DIFF_MARCH_FLOATS);
            march_floats(g, fg + n * DIFF_MARCH_FLOATS);
            n++;
            d->crossings += info.jumps > 0;
            if (e == PGT_MARCH_STOP || PGT_MARCH_EVENT_OF(ev[at]) == PGT_MARCH_STOP) {
                d->stops++;
                break;
            }
        }
    d->steps = n;
    pgt_diff_floats_run(&d->state, fr, fg, n * DIFF_MARCH_FLOATS, d->tolerance->max_ulp,
                        d->tolerance->max_abs_rel);
    d->pass = d->discrete == 0 && d->state.outside == 0;
    free(fr), free(fg);
    return PGT_OK;
}

void pgt_diff_march_print(FILE *f, const char *label, const pgt_diff_march *d, int json) {
    static const char *const field[DIFF_MARCH_FLOATS] = {"x", "y", "dx", "dy", "in_dx", "in_dy"};
    const uint64_t w = d->state.worst;
    if (json) {
        fprintf(f, "{\"algorithm\":\"march\",\"case\":");
        pgt_cli_json_string(f, label);
        fprintf(f,
                ",\"pass\":%s,\"walkers\":%u,\"steps\":%llu,\"crossings\":%llu,\"stops\":%llu,"
                "\"discrete_mismatches\":%llu,\"state\":{\"max_abs\":",
                d->pass ? "true" : "false", d->walkers, (unsigned long long)d->steps,
                (unsigned long long)d->crossings, (unsigned long long)d->stops,
                (unsigned long long)d->discrete);
        json_number(f, d->state.max_abs);
        fprintf(f,
                ",\"max_ulp\":%llu,\"outside\":%llu},\"tolerance\":{\"max_ulp\":%u,"
                "\"max_abs\":%g},\"reference_ms\":%.3f,\"backend_ms\":%.3f}\n",
                (unsigned long long)d->state.max_ulp, (unsigned long long)d->state.outside,
                d->tolerance->max_ulp, d->tolerance->max_abs_rel, d->ref_ms, d->got_ms);
        return;
    }
    fprintf(f,
            "march %s: %u walkers, %llu steps (%llu crossing charts, %llu stops); discrete "
            "mismatches %llu",
            label, d->walkers, (unsigned long long)d->steps, (unsigned long long)d->crossings,
            (unsigned long long)d->stops, (unsigned long long)d->discrete);
    if (d->discrete)
        fprintf(f, " (first: walker %llu step %llu, event word ref 0x%x got 0x%x)",
                (unsigned long long)d->first_walker, (unsigned long long)d->first_step,
                d->ref_event, d->got_event);
    fprintf(f,
            "; state: max abs %.3g, max ulp %llu (step %llu.%s ref %.9g got %.9g), %llu outside "
            "%u ulp / %.0e; %.1f vs %.1f ms: %s\n",
            d->state.max_abs, (unsigned long long)d->state.max_ulp,
            (unsigned long long)(w / DIFF_MARCH_FLOATS), field[w % DIFF_MARCH_FLOATS],
            d->state.worst_ref, d->state.worst_got, (unsigned long long)d->state.outside,
            d->tolerance->max_ulp, d->tolerance->max_abs_rel, d->ref_ms, d->got_ms,
            d->pass ? "ok" : "FAIL");
}
