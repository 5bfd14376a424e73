/* pgt: sqrt(3) subdivision on Vulkan, the host side of shaders/s3_*.comp.
 *
 * A port of ref_cpu/src/sqrt3.c (the specification: Kobbelt 2000, paper 004 Algorithm 2 and
 * 4.2.2) that gives its output element by element. The host validates the input and builds the
 * level-0 adjacency exactly as the reference, then each iteration runs the reference's
 * data-parallel passes on the device:
 *   classify (per face) -> scan (pt_off, face_off and the two totals, the only values read back)
 *   -> vertices (per old vertex) -> faces (per face),
 * classify and scan being skipped on a "uniform" step (offsets f and 3f). Only the general passes
 * are ported; the reference's closed-mesh fast paths produce the same bytes.
 *
 * Storage-buffer bindings are limited (maxStorageBufferRange, 128 MiB on lavapipe). A step's
 * inputs are read at random, so each must fit one binding (PGT_ERROR_LIMIT otherwise), and so
 * must the outputs of every step but the last, which the next step reads. The outputs of the last
 * step may be larger: the vertices and faces passes are then dispatched in ranges of items whose
 * writes fall in one window of each output array, bound at an aligned offset whose first element
 * index goes to the shader in the push constants (s3_pass). */
#include <stdlib.h>
#include <string.h>
#include <stdio.h>

#include "pgt/adjacency.h"
#include "vk_internal.h"

#define S3_G PGT_S3_GROUP_SIZE

/* One level of the subdivision on the device (the flat arrays of sqrt3_layout.h). prot exists
 * when a later step reads it or the caller asked for it, parent when the caller asked for
 * parents or the input has labels, opp and vh when with_adj. */
typedef struct s3_level {
    uint32_t V, F;
    pgt_vk_buf pos, idx, opp, vh, prot, parent;
} s3_level;

static pgt_result s3_level_release(pgt_vk *ctx, s3_level *l, pgt_error *err) {
    pgt_vk_buf *b[6] = {&l->pos, &l->idx, &l->opp, &l->vh, &l->prot, &l->parent};
    pgt_result r = PGT_OK;
    for (int i = 0; i < 6; ++i) {
        pgt_result ri = pgt_vk_buf_release(ctx, b[i], err);
        if (r == PGT_OK) r = ri;
    }
    return r;
}

/* An array that a step reads at random (or the next step will) must fit one binding. */
static pgt_result s3_fits(const pgt_vk *ctx, const char *array, uint32_t level, uint64_t bytes,
                          pgt_error *err) {
    char what[128];
    snprintf(what, sizeof what, "sqrt3 on vulkan: the %s array of level %u", array, level);
    return pgt_vk_fits(ctx, bytes, what, "a step reads it at random", err);
}

/* ---- dispatch in ranges --------------------------------------------------------------------- */

/* One output array of a pass and where each item e of the pass starts writing in it:
 * element per * (add + units(e)), units(e) = table[e] (or e * mul without a table) and
 * units(n) = total, n being the pass's item count. Starts never decrease with e. */
typedef struct s3_out {
    const pgt_vk_buf *buf; /* not written when it has no buffer */
    uint32_t binding;
    uint32_t *base; /* the push-constant field taking the window's first element */
    uint32_t per, add;
    const uint32_t *table;
    uint32_t mul, total;
} s3_out;

static uint64_t s3_out_bytes(const s3_out *o, uint32_t e, uint32_t n) {
    const uint64_t units = e >= n ? o->total : o->table ? o->table[e] : (uint64_t)e * o->mul;
    return 4 * (uint64_t)o->per * ((uint64_t)o->add + units);
}

