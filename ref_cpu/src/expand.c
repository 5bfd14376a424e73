/* pgt: the per-seed rule expander (expand.h).
 *
 * This work is based on:
 *   Paper 000, sec. 5 (the marching rule), sec. 6 (depth first, TopSucc before ExtrudedSucc),
 *   sec. 8 (candidate directions in the 2D semicircle when the condition fails).
 *
 * One seed is one job: an explicit stack of work items (sequence, next item, state, frame) and
 * growable arrays of points and terminals (AoS, scattered into the output's SoA arrays in seed
 * order at the end). Seeds share nothing but the read-only inputs. */
#include "pgt/expand.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/parallel.h"
#include "pgt/terminals.h"

/* Work per seed for pgt_parallel_for_items: a seed is hundreds to thousands of march steps, so
 * every seed is its own block. */
#define EXPAND_SEED_WEIGHT 4096u

typedef struct xwork {
    uint32_t seq, pos; /* run sequences[seq] from item pos */
    uint32_t point;    /* current point (seed-local) */
    uint32_t segment;  /* extrusion segment (seed-local end point) or PGT_NONE */
    float dx, dy;      /* current direction */
    /* the marcher's memory of the last jump (pgt_march_state), carried from step to step */
    uint32_t from, bounces;
    float in_dx, in_dy;
    uint32_t argc;
    float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
} xwork;

typedef struct xpoint {
    float p[3], n[3], u, v;
    uint32_t chart, parent, branch, children;
    uint32_t leaves; /* Leaves records on the segment that ends here */
} xpoint;

typedef struct xterm {
    uint32_t segment, kind, smoothness;
    float a, b;
} xterm;

/* One seed's result. */
typedef struct xseed {
    xpoint *points;
    uint32_t point_count, point_cap;
    xterm *terms;
    uint32_t term_count, term_cap;
    uint32_t branch_count;
    uint64_t stopped, rejected, candidates, dropped, counter;
    pgt_error err;
} xseed;

typedef struct xjob {
    const pgt_expand_input *in;
    pgt_march_options march;
    uint32_t max_points, max_depth, max_terminals, max_items, candidates, stream;
    uint64_t max_total_items; /* when max_items is its share: the total, else 0 */
    float cand_angle[PGT_EXPAND_MAX_CANDIDATES];
    xseed *seeds;
    /* The lowest index of a seed that failed so far (UINT32_MAX: none). pgt_expand reports the
     * lowest failing seed's error, so a seed above it has nothing left to tell: it is skipped,
     * or stopped within EXPAND_CHECK_ITEMS items (a runaway grammar fails on every seed, each
     * after max_items items: 16 seeds took 6x as long as one to give the same error). */
    atomic_uint *first_failed;
    pgt_progress *progress;
} xjob;

/* Items a seed runs between looks at xjob.first_failed (a relaxed atomic load). */
#define EXPAND_CHECK_ITEMS 65536u

/* The context planes and their size (pgt_grammar_context_fn's data). */
typedef struct xcontext {
    const float *plane[PGT_GRAMMAR_CONTEXT_COUNT];
    uint32_t w, h;
} xcontext;

static float context_read(void *data, uint32_t id, float u, float v) {
    const xcontext *c = data;
    if (id >= PGT_GRAMMAR_CONTEXT_COUNT || !c->plane[id]) return 0.0f;
    if (!(u >= 0.0f && v >= 0.0f && u < (float)c->w && v < (float)c->h)) return 0.0f;
    return c->plane[id][(size_t)(uint32_t)v * c->w + (uint32_t)u];
}

/* The grammar condition of a Marching, evaluated by pgt_march_step at each destination. */
typedef struct xcond {
    const pgt_grammar *g;
    uint32_t expr;
    const xwork *w;
    pgt_grammar_env env;
    pgt_result status;
    int rejected; /* the last evaluation gave 0 */
    pgt_error err;
} xcond;

static int cond_eval(void *ctx, float x, float y, uint32_t chart) {
    xcond *c = ctx;
    (void)chart;
    c->env.u = x, c->env.v = y;
    float val = 0.0f;
    const pgt_result r =
        pgt_grammar_eval(c->g, c->expr, c->w->args, c->w->argc, &c->env, &val, &c->err);
    if (r != PGT_OK) c->status = r;
    c->rejected = r == PGT_OK && val == 0.0f;
    return r == PGT_OK && val != 0.0f;
}

