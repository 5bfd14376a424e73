/* pgt: atlas step 1, charts from per-corner UVs (paper 000 section 4: "multi-chart geometry
 * images", after Sander et al. 2003).
 *
 * Two faces are in one chart when they share a mesh edge (pgt_adjacency opposite half-edges)
 * whose two corners carry bit-identical UVs on both sides. Decisions (atlas_build.h):
 * - a chart whose total signed UV area is negative is mirrored, which 5.2 forbids (a rotation
 *   cannot undo a reflection): it is flipped in u inside its own UV bounding box;
 * - a face whose |UV area| <= PGT_ATLAS_DEGENERATE_UV_AREA is degenerate: it still joins its
 *   neighbours but is not rasterized (face_chart = PGT_NONE); a chart left with no other face is
 *   dropped. Chart ids follow the smallest face id of each chart, so they do not depend on the
 *   thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_internal.h"
#include "pgt/adjacency.h"
#include "pgt/parallel.h"

void atlas_charts_destroy(atlas_charts *c) {
    if (!c) return;
    free(c->face_chart);
    free(c->uvs);
    free(c->chart_mirrored);
    free(c->chart_area_uv);
    free(c->chart_area_3d);
    free(c->border_half_edges);
    free(c->seam_half_edges);
    free(c->cross_half_edges);
    memset(c, 0, sizeof(*c));
}

/* Half-edge h lies on the mesh border (no opposite half-edge) and its face is rasterized. */
static int on_border(const pgt_adjacency *adj, const uint32_t *face_chart, uint32_t h) {
    return adj->opposite[h] == PGT_NONE && face_chart[h / 3u] != PGT_NONE;
}

/* Half-edge h of a rasterized face has a face of another chart across, or a degenerate UV
 * triangle (in no chart): a gap when nothing of that side is rasterized (atlas_build). */
static int between_charts(const pgt_adjacency *adj, const uint32_t *face_chart, uint32_t h) {
    const uint32_t o = adj->opposite[h];
    return face_chart[h / 3u] != PGT_NONE && o != PGT_NONE &&
           face_chart[o / 3u] != face_chart[h / 3u];
}

/* The corners of half-edge h and of its opposite o carry the same UVs on both sides: h runs
 * corner c -> c+1 of its face, o the other way, so corner c of h's face meets corner next(o)
 * of o's face, and next(h) meets o. */
static int same_uvs(const float *uvs, uint32_t h, uint32_t o) {
    const float *a0 = &uvs[2u * h], *a1 = &uvs[2u * pgt_half_edge_next(h)];
    const float *b0 = &uvs[2u * pgt_half_edge_next(o)], *b1 = &uvs[2u * o];
    return a0[0] == b0[0] && a0[1] == b0[1] && a1[0] == b1[0] && a1[1] == b1[1];
}

/* Half-edge h is a seam inside one rasterized chart: the smaller of a pair whose UVs differ
 * (uv_cut, set by the union of the charts) with both faces in one chart. */
static int inside_seam(const pgt_adjacency *adj, const uint32_t *face_chart, const uint8_t *uv_cut,
                       uint32_t h) {
    return uv_cut[h] && face_chart[h / 3u] != PGT_NONE &&
           face_chart[h / 3u] == face_chart[adj->opposite[h] / 3u];
}

