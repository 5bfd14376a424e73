/* pgt: opposite half-edge array and 2-manifold checks.
 *
 * Half-edges are bucketed by source vertex (a counting sort, CSR), then each half-edge a->b looks
 * for a->b among a's outgoing half-edges and for b->a among b's: a scan of a short bucket, a
 * bisection of a long one (sorted by destination first): O(half-edges x min(valence, log
 * valence)), no hashing, deterministic. (Scans alone were O(half-edges x valence): a
 * 300,000-gon, fan-triangulated, took 38 s, 100,000 copies of one triangle 80 s.) */
#include "pgt/adjacency.h"

#include <stdlib.h>
#include <string.h>

#include "pgt/parallel.h"

/* Outgoing half-edge of a vertex with its destination, packed so a scan reads one cache line. */
typedef struct adj_out {
    uint32_t dst, h;
} adj_out;

typedef struct adj_ctx {
    const uint32_t *idx;
    const uint32_t *start; /* V + 1 */
    /* half-edges bucketed by source: ascending h within a bucket of up to ADJ_SCAN_MAX, sorted
     * by (dst, h) within a longer one */
    adj_out *list;
    const uint32_t *first; /* per vertex: its smallest outgoing half-edge */
    const uint8_t *degenerate;
    uint32_t *opposite;
    uint8_t *bad; /* per half-edge: part of a non-manifold edge; per vertex: more than one fan */
} adj_ctx;

static uint32_t dst_of(const uint32_t *idx, uint32_t h) { return idx[pgt_half_edge_next(h)]; }

/* Buckets up to this size (most vertices have valence 4 to 8) are scanned as they are; longer
 * ones are sorted by (dst, h) and bisected. */
#define ADJ_SCAN_MAX 16u

static int out_cmp(const void *pa, const void *pb) {
    const adj_out *x = pa, *y = pb;
    if (x->dst != y->dst) return x->dst < y->dst ? -1 : 1;
    return x->h < y->h ? -1 : x->h > y->h;
}

static void adj_sort_range(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    adj_ctx *c = p;
    (void)worker;
    for (uint32_t v = begin; v < end; ++v) {
        const uint32_t n = c->start[v + 1] - c->start[v];
        if (n > ADJ_SCAN_MAX) qsort(c->list + c->start[v], n, sizeof(adj_out), out_cmp);
    }
}

/* The first half-edge v->d of a long bucket (sorted by dst): its index in list. */
static uint32_t lower_bound(const adj_ctx *c, uint32_t v, uint32_t d) {
    uint32_t l = c->start[v], r = c->start[v + 1];
    while (l < r) {
        const uint32_t m = l + (r - l) / 2u;
        if (c->list[m].dst < d)
            l = m + 1u;
        else
            r = m;
    }
    return l;
}

/* The half-edges v->d: how many (returned), and one of them (*one; the only one when the count
 * is 1). */
static inline uint32_t count_out(const adj_ctx *c, uint32_t v, uint32_t d, uint32_t *one) {
    const uint32_t l = c->start[v], r = c->start[v + 1];
    uint32_t n = 0;
    if (r - l <= ADJ_SCAN_MAX) {
        for (uint32_t i = l; i < r; ++i)
            if (c->list[i].dst == d) n++, *one = c->list[i].h;
        return n;
    }
    for (uint32_t i = lower_bound(c, v, d); i < r && c->list[i].dst == d; ++i)
        n++, *one = c->list[i].h;
    return n;
}

/* The smallest half-edge v->d (PGT_NONE for none). */
static uint32_t min_out(const adj_ctx *c, uint32_t v, uint32_t d) {
    const uint32_t l = c->start[v], r = c->start[v + 1];
    if (r - l <= ADJ_SCAN_MAX) { /* ascending h: the first found */
        for (uint32_t i = l; i < r; ++i)
            if (c->list[i].dst == d) return c->list[i].h;
        return PGT_NONE;
    }
    const uint32_t i = lower_bound(c, v, d); /* (dst, h) order: the first of dst d */
    return i < r && c->list[i].dst == d ? c->list[i].h : PGT_NONE;
}