/* The atlas's N at (x, y), interpolated as pgt_march_position interpolates P (bilinear over the
 * four texel centres around it that carry the containing texel's code), made unit. */
static void normal_at(const pgt_march_atlas *a, const float *const N[3], float x, float y,
                      float out[3]) {
    const int i0 = (int)(x + 0.5f) - 1, j0 = (int)(y + 0.5f) - 1;
    const float fx = x - 0.5f - (float)i0, fy = y - 0.5f - (float)j0;
    const float wx[2] = {1.0f - fx, fx}, wy[2] = {1.0f - fy, fy};
    const uint32_t code = a->codes[(size_t)(uint32_t)y * a->width + (uint32_t)x];
    float n[3] = {0.0f, 0.0f, 0.0f};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int xi = i0 + i, yj = j0 + j;
            if (xi < 0 || yj < 0 || xi >= (int)a->width || yj >= (int)a->height) continue;
            const size_t t = (size_t)(uint32_t)yj * a->width + (uint32_t)xi;
            if (a->codes[t] != code) continue;
            for (int k = 0; k < 3; ++k) n[k] += wx[i] * wy[j] * N[k][t];
        }
    const float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) out[k] = len > 0.0f ? n[k] / len : 0.0f;
}

static const char *file_of(const pgt_grammar *g) { return g->names + g->file_name; }

/* Grows *p (count elements of size, capacity *cap) for one more. */
static int grow(void **p, uint32_t count, uint32_t *cap, size_t size) {
    if (count < *cap) return 1;
    if (*cap == UINT32_MAX) return 0; /* no index left to grow to */
    const uint32_t ncap = *cap ? (*cap > UINT32_MAX / 2 ? UINT32_MAX : *cap * 2) : 64u;
    void *np = realloc(*p, (size_t)ncap * size);
    if (!np) return 0;
    *p = np, *cap = ncap;
    return 1;
}

/* One seed's expansion state. */
typedef struct xrun {
    const xjob *job;
    const pgt_grammar *g;
    xseed *out;
    uint32_t index, id; /* seed index and seed id */
    xwork *stack;
    uint32_t depth, cap;
    uint32_t items; /* grammar items run (max_items) */
    xcontext ctx;
    pgt_grammar_env env;
} xrun;

static pgt_result limit(xrun *r, const pgt_grammar_item *it, const char *what, uint32_t bound,
                        const char *option) {
    return pgt_error_set(&r->out->err, PGT_ERROR_LIMIT,
                         "%s:%u:%u: seed %u (id %u): more than %u %s (option %s); the grammar "
                         "does not stop growing here",
                         file_of(r->g), it->line, it->col, r->index, r->id, bound, what, option);
}

static pgt_result push(xrun *r, const pgt_grammar_item *it, const xwork *w) {
    if (r->depth >= r->job->max_depth)
        return limit(r, it, "work items on the stack", r->job->max_depth, "max_depth");
    if (!grow((void **)&r->stack, r->depth, &r->cap, sizeof(xwork)))
        return pgt_error_set(&r->out->err, PGT_ERROR_OUT_OF_MEMORY, "seed %u: out of memory",
                             r->index);
    r->stack[r->depth++] = *w;
    return PGT_OK;
}

/* Appends a point at walker state s with the given parent (PGT_NONE: a root). */
static pgt_result add_point(xrun *r, const pgt_grammar_item *it, const pgt_march_state *s,
                            uint32_t parent) {
    xseed *o = r->out;
    if (o->point_count >= r->job->max_points)
        return limit(r, it, "points", r->job->max_points, "max_points");
    if (!grow((void **)&o->points, o->point_count, &o->point_cap, sizeof(xpoint)))
        return pgt_error_set(&o->err, PGT_ERROR_OUT_OF_MEMORY, "seed %u: out of memory", r->index);
    xpoint *p = &o->points[o->point_count];
    pgt_march_position(r->job->in->atlas, s->x, s->y, p->p);
    normal_at(r->job->in->atlas, r->job->in->normal, s->x, s->y, p->n);
    p->u = s->x, p->v = s->y, p->chart = s->chart, p->parent = parent, p->children = 0;
    p->leaves = 0;
    if (parent == PGT_NONE || o->points[parent].children > 0)
        p->branch = o->branch_count++;
    else
        p->branch = o->points[parent].branch;
    if (parent != PGT_NONE) o->points[parent].children++;
    o->point_count++;
    return PGT_OK;
}