/* Whether items [e0, e1) write within max_binding bytes of the window starts `from`. */
static int s3_range_fits(const pgt_vk *ctx, const s3_out *outs, uint32_t n_outs,
                         const uint64_t *from, const int *split, uint32_t e1, uint32_t n) {
    for (uint32_t j = 0; j < n_outs; ++j)
        if (split[j] && s3_out_bytes(&outs[j], e1, n) - from[j] > ctx->max_binding) return 0;
    return 1;
}

/* Runs `pipe` over items [0, n): dispatches of at most maxComputeWorkGroupCount groups (whose
 * first item is then a multiple of the group size), cut further where an output array too large
 * for one binding needs a new window. */
static pgt_result s3_pass(pgt_vk *ctx, pgt_vk_pipe pipe, pgt_vk_binding *bind, pgt_vk_s3_push *push,
                          uint32_t n, const s3_out *outs, uint32_t n_outs, pgt_error *err) {
    pgt_result r = PGT_OK;
    enum { MAX_OUTS = 6 };
    uint64_t from[MAX_OUTS];
    int split[MAX_OUTS];
    const uint64_t chunk = (uint64_t)ctx->max_groups * S3_G;
    for (uint32_t j = 0; j < n_outs; ++j) {
        split[j] = outs[j].buf->buf && s3_out_bytes(&outs[j], n, n) > ctx->max_binding;
        *outs[j].base = 0;
        bind[outs[j].binding] = pgt_vk_whole(ctx, outs[j].buf);
    }
    for (uint32_t e0 = 0; e0 < n;) {
        for (uint32_t j = 0; j < n_outs; ++j)
            if (split[j])
                from[j] = s3_out_bytes(&outs[j], e0, n) / ctx->binding_align * ctx->binding_align;
        uint32_t lo = e0 + 1, hi = (uint32_t)(n - e0 < chunk ? n : e0 + chunk), e1;
        if (!s3_range_fits(ctx, outs, n_outs, from, split, lo, n))
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "sqrt3 on vulkan: one item of %s writes more than a binding "
                                 "window of %llu bytes holds",
                                 pgt_vk_pipe_name(pipe), (unsigned long long)ctx->max_binding);
        if (s3_range_fits(ctx, outs, n_outs, from, split, hi, n)) {
            e1 = hi;
        } else { /* the largest e1 that fits, by bisection: lo fits, hi does not */
            while (hi - lo > 1) {
                const uint32_t mid = lo + (hi - lo) / 2;
                if (s3_range_fits(ctx, outs, n_outs, from, split, mid, n))
                    lo = mid;
                else
                    hi = mid;
            }
            e1 = lo;
        }
        for (uint32_t j = 0; j < n_outs; ++j) {
            if (!split[j]) continue;
            const uint64_t end = s3_out_bytes(&outs[j], e1, n);
            pgt_vk_binding *b = &bind[outs[j].binding];
            if (end > from[j]) {
                b->offset = from[j];
                b->range = end - from[j];
                *outs[j].base = (uint32_t)(from[j] / 4);
            } else { /* nothing written here: any valid window */
                b->offset = 0;
                b->range = ctx->max_binding;
                *outs[j].base = 0;
            }
        }
        push->s3.first = e0;
        push->s3.count = e1 - e0;
        PGT_VK_TRY(pgt_vk_dispatch(ctx, pipe, bind, push, sizeof(*push),
                                   (e1 - e0 + S3_G - 1) / S3_G, err));
        e0 = e1;
    }
cleanup:
    return r;
}

/* ---- the scan ------------------------------------------------------------------------------- */

/* Levels of the exclusive scan of F faces: level 0 is the faces (pt_off, face_off), level l >= 1
 * holds the totals of level l - 1's work-groups, in sums[off[l] ...]; the last level has one
 * element, the grand totals. */
#define S3_SCAN_MAX_LEVELS 8
typedef struct s3_scan {
    uint32_t levels; /* above level 0 */
    uint32_t n[S3_SCAN_MAX_LEVELS], off[S3_SCAN_MAX_LEVELS];
} s3_scan;

