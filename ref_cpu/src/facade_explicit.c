/* pgt: explicit generation of facades (issue 6 item 8): the grammar of every facade developed
 * completely, every terminal's rectangles turned into two world-space triangles each and every
 * geometry image's triangles copied (on a generic mesh's quad, both clipped to the quad's window
 * in grammar space, paper 003 sec. 10, as the ray test cuts its hits there). The same
 * evaluation helpers as the ray development (facade_internal.h), so the two see the same split
 * layouts, the same random draws (keyed by node) and the same rectangles; only the order of the
 * traversal differs (every child, depth first, explicit stack). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facade_internal.h"

typedef struct xframe {
    uint32_t type; /* 0: sequence, 1: split */
    uint32_t key;
    uint32_t path; /* nodes from the axiom to this one (a tail item's frame counts on) */
    float x0, y0, w, h;
    uint32_t argc;
    float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
    uint32_t seq, pos;        /* sequence */
    uint32_t axis, next;      /* split */
    facade_split_state split; /* split */
} xframe;

typedef struct xmesh {
    pgt_facade_mesh *m;
    uint32_t vcap, tcap;
    uint32_t max_t;      /* triangles at most (pgt_facade_explicit_limit) */
    int dry;             /* pgt_facade_explain: every check, no triangle stored */
    uint64_t nodes_left; /* steps of the development left (pgt_facade_explain's bound) */
} xmesh;

static int grow(void **p, uint32_t cap, size_t elem) {
    void *q = realloc(*p, (size_t)cap * elem);
    if (!q) return 0;
    *p = q;
    return 1;
}

static pgt_result too_many(const xmesh *x, pgt_error *err) {
    return pgt_error_set(err, PGT_ERROR_LIMIT, "explicit facades: more than %u triangles",
                         x->max_t);
}

static int reserve(xmesh *x, uint32_t add_v, uint32_t add_t) {
    pgt_facade_mesh *m = x->m;
    if (m->vertex_count + add_v > x->vcap) {
        uint32_t cap = x->vcap ? x->vcap : 4096u;
        while (cap < m->vertex_count + add_v) cap *= 2u;
        /* at most 3 vertices a triangle (a roof's; 2 for a rectangle's): the arrays never
         * outgrow the limit's share of memory */
        if (cap > 3u * x->max_t) cap = 3u * x->max_t;
        if (!grow((void **)&m->positions, cap, 3 * sizeof(float))) return 0;
        x->vcap = cap;
    }
    if (m->triangle_count + add_t > x->tcap) {
        uint32_t cap = x->tcap ? x->tcap : 2048u;
        while (cap < m->triangle_count + add_t) cap *= 2u;
        if (cap > x->max_t) cap = x->max_t;
        if (!grow((void **)&m->indices, cap, 3 * sizeof(uint32_t)) ||
            !grow((void **)&m->facade, cap, sizeof(uint32_t)) ||
            !grow((void **)&m->node, cap, sizeof(uint32_t)) ||
            !grow((void **)&m->kind, cap, sizeof(uint32_t)) ||
            !grow((void **)&m->surface, cap, sizeof(uint32_t)))
            return 0;
        x->tcap = cap;
    }
    return 1;
}

void pgt_facade_mesh_destroy(pgt_facade_mesh *m) {
    if (!m) return;
    free(m->positions);
    free(m->indices);
    free(m->facade);
    free(m->node);
    free(m->kind);
    free(m->surface);
    memset(m, 0, sizeof *m);
}

static const char *gfile(const pgt_grammar *g) { return g->names + g->file_name; }

/* Clips rectangle r to the window [w[0], w[2]] x [w[1], w[3]] of facade space in x and y (the
 * part of a terminal that this quad of a mesh shows, sec. 10); 0 when nothing of positive area is
 * left. */
