/* pgt: sqrt(3) subdivision on an OpenCL device (pgt_cl_sqrt3), the host side of
 * kernels/sqrt3.cl.
 *
 * The host does what the reference does before its first pass (validation, the input adjacency,
 * vh, protected flags, parents, the alpha table: ref_cpu/src/sqrt3.c, pgt_sqrt3_subdivide),
 * uploads one level, then runs every iteration on the device: classify and the prefix sums when
 * the step is not uniform (only their two totals come back, to size the next level), then the
 * vertex and face passes, which write the next level and its adjacency. Only the last level is
 * read back. Uniform steps of a mesh without border run the reference's closed fast path
 * (s3_vertices_closed, s3_faces_closed: the same bytes without the tests); its implicit last
 * step, a CPU memory optimisation, is not ported. */
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cl_internal.h"
#include "pgt/adjacency.h"
#include "sqrt3_cl.h"
#include "sqrt3_layout.h"

/* Most launches of one iteration: classify, 4 scan levels, 3 adds, vertices, faces. */
#define S3_LAUNCHES_PER_STEP 10u

/* One level of the subdivision on the device. */
typedef struct s3_level {
    uint32_t V, F;
    cl_mem pos, idx; /* 3V floats, 3F uints */
    cl_mem opp, vh;  /* 3F, V: when the level has its adjacency */
    cl_mem prot;     /* F: when the call has protected faces */
    cl_mem parent;   /* F: when parents are wanted */
} s3_level;

/* The classification and prefix sums of a non-uniform step. scan_a holds the points per face
 * (then pt_off) followed by every level of group sums, scan_b the same for triangles. */
typedef struct s3_scratch {
    cl_mem kind, bslot, scan_a, scan_b;
} s3_scratch;

/* What one call keeps across its launches. */
typedef struct s3_call {
    pgt_cl *cl;
    cl_event *events; /* profiling: one per launch, NULL until enqueued */
    uint8_t *event_k; /* kernel of each event */
    uint32_t n_events, cap_events;
} s3_call;

/* One kernel argument for s3_launch: S3_ARG(x) passes variable x (a cl_mem, cl_uint or
 * pgt_s3_params) by address, as clSetKernelArg takes it. */
typedef struct s3_arg {
    size_t size;
    const void *value;
} s3_arg;
#define S3_ARG(x)                                                                                  \
    { sizeof(x), &(x) }
#define S3_COUNT(args) ((cl_uint)(sizeof(args) / sizeof((args)[0])))

static void s3_release(cl_mem *m) {
    if (*m) clReleaseMemObject(*m);
    *m = NULL;
}

static void s3_level_release(s3_level *l) {
    s3_release(&l->pos), s3_release(&l->idx), s3_release(&l->opp), s3_release(&l->vh);
    s3_release(&l->prot), s3_release(&l->parent);
}

static void s3_scratch_release(s3_scratch *s) {
    s3_release(&s->kind), s3_release(&s->bslot), s3_release(&s->scan_a), s3_release(&s->scan_b);
}

/* Sets the arguments of kernel `k` and launches it over `count` elements (rounded up to whole
 * work-groups; every kernel guards its index). With profiling, the launch's event is kept. */