/* Evaluates expression e of frame w with texCoord at w's point. */
static pgt_result eval(xrun *r, uint32_t e, const xwork *w, float *val) {
    const xpoint *p = &r->out->points[w->point];
    r->env.u = p->u, r->env.v = p->v;
    pgt_error e2 = {0};
    const pgt_result res = pgt_grammar_eval(r->g, e, w->args, w->argc, &r->env, val, &e2);
    if (res != PGT_OK)
        pgt_error_set(&r->out->err, res, "%s (seed %u, id %u)", e2.message, r->index, r->id);
    return res;
}

static pgt_result do_call(xrun *r, const pgt_grammar_item *it, const xwork *w) {
    const pgt_grammar *g = r->g;
    xwork callee = *w;
    callee.pos = 0;
    callee.argc = it->arg_count;
    for (uint32_t k = 0; k < it->arg_count; ++k) {
        const pgt_result res = eval(r, g->args[it->first_arg + k], w, &callee.args[k]);
        if (res != PGT_OK) return res;
    }
    const pgt_grammar_rule *rule = &g->rules[it->target];
    for (uint32_t c = 0; c < rule->case_count; ++c) {
        const pgt_grammar_case *cs = &g->cases[rule->first_case + c];
        float cond = 1.0f;
        if (cs->condition != PGT_NONE) {
            const pgt_result res = eval(r, cs->condition, &callee, &cond);
            if (res != PGT_OK) return res;
        }
        if (cond != 0.0f) {
            callee.seq = cs->sequence;
            return push(r, it, &callee);
        }
    }
    return PGT_OK;
}

static pgt_result do_marching(xrun *r, const pgt_grammar_item *it, const xwork *w) {
    const pgt_grammar *g = r->g;
    const xjob *job = r->job;
    float len = 0.0f, angle = 0.0f;
    pgt_result res = eval(r, g->args[it->first_arg], w, &len);
    if (res == PGT_OK) res = eval(r, g->args[it->first_arg + 1], w, &angle);
    if (res != PGT_OK) return res;
    if (!(len > 0.0f && len <= PGT_MARCH_MAX_LENGTH))
        return pgt_error_set(&r->out->err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s:%u:%u: seed %u (id %u): Marching length %g is outside (0, %g] "
                             "texels",
                             file_of(g), it->line, it->col, r->index, r->id, (double)len,
                             (double)PGT_MARCH_MAX_LENGTH);
    const uint32_t ce = g->args[it->first_arg + 2];
    xcond cond = {g, ce, w, r->env, PGT_OK, 0, {0}};
    /* a condition reading neither context nor rand has the same value in every direction */
    const int fixed = !(g->exprs[ce].flags & (PGT_GRAMMAR_EXPR_CONTEXT | PGT_GRAMMAR_EXPR_RAND));
    pgt_march_options mo = job->march;
    mo.condition = cond_eval, mo.condition_ctx = &cond;
    const xpoint *cur = &r->out->points[w->point];
    const pgt_march_state start = {cur->u,  cur->v,   w->dx,    w->dy,     cur->chart,
                                   w->from, w->in_dx, w->in_dy, w->bounces};
    pgt_march_state s = start;
    uint32_t t = 0;
    for (; t <= job->candidates; ++t) {
        s = start;
        cond.rejected = 0;
        pgt_march_info info;
        const float a = t == 0 ? angle : angle + job->cand_angle[t - 1];
        const pgt_march_event ev = pgt_march_step(job->in->atlas, &mo, &s, len, a, &info);
        if (cond.status != PGT_OK) {
            return pgt_error_set(&r->out->err, cond.status, "%s (seed %u, id %u)", cond.err.message,
                                 r->index, r->id);
        }
        if (ev != PGT_MARCH_STOP) break;
        if (info.stop == PGT_MARCH_STOP_REJECTED) r->out->rejected++;
        if (cond.rejected && fixed) t = job->candidates; /* no candidate can do better */
    }
    if (t > job->candidates) {
        r->out->stopped++;
        return PGT_OK;
    }
    if (t > 0) r->out->candidates++;
    const uint32_t q = r->out->point_count;
    res = add_point(r, it, &s, w->point);
    if (res != PGT_OK) return res;
    xwork next = *w;
    next.pos = 0, next.point = q, next.dx = s.dx, next.dy = s.dy;
    next.from = s.from, next.in_dx = s.in_dx, next.in_dy = s.in_dy, next.bounces = s.bounces;
    next.seq = g->subs[it->first_sub + 1], next.segment = q; /* Extruded, after Top */
    res = push(r, it, &next);
    if (res != PGT_OK) return res;
    next.seq = g->subs[it->first_sub], next.segment = w->segment; /* Top, first */
    return push(r, it, &next);
}