static int clip_to_window(pgt_facade_quad *r, const float w[4]) {
    static const uint32_t other[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    const uint32_t ax = r->axis;
    if (ax != 2 && (r->c < w[ax] || r->c > w[2 + ax])) return 0;
    for (uint32_t k = 0; k < 2; ++k) {
        const uint32_t o = other[ax][k];
        if (o == 2) continue;
        if (r->lo[k] < w[o]) r->lo[k] = w[o];
        if (r->hi[k] > w[2 + o]) r->hi[k] = w[2 + o];
        if (!(r->hi[k] > r->lo[k])) return 0;
    }
    return 1;
}

/* Appends the rectangles of one terminal. */
static pgt_result emit(xmesh *x, const pgt_facade *f, uint32_t fi, const pgt_grammar *g,
                       const pgt_grammar_item *it, uint32_t key, const pgt_facade_quad *q,
                       uint32_t n, pgt_error *err) {
    static const uint32_t other[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    const uint32_t kind = pgt_facade_kind_of(it->target);
    const int whole = facade_is_whole(f);
    const float win[4] = {f->u0, f->v0, f->u0 + f->width, f->v0 + f->height};
    for (uint32_t k = 0; k < n; ++k) {
        if (!(q[k].hi[0] > q[k].lo[0])) continue;
        const uint32_t ax = q[k].axis;
        float zlo, zhi;
        if (facade_quad_outside_volume(f, &q[k], &zlo, &zhi))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s:%u:%u: building %u facade %u: %s surface %u spans z [%g, %g] "
                                 "outside the facade volume [-recess, protrusion] = [%g, %g] (the "
                                 "grammar must bound its terminals, paper 003 sec. 8)",
                                 gfile(g), it->line, it->col, f->building, f->edge,
                                 pgt_grammar_terminal_name(it->target), k, (double)zlo, (double)zhi,
                                 -(double)f->recess, (double)f->protrusion);
        pgt_facade_quad r = q[k];
        if (!whole && !clip_to_window(&r, win)) continue;
        if (x->dry) continue;
        if (x->m->triangle_count + 2u > x->max_t) return too_many(x, err);
        if (!reserve(x, 4, 2))
            return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "explicit facades: out of memory");
        pgt_facade_mesh *m = x->m;
        const uint32_t v0 = m->vertex_count;
        const float u0[4] = {r.lo[0], r.hi[0], r.hi[0], r.lo[0]};
        const float u1[4] = {r.lo[1], r.lo[1], r.hi[1], r.hi[1]};
        for (int c = 0; c < 4; ++c) {
            float p[3];
            p[ax] = r.c, p[other[ax][0]] = u0[c], p[other[ax][1]] = u1[c];
            facade_to_world(f, p, &m->positions[3u * (v0 + (uint32_t)c)]);
        }
        m->vertex_count += 4;
        static const uint32_t tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int t = 0; t < 2; ++t) {
            const uint32_t ti = m->triangle_count++;
            for (int c = 0; c < 3; ++c) m->indices[3u * ti + (uint32_t)c] = v0 + tri[t][c];
            m->facade[ti] = fi, m->node[ti] = key, m->kind[ti] = kind, m->surface[ti] = k;
        }
    }
    return PGT_OK;
}

/* Corners of a geometry-image triangle clipped to a window (sec. 10): 3, plus at most one per
 * clipping line for a convex polygon; the buffers hold more so that a polygon that rounding makes
 * slightly non-convex cannot overflow them (corners past the buffer are dropped). */
#define GIMAGE_CLIP_CORNERS 16u

/* One Sutherland-Hodgman step: the part of the convex polygon p[0 .. n) (facade space) with
 * coordinate `axis` >= c (side > 0) or <= c (side < 0) into out; returns its corner count. A
 * crossing corner is interpolated in double and put exactly on the line, so a clipped piece's
 * border is the window's border, where the ray test's window check cuts. */
static uint32_t clip_line(float (*out)[3], const float (*p)[3], uint32_t n, uint32_t axis, float c,
                          int side) {
    uint32_t m = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const float *S = p[(i + n - 1u) % n], *E = p[i];
        const int s_in = side > 0 ? S[axis] >= c : S[axis] <= c;
        const int e_in = side > 0 ? E[axis] >= c : E[axis] <= c;
        if (s_in != e_in && m < GIMAGE_CLIP_CORNERS) {
            const double r = ((double)c - S[axis]) / ((double)E[axis] - S[axis]);
            for (uint32_t k = 0; k < 3; ++k)
                out[m][k] = (float)((double)S[k] + r * ((double)E[k] - S[k]));
            out[m++][axis] = c;
        }
        if (e_in && m < GIMAGE_CLIP_CORNERS) memcpy(out[m++], E, 3 * sizeof(float));
    }
    return m;
}