static void adj_pair_range(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    adj_ctx *c = p;
    (void)worker;
    for (uint32_t h = begin; h < end; ++h) {
        c->opposite[h] = PGT_NONE;
        c->bad[h] = 0;
        if (c->degenerate[h / 3]) continue;
        const uint32_t a = c->idx[h], b = dst_of(c->idx, h);
        uint32_t any_same, found = PGT_NONE;
        const uint32_t same = count_out(c, a, b, &any_same), opp = count_out(c, b, a, &found);
        if (same == 1 && opp <= 1)
            c->opposite[h] = found;
        else
            c->bad[h] = 1;
    }
}

/* A vertex is manifold when one walk around its fan meets all its outgoing half-edges. */
static void adj_vertex_range(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    adj_ctx *c = p;
    uint8_t *bad_vertex = c->bad;
    (void)worker;
    for (uint32_t v = begin; v < end; ++v) {
        uint32_t n = c->start[v + 1] - c->start[v];
        bad_vertex[v] = 0;
        if (n == 0) continue;
        uint32_t h0 = c->first[v], h = h0, steps = 0;
        for (;;) { /* backward to the fan start (a border half-edge) or all the way round */
            uint32_t o = c->opposite[h];
            if (o == PGT_NONE) break;
            uint32_t hp = pgt_half_edge_next(o);
            if (hp == h0 || ++steps > n) break;
            h = hp;
        }
        uint32_t first = h, count = 0;
        for (;;) {
            count++;
            uint32_t o = c->opposite[pgt_half_edge_prev(h)];
            if (o == PGT_NONE || o == first || count > n) break;
            h = o;
        }
        bad_vertex[v] = count != n;
    }
}

pgt_result pgt_adjacency_build(pgt_adjacency *out, const pgt_mesh *mesh, uint32_t threads,
                               pgt_error *err) {
    memset(out, 0, sizeof(*out));
    out->bad_edge[0] = out->bad_edge[1] = out->bad_vertex = out->bad_face = PGT_NONE;
    out->bad_edge_face = out->bad_vertex_face = PGT_NONE;
    out->bad_pair_face[0] = out->bad_pair_face[1] = PGT_NONE;
    if (!mesh || (mesh->face_count && (!mesh->indices || !mesh->positions)))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "adjacency: no mesh");
    const uint32_t V = mesh->vertex_count, F = mesh->face_count, H = 3 * F;
    const uint32_t *idx = mesh->indices;
    for (uint32_t i = 0; i < H; ++i)
        if (idx[i] >= V)
            return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                 "adjacency: face %u uses vertex %u of %u", i / 3, idx[i], V);

    uint32_t *start = calloc((size_t)V + 2, sizeof(uint32_t));
    adj_out *list = malloc(((size_t)H + 1) * sizeof(adj_out));
    uint8_t *degenerate = calloc((size_t)F + 1, 1);
    uint8_t *bad = malloc((size_t)(H > V ? H : V) + 1);
    uint32_t *fill = malloc(((size_t)V + 1) * sizeof(uint32_t));
    uint32_t *first = malloc(((size_t)V + 1) * sizeof(uint32_t));
    out->opposite = malloc(((size_t)H + 1) * sizeof(uint32_t));
    if (!start || !list || !degenerate || !bad || !fill || !first || !out->opposite) {
        free(start), free(list), free(degenerate), free(bad), free(fill), free(first);
        pgt_adjacency_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "adjacency: out of memory (%u faces)",
                             F);
    }
    out->half_edge_count = H;

    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t *t = idx + 3 * (size_t)f;
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
            degenerate[f] = 1;
            if (out->degenerate_faces++ == 0) out->bad_face = f;
        }
    }
    for (uint32_t h = 0; h < H; ++h) start[idx[h] + 1]++;
    for (uint32_t v = 0; v < V; ++v) start[v + 1] += start[v];
    memcpy(fill, start, (size_t)V * sizeof(uint32_t));
    for (uint32_t h = 0; h < H; ++h) list[fill[idx[h]]++] = (adj_out){dst_of(idx, h), h};
    for (uint32_t v = 0; v < V; ++v)
        first[v] = start[v] < start[v + 1] ? list[start[v]].h : PGT_NONE;

    adj_ctx ctx = {idx, start, list, first, degenerate, out->opposite, bad};
    pgt_parallel_for(V, threads, adj_sort_range, &ctx);
    pgt_parallel_for(H, threads, adj_pair_range, &ctx);

    for (uint32_t h = 0; h < H; ++h) {
        if (bad[h]) {
            /* count each bad undirected edge once: at its smallest half-edge */
            const uint32_t a = idx[h], b = dst_of(idx, h);
            uint32_t lo = h, m;
            if ((m = min_out(&ctx, a, b)) < lo) lo = m;
            if ((m = min_out(&ctx, b, a)) < lo) lo = m;
            if (lo == h && out->non_manifold_edges++ == 0) {
                out->bad_edge[0] = a < b ? a : b;
                out->bad_edge[1] = a < b ? b : a;
                out->bad_edge_face = h / 3u; /* h is the edge's smallest half-edge */
            }
        } else if (out->opposite[h] == PGT_NONE && !degenerate[h / 3]) {
            out->border_half_edges++;
        }
    }

    pgt_parallel_for(V, threads, adj_vertex_range, &ctx); /* reuses bad[] per vertex */
    for (uint32_t v = 0; v < V; ++v)
        if (bad[v] && out->non_manifold_vertices++ == 0) {
            out->bad_vertex = v;
            out->bad_vertex_face = first[v] / 3u;
        }
    /* two of a face's edges to one face (a triangle on both sides) */
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t *o = out->opposite + 3 * (size_t)f;
        const uint32_t n0 = o[0] == PGT_NONE ? PGT_NONE : o[0] / 3u,
                       n1 = o[1] == PGT_NONE ? PGT_NONE : o[1] / 3u,
                       n2 = o[2] == PGT_NONE ? PGT_NONE : o[2] / 3u;
        const uint32_t twice = n0 != PGT_NONE && (n0 == n1 || n0 == n2) ? n0
                               : n1 != PGT_NONE && n1 == n2             ? n1
                                                                        : PGT_NONE;
        if (twice != PGT_NONE && out->double_neighbour_faces++ == 0)
            out->bad_pair_face[0] = f, out->bad_pair_face[1] = twice;
    }

    free(start), free(list), free(degenerate), free(bad), free(fill), free(first);
    return PGT_OK;
}