static pgt_result do_terminal(xrun *r, const pgt_grammar_item *it, const xwork *w) {
    if (it->target != PGT_GRAMMAR_TERMINAL_BARK && it->target != PGT_GRAMMAR_TERMINAL_LEAVES)
        return pgt_error_set(&r->out->err, PGT_ERROR_UNSUPPORTED,
                             "%s:%u:%u: seed %u (id %u): %s is a facade terminal, the on-mesh "
                             "expander grows Bark and Leaves only",
                             file_of(r->g), it->line, it->col, r->index, r->id,
                             pgt_grammar_terminal_name(it->target));
    float v[2] = {0.0f, 0.0f};
    for (uint32_t k = 0; k < it->arg_count && k < 2; ++k) {
        const pgt_result res = eval(r, r->g->args[it->first_arg + k], w, &v[k]);
        if (res != PGT_OK) return res;
    }
    /* the terminal builder's checks, here where the grammar's place is known */
    const int bark = it->target == PGT_GRAMMAR_TERMINAL_BARK;
    const float size = bark ? v[0] : v[1];
    if (!(size > 0.0f && size <= PGT_TERMINALS_MAX_SIZE))
        return pgt_error_set(&r->out->err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s:%u:%u: seed %u (id %u): %s %s %g is not in (0, %g]", file_of(r->g),
                             it->line, it->col, r->index, r->id, bark ? "Bark" : "Leaves",
                             bark ? "radius" : "size", (double)size,
                             (double)PGT_TERMINALS_MAX_SIZE);
    if (!bark && !(v[0] >= 0.0f && v[0] <= PGT_TERMINALS_MAX_LEAF_DENSITY))
        return pgt_error_set(&r->out->err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s:%u:%u: seed %u (id %u): Leaves density %g is not in [0, %g]",
                             file_of(r->g), it->line, it->col, r->index, r->id, (double)v[0],
                             (double)PGT_TERMINALS_MAX_LEAF_DENSITY);
    xseed *o = r->out;
    uint32_t seg = w->segment;
    if (seg == PGT_NONE && o->points[w->point].parent != PGT_NONE) seg = w->point;
    if (seg == PGT_NONE) {
        o->dropped++;
        return PGT_OK;
    }
    if (o->term_count >= r->job->max_terminals)
        return limit(r, it, "terminals", r->job->max_terminals, "max_terminals");
    if (!bark && o->points[seg].leaves++ >= PGT_TERMINALS_MAX_LEAVES_RECORDS)
        return pgt_error_set(&o->err, PGT_ERROR_LIMIT,
                             "%s:%u:%u: seed %u (id %u): more than %u Leaves records on one "
                             "segment (the terminal builder's PGT_TERMINALS_MAX_LEAVES_RECORDS)",
                             file_of(r->g), it->line, it->col, r->index, r->id,
                             PGT_TERMINALS_MAX_LEAVES_RECORDS);
    if (!grow((void **)&o->terms, o->term_count, &o->term_cap, sizeof(xterm)))
        return pgt_error_set(&o->err, PGT_ERROR_OUT_OF_MEMORY, "seed %u: out of memory", r->index);
    xterm *tm = &o->terms[o->term_count++];
    tm->segment = seg, tm->kind = it->target, tm->a = v[0], tm->b = v[1];
    tm->smoothness = it->target == PGT_GRAMMAR_TERMINAL_BARK ? (uint32_t)v[1] : PGT_NONE;
    return PGT_OK;
}