static pgt_result s3_launch(s3_call *c, int k, const s3_arg *args, cl_uint n_args, uint32_t count,
                            pgt_error *err) {
    pgt_result r = PGT_OK;
    const int fresh = err && err->code == PGT_OK;
    cl_kernel kernel = c->cl->kernels[k];
    if (count == 0) return PGT_OK;
    cl_uint i = 0;
    for (; i < n_args; ++i) PGT_CL_CHECK(clSetKernelArg(kernel, i, args[i].size, args[i].value));
    const size_t local = PGT_S3_GROUP_SIZE;
    const size_t global = ((size_t)count + local - 1) / local * local;
    cl_event *ev = NULL;
    if (c->cl->profile) {
        assert(c->n_events < c->cap_events);
        c->event_k[c->n_events] = (uint8_t)k;
        ev = &c->events[c->n_events++];
    }
    PGT_CL_CHECK(
        clEnqueueNDRangeKernel(c->cl->queue, kernel, 1, NULL, &global, &local, 0, NULL, ev));
cleanup:
    if (r != PGT_OK && fresh) { /* name the kernel in the message this call recorded */
        const size_t n = strlen(err->message);
        if (i < n_args)
            snprintf(err->message + n, sizeof(err->message) - n, " [kernel %s, argument %u]",
                     pgt_cl_kernel_names[k], (unsigned)i);
        else
            snprintf(err->message + n, sizeof(err->message) - n, " [kernel %s]",
                     pgt_cl_kernel_names[k]);
    }
    return r;
}

/* Classify and scan one non-uniform step: fills sc and returns the points and triangles the
 * step emits. */
static pgt_result s3_classify_and_scan(s3_call *c, const s3_level *in, pgt_s3_params p,
                                       cl_uint flags, s3_scratch *sc, uint32_t *out_points,
                                       uint32_t *out_tris, pgt_error *err) {
    pgt_result r = PGT_OK;
    pgt_cl *cl = c->cl;
    /* Levels of the scan: level 0 is the F faces at offset 0; level l + 1 holds the block sums
     * of level l right after it, until one block remains: its sum is the total. */
    uint32_t off[8], n[8], levels = 0;
    assert(in->F > 0); /* a step with no face is uniform */
    off[0] = 0, n[0] = in->F;
    for (;;) {
        assert(levels + 1 < 8);
        off[levels + 1] = off[levels] + n[levels];
        n[levels + 1] = (n[levels] + PGT_CL_S3_SCAN_BLOCK - 1) / PGT_CL_S3_SCAN_BLOCK;
        levels++;
        if (n[levels] == 1) break;
    }
    const uint64_t scan_bytes = ((uint64_t)off[levels] + 1) * sizeof(cl_uint);
    if ((r = pgt_cl_buffer(cl, &sc->kind, (uint64_t)in->F * 4, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &sc->bslot, (uint64_t)in->F * 4, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &sc->scan_a, scan_bytes, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &sc->scan_b, scan_bytes, err)) != PGT_OK)
        return r;
    cl_mem prot = flags & PGT_CL_S3_PROT ? in->prot : cl->placeholder;
    p.first = 0, p.count = in->F;
    const s3_arg classify[] = {S3_ARG(p),          S3_ARG(flags),     S3_ARG(in->opp),
                               S3_ARG(prot),       S3_ARG(sc->kind),  S3_ARG(sc->bslot),
                               S3_ARG(sc->scan_a), S3_ARG(sc->scan_b)};
    r = s3_launch(c, PGT_CL_K_S3_CLASSIFY, classify, S3_COUNT(classify), in->F, err);
    for (uint32_t l = 0; r == PGT_OK && l < levels; ++l) {
        const s3_arg scan[] = {S3_ARG(sc->scan_a), S3_ARG(sc->scan_b), S3_ARG(off[l]), S3_ARG(n[l]),
                               S3_ARG(off[l + 1])};
        r = s3_launch(c, PGT_CL_K_S3_SCAN, scan, S3_COUNT(scan), n[l + 1] * PGT_S3_GROUP_SIZE, err);
    }
    /* The top level scanned in one block needs no add; the ones below get their block sums. */
    for (uint32_t l = levels - 1; r == PGT_OK && l-- > 0;) {
        const s3_arg add[] = {S3_ARG(sc->scan_a), S3_ARG(sc->scan_b), S3_ARG(off[l]), S3_ARG(n[l]),
                              S3_ARG(off[l + 1])};
        r = s3_launch(c, PGT_CL_K_S3_SCAN_ADD, add, S3_COUNT(add), n[l], err);
    }
    if (r != PGT_OK) return r;
    cl_uint totals[2];
    const size_t at = (size_t)off[levels] * sizeof(cl_uint);
    /* Blocking both: a pending read must not outlive `totals` when the second one fails. */
    PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, sc->scan_a, CL_TRUE, at, sizeof(cl_uint),
                                     &totals[0], 0, NULL, NULL));
    PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, sc->scan_b, CL_TRUE, at, sizeof(cl_uint),
                                     &totals[1], 0, NULL, NULL));
    *out_points = totals[0], *out_tris = totals[1];