/* Union-find root with path halving (iterative). */
static uint32_t find_root(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static double uv_area(const float *uv) { /* signed, counter-clockwise positive */
    const double ax = (double)uv[2] - uv[0], ay = (double)uv[3] - uv[1];
    const double bx = (double)uv[4] - uv[0], by = (double)uv[5] - uv[1];
    return 0.5 * (ax * by - ay * bx);
}

static double area_3d(const pgt_mesh *m, uint32_t f) {
    const float *p0 = &m->positions[3u * m->indices[3u * f]];
    const float *p1 = &m->positions[3u * m->indices[3u * f + 1u]];
    const float *p2 = &m->positions[3u * m->indices[3u * f + 2u]];
    double a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = (double)p1[k] - p0[k], b[k] = (double)p2[k] - p0[k];
    const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
                 cz = a[0] * b[1] - a[1] * b[0];
    return 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
}

/* Per face: the signed UV area and the 3D area (independent per face: in parallel). */
typedef struct area_ctx {
    const pgt_mesh *m;
    double *uv, *d3;
} area_ctx;

static void area_range(void *vctx, uint32_t f0, uint32_t f1, uint32_t worker) {
    const area_ctx *a = vctx;
    (void)worker;
    for (uint32_t f = f0; f < f1; ++f) {
        a->uv[f] = uv_area(&a->m->uvs[6u * f]);
        a->d3[f] = area_3d(a->m, f);
    }
}

pgt_result atlas_charts_build(atlas_charts *out, const pgt_mesh *m, uint32_t threads,
                              const char *what, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    const uint32_t F = m->face_count;
    for (uint64_t i = 0; i < 6ull * F; ++i)
        if (!isfinite(m->uvs[i]))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: face %u has a non-finite UV",
                                 what, (uint32_t)(i / 6u));
    pgt_adjacency adj;
    pgt_result r = pgt_adjacency_build(&adj, m, threads, err);
    if (r != PGT_OK) return r;
    uint32_t *parent = malloc(sizeof(uint32_t) * F);
    uint32_t *root_chart = malloc(sizeof(uint32_t) * F);
    double *area = malloc(sizeof(double) * F), *area3 = malloc(sizeof(double) * F);
    out->face_chart = malloc(sizeof(uint32_t) * F);
    out->uvs = malloc(sizeof(float) * 6u * F);
    uint8_t *uv_cut = calloc(3u * (size_t)F, 1); /* per half-edge: see inside_seam */
    if (!parent || !root_chart || !area || !area3 || !out->face_chart || !out->uvs || !uv_cut) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (charts)", what);
        goto done;
    }
    memcpy(out->uvs, m->uvs, sizeof(float) * 6u * F);
    for (uint32_t f = 0; f < F; ++f) parent[f] = f;
    for (uint32_t h = 0; h < 3u * F; ++h) {
        const uint32_t o = adj.opposite[h];
        if (o == PGT_NONE || o < h) continue;
        if (!same_uvs(m->uvs, h, o)) {
            uv_cut[h] = 1;
            continue;
        }
        const uint32_t ra = find_root(parent, h / 3u), rb = find_root(parent, o / 3u);
        if (ra != rb) parent[ra > rb ? ra : rb] = ra < rb ? ra : rb; /* root = smallest face */
    }
    /* Chart ids in order of each chart's smallest face, counting only charts with at least one
     * non-degenerate face. */
    uint32_t charts = 0, degenerate = 0, all_charts = 0;
    area_ctx ac = {m, area, area3};
    pgt_parallel_for(F, threads, area_range, &ac);
    for (uint32_t f = 0; f < F; ++f) root_chart[f] = PGT_NONE;
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t rt = find_root(parent, f);
        if (rt == f) all_charts++;
        if (fabs(area[f]) <= PGT_ATLAS_DEGENERATE_UV_AREA) {
            degenerate++;
            out->face_chart[f] = PGT_NONE;
            continue;
        }
        if (root_chart[rt] == PGT_NONE) {
            if (charts == PGT_ATLAS_MAX_CHARTS) {
                r = pgt_error_set(err, PGT_ERROR_LIMIT, "%s: more than %u UV charts", what,
                                  PGT_ATLAS_MAX_CHARTS);
                goto done;
            }
            root_chart[rt] = charts++;
        }
        out->face_chart[f] = root_chart[rt];
    }
    out->face_count = F;
    out->chart_count = charts;
    out->degenerate_faces = degenerate;
    out->degenerate_charts = all_charts - charts;
    if (charts == 0) {
        r = pgt_error_set(err, PGT_ERROR_EMPTY,
                          "%s: every UV triangle is degenerate (%u of %u have zero UV area)", what,
                          degenerate, F);
        goto done;
    }
    out->chart_mirrored = calloc(charts, 1);
    out->chart_area_uv = calloc(charts, sizeof(double));
    out->chart_area_3d = calloc(charts, sizeof(double));
    double *signed_area = calloc(charts, sizeof(double));
    float *box = malloc(sizeof(float) * 2u * charts); /* umin, umax per chart */
    if (!out->chart_mirrored || !out->chart_area_uv || !out->chart_area_3d || !signed_area ||
        !box) {
        free(signed_area);
        free(box);
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (charts)", what);
        goto done;
    }
    for (uint32_t c = 0; c < charts; ++c) box[2u * c] = INFINITY, box[2u * c + 1u] = -INFINITY;
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t c = out->face_chart[f];
        if (c == PGT_NONE) continue;
        signed_area[c] += area[f];
        out->chart_area_uv[c] += fabs(area[f]);
        out->chart_area_3d[c] += area3[f];
        for (uint32_t k = 0; k < 3; ++k) {
            const float u = m->uvs[6u * f + 2u * k];
            if (u < box[2u * c]) box[2u * c] = u;
            if (u > box[2u * c + 1u]) box[2u * c + 1u] = u;
        }
    }
    for (uint32_t c = 0; c < charts; ++c)
        if (signed_area[c] < 0.0) out->chart_mirrored[c] = 1, out->mirrored++;
    {
        /* the mesh border and the seams inside a chart: counted, then listed */
        uint32_t nb = 0, ns = 0, nc = 0;
        for (uint32_t h = 0; h < 3u * F; ++h) {
            nb += on_border(&adj, out->face_chart, h);
            ns += inside_seam(&adj, out->face_chart, uv_cut, h);
            nc += between_charts(&adj, out->face_chart, h);
        }
        out->border_half_edges = malloc(sizeof(uint32_t) * (nb ? nb : 1u));
        out->seam_half_edges = malloc(sizeof(uint32_t) * 2u * (ns ? ns : 1u));
        out->cross_half_edges = malloc(sizeof(uint32_t) * 2u * (nc ? nc : 1u));
        if (!out->border_half_edges || !out->seam_half_edges || !out->cross_half_edges) {
            free(signed_area);
            free(box);
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (charts)", what);
            goto done;
        }
        for (uint32_t h = 0; h < 3u * F; ++h) {
            if (on_border(&adj, out->face_chart, h))
                out->border_half_edges[out->border_count++] = h;
            if (inside_seam(&adj, out->face_chart, uv_cut, h)) {
                out->seam_half_edges[2u * out->seam_count] = h;
                out->seam_half_edges[2u * out->seam_count++ + 1u] = adj.opposite[h];
            }
            if (between_charts(&adj, out->face_chart, h)) {
                out->cross_half_edges[2u * out->cross_count] = h;
                out->cross_half_edges[2u * out->cross_count++ + 1u] =
                    out->face_chart[adj.opposite[h] / 3u];
            }
        }
    }
    /* Flip mirrored charts in u, degenerate faces of the chart included (they may be
     * rasterized by nobody, but keep the chart's UVs consistent). */
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t c = root_chart[find_root(parent, f)];
        if (c == PGT_NONE || !out->chart_mirrored[c]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            float *u = &out->uvs[6u * f + 2u * k];
            *u = (box[2u * c] + box[2u * c + 1u]) - *u;
        }
    }
    free(signed_area);
    free(box);
done:
    free(uv_cut);
    free(parent);
    free(root_chart);
    free(area);
    free(area3);
    pgt_adjacency_destroy(&adj);
    if (r != PGT_OK) atlas_charts_destroy(out);
    return r;
}