static void s3_scan_plan(uint32_t F, s3_scan *s) {
    uint32_t l = 0;
    memset(s, 0, sizeof(*s));
    s->n[0] = F;
    do {
        s->n[l + 1] = (s->n[l] + S3_G - 1) / S3_G;
        s->off[l + 1] = l == 0 ? 0 : s->off[l] + s->n[l];
        l++;
    } while (s->n[l] > 1); /* 64^5 > PGT_MESH_MAX_ELEMENTS: at most 5 levels */
    s->levels = l;
}

/* Pass 2: pt_off, face_off and the totals (np, nf) of a non-uniform step, on the device. */
static pgt_result s3_scan_run(pgt_vk *ctx, pgt_vk_binding *bind, pgt_vk_s3_push *push,
                              const s3_scan *s, pgt_error *err) {
    pgt_result r = PGT_OK;
    for (uint32_t l = 0; l < s->levels; ++l) { /* work-group scans, bottom up */
        push->scan_level = l;
        push->scan_in = s->off[l];
        push->scan_out = s->off[l + 1];
        PGT_VK_TRY(s3_pass(ctx, PGT_VK_PIPE_S3_SCAN_LOCAL, bind, push, s->n[l], NULL, 0, err));
    }
    for (uint32_t l = s->levels - 1; l-- > 0;) { /* add the groups' offsets, top down */
        push->scan_level = l;
        push->scan_in = s->off[l];
        push->scan_out = s->off[l + 1];
        PGT_VK_TRY(s3_pass(ctx, PGT_VK_PIPE_S3_SCAN_ADD, bind, push, s->n[l], NULL, 0, err));
    }
cleanup:
    return r;
}

/* ---- the iterations ------------------------------------------------------------------------- */

/* Everything a call holds, released in one place. */
typedef struct s3_call {
    s3_level cur, nx;
    pgt_vk_buf alpha, kind, bslot, pt_off, face_off, sums, fault;
    uint32_t *host;              /* level-0 arrays on their way up, the last level's down */
    uint32_t *pt_tab, *face_tab; /* host copies of pt_off and face_off, for split outputs */
} s3_call;

static void s3_call_release(pgt_vk *ctx, s3_call *c) {
    pgt_vk_buf *b[7] = {&c->alpha,    &c->kind, &c->bslot, &c->pt_off,
                        &c->face_off, &c->sums, &c->fault};
    s3_level_release(ctx, &c->cur, NULL);
    s3_level_release(ctx, &c->nx, NULL);
    for (int i = 0; i < 7; ++i) pgt_vk_buf_release(ctx, b[i], NULL);
    free(c->host), free(c->pt_tab), free(c->face_tab);
    c->host = c->pt_tab = c->face_tab = NULL;
}

/* The fault buffer after the last step: a fan walk that stopped at the bound (lavapipe's loop
 * limit, s3_vk_layout.h) made the output wrong, so the call is refused, naming the first. Later
 * steps still ran: a stopped walk leaves every index it produced in range, and the topology
 * (triangles, opposites, the sizes of the levels) never depends on a walk. */
static pgt_result s3_check_walks(pgt_vk *ctx, const pgt_vk_buf *fault, pgt_error *err) {
    uint32_t f[PGT_VK_FAULT_WORDS];
    const pgt_result r = pgt_vk_download(ctx, fault, 0, sizeof(f), f, err);
    if (r != PGT_OK || f[PGT_VK_FAULT_CODE] == 0) return r;
    const uint32_t level = (f[PGT_VK_FAULT_CODE] - 1) / 2;
    const int faces = (f[PGT_VK_FAULT_CODE] - 1) % 2;
    const int lavapipe = ctx->s3_walk == PGT_VK_S3_WALK_LAVAPIPE;
    return pgt_error_set(err, PGT_ERROR_LIMIT,
                         "sqrt3 on vulkan: %s %u of level %u (the input of iteration %u) walks a "
                         "fan of more than %u half-edges, %s; use --backend cl or cpu",
                         faces ? "border face" : "vertex", f[PGT_VK_FAULT_ELEMENT], level,
                         level + 1, ctx->s3_walk,
                         lavapipe ? "more than lavapipe runs correctly (its shader loops stop "
                                    "after 65535 iterations in all)"
                                  : "the bound PGT_VK_S3_WALK sets");
}

