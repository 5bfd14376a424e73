/* pgt: ivy on a mesh end to end: random seeds, painting, and the expand -> Bezier -> terminals
 * pipeline (see pgt/ivy.h). */
#include "pgt/ivy.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/bezier.h"
#include "pgt/grammar.h"
#include "pgt/parallel.h"
#include "pgt/rng.h"
#include "time_internal.h"

#define TWO_PI 6.283185307179586

/* An inner texel the mask (NULL: none) allows. */
static int seedable(const pgt_march_atlas *a, const float *mask, size_t i) {
    return (a->codes[i] & 3u) == PGT_TEXEL_INNER && !(mask && mask[i] >= PGT_MARCH_MASK_THRESHOLD);
}

pgt_result pgt_ivy_random_seeds(pgt_expand_seed *out, uint32_t count, const pgt_march_atlas *a,
                                const float *mask, uint32_t seed, pgt_error *err) {
    if (!count) return PGT_OK;
    if (!out || !a || !a->codes)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "ivy seeds: NULL argument");
    const size_t texels = (size_t)a->width * a->height;
    uint32_t inner = 0;
    for (size_t i = 0; i < texels; ++i) inner += seedable(a, mask, i);
    if (!inner)
        return pgt_error_set(err, PGT_ERROR_EMPTY, "ivy seeds: the atlas has no inner texel%s",
                             mask ? " that the mask allows" : "");
    uint32_t *list = malloc((size_t)inner * sizeof(uint32_t));
    if (!list) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "ivy seeds: out of memory");
    uint32_t n = 0;
    for (size_t i = 0; i < texels; ++i)
        if (seedable(a, mask, i)) list[n++] = (uint32_t)i;
    for (uint32_t s = 0; s < count; ++s) {
        uint64_t k =
            (uint64_t)(pgt_rng_double(seed, PGT_IVY_SEED_STREAM, 2u * (uint64_t)s) * inner);
        if (k >= inner) k = inner - 1u; /* cannot happen with 53-bit draws below 1; kept safe */
        const double ang =
            TWO_PI * pgt_rng_double(seed, PGT_IVY_SEED_STREAM, 2u * (uint64_t)s + 1u);
        const uint32_t t = list[k];
        out[s].x = (float)(t % a->width) + 0.5f;
        out[s].y = (float)(t / a->width) + 0.5f;
        out[s].dx = (float)cos(ang), out[s].dy = (float)sin(ang);
    }
    free(list);
    return PGT_OK;
}

/* ---- painting ---- */

typedef struct paint_grid {
    float lo[3], cell;
    uint32_t dim[3];
    uint32_t *first; /* cells + 1 */
    uint32_t *seg;   /* segment ids per cell */
} paint_grid;

typedef struct paint_job {
    float *mask;
    const pgt_march_atlas *a;
    const float *points;
    const uint32_t *seg_a; /* segment k runs points seg_a[k] -> seg_b[k] */
    const uint32_t *seg_b;
    const paint_grid *g;
    float r2;
    uint64_t *painted; /* per row */
} paint_job;

/* Squared distance from p to the segment a-b (a == b: to the point). */
static float seg_dist2(const float p[3], const float a[3], const float b[3]) {
    float ab[3], ap[3], ab2 = 0.0f, t = 0.0f;
    for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ap[k] = p[k] - a[k], ab2 += ab[k] * ab[k];
    if (ab2 > 0.0f) {
        for (int k = 0; k < 3; ++k) t += ap[k] * ab[k];
        t /= ab2;
        t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
    }
    float d2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        const float d = ap[k] - t * ab[k];
        d2 += d * d;
    }
    return d2;
}

/* The cell of p, or 0 when p is more than a cell outside the grid. A point on or just past the
 * grid's border goes to the border cell, as grid_box clamps segments' boxes: with a brush below
 * the coordinates' float resolution, lo - r == lo and hi + r == hi, and a stroke's end point
 * lies on the border (floor((hi - lo) / cell) == dim). The distance test decides. */