static pgt_result run_item(xrun *r, const pgt_grammar_item *it, const xwork *w) {
    switch ((pgt_grammar_item_kind)it->kind) {
    case PGT_GRAMMAR_ITEM_CALL:
        return do_call(r, it, w);
    case PGT_GRAMMAR_ITEM_MARCHING:
        return do_marching(r, it, w);
    case PGT_GRAMMAR_ITEM_BRANCH:
        for (uint32_t k = it->sub_count; k-- > 0;) { /* pushed last to first: S1 runs first */
            xwork sub = *w;
            sub.seq = r->g->subs[it->first_sub + k], sub.pos = 0;
            const pgt_result res = push(r, it, &sub);
            if (res != PGT_OK) return res;
        }
        return PGT_OK;
    case PGT_GRAMMAR_ITEM_TERMINAL:
        return do_terminal(r, it, w);
    case PGT_GRAMMAR_ITEM_SPLIT:
        break;
    }
    return pgt_error_set(&r->out->err, PGT_ERROR_UNSUPPORTED,
                         "%s:%u:%u: seed %u (id %u): split is not supported by the on-mesh "
                         "expander (issue 6 gives splits their semantics)",
                         file_of(r->g), it->line, it->col, r->index, r->id);
}

static pgt_result run_seed(const xjob *job, uint32_t index, xseed *out) {
    const pgt_expand_input *in = job->in;
    const pgt_expand_seed *sd = &in->seeds[index];
    xrun r = {job, in->grammar, out, index, in->seed_base + index, NULL, 0, 0, 0, {{0}, 0, 0}, {0}};
    r.ctx.plane[PGT_GRAMMAR_CONTEXT_MASK] = in->mask;
    r.ctx.plane[PGT_GRAMMAR_CONTEXT_DENSITY] = in->density;
    r.ctx.w = in->atlas->width, r.ctx.h = in->atlas->height;
    r.env.seed = r.id, r.env.stream = job->stream, r.env.counter = &out->counter;
    r.env.context = context_read, r.env.context_data = &r.ctx;
    pgt_march_state s;
    pgt_error e = {0};
    if (pgt_march_start(in->atlas, sd->x, sd->y, sd->dx, sd->dy, &s, &e) != PGT_OK)
        return pgt_error_set(&out->err, e.code, "seed %u (id %u): %s", index, r.id, e.message);
    const pgt_grammar *g = r.g;
    const pgt_grammar_rule *axiom = &g->rules[0];
    /* the root: a pseudo item at the axiom's position names it in a max_points error */
    const pgt_grammar_item root = {PGT_GRAMMAR_ITEM_CALL, 0, 0, 0, 0, 0, axiom->line, axiom->col};
    pgt_result res = add_point(&r, &root, &s, PGT_NONE);
    xwork w0;
    memset(&w0, 0, sizeof w0);
    w0.seq = g->cases[axiom->first_case].sequence, w0.segment = PGT_NONE;
    w0.dx = s.dx, w0.dy = s.dy;
    if (res == PGT_OK) res = push(&r, &root, &w0);
    while (res == PGT_OK && r.depth > 0) {
        const xwork w = r.stack[--r.depth];
        const pgt_grammar_sequence *sq = &g->sequences[w.seq];
        if (w.pos >= sq->item_count) continue;
        const pgt_grammar_item *it = &g->items[sq->first_item + w.pos];
        if (r.items++ == job->max_items) {
            char option[96] = "max_items";
            if (job->max_total_items) /* the bound is the seed's share of the total */
                snprintf(option, sizeof option,
                         "max_total_items: %llu over all %u seed%s, %u a seed",
                         (unsigned long long)job->max_total_items, job->in->seed_count,
                         job->in->seed_count == 1u ? "" : "s", job->max_items);
            res = limit(&r, it, "grammar items run", job->max_items, option);
            break;
        }
        if (r.items % EXPAND_CHECK_ITEMS == 0 &&
            atomic_load_explicit(job->first_failed, memory_order_relaxed) < index) {
            res =
                pgt_error_set(&out->err, PGT_ERROR_LIMIT, "seed %u: stopped (a lower seed failed)",
                              index); /* never reported: the lower seed's error is */
            break;
        }
        xwork rest = w; /* no tail-call elimination: see expand.h */
        rest.pos++;
        res = push(&r, it, &rest);
        if (res == PGT_OK) res = run_item(&r, it, &w);
    }
    free(r.stack);
    return res;
}