/* k >= 1 iterations of a validated input with its adjacency. */
static pgt_result s3_device(pgt_vk *ctx, s3_call *c, pgt_mesh *out, const pgt_mesh *in,
                            const pgt_sqrt3_options *opts, const pgt_gpu_sqrt3_input *prep,
                            pgt_gpu_times *times, pgt_error *err) {
    pgt_result r = PGT_OK;
    const uint32_t k = opts->iterations, V0 = in->vertex_count, F0 = in->face_count;
    const int want_parent = opts->out_face_parent || in->labels;
    const pgt_adjacency *adj = &prep->adj;
    const uint32_t n_protected = prep->n_protected, alpha_count = prep->alpha_count;
    uint32_t border = adj->border_half_edges;

    /* ---- level 0 on the host: vh, prot, the alpha table ---- */
    const size_t host_n = (V0 > F0 ? V0 : F0) + 1;
    c->host = malloc(host_n * sizeof(uint32_t));
    if (!c->host) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");

    const double t_up = pgt_gpu_now_ms();
    c->cur.V = V0, c->cur.F = F0;
    PGT_VK_TRY(s3_fits(ctx, "positions", 0, 12 * (uint64_t)V0, err));
    PGT_VK_TRY(s3_fits(ctx, "triangles", 0, 12 * (uint64_t)F0, err));
    PGT_VK_TRY(s3_fits(ctx, "alpha", 0, 4 * (uint64_t)alpha_count, err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->cur.pos, 12 * (uint64_t)V0, "positions", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->cur.idx, 12 * (uint64_t)F0, "triangles", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->cur.opp, 12 * (uint64_t)F0, "opposites", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->cur.vh, 4 * (uint64_t)V0, "vertex half-edges", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->cur.prot, 4 * (uint64_t)F0, "protected flags", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->alpha, 4 * (uint64_t)alpha_count, "alpha", err));
    PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->fault, 4 * PGT_VK_FAULT_WORDS, "fault", err));
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->cur.pos, in->positions, 12 * (size_t)V0, err));
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->cur.idx, in->indices, 12 * (size_t)F0, err));
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->cur.opp, adj->opposite, 12 * (size_t)F0, err));
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->cur.vh, prep->vh, 4 * (size_t)V0, err));
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->cur.prot, prep->prot, 4 * (size_t)F0, err));
    PGT_VK_TRY(
        pgt_vk_upload(ctx, &c->alpha, prep->alpha, (size_t)alpha_count * sizeof(float), err));
    const uint32_t no_fault[PGT_VK_FAULT_WORDS] = {0, PGT_GPU_NONE};
    PGT_VK_TRY(pgt_vk_upload(ctx, &c->fault, no_fault, sizeof(no_fault), err));
    PGT_VK_TRY(pgt_vk_flush(ctx, err));
    if (times) times->upload_ms += pgt_gpu_now_ms() - t_up;

    for (uint32_t it = 0; it < k; ++it) {
        s3_level *cur = &c->cur, *nx = &c->nx;
        const int last = it + 1 == k;
        pgt_vk_s3_push push;
        memset(&push, 0, sizeof(push));
        push.s3.V = cur->V;
        push.s3.F = cur->F;
        push.s3.even = (it % 2) == 1; /* CGAL: refine_border on i % 2 == 1, per call */
        /* Uniform is known without classifying: no protected face (they stay protected), and
         * no border face to trisect. */
        push.s3.is_uniform = n_protected == 0 && (!push.s3.even || border == 0);
        push.s3.with_adj = !last || opts->out_opposite != NULL;
        push.s3.alpha_count = alpha_count;
        push.walk_budget = ctx->s3_walk;
        push.level = it;
        push.parent_mode = !want_parent ? PGT_VK_PARENT_NONE
                           : it == 0    ? PGT_VK_PARENT_IDENTITY
                                        : PGT_VK_PARENT_READ;

        pgt_vk_binding bind[PGT_VK_S3_BINDINGS];
        memset(bind, 0, sizeof(bind));
        bind[PGT_VK_B_POS_IN] = pgt_vk_whole(ctx, &cur->pos);
        bind[PGT_VK_B_IDX_IN] = pgt_vk_whole(ctx, &cur->idx);
        bind[PGT_VK_B_OPP_IN] = pgt_vk_whole(ctx, &cur->opp);
        bind[PGT_VK_B_VH_IN] = pgt_vk_whole(ctx, &cur->vh);
        bind[PGT_VK_B_PROT_IN] = pgt_vk_whole(ctx, &cur->prot);
        bind[PGT_VK_B_PARENT_IN] = pgt_vk_whole(ctx, &cur->parent);
        bind[PGT_VK_B_ALPHA] = pgt_vk_whole(ctx, &c->alpha);
        bind[PGT_VK_B_FAULT] = pgt_vk_whole(ctx, &c->fault);

        /* ---- passes 1 and 2: classify and scan, then the output's size ---- */
        uint32_t np = cur->F, nf = 3 * cur->F; /* uniform: one point, three triangles a face */
        if (!push.s3.is_uniform) {
            np = nf = 0;
            if (cur->F) {
                s3_scan scan;
                s3_scan_plan(cur->F, &scan);
                const uint64_t per_face = 4 * (uint64_t)cur->F;
                const uint64_t sums = 8 * ((uint64_t)scan.off[scan.levels] + 1);
                PGT_VK_TRY(s3_fits(ctx, "scan", it, sums, err));
                PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->kind, per_face, "face kinds", err));
                PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->bslot, per_face, "border slots", err));
                PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->pt_off, per_face, "point offsets", err));
                PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->face_off, per_face, "face offsets", err));
                PGT_VK_TRY(pgt_vk_buf_create(ctx, &c->sums, sums, "scan sums", err));
                bind[PGT_VK_B_KIND] = pgt_vk_whole(ctx, &c->kind);
                bind[PGT_VK_B_BSLOT] = pgt_vk_whole(ctx, &c->bslot);
                bind[PGT_VK_B_PT_OFF] = pgt_vk_whole(ctx, &c->pt_off);
                bind[PGT_VK_B_FACE_OFF] = pgt_vk_whole(ctx, &c->face_off);
                bind[PGT_VK_B_SUMS] = pgt_vk_whole(ctx, &c->sums);
                PGT_VK_TRY(
                    s3_pass(ctx, PGT_VK_PIPE_S3_CLASSIFY, bind, &push, cur->F, NULL, 0, err));
                PGT_VK_TRY(s3_scan_run(ctx, bind, &push, &scan, err));
                uint32_t totals[2];
                PGT_VK_TRY(pgt_vk_download(ctx, &c->sums, 8 * (VkDeviceSize)scan.off[scan.levels],
                                           sizeof(totals), totals, err));
                np = totals[0], nf = totals[1];
            }
        }

        /* ---- the next level's arrays ---- */
        nx->V = cur->V + np, nx->F = nf;
        const int want_prot = push.s3.with_adj || opts->out_protected;
        const uint64_t pos_bytes = 12 * (uint64_t)nx->V, tri_bytes = 12 * (uint64_t)nx->F;
        const uint64_t vert_bytes = 4 * (uint64_t)nx->V, face_bytes = 4 * (uint64_t)nx->F;
        if (!last) { /* the next step reads them at random */
            PGT_VK_TRY(s3_fits(ctx, "positions", it + 1, pos_bytes, err));
            PGT_VK_TRY(s3_fits(ctx, "triangles", it + 1, tri_bytes, err));
        }
        PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->pos, pos_bytes, "positions", err));
        PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->idx, tri_bytes, "triangles", err));
        if (push.s3.with_adj) {
            PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->opp, tri_bytes, "opposites", err));
            PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->vh, vert_bytes, "vertex half-edges", err));
        }
        if (want_prot)
            PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->prot, face_bytes, "protected flags", err));
        if (want_parent)
            PGT_VK_TRY(pgt_vk_buf_create(ctx, &nx->parent, face_bytes, "parents", err));
        push.write_prot = want_prot;

        /* ---- passes 3 and 4 ---- */
        const s3_out vouts[2] = {
            {&nx->pos, PGT_VK_B_POS_OUT, &push.pos_base, 3, 0, NULL, 1, cur->V},
            {&nx->vh, PGT_VK_B_VH_OUT, &push.vh_base, 1, 0, NULL, 1, cur->V},
        };
        PGT_VK_TRY(s3_pass(ctx, PGT_VK_PIPE_S3_VERTICES, bind, &push, cur->V, vouts, 2, err));
        s3_out fouts[6] = {
            {&nx->pos, PGT_VK_B_POS_OUT, &push.pos_base, 3, cur->V, NULL, 1, np},
            {&nx->vh, PGT_VK_B_VH_OUT, &push.vh_base, 1, cur->V, NULL, 1, np},
            {&nx->idx, PGT_VK_B_IDX_OUT, &push.idx_base, 3, 0, NULL, 3, nf},
            {&nx->opp, PGT_VK_B_OPP_OUT, &push.opp_base, 3, 0, NULL, 3, nf},
            {&nx->prot, PGT_VK_B_PROT_OUT, &push.prot_base, 1, 0, NULL, 3, nf},
            {&nx->parent, PGT_VK_B_PARENT_OUT, &push.parent_base, 1, 0, NULL, 3, nf},
        };
        if (!push.s3.is_uniform && cur->F &&
            (pos_bytes > ctx->max_binding || tri_bytes > ctx->max_binding)) {
            /* split outputs of a non-uniform step: the host needs the offsets to cut ranges */
            c->pt_tab = malloc((size_t)cur->F * sizeof(uint32_t));
            c->face_tab = malloc((size_t)cur->F * sizeof(uint32_t));
            if (!c->pt_tab || !c->face_tab) {
                r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
                goto cleanup;
            }
            PGT_VK_TRY(pgt_vk_download(ctx, &c->pt_off, 0, 4 * (size_t)cur->F, c->pt_tab, err));
            PGT_VK_TRY(pgt_vk_download(ctx, &c->face_off, 0, 4 * (size_t)cur->F, c->face_tab, err));
            for (int j = 0; j < 2; ++j) fouts[j].table = c->pt_tab;
            for (int j = 2; j < 6; ++j) fouts[j].table = c->face_tab;
        }
        PGT_VK_TRY(s3_pass(ctx, PGT_VK_PIPE_S3_FACES, bind, &push, cur->F, fouts, 6, err));
        free(c->pt_tab), free(c->face_tab);
        c->pt_tab = c->face_tab = NULL;

        /* the input level and the scratch go once the batch has run */
        PGT_VK_TRY(s3_level_release(ctx, cur, err));
        PGT_VK_TRY(pgt_vk_buf_release(ctx, &c->kind, err));
        PGT_VK_TRY(pgt_vk_buf_release(ctx, &c->bslot, err));
        PGT_VK_TRY(pgt_vk_buf_release(ctx, &c->pt_off, err));
        PGT_VK_TRY(pgt_vk_buf_release(ctx, &c->face_off, err));
        PGT_VK_TRY(pgt_vk_buf_release(ctx, &c->sums, err));
        if (push.s3.even) border *= 3; /* every border edge was trisected */
        *cur = *nx;
        memset(nx, 0, sizeof(*nx));
    }
    PGT_VK_TRY(pgt_vk_flush(ctx, err));
    PGT_VK_TRY(s3_check_walks(ctx, &c->fault, err));

    /* ---- the last level down to the host ---- */
    const double t_down = pgt_gpu_now_ms();
    const s3_level *l = &c->cur;
    PGT_VK_TRY(pgt_mesh_create(out, l->V, l->F, 0, in->labels != NULL, err));
    PGT_VK_TRY(pgt_vk_download(ctx, &l->pos, 0, 12 * (size_t)l->V, out->positions, err));
    PGT_VK_TRY(pgt_vk_download(ctx, &l->idx, 0, 12 * (size_t)l->F, out->indices, err));
    if (opts->out_opposite)
        PGT_VK_TRY(pgt_vk_download(ctx, &l->opp, 0, 12 * (size_t)l->F, opts->out_opposite, err));
    if (opts->out_protected || (want_parent && !opts->out_face_parent)) {
        free(c->host);
        c->host = malloc(((size_t)l->F + 1) * sizeof(uint32_t));
        if (!c->host) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
            goto cleanup;
        }
    }
    if (opts->out_protected) {
        PGT_VK_TRY(pgt_vk_download(ctx, &l->prot, 0, 4 * (size_t)l->F, c->host, err));
        for (uint32_t f = 0; f < l->F; ++f) opts->out_protected[f] = (uint8_t)c->host[f];
    }
    if (want_parent) {
        uint32_t *parent = opts->out_face_parent ? opts->out_face_parent : c->host;
        PGT_VK_TRY(pgt_vk_download(ctx, &l->parent, 0, 4 * (size_t)l->F, parent, err));
        if (in->labels)
            for (uint32_t f = 0; f < l->F; ++f) out->labels[f] = in->labels[parent[f]];
    }
    if (times) times->download_ms += pgt_gpu_now_ms() - t_down;