static int grid_cell(const paint_grid *g, const float p[3], uint32_t c[3]) {
    for (int k = 0; k < 3; ++k) {
        const float f = floorf((p[k] - g->lo[k]) / g->cell);
        if (!(f >= -1.0f) || f > (float)g->dim[k]) return 0;
        c[k] = f < 0.0f ? 0u : f >= (float)g->dim[k] ? g->dim[k] - 1u : (uint32_t)f;
    }
    return 1;
}

static void paint_rows(void *ctx, uint32_t begin, uint32_t end, uint32_t worker) {
    (void)worker;
    const paint_job *j = ctx;
    const pgt_march_atlas *a = j->a;
    const paint_grid *g = j->g;
    for (uint32_t y = begin; y < end; ++y) {
        uint64_t painted = 0;
        for (uint32_t x = 0; x < a->width; ++x) {
            const size_t i = (size_t)y * a->width + x;
            const uint32_t kind = a->codes[i] & 3u;
            if (kind != PGT_TEXEL_INNER && kind != PGT_TEXEL_INDIRECTION) continue;
            const float p[3] = {a->texels[i].x, a->texels[i].y, a->texels[i].z};
            uint32_t c[3];
            if (!grid_cell(g, p, c)) continue;
            const size_t cell = ((size_t)c[2] * g->dim[1] + c[1]) * g->dim[0] + c[0];
            for (uint32_t e = g->first[cell]; e < g->first[cell + 1]; ++e) {
                const uint32_t s = g->seg[e];
                if (seg_dist2(p, &j->points[3u * (size_t)j->seg_a[s]],
                              &j->points[3u * (size_t)j->seg_b[s]]) <= j->r2) {
                    j->mask[i] = 0.0f;
                    painted++;
                    break;
                }
            }
        }
        j->painted[y] = painted;
    }
}

/* The cell range [c0, c1] of the bounding box of segment (a, b) grown by r; returns its cell
 * count. */
static uint64_t grid_box(const paint_grid *g, const float *a, const float *b, float r,
                         uint32_t c0[3], uint32_t c1[3]) {
    uint64_t n = 1;
    for (int k = 0; k < 3; ++k) {
        const float lo = fminf(a[k], b[k]) - r, hi = fmaxf(a[k], b[k]) + r;
        float f0 = floorf((lo - g->lo[k]) / g->cell), f1 = floorf((hi - g->lo[k]) / g->cell);
        f0 = f0 < 0.0f ? 0.0f : f0;
        f1 = f1 > (float)(g->dim[k] - 1u) ? (float)(g->dim[k] - 1u) : f1;
        c0[k] = (uint32_t)f0, c1[k] = (uint32_t)f1;
        n *= c1[k] >= c0[k] ? (uint64_t)(c1[k] - c0[k]) + 1u : 0u;
    }
    return n;
}

/* Visits the cells of segment s's bounding box grown by r: counts (fill == 0) or fills. */
static void grid_visit(paint_grid *g, const float *a, const float *b, float r, uint32_t s,
                       uint32_t *cursor, int fill) {
    uint32_t c0[3], c1[3];
    grid_box(g, a, b, r, c0, c1);
    for (uint32_t z = c0[2]; z <= c1[2]; ++z)
        for (uint32_t y = c0[1]; y <= c1[1]; ++y)
            for (uint32_t x = c0[0]; x <= c1[0]; ++x) {
                const size_t cell = ((size_t)z * g->dim[1] + y) * g->dim[0] + x;
                if (fill)
                    g->seg[cursor[cell]++] = s;
                else
                    g->first[cell + 1]++;
            }
}