static void run_range(void *ctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const xjob *job = ctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i) {
        if (atomic_load_explicit(job->first_failed, memory_order_relaxed) < i) return;
        const pgt_result r = run_seed(job, i, &job->seeds[i]);
        pgt_progress_add(job->progress, 1);
        if (r == PGT_OK) continue;
        unsigned low = atomic_load_explicit(job->first_failed, memory_order_relaxed);
        while (i < low &&
               !atomic_compare_exchange_weak_explicit(job->first_failed, &low, i,
                                                      memory_order_relaxed, memory_order_relaxed)) {
        }
    }
}

void pgt_expand_destroy(pgt_expand_output *out) {
    if (!out) return;
    void *arrays[] = {out->x,
                      out->y,
                      out->z,
                      out->nx,
                      out->ny,
                      out->nz,
                      out->u,
                      out->v,
                      out->chart,
                      out->parent,
                      out->seed,
                      out->branch,
                      out->terminal_segment,
                      out->terminal_kind,
                      out->terminal_a,
                      out->terminal_b,
                      out->terminal_smoothness,
                      out->seed_first_point,
                      out->seed_point_count,
                      out->seed_first_terminal,
                      out->seed_terminal_count};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) free(arrays[i]);
    memset(out, 0, sizeof *out);
}

static pgt_result check_inputs(const pgt_expand_input *in, const pgt_expand_options *o,
                               pgt_error *err) {
    if (!in || !in->grammar || !in->atlas || !in->normal[0] || !in->normal[1] || !in->normal[2] ||
        (in->seed_count && !in->seeds))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_expand: grammar, atlas, the three normal planes and the seeds "
                             "are required");
    if (in->grammar->rule_count == 0 || in->grammar->rules[0].param_count != 0)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_expand: the grammar needs an axiom without parameters");
    if (o && o->march.condition)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_expand: options.march.condition must be NULL (the expander "
                             "evaluates the grammar's conditions)");
    if (o && o->candidates > PGT_EXPAND_MAX_CANDIDATES)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_expand: %u candidate directions, at most %u", o->candidates,
                             PGT_EXPAND_MAX_CANDIDATES);
    return PGT_OK;
}

/* Scatters the seeds' results into the output's SoA arrays. */
static pgt_result gather(pgt_expand_output *out, const xseed *seeds, uint32_t n, pgt_error *err) {
    uint64_t np = 0, nt = 0;
    for (uint32_t i = 0; i < n; ++i) np += seeds[i].point_count, nt += seeds[i].term_count;
    if (np >= PGT_NONE || nt >= PGT_NONE)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "pgt_expand: %llu points and %llu terminals, more than 2^32 - 2",
                             (unsigned long long)np, (unsigned long long)nt);
    const size_t P = np ? (size_t)np : 1, T = nt ? (size_t)nt : 1, S = n ? n : 1;
    float **pf[] = {&out->x,  &out->y, &out->z, &out->nx,         &out->ny,
                    &out->nz, &out->u, &out->v, &out->terminal_a, &out->terminal_b};
    uint32_t **pu[] = {&out->chart,
                       &out->parent,
                       &out->seed,
                       &out->branch,
                       &out->terminal_segment,
                       &out->terminal_kind,
                       &out->terminal_smoothness,
                       &out->seed_first_point,
                       &out->seed_point_count,
                       &out->seed_first_terminal,
                       &out->seed_terminal_count};
    int ok = 1;
    for (size_t i = 0; i < sizeof pf / sizeof pf[0]; ++i)
        ok &= (*pf[i] = malloc((i < 8 ? P : T) * sizeof(float))) != NULL;
    for (size_t i = 0; i < sizeof pu / sizeof pu[0]; ++i)
        ok &= (*pu[i] = malloc((i < 4 ? P : i < 7 ? T : S) * sizeof(uint32_t))) != NULL;
    if (!ok) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_expand: out of memory");
    uint32_t p0 = 0, t0 = 0, b0 = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const xseed *s = &seeds[i];
        out->seed_first_point[i] = p0, out->seed_point_count[i] = s->point_count;
        out->seed_first_terminal[i] = t0, out->seed_terminal_count[i] = s->term_count;
        for (uint32_t k = 0; k < s->point_count; ++k) {
            const xpoint *q = &s->points[k];
            const uint32_t j = p0 + k;
            out->x[j] = q->p[0], out->y[j] = q->p[1], out->z[j] = q->p[2];
            out->nx[j] = q->n[0], out->ny[j] = q->n[1], out->nz[j] = q->n[2];
            out->u[j] = q->u, out->v[j] = q->v, out->chart[j] = q->chart;
            out->parent[j] = q->parent == PGT_NONE ? PGT_NONE : p0 + q->parent;
            out->seed[j] = i, out->branch[j] = b0 + q->branch;
        }
        for (uint32_t k = 0; k < s->term_count; ++k) {
            const xterm *q = &s->terms[k];
            const uint32_t j = t0 + k;
            out->terminal_segment[j] = p0 + q->segment, out->terminal_kind[j] = q->kind;
            out->terminal_a[j] = q->a, out->terminal_b[j] = q->b;
            out->terminal_smoothness[j] = q->smoothness;
        }
        p0 += s->point_count, t0 += s->term_count, b0 += s->branch_count;
        out->stopped_marches += s->stopped, out->rejected_tries += s->rejected;
        out->candidates_used += s->candidates, out->dropped_terminals += s->dropped;
        out->draws += s->counter;
    }
    out->point_count = p0, out->terminal_count = t0, out->branch_count = b0, out->seed_count = n;
    return PGT_OK;
}