cleanup:
    return r;
}

pgt_result pgt_vk_sqrt3(pgt_vk *ctx, pgt_mesh *out, const pgt_mesh *in_mesh,
                        const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err) {
    pgt_sqrt3_options defaults = {1, 1, NULL, NULL, NULL, NULL, NULL};
    if (!opts) opts = &defaults;
    if (times) memset(times, 0, sizeof(*times));
    memset(out, 0, sizeof(*out));
    if (!ctx) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "sqrt3 on vulkan: no context");
    /* the reference's checks and level-0 arrays (gpu_shared/host.c), shared by every backend */
    pgt_gpu_sqrt3_input prep;
    pgt_result r = pgt_gpu_sqrt3_prepare(&prep, in_mesh, opts, err);
    if (r != PGT_OK) return r;
    const uint32_t k = opts->iterations;

    pgt_vk_call_begin(ctx);
    ctx->batch_ms = 0.0;
    if (k == 0) { /* a copy, as the reference */
        r = pgt_gpu_sqrt3_copy(out, in_mesh, opts, &prep.adj, err);
    } else {
        s3_call c;
        memset(&c, 0, sizeof(c));
        r = s3_device(ctx, &c, out, in_mesh, opts, &prep, times, err);
        if (r != PGT_OK) pgt_vk_abandon(ctx);
        s3_call_release(ctx, &c);
    }
    pgt_gpu_sqrt3_input_free(&prep);
    r = pgt_vk_call_end(ctx, "pgt_vk_sqrt3", r, err);
    if (r != PGT_OK) {
        pgt_mesh_destroy(out);
        if (times) memset(times, 0, sizeof(*times));
        return r;
    }
    if (times) times->device_ms = ctx->queries ? ctx->batch_ms : 0.0;
    return PGT_OK;
}