pgt_result pgt_ivy_paint(float *mask, const pgt_march_atlas *a, const float *points,
                         uint32_t point_count, const uint32_t *stroke_first, uint32_t stroke_count,
                         float radius, uint32_t threads, uint64_t *out_painted, pgt_error *err) {
    if (out_painted) *out_painted = 0;
    if (!mask || !a || !a->codes || (point_count && !points) || !stroke_first)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "paint: NULL argument");
    if (!(radius > 0.0f) || !isfinite(radius))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "paint: the brush radius must be a finite number > 0, got %g",
                             (double)radius);
    if (stroke_first[0] != 0 || stroke_first[stroke_count] != point_count)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "paint: strokes must cover the points 0 .. %u exactly", point_count);
    for (uint32_t k = 0; k < stroke_count; ++k)
        if (stroke_first[k + 1] < stroke_first[k])
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "paint: stroke %u ends before it starts", k);
    for (size_t i = 0; i < 3u * (size_t)point_count; ++i)
        if (!isfinite(points[i]))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "paint: point %zu is not finite",
                                 i / 3);
    if (!point_count) return PGT_OK;

    /* segments: consecutive points of a stroke; a one-point stroke is a zero-length segment */
    uint32_t segs = 0;
    for (uint32_t k = 0; k < stroke_count; ++k) {
        const uint32_t n = stroke_first[k + 1] - stroke_first[k];
        segs += n == 0 ? 0u : n == 1 ? 1u : n - 1u;
    }
    uint32_t *seg_a = malloc((size_t)segs * sizeof(uint32_t) * 2u);
    paint_grid g = {0};
    uint64_t *painted = calloc(a->height, sizeof(uint64_t));
    pgt_result r = PGT_OK;
    if (!seg_a || !painted) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "paint: out of memory");
        goto done;
    }
    uint32_t *seg_b = seg_a + segs, m = 0;
    for (uint32_t k = 0; k < stroke_count; ++k) {
        const uint32_t f = stroke_first[k], n = stroke_first[k + 1] - f;
        if (n == 1) seg_a[m] = seg_b[m] = f, m++;
        for (uint32_t q = 1; q < n; ++q) seg_a[m] = f + q - 1u, seg_b[m] = f + q, m++;
    }
    float hi[3];
    for (int k = 0; k < 3; ++k) g.lo[k] = hi[k] = points[k];
    for (uint32_t i = 1; i < point_count; ++i)
        for (int k = 0; k < 3; ++k) {
            g.lo[k] = fminf(g.lo[k], points[3u * (size_t)i + (size_t)k]);
            hi[k] = fmaxf(hi[k], points[3u * (size_t)i + (size_t)k]);
        }
    float extent = 0.0f;
    for (int k = 0; k < 3; ++k)
        g.lo[k] -= radius, hi[k] += radius, extent = fmaxf(extent, hi[k] - g.lo[k]);
    /* a cell at least one brush radius wide, at most PGT_IVY_PAINT_GRID_SIDE cells a side */
    g.cell = fmaxf(radius, extent / (float)PGT_IVY_PAINT_GRID_SIDE);
    size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
        const float d = ceilf((hi[k] - g.lo[k]) / g.cell);
        g.dim[k] = d < 1.0f                             ? 1u
                   : d > (float)PGT_IVY_PAINT_GRID_SIDE ? PGT_IVY_PAINT_GRID_SIDE
                                                        : (uint32_t)d;
        cells *= g.dim[k];
    }
    g.first = calloc(cells + 1u, sizeof(uint32_t));
    if (!g.first) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "paint: out of memory");
        goto done;
    }
    /* the entries counted from the boxes' sizes first: visiting a million long segments' cells
     * one by one before refusing them took a minute */
    uint64_t entries = 0;
    for (uint32_t s = 0; s < segs && entries <= PGT_IVY_PAINT_MAX_ENTRIES; ++s) {
        uint32_t c0[3], c1[3];
        entries += grid_box(&g, &points[3u * (size_t)seg_a[s]], &points[3u * (size_t)seg_b[s]],
                            radius, c0, c1);
    }
    if (entries > PGT_IVY_PAINT_MAX_ENTRIES) {
        r = pgt_error_set(err, PGT_ERROR_LIMIT,
                          "paint: the strokes cover more than %u grid cells in all (long "
                          "segments with a large brush); split them into shorter segments",
                          PGT_IVY_PAINT_MAX_ENTRIES);
        goto done;
    }
    for (uint32_t s = 0; s < segs; ++s)
        grid_visit(&g, &points[3u * (size_t)seg_a[s]], &points[3u * (size_t)seg_b[s]], radius, s,
                   NULL, 0);
    uint64_t total = 0;
    for (size_t c = 0; c < cells; ++c) {
        total += g.first[c + 1];
        g.first[c + 1] = (uint32_t)total;
    }
    assert(total == entries); /* the same boxes */
    g.seg = malloc((total ? total : 1u) * sizeof(uint32_t));
    uint32_t *cursor = malloc(cells * sizeof(uint32_t));
    if (!g.seg || !cursor) {
        free(cursor);
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "paint: out of memory");
        goto done;
    }
    memcpy(cursor, g.first, cells * sizeof(uint32_t));
    for (uint32_t s = 0; s < segs; ++s)
        grid_visit(&g, &points[3u * (size_t)seg_a[s]], &points[3u * (size_t)seg_b[s]], radius, s,
                   cursor, 1);
    free(cursor);
    paint_job job = {mask, a, points, seg_a, seg_b, &g, radius * radius, painted};
    pgt_parallel_for_items(a->height, a->width, threads ? threads : 1u, paint_rows, &job);
    if (out_painted)
        for (uint32_t y = 0; y < a->height; ++y) *out_painted += painted[y];