/* Does triangle a b c (facade space) have area? Its edges' cross product in double is not 0. */
static int piece_has_area(const float *a, const float *b, const float *c) {
    const double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
    const double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
    return e1[1] * e2[2] - e1[2] * e2[1] != 0.0 || e1[2] * e2[0] - e1[0] * e2[2] != 0.0 ||
           e1[0] * e2[1] - e1[1] * e2[0] != 0.0;
}

/* Appends the triangles of a geometry image on the scope [x0, x0 + w] x [y0, y0 + h]. On a mesh
 * quad (a window that is not the whole facade, sec. 10) each triangle is clipped to the window
 * in x and y (Sutherland-Hodgman against its 4 lines), the convex rest fanned into triangles and
 * pieces of zero area dropped; every piece keeps the triangle's ids (surface = its index in the
 * scene's geometry image). */
static pgt_result emit_gimage(xmesh *x, const pgt_facade *f, uint32_t fi, const pgt_grammar *g,
                              const pgt_grammar_item *it, uint32_t key, const float *td, uint32_t n,
                              uint32_t first, float x0, float y0, float w, float h,
                              pgt_error *err) {
    const int whole = facade_is_whole(f);
    const float win[4] = {f->u0, f->v0, f->u0 + f->width, f->v0 + f->height};
    for (uint32_t k = 0; k < n; ++k) {
        const float *T = td + 9u * k;
        for (int c = 0; c < 3; ++c)
            if (T[3 * c + 2] < -f->recess || T[3 * c + 2] > f->protrusion)
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "%s:%u:%u: building %u facade %u: Mesh triangle %u reaches z "
                                     "%g outside the facade volume [-recess, protrusion] = [%g, "
                                     "%g] (paper 003 sec. 8)",
                                     gfile(g), it->line, it->col, f->building, f->edge, k,
                                     (double)T[3 * c + 2], -(double)f->recess,
                                     (double)f->protrusion);
        if (x->dry) continue;
        float poly[GIMAGE_CLIP_CORNERS][3], tmp[GIMAGE_CLIP_CORNERS][3];
        for (int c = 0; c < 3; ++c) {
            poly[c][0] = x0 + T[3 * c] * w, poly[c][1] = y0 + T[3 * c + 1] * h;
            poly[c][2] = T[3 * c + 2];
        }
        uint32_t m = 3;
        if (!whole) {
            m = clip_line(tmp, (const float(*)[3])poly, m, 0, win[0], 1);
            m = clip_line(poly, (const float(*)[3])tmp, m, 0, win[2], -1);
            m = clip_line(tmp, (const float(*)[3])poly, m, 1, win[1], 1);
            m = clip_line(poly, (const float(*)[3])tmp, m, 1, win[3], -1);
        }
        for (uint32_t p = 1; p + 1u < m; ++p) {
            if (!whole && !piece_has_area(poly[0], poly[p], poly[p + 1u])) continue;
            if (x->m->triangle_count + 1u > x->max_t) return too_many(x, err);
            if (!reserve(x, 3, 1))
                return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                                     "explicit facades: out of memory");
            pgt_facade_mesh *me = x->m;
            const uint32_t v0 = me->vertex_count, ti = me->triangle_count++;
            const uint32_t corner[3] = {0, p, p + 1u};
            for (uint32_t c = 0; c < 3; ++c) {
                facade_to_world(f, poly[corner[c]], &me->positions[3u * (v0 + c)]);
                me->indices[3u * ti + c] = v0 + c;
            }
            me->vertex_count += 3;
            me->facade[ti] = fi, me->node[ti] = key, me->kind[ti] = PGT_FACADE_MESH,
            me->surface[ti] = first + k;
        }
    }
    return PGT_OK;
}