void pgt_adjacency_destroy(pgt_adjacency *adj) {
    if (!adj) return;
    free(adj->opposite);
    memset(adj, 0, sizeof(*adj));
}

pgt_result pgt_adjacency_require_manifold(const pgt_adjacency *adj, const char *what,
                                          pgt_error *err) {
    if (!what) what = "input";
    if (adj->degenerate_faces)
        return pgt_error_set(err, PGT_ERROR_DEGENERATE,
                             "%s: face %u (0-based) repeats a vertex (%u degenerate faces)", what,
                             adj->bad_face, adj->degenerate_faces);
    if (adj->non_manifold_edges)
        return pgt_error_set(err, PGT_ERROR_NON_MANIFOLD,
                             "%s: non-manifold edge (%u, %u) (0-based vertices): more than two "
                             "faces or inconsistent orientation (%u such edges)",
                             what, adj->bad_edge[0], adj->bad_edge[1], adj->non_manifold_edges);
    if (adj->non_manifold_vertices)
        return pgt_error_set(err, PGT_ERROR_NON_MANIFOLD,
                             "%s: non-manifold vertex %u (0-based): its faces form more than one "
                             "fan (%u such vertices)",
                             what, adj->bad_vertex, adj->non_manifold_vertices);
    if (adj->double_neighbour_faces)
        return pgt_error_set(err, PGT_ERROR_NON_MANIFOLD,
                             "%s: faces %u and %u (0-based) share two edges (one triangle on both "
                             "sides): sqrt(3) would flip them into one edge (%u such faces)",
                             what, adj->bad_pair_face[0], adj->bad_pair_face[1],
                             adj->double_neighbour_faces);
    return PGT_OK;
}

uint32_t pgt_adjacency_error_face(const pgt_adjacency *adj) {
    if (adj->degenerate_faces) return adj->bad_face;
    if (adj->non_manifold_edges) return adj->bad_edge_face;
    if (adj->non_manifold_vertices) return adj->bad_vertex_face;
    if (adj->double_neighbour_faces) return adj->bad_pair_face[0];
    return PGT_NONE;
}