pgt_result pgt_expand(pgt_expand_output *out, const pgt_expand_input *in,
                      const pgt_expand_options *o, pgt_error *err) {
    memset(out, 0, sizeof *out);
    pgt_result res = check_inputs(in, o, err);
    if (res != PGT_OK) return res;
    const pgt_expand_options zero = {0};
    if (!o) o = &zero;
    xjob job;
    memset(&job, 0, sizeof job);
    job.in = in, job.march = o->march, job.stream = o->stream;
    job.max_points = o->max_points ? o->max_points : PGT_EXPAND_DEFAULT_MAX_POINTS;
    job.max_depth = o->max_depth ? o->max_depth : PGT_EXPAND_DEFAULT_MAX_DEPTH;
    job.max_terminals = o->max_terminals ? o->max_terminals : PGT_EXPAND_DEFAULT_MAX_TERMINALS;
    job.max_items = o->max_items ? o->max_items : PGT_EXPAND_DEFAULT_MAX_ITEMS;
    const uint64_t total =
        o->max_total_items ? o->max_total_items : PGT_EXPAND_DEFAULT_MAX_TOTAL_ITEMS;
    const uint64_t share = in->seed_count ? total / in->seed_count : total;
    if (share < job.max_items) {
        job.max_items = share > 0 ? (uint32_t)share : 1u;
        job.max_total_items = total;
    }
    job.candidates = o->no_candidates ? 0u
                     : o->candidates  ? o->candidates
                                      : PGT_EXPAND_DEFAULT_CANDIDATES;
    const uint32_t half = (job.candidates + 1u) / 2u;
    for (uint32_t j = 1; j <= job.candidates; ++j) { /* +a_1, -a_1, +a_2, ... (expand.h) */
        const float a = 1.57079632679489662f * (float)((j + 1u) / 2u) / (float)half;
        job.cand_angle[j - 1] = j % 2u ? a : -a;
    }
    atomic_uint first_failed = UINT32_MAX;
    job.first_failed = &first_failed;
    job.progress = o->progress;
    pgt_progress_stage(o->progress, "expand", in->seed_count, "seeds");
    job.seeds = calloc(in->seed_count ? in->seed_count : 1u, sizeof(xseed));
    if (!job.seeds) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_expand: out of memory");
    pgt_parallel_for_items(in->seed_count, EXPAND_SEED_WEIGHT, o->threads ? o->threads : 1u,
                           run_range, &job);
    for (uint32_t i = 0; i < in->seed_count && res == PGT_OK; ++i)
        if (job.seeds[i].err.code != PGT_OK)
            res = pgt_error_set(err, job.seeds[i].err.code, "%s", job.seeds[i].err.message);
    if (res == PGT_OK) res = gather(out, job.seeds, in->seed_count, err);
    for (uint32_t i = 0; i < in->seed_count; ++i)
        free(job.seeds[i].points), free(job.seeds[i].terms);
    free(job.seeds);
    if (res != PGT_OK) pgt_expand_destroy(out);
    return res;
}