static pgt_result expand_facade(xmesh *x, const pgt_facade_scene *s, const pgt_facade *f,
                                uint32_t fi, xframe *stack, pgt_error *err) {
    const pgt_facade_building *B = &s->buildings[f->building];
    pgt_facade_ray_stats st;
    memset(&st, 0, sizeof st);
    pgt_error eerr;
    memset(&eerr, 0, sizeof eerr);
    const facade_ctx c = {&s->grammars[B->grammar], s->params + B->first_param, B->seed, &st,
                          &eerr};
    const pgt_grammar *g = c.g;
    pgt_facade_quad quads[PGT_FACADE_MAX_QUADS];
    uint32_t sp = 0;
    const uint32_t key0 = facade_axiom_key(s, f);
    const uint32_t seq0 = facade_select_case(&c, 0, NULL, 0, key0);
    const pgt_grammar_item *where = NULL;
    if (seq0 != PGT_NONE) {
        xframe *fr = &stack[sp++];
        fr->type = 0, fr->key = key0, fr->x0 = 0.0f, fr->y0 = 0.0f, fr->w = f->scope_w;
        fr->h = f->scope_h, fr->argc = 0, fr->seq = seq0, fr->pos = 0, fr->path = 1;
    }
    while (sp > 0 && !st.errors) {
        if (x->nodes_left-- == 0)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "building %u facade %u: no error found in the development's "
                                 "first %llu steps",
                                 f->building, f->edge,
                                 (unsigned long long)PGT_FACADE_EXPLAIN_STEPS);
        xframe *fr = &stack[sp - 1];
        if (fr->type == 1) {
            pgt_split_child ch;
            if (fr->next >= fr->split.plan.child_count) {
                --sp;
                continue;
            }
            const uint32_t cur = fr->next++;
            pgt_split_child_get(&fr->split.plan, fr->split.slots, cur, &ch);
            const uint32_t seq = fr->split.seq[ch.part];
            if (seq == PGT_NONE || !(ch.end > ch.start)) continue;
            /* a child outside the window (a mesh quad's, sec. 10) has nothing to show in it:
             * terminals stay inside their scope. A child that only touches the window's border
             * is outside too, as for the rays: their development enters the child that holds a
             * point on the window's interval, the one starting there (half-open [start, end)),
             * so a child starting at the window's top or ending at its bottom belongs to the
             * neighbouring quad (kept here, its faces on the border were hit by Embree in this
             * quad's frame and by no ray of ours: a review found 81 such pixels on a tower) */
            const float o = fr->axis == 0 ? fr->x0 : fr->y0;
            const float wlo = fr->axis == 0 ? f->u0 : f->v0;
            const float whi = wlo + (fr->axis == 0 ? f->width : f->height);
            if (!facade_is_whole(f) && (o + ch.end < wlo || o + ch.start >= whi)) continue;
            if (sp == PGT_FACADE_MAX_DEPTH) {
                st.errors |= PGT_FACADE_ERR_DEPTH;
                break;
            }
            xframe *nf = &stack[sp++];
            nf->type = 0, nf->key = pgt_facade_child_key(fr->key, cur), nf->path = fr->path + 1u;
            nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w, nf->h = fr->h;
            if (fr->axis == 0)
                nf->x0 = fr->x0 + ch.start, nf->w = ch.end - ch.start;
            else
                nf->y0 = fr->y0 + ch.start, nf->h = ch.end - ch.start;
            nf->argc = fr->argc;
            memcpy(nf->args, fr->args, fr->argc * sizeof(float));
            nf->seq = seq, nf->pos = 0;
            continue;
        }
        const pgt_grammar_sequence *sq = &g->sequences[fr->seq];
        if (fr->pos >= sq->item_count) {
            --sp;
            continue;
        }
        const uint32_t pos = fr->pos++;
        const pgt_grammar_item *it = &g->items[sq->first_item + pos];
        const uint32_t key = pgt_facade_child_key(fr->key, pos);
        where = it;
        if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL) {
            if (pgt_facade_kind_of(it->target) == PGT_FACADE_MISS) {
                st.errors |= PGT_FACADE_ERR_ITEM;
                break;
            }
            if (it->target == PGT_GRAMMAR_TERMINAL_MESH) {
                float id;
                uint64_t counter = 0;
                if (!facade_eval(&c, g->args[it->first_arg], fr->args, fr->argc, key, &counter,
                                 &id))
                    break;
                const float *td = NULL;
                uint32_t first = 0;
                const uint32_t n = facade_gimage_triangles(s, id, &td, &first);
                if (n == 0)
                    return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                         "%s:%u:%u: building %u facade %u: Mesh(%g): the scene has "
                                         "%u geometry images (ids 0 to %u)",
                                         gfile(g), it->line, it->col, f->building, f->edge,
                                         (double)id, s->gimage_count,
                                         s->gimage_count ? s->gimage_count - 1u : 0u);
                const pgt_result r = emit_gimage(x, f, fi, g, it, key, td, n, first, fr->x0, fr->y0,
                                                 fr->w, fr->h, err);
                if (r != PGT_OK) return r;
                continue;
            }
            const uint32_t n = facade_terminal(&c, it, fr->args, fr->argc, key, fr->x0, fr->y0,
                                               fr->w, fr->h, quads);
            if (st.errors) break;
            const pgt_result r = emit(x, f, fi, g, it, key, quads, n, err);
            if (r != PGT_OK) return r;
            continue;
        }
        /* An item in tail position (the sequence's last) takes over its sequence's frame, as in
         * facade_intersect: the two count frames alike, so a development that renders also
         * expands (a chain of 40 rule calls needs one frame, not 40). */
        const int tail = fr->pos == sq->item_count;
        if (!tail && sp == PGT_FACADE_MAX_DEPTH) {
            st.errors |= PGT_FACADE_ERR_DEPTH;
            break;
        }
        /* A rule that calls itself in tail position takes no new frame: the path's length stops
         * it, as the ray's node budget stops the renderer (a ray that reaches the node has
         * developed at least the nodes on its path). */
        if (fr->path >= PGT_FACADE_NODE_BUDGET) {
            st.errors |= PGT_FACADE_ERR_BUDGET;
            break;
        }
        const uint32_t path = fr->path + 1u;
        if (it->kind == PGT_GRAMMAR_ITEM_CALL) {
            xframe *nf = tail ? fr : &stack[sp];
            float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
            uint32_t seq;
            if (!facade_call(&c, it, fr->args, fr->argc, key, args, &seq)) break;
            if (seq == PGT_NONE) continue;
            if (!tail) ++sp;
            nf->type = 0, nf->key = key, nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w;
            nf->h = fr->h, nf->argc = it->arg_count, nf->seq = seq, nf->pos = 0, nf->path = path;
            memcpy(nf->args, args, it->arg_count * sizeof(float));
            continue;
        }
        if (it->kind != PGT_GRAMMAR_ITEM_SPLIT || it->target > 1u) {
            st.errors |= PGT_FACADE_ERR_ITEM;
            break;
        }
        xframe *nf = tail ? fr : &stack[sp];
        if (!facade_split(&c, it, fr->args, fr->argc, key, it->target == 0 ? fr->w : fr->h,
                          &nf->split))
            break;
        if (!tail) {
            ++sp;
            nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w, nf->h = fr->h, nf->argc = fr->argc;
            memcpy(nf->args, fr->args, fr->argc * sizeof(float));
        }
        nf->type = 1, nf->key = key, nf->axis = it->target, nf->next = 0, nf->path = path;
    }
    if (!st.errors) return PGT_OK;
    const uint32_t line = where ? where->line : 1u, col = where ? where->col : 1u;
    if (st.errors & PGT_FACADE_ERR_EVAL)
        return pgt_error_set(err, eerr.code ? eerr.code : PGT_ERROR_INVALID_ARGUMENT,
                             "building %u facade %u: %s", f->building, f->edge, eerr.message);
    const char *why = (st.errors & PGT_FACADE_ERR_DEPTH)
                          ? "the development is deeper than PGT_FACADE_MAX_DEPTH (a rule that "
                            "calls itself without splitting?)"
                      : (st.errors & PGT_FACADE_ERR_BUDGET)
                          ? "a path of the development is longer than PGT_FACADE_NODE_BUDGET "
                            "nodes (a rule that calls itself without splitting?)"
                      : (st.errors & PGT_FACADE_ERR_PARTS)
                          ? "a split has more parts than PGT_FACADE_MAX_PARTS"
                          : "a facade holds split(x), split(y), rule calls and the facade "
                            "terminals only (no Marching, Branch, Bark, Leaves or split(z))";
    return pgt_error_set(err, PGT_ERROR_UNSUPPORTED, "%s:%u:%u: building %u facade %u: %s",
                         gfile(g), line, col, f->building, f->edge, why);
}