cleanup:
    return r;
}

/* Appends one profile event per launch (all complete) and sums their device time. */
static pgt_result s3_collect_events(s3_call *c, double *device_ms, pgt_error *err) {
    pgt_result r = PGT_OK;
    for (uint32_t i = 0; i < c->n_events; ++i) {
        cl_ulong t0 = 0, t1 = 0;
        PGT_CL_CHECK(clGetEventProfilingInfo(c->events[i], CL_PROFILING_COMMAND_START, sizeof(t0),
                                             &t0, NULL));
        PGT_CL_CHECK(
            clGetEventProfilingInfo(c->events[i], CL_PROFILING_COMMAND_END, sizeof(t1), &t1, NULL));
        const double ms = t1 > t0 ? (double)(t1 - t0) * 1e-6 : 0.0;
        *device_ms += ms;
        if (!pgt_gpu_profile_add(c->cl->profile, pgt_cl_kernel_names[c->event_k[i]], ms))
            return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "OpenCL: out of memory (profile)");
    }
cleanup:
    return r;
}

/* k = 0: the reference's copy, on the host, without UVs like every output of this backend. */
pgt_result pgt_cl_sqrt3(pgt_cl *cl, pgt_mesh *out, const pgt_mesh *in,
                        const pgt_sqrt3_options *opts, pgt_gpu_times *times, pgt_error *err) {
    pgt_sqrt3_options defaults = {1, 1, NULL, NULL, NULL, NULL, NULL};
    if (!opts) opts = &defaults;
    if (times) memset(times, 0, sizeof(*times));
    if (!cl || !out) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "sqrt3: no context");
    memset(out, 0, sizeof(*out));
    /* The reference's checks and level-0 arrays (gpu_shared/host.c), shared by every backend. */
    pgt_gpu_sqrt3_input prep;
    pgt_result r = pgt_gpu_sqrt3_prepare(&prep, in, opts, err);
    if (r != PGT_OK) return r;
    const uint32_t k = opts->iterations;
    if (k == 0) {
        r = pgt_gpu_sqrt3_copy(out, in, opts, &prep.adj, err);
        pgt_gpu_sqrt3_input_free(&prep);
        return r;
    }
    const pgt_adjacency adj = prep.adj;
    const uint32_t *vh = prep.vh, *prot = prep.prot, n_protected = prep.n_protected;
    const uint32_t alpha_count = prep.alpha_count;
    const float *alpha = prep.alpha;
    uint32_t v_bound = 0, f_bound = 0; /* checked by the preparation: cannot fail here */
    pgt_sqrt3_bound(in->vertex_count, in->face_count, 0, k, &v_bound, &f_bound, NULL);

    const uint32_t V0 = in->vertex_count, F0 = in->face_count;
    const int want_parent = opts->out_face_parent || in->labels;
    s3_call call = {cl, NULL, NULL, 0, 0};
    s3_level cur = {0}, nxt = {0};
    s3_scratch sc = {0};
    cl_mem alpha_buf = NULL;
    uint32_t *parent = NULL, *tmp = NULL, *prot_dl = NULL;
    double t0;

    /* Host arrays of level 0, as the reference makes them. */
    if (want_parent) parent = malloc(((size_t)F0 + 1) * sizeof(uint32_t));
    if (cl->profile) {
        call.cap_events = k * S3_LAUNCHES_PER_STEP;
        call.events = calloc(call.cap_events, sizeof(cl_event));
        call.event_k = calloc(call.cap_events, 1);
    }
    if ((want_parent && !parent) || (cl->profile && (!call.events || !call.event_k))) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
        goto cleanup;
    }
    if (parent)
        for (uint32_t f = 0; f < F0; ++f) parent[f] = f;

    const cl_uint flags =
        (n_protected ? PGT_CL_S3_PROT : 0u) | (want_parent ? PGT_CL_S3_PARENT : 0u);
    cur.V = V0, cur.F = F0;

    /* ---- upload level 0 ---- */
    t0 = pgt_gpu_now_ms();
    if ((r = pgt_cl_buffer(cl, &cur.pos, (uint64_t)V0 * 12, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &cur.idx, (uint64_t)F0 * 12, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &cur.opp, (uint64_t)F0 * 12, err)) != PGT_OK ||
        (r = pgt_cl_buffer(cl, &cur.vh, (uint64_t)V0 * 4, err)) != PGT_OK ||
        (n_protected && (r = pgt_cl_buffer(cl, &cur.prot, (uint64_t)F0 * 4, err)) != PGT_OK) ||
        (want_parent && (r = pgt_cl_buffer(cl, &cur.parent, (uint64_t)F0 * 4, err)) != PGT_OK) ||
        (r = pgt_cl_buffer(cl, &alpha_buf, (uint64_t)alpha_count * 4, err)) != PGT_OK)
        goto cleanup;
    if (V0) {
        PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.pos, CL_FALSE, 0, (size_t)V0 * 12,
                                          in->positions, 0, NULL, NULL));
        PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.vh, CL_FALSE, 0, (size_t)V0 * 4, vh, 0,
                                          NULL, NULL));
    }
    if (F0) {
        PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.idx, CL_FALSE, 0, (size_t)F0 * 12,
                                          in->indices, 0, NULL, NULL));
        PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.opp, CL_FALSE, 0, (size_t)F0 * 12,
                                          adj.opposite, 0, NULL, NULL));
        if (n_protected)
            PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.prot, CL_FALSE, 0, (size_t)F0 * 4,
                                              prot, 0, NULL, NULL));
        if (want_parent)
            PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, cur.parent, CL_FALSE, 0, (size_t)F0 * 4,
                                              parent, 0, NULL, NULL));
    }
    PGT_CL_CHECK(clEnqueueWriteBuffer(cl->queue, alpha_buf, CL_FALSE, 0, (size_t)alpha_count * 4,
                                      alpha, 0, NULL, NULL));
    PGT_CL_CHECK(clFinish(cl->queue));
    if (times) times->upload_ms = pgt_gpu_now_ms() - t0;

    /* ---- the iterations ---- */
    uint32_t border = adj.border_half_edges; /* of the current level */
    for (uint32_t it = 0; it < k; ++it) {
        pgt_s3_params p = {0};
        p.V = cur.V, p.F = cur.F;
        p.even = (it % 2) == 1; /* CGAL: refine_border on i % 2 == 1, restarting every call */
        p.is_uniform = n_protected == 0 && (!p.even || border == 0);
        p.with_adj = it + 1 < k || opts->out_opposite != NULL;
        p.alpha_count = alpha_count;
        /* Closed and uniform: the reference's fast path, same bytes without the tests for
         * borders, protection and classification. */
        const int closed = p.is_uniform && border == 0;
        uint32_t np = cur.F, nf = 3 * cur.F; /* uniform: one point, three triangles a face */
        if (!p.is_uniform &&
            (r = s3_classify_and_scan(&call, &cur, p, flags, &sc, &np, &nf, err)) != PGT_OK)
            goto cleanup;
        nxt.V = cur.V + np, nxt.F = nf;
        assert(nxt.V <= v_bound && nxt.F <= f_bound);
        if ((r = pgt_cl_buffer(cl, &nxt.pos, (uint64_t)nxt.V * 12, err)) != PGT_OK ||
            (r = pgt_cl_buffer(cl, &nxt.idx, (uint64_t)nxt.F * 12, err)) != PGT_OK ||
            (p.with_adj &&
             (r = pgt_cl_buffer(cl, &nxt.opp, (uint64_t)nxt.F * 12, err)) != PGT_OK) ||
            (p.with_adj && (r = pgt_cl_buffer(cl, &nxt.vh, (uint64_t)nxt.V * 4, err)) != PGT_OK) ||
            (n_protected &&
             (r = pgt_cl_buffer(cl, &nxt.prot, (uint64_t)nxt.F * 4, err)) != PGT_OK) ||
            (want_parent &&
             (r = pgt_cl_buffer(cl, &nxt.parent, (uint64_t)nxt.F * 4, err)) != PGT_OK))
            goto cleanup;
        /* Buffers a launch does not read are bound to the placeholder. */
        const cl_mem ph = cl->placeholder;
        const cl_mem kind = p.is_uniform ? ph : sc.kind, bslot = p.is_uniform ? ph : sc.bslot;
        const cl_mem pt_off = p.is_uniform ? ph : sc.scan_a,
                     face_off = p.is_uniform ? ph : sc.scan_b;
        const cl_mem in_prot = n_protected ? cur.prot : ph, out_prot = n_protected ? nxt.prot : ph;
        const cl_mem in_parent = want_parent ? cur.parent : ph;
        const cl_mem out_parent = want_parent ? nxt.parent : ph;
        const cl_mem out_opp = p.with_adj ? nxt.opp : ph, out_vh = p.with_adj ? nxt.vh : ph;

        if (closed) {
            p.first = 0, p.count = cur.V;
            const s3_arg vertices[] = {S3_ARG(p),       S3_ARG(cur.pos), S3_ARG(cur.idx),
                                       S3_ARG(cur.opp), S3_ARG(cur.vh),  S3_ARG(alpha_buf),
                                       S3_ARG(nxt.pos), S3_ARG(out_vh)};
            if ((r = s3_launch(&call, PGT_CL_K_S3_VERTICES_CLOSED, vertices, S3_COUNT(vertices),
                               cur.V, err)) != PGT_OK)
                goto cleanup;
            p.first = 0, p.count = cur.F;
            const s3_arg faces[] = {S3_ARG(p),       S3_ARG(flags),     S3_ARG(cur.pos),
                                    S3_ARG(cur.idx), S3_ARG(cur.opp),   S3_ARG(in_parent),
                                    S3_ARG(nxt.pos), S3_ARG(nxt.idx),   S3_ARG(out_opp),
                                    S3_ARG(out_vh),  S3_ARG(out_parent)};
            if ((r = s3_launch(&call, PGT_CL_K_S3_FACES_CLOSED, faces, S3_COUNT(faces), cur.F,
                               err)) != PGT_OK)
                goto cleanup;
        } else {
            p.first = 0, p.count = cur.V;
            const s3_arg vertices[] = {S3_ARG(p),        S3_ARG(flags),     S3_ARG(cur.pos),
                                       S3_ARG(cur.idx),  S3_ARG(cur.opp),   S3_ARG(cur.vh),
                                       S3_ARG(in_prot),  S3_ARG(alpha_buf), S3_ARG(kind),
                                       S3_ARG(face_off), S3_ARG(nxt.pos),   S3_ARG(out_vh)};
            if ((r = s3_launch(&call, PGT_CL_K_S3_VERTICES, vertices, S3_COUNT(vertices), cur.V,
                               err)) != PGT_OK)
                goto cleanup;
            p.first = 0, p.count = cur.F;
            const s3_arg faces[] = {
                S3_ARG(p),       S3_ARG(flags),     S3_ARG(cur.pos),  S3_ARG(cur.idx),
                S3_ARG(cur.opp), S3_ARG(in_parent), S3_ARG(kind),     S3_ARG(bslot),
                S3_ARG(pt_off),  S3_ARG(face_off),  S3_ARG(nxt.pos),  S3_ARG(nxt.idx),
                S3_ARG(out_opp), S3_ARG(out_vh),    S3_ARG(out_prot), S3_ARG(out_parent)};
            if ((r = s3_launch(&call, PGT_CL_K_S3_FACES, faces, S3_COUNT(faces), cur.F, err)) !=
                PGT_OK)
                goto cleanup;
        }
        /* Released now, freed by OpenCL once the launches that read them are done. */
        s3_scratch_release(&sc);
        s3_level_release(&cur);
        cur = nxt;
        memset(&nxt, 0, sizeof(nxt));
        if (p.even) border *= 3; /* every border edge was trisected */
    }
    /* The download is timed alone: wait for the kernels first. */
    PGT_CL_CHECK(clFinish(cl->queue));
    if (cl->profile) {
        double device_ms = 0.0;
        if ((r = s3_collect_events(&call, &device_ms, err)) != PGT_OK) goto cleanup;
        if (times) times->device_ms = device_ms;
    }

    /* ---- download the last level ---- */
    t0 = pgt_gpu_now_ms();
    if ((r = pgt_mesh_create(out, cur.V, cur.F, 0, in->labels != NULL, err)) != PGT_OK)
        goto cleanup;
    const size_t F = cur.F;
    uint32_t *parents = opts->out_face_parent;
    if (!parents && in->labels) {
        parents = tmp = malloc((F + 1) * sizeof(uint32_t));
        if (!tmp) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
            goto cleanup;
        }
    }
    if (cur.V)
        PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, cur.pos, CL_FALSE, 0, (size_t)cur.V * 12,
                                         out->positions, 0, NULL, NULL));
    if (F) {
        PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, cur.idx, CL_FALSE, 0, F * 12, out->indices, 0,
                                         NULL, NULL));
        if (parents)
            PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, cur.parent, CL_FALSE, 0, F * 4, parents, 0,
                                             NULL, NULL));
        if (opts->out_opposite)
            PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, cur.opp, CL_FALSE, 0, F * 12,
                                             opts->out_opposite, 0, NULL, NULL));
        if (opts->out_protected && n_protected) {
            /* uint flags on the device (sqrt3_layout.h), bytes in the API */
            prot_dl = malloc((F + 1) * sizeof(uint32_t));
            if (!prot_dl) {
                r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
                goto cleanup;
            }
            PGT_CL_CHECK(clEnqueueReadBuffer(cl->queue, cur.prot, CL_FALSE, 0, F * 4, prot_dl, 0,
                                             NULL, NULL));
        }
    }
    PGT_CL_CHECK(clFinish(cl->queue));
    if (opts->out_protected) {
        if (n_protected)
            for (size_t f = 0; f < F; ++f) opts->out_protected[f] = (uint8_t)prot_dl[f];
        else
            memset(opts->out_protected, 0, F); /* no protected face: none was made */
    }
    if (in->labels)
        for (size_t t = 0; t < F; ++t) out->labels[t] = in->labels[parents[t]];
    if (times) times->download_ms = pgt_gpu_now_ms() - t0;

cleanup:
    /* Nothing may still read or write host memory freed below. */
    clFinish(cl->queue);
    for (uint32_t i = 0; i < call.n_events; ++i)
        if (call.events[i]) clReleaseEvent(call.events[i]);
    free(call.events), free(call.event_k);
    s3_scratch_release(&sc);
    s3_level_release(&cur);
    s3_level_release(&nxt);
    s3_release(&alpha_buf);
    free(parent), free(tmp), free(prot_dl);
    pgt_gpu_sqrt3_input_free(&prep);
    if (r != PGT_OK) {
        pgt_mesh_destroy(out);
        if (times) memset(times, 0, sizeof(*times));
    }
    return r;
}