done:
    free(seg_a), free(painted), free(g.first), free(g.seg);
    return r;
}

/* ---- the pipeline ---- */

void pgt_ivy_destroy(pgt_ivy_output *out) {
    if (!out) return;
    pgt_expand_destroy(&out->expand);
    pgt_terminals_destroy(&out->mesh);
    free(out->positions), free(out->normals), free(out->b1), free(out->b2), free(out->smoothness);
    free(out->leaf_seed), free(out->leaf_key);
    memset(out, 0, sizeof(*out));
}

pgt_result pgt_ivy_generate(pgt_ivy_output *out, const pgt_expand_input *in,
                            const pgt_ivy_options *o, pgt_error *err) {
    const pgt_ivy_options defaults = {0};
    if (!o) o = &defaults;
    /* o->reuse: the previous output's mesh arrays are kept for the terminal evaluator */
    pgt_terminals_output mesh;
    memset(&mesh, 0, sizeof mesh);
    if (o->reuse) {
        mesh = out->mesh;
        memset(&out->mesh, 0, sizeof out->mesh);
        pgt_ivy_destroy(out);
    }
    memset(out, 0, sizeof(*out));
    const uint32_t threads = o->threads ? o->threads : 1u;
    pgt_expand_options eo = o->expand;
    eo.threads = threads;
    eo.progress = o->progress;
    double t0 = pgt_now_ms();
    pgt_result r = pgt_expand(&out->expand, in, &eo, err);
    if (r != PGT_OK) {
        pgt_terminals_destroy(&mesh);
        return r;
    }
    double t1 = pgt_now_ms();
    out->ms_expand = t1 - t0;
    pgt_progress_stage(o->progress, "bezier", 0, "");

    const pgt_expand_output *ex = &out->expand;
    const uint32_t n = ex->point_count;
    const size_t n3 = 3u * (size_t)(n ? n : 1u);
    out->positions = malloc(n3 * sizeof(float));
    out->normals = malloc(n3 * sizeof(float));
    out->b1 = malloc(n3 * sizeof(float));
    out->b2 = malloc(n3 * sizeof(float));
    out->smoothness = malloc(n ? n : 1u);
    out->leaf_seed = malloc((n ? n : 1u) * sizeof(uint32_t));
    out->leaf_key = malloc((n ? n : 1u) * sizeof(uint32_t));
    /* the terminal records the evaluator gets: all, or all but Leaves */
    uint32_t kept = ex->terminal_count;
    uint32_t *keep = NULL;
    if (o->no_leaves) keep = malloc(((size_t)ex->terminal_count + 1u) * sizeof(uint32_t));
    if (!out->positions || !out->normals || !out->b1 || !out->b2 || !out->smoothness ||
        !out->leaf_seed || !out->leaf_key || (o->no_leaves && !keep)) {
        free(keep);
        pgt_terminals_destroy(&mesh);
        pgt_ivy_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "ivy: out of memory");
    }
    for (uint32_t i = 0; i < n; ++i) {
        out->positions[3u * (size_t)i] = ex->x[i], out->positions[3u * (size_t)i + 1u] = ex->y[i];
        out->positions[3u * (size_t)i + 2u] = ex->z[i];
        out->normals[3u * (size_t)i] = ex->nx[i], out->normals[3u * (size_t)i + 1u] = ex->ny[i];
        out->normals[3u * (size_t)i + 2u] = ex->nz[i];
        out->smoothness[i] = PGT_BEZIER_C1;
        /* leaves keyed by the seed's id and the segment's index within its seed */
        out->leaf_seed[i] = in->seed_base + ex->seed[i];
        out->leaf_key[i] = i - ex->seed_first_point[ex->seed[i]];
        out->segments += ex->parent[i] != PGT_NONE;
    }
    /* a segment's smoothness is that of its first Bark record: walk the records backwards so
     * the first one is written last */
    for (uint32_t t = ex->terminal_count; t-- > 0;)
        if (ex->terminal_kind[t] == PGT_GRAMMAR_TERMINAL_BARK)
            out->smoothness[ex->terminal_segment[t]] = (uint8_t)ex->terminal_smoothness[t];
    r = pgt_bezier_build(out->positions, out->normals, ex->parent, out->smoothness, n, threads,
                         out->b1, out->b2, err);
    if (r != PGT_OK) {
        free(keep);
        pgt_terminals_destroy(&mesh);
        pgt_ivy_destroy(out);
        return r;
    }
    double t2 = pgt_now_ms();
    out->ms_bezier = t2 - t1;

    pgt_terminals_input ti;
    memset(&ti, 0, sizeof ti);
    ti.point_count = n, ti.positions = out->positions, ti.normals = out->normals;
    ti.parent = ex->parent, ti.b1 = out->b1, ti.b2 = out->b2, ti.seed_id = 0;
    ti.segment_seed_id = out->leaf_seed, ti.segment_key = out->leaf_key;
    uint32_t *rec[4] = {NULL, NULL, NULL, NULL};
    float *rec_f[2] = {NULL, NULL};
    if (keep) {
        kept = 0;
        for (uint32_t t = 0; t < ex->terminal_count; ++t)
            if (ex->terminal_kind[t] != PGT_GRAMMAR_TERMINAL_LEAVES) keep[kept++] = t;
        out->dropped_leaves = ex->terminal_count - kept;
        const size_t bytes = ((size_t)kept + 1u) * 4u;
        for (int k = 0; k < 4; ++k) rec[k] = malloc(bytes);
        for (int k = 0; k < 2; ++k) rec_f[k] = malloc(bytes);
        if (!rec[0] || !rec[1] || !rec[2] || !rec_f[0] || !rec_f[1]) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "ivy: out of memory");
            goto records_done;
        }
        for (uint32_t q = 0; q < kept; ++q) {
            const uint32_t t = keep[q];
            rec[0][q] = ex->terminal_segment[t], rec[1][q] = ex->terminal_kind[t];
            rec[2][q] = ex->terminal_smoothness[t];
            rec_f[0][q] = ex->terminal_a[t], rec_f[1][q] = ex->terminal_b[t];
        }
        ti.terminal_segment = rec[0], ti.terminal_kind = rec[1], ti.terminal_smoothness = rec[2];
        ti.terminal_a = rec_f[0], ti.terminal_b = rec_f[1];
    } else {
        ti.terminal_segment = ex->terminal_segment, ti.terminal_kind = ex->terminal_kind;
        ti.terminal_smoothness = ex->terminal_smoothness;
        ti.terminal_a = ex->terminal_a, ti.terminal_b = ex->terminal_b;
    }
    ti.terminal_count = kept;
    pgt_terminals_options to = o->terminals;
    to.threads = threads;
    to.progress = o->progress;
    to.reuse = o->reuse;
    out->mesh = mesh; /* zeroed unless reused */
    memset(&mesh, 0, sizeof mesh);
    r = pgt_terminals_build(&out->mesh, &ti, &to, err);
records_done:
    pgt_terminals_destroy(&mesh); /* zeroed once handed to out->mesh */
    free(keep);
    for (int k = 0; k < 4; ++k) free(rec[k]);
    for (int k = 0; k < 2; ++k) free(rec_f[k]);
    if (r != PGT_OK) {
        pgt_ivy_destroy(out);
        return r;
    }
    out->ms_terminals = pgt_now_ms() - t2;
    out->polygons = out->mesh.bark_quads + out->mesh.leaf_count;
    return PGT_OK;
}