pgt_result pgt_facade_explicit(const pgt_facade_scene *s, const pgt_facade *facades,
                               uint32_t facade_count, pgt_facade_mesh *out, pgt_error *err) {
    return pgt_facade_explicit_limit(s, facades, facade_count, PGT_FACADE_MAX_TRIANGLES, out, err);
}

pgt_result pgt_facade_explicit_limit(const pgt_facade_scene *s, const pgt_facade *facades,
                                     uint32_t facade_count, uint32_t max_triangles,
                                     pgt_facade_mesh *out, pgt_error *err) {
    memset(out, 0, sizeof *out);
    if (max_triangles == 0 || max_triangles > PGT_FACADE_MAX_TRIANGLES)
        max_triangles = PGT_FACADE_MAX_TRIANGLES;
    xmesh x = {out, 0, 0, max_triangles, 0, UINT64_MAX};
    xframe *stack = malloc(PGT_FACADE_MAX_DEPTH * sizeof *stack);
    if (!stack) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "explicit: out of memory");
    pgt_result r = PGT_OK;
    for (uint32_t i = 0; i < facade_count && r == PGT_OK; ++i)
        r = expand_facade(&x, s, &facades[i], i, stack, err);
    free(stack);
    /* roofs: each footprint at base + height, ear-clipped */
    uint32_t maxc = 3;
    for (uint32_t b = 0; b < s->building_count; ++b)
        if (s->buildings[b].corner_count > maxc) maxc = s->buildings[b].corner_count;
    uint32_t *tris = malloc(3u * (size_t)maxc * sizeof *tris),
             *scratch = malloc(maxc * sizeof *scratch);
    if (r == PGT_OK && (!tris || !scratch))
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "explicit: out of memory");
    for (uint32_t b = 0; b < s->building_count && r == PGT_OK; ++b) {
        const pgt_facade_building *B = &s->buildings[b];
        const float *c = s->corners + 2u * B->first_corner, y = B->base + B->height;
        const uint32_t nt = facade_triangulate(c, B->corner_count, tris, scratch);
        if (x.m->triangle_count + nt > x.max_t) {
            r = too_many(&x, err);
            break;
        }
        if (!reserve(&x, 3u * nt, nt)) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "explicit: out of memory");
            break;
        }
        pgt_facade_mesh *m = x.m;
        for (uint32_t t = 0; t < nt; ++t) {
            const uint32_t ti = m->triangle_count++, v0 = m->vertex_count;
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t q = tris[3 * t + k];
                float *P = &m->positions[3u * (v0 + k)];
                P[0] = c[2 * q], P[1] = y, P[2] = c[2 * q + 1];
                m->indices[3u * ti + k] = v0 + k;
            }
            m->vertex_count += 3;
            m->facade[ti] = facade_count + b, m->node[ti] = 0, m->kind[ti] = PGT_FACADE_ROOF;
            m->surface[ti] = 0;
        }
    }
    free(tris);
    free(scratch);
    if (r != PGT_OK) pgt_facade_mesh_destroy(out);
    return r;
}

pgt_result pgt_facade_explain(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                              pgt_error *err) {
    pgt_facade_mesh none;
    memset(&none, 0, sizeof none);
    xmesh x = {&none, 0, 0, PGT_FACADE_MAX_TRIANGLES, 1, PGT_FACADE_EXPLAIN_STEPS};
    xframe *stack = malloc(PGT_FACADE_MAX_DEPTH * sizeof *stack);
    if (!stack) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "explain: out of memory");
    const pgt_result r = expand_facade(&x, s, f, fi, stack, err);
    free(stack);
    return r;
}
