/* pgt harness: the Embree cross-check of procedural facades (facade_embree.h says what). */
#include "facade_embree.h"

#include <embree3/rtcore.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/parallel.h"

/* Pixels per side of a packet tile (4 x 4 = rtcIntersect16). */
#define TILE 4u

/* ---- Embree errors and memory ---- */

typedef struct monitor {
    atomic_llong current, peak;
    pthread_mutex_t lock;
    int error_set;
    char message[PGT_ERROR_MESSAGE_SIZE];
} monitor;

static bool on_memory(void *user, ssize_t bytes, bool post) {
    (void)post;
    monitor *m = user;
    const long long now = atomic_fetch_add(&m->current, (long long)bytes) + (long long)bytes;
    long long peak = atomic_load(&m->peak);
    while (now > peak && !atomic_compare_exchange_weak(&m->peak, &peak, now)) {
    }
    return true;
}

static void on_error(void *user, enum RTCError code, const char *str) {
    monitor *m = user;
    pthread_mutex_lock(&m->lock);
    if (!m->error_set) {
        m->error_set = 1;
        snprintf(m->message, sizeof m->message, "embree: error %d: %s", (int)code, str ? str : "");
    }
    pthread_mutex_unlock(&m->lock);
}

static pgt_result status(RTCDevice dev, monitor *m, const char *what, pgt_error *err) {
    const enum RTCError code = rtcGetDeviceError(dev);
    pthread_mutex_lock(&m->lock);
    const int set = m->error_set;
    pthread_mutex_unlock(&m->lock);
    if (set) return pgt_error_set(err, PGT_ERROR_BACKEND, "%s (%s)", m->message, what);
    if (code != RTC_ERROR_NONE)
        return pgt_error_set(err, PGT_ERROR_BACKEND, "embree: error %d (%s)", (int)code, what);
    return PGT_OK;
}

/* ---- scene ---- */

/* Embree's build progress n in [0, 1] as triangles of the progress's stage (rtcSetSceneProgress
 * MonitorFunction: may run on Embree's threads; returning true lets the build go on). */
typedef struct build_progress {
    pgt_progress *progress;
    uint32_t triangles;
} build_progress;

static bool on_build_progress(void *vp, double n) {
    const build_progress *b = vp;
    if (n >= 0.0 && n <= 1.0) pgt_progress_raise(b->progress, (uint64_t)(n * b->triangles));
    return true;
}

pgt_result pgt_facade_embree_create(pgt_facade_embree *e, const pgt_facade_mesh *mesh,
                                    uint32_t threads, pgt_progress *progress, pgt_error *err) {
    memset(e, 0, sizeof *e);
    /* an explicit mesh without triangles (a valid grammar that generates nothing) is a scene
     * without geometry: every ray misses, as every ray of ours does */
    const double t0 = pgt_cli_now_ms();
    monitor *m = calloc(1, sizeof *m);
    e->vertices = malloc((3u * (size_t)mesh->vertex_count + 1u) * sizeof(float));
    if (!m || !e->vertices) {
        free(m);
        free(e->vertices);
        e->vertices = NULL;
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "embree check: out of memory");
    }
    atomic_init(&m->current, 0);
    atomic_init(&m->peak, 0);
    pthread_mutex_init(&m->lock, NULL);
    e->monitor = m;
    e->mesh = mesh;
    e->threads = threads ? threads : pgt_cli_cpu_count();
    if (mesh->vertex_count) /* an empty mesh may have no positions array (memcpy from NULL) */
        memcpy(e->vertices, mesh->positions, 3u * (size_t)mesh->vertex_count * sizeof(float));
    e->vertices[3u * (size_t)mesh->vertex_count] = 0.0f;
    e->buffer_bytes = (3u * (size_t)mesh->vertex_count + 1u) * sizeof(float) +
                      3u * (size_t)mesh->triangle_count * sizeof(uint32_t);
    char config[64];
    snprintf(config, sizeof config, "threads=%u", e->threads);
    RTCDevice dev = rtcNewDevice(config);
    if (!dev)
        return pgt_error_set(err, PGT_ERROR_BACKEND, "embree: error %d (rtcNewDevice)",
                             (int)rtcGetDeviceError(NULL));
    e->device = dev;
    rtcSetDeviceErrorFunction(dev, on_error, m);
    rtcSetDeviceMemoryMonitorFunction(dev, on_memory, m);
    RTCScene scene = rtcNewScene(dev);
    e->scene = scene;
    pgt_result r = status(dev, m, "rtcNewScene", err);
    if (r != PGT_OK) return r;
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    pgt_progress_stage(progress, "Embree's BVH", mesh->triangle_count, "triangles");
    if (mesh->triangle_count == 0) {
        rtcCommitScene(scene);
        if ((r = status(dev, m, "rtcCommitScene", err)) != PGT_OK) return r;
        e->build_ms = pgt_cli_now_ms() - t0;
        e->embree_bytes = (size_t)atomic_load(&m->peak);
        return PGT_OK;
    }
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, e->vertices, 0,
                               3u * sizeof(float), mesh->vertex_count);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh->indices, 0,
                               3u * sizeof(uint32_t), mesh->triangle_count);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, 0);
    rtcReleaseGeometry(g);
    if ((r = status(dev, m, "geometry", err)) != PGT_OK) return r;
    /* the build's progress, set around the commit only: bp is this call's */
    build_progress bp = {progress, mesh->triangle_count};
    if (progress) rtcSetSceneProgressMonitorFunction(scene, on_build_progress, &bp);
    rtcCommitScene(scene);
    if (progress) rtcSetSceneProgressMonitorFunction(scene, NULL, NULL);
    if ((r = status(dev, m, "rtcCommitScene", err)) != PGT_OK) return r;
    e->build_ms = pgt_cli_now_ms() - t0;
    e->embree_bytes = (size_t)atomic_load(&m->peak);
    return PGT_OK;
}

void pgt_facade_embree_destroy(pgt_facade_embree *e) {
    if (!e) return;
    if (e->scene) rtcReleaseScene((RTCScene)e->scene);
    if (e->device) rtcReleaseDevice((RTCDevice)e->device);
    if (e->monitor) {
        monitor *m = e->monitor;
        pthread_mutex_destroy(&m->lock);
        free(m);
    }
    free(e->vertices);
    memset(e, 0, sizeof *e);
}

pgt_result pgt_facade_embree_hits_create(pgt_facade_embree_hits *h, uint32_t width, uint32_t height,
                                         pgt_error *err) {
    memset(h, 0, sizeof *h);
    const size_t n = (size_t)width * height;
    h->width = width, h->height = height;
    h->t = malloc(n * sizeof(float));
    h->tri = malloc(n * sizeof(uint32_t));
    h->u = malloc(n * sizeof(float));
    h->v = malloc(n * sizeof(float));
    if (!h->t || !h->tri || !h->u || !h->v) {
        pgt_facade_embree_hits_destroy(h);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "embree check: out of memory");
    }
    return PGT_OK;
}

void pgt_facade_embree_hits_destroy(pgt_facade_embree_hits *h) {
    if (!h) return;
    free(h->t), free(h->tri), free(h->u), free(h->v);
    memset(h, 0, sizeof *h);
}

/* ---- tracing ---- */

typedef struct trace_job {
    RTCScene scene;
    const pgt_facade_camera *cam;
    pgt_facade_embree_hits *out;
    uint32_t tiles_x;
    int coherent; /* RTC_INTERSECT_CONTEXT_FLAG_COHERENT (else INCOHERENT) */
    struct RTCRayHit *stream[PGT_MAX_THREADS]; /* per worker: one tile row of rays */
} trace_job;

static void store(trace_job *job, uint32_t x, uint32_t y, float tfar, unsigned geom, unsigned prim,
                  float u, float v) {
    const size_t i = (size_t)y * job->out->width + x;
    if (geom == RTC_INVALID_GEOMETRY_ID) {
        job->out->t[i] = INFINITY;
        job->out->tri[i] = PGT_NONE;
        job->out->u[i] = job->out->v[i] = 0.0f;
    } else {
        job->out->t[i] = tfar;
        job->out->tri[i] = prim;
        job->out->u[i] = u, job->out->v[i] = v;
    }
}

static void trace_packets(void *ctx_, uint32_t begin, uint32_t end, uint32_t worker) {
    (void)worker;
    trace_job *job = ctx_;
    const uint32_t W = job->out->width, H = job->out->height;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags =
        job->coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    /* Embree's 16-wide kernels read the packet and the valid mask with aligned 64-byte loads:
     * RTCRayHit16 carries that alignment, the int array needs it spelled out (without it the
     * AVX-512 kernels fault where the stack puts it elsewhere, as ASan's layout did) */
    struct RTCRayHit16 rh;
    _Alignas(64) int valid[16];
    for (uint32_t ty = begin; ty < end; ++ty)
        for (uint32_t tx = 0; tx < job->tiles_x; ++tx) {
            for (uint32_t i = 0; i < 16u; ++i) {
                const uint32_t x = tx * TILE + i % TILE, y = ty * TILE + i / TILE;
                float o[3] = {0, 0, 0}, d[3] = {0, 0, 1};
                valid[i] = x < W && y < H ? -1 : 0;
                if (valid[i]) pgt_facade_camera_ray(job->cam, x, y, o, d);
                rh.ray.org_x[i] = o[0], rh.ray.org_y[i] = o[1], rh.ray.org_z[i] = o[2];
                rh.ray.dir_x[i] = d[0], rh.ray.dir_y[i] = d[1], rh.ray.dir_z[i] = d[2];
                rh.ray.tnear[i] = 0.0f, rh.ray.tfar[i] = INFINITY, rh.ray.time[i] = 0.0f;
                rh.ray.mask[i] = 0xFFFFFFFFu, rh.ray.id[i] = i, rh.ray.flags[i] = 0;
                rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, job->scene, &ctx, &rh);
            for (uint32_t i = 0; i < 16u; ++i)
                if (valid[i])
                    store(job, tx * TILE + i % TILE, ty * TILE + i / TILE, rh.ray.tfar[i],
                          rh.hit.geomID[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]);
        }
}

static void trace_streams(void *ctx_, uint32_t begin, uint32_t end, uint32_t worker) {
    trace_job *job = ctx_;
    const uint32_t W = job->out->width, H = job->out->height;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    struct RTCRayHit *rays = job->stream[worker];
    uint32_t *px = (uint32_t *)(rays + (size_t)job->tiles_x * 16u);
    for (uint32_t ty = begin; ty < end; ++ty) {
        uint32_t n = 0;
        for (uint32_t tx = 0; tx < job->tiles_x; ++tx) /* tile by tile: coherent neighbours */
            for (uint32_t i = 0; i < 16u; ++i) {
                const uint32_t x = tx * TILE + i % TILE, y = ty * TILE + i / TILE;
                if (x >= W || y >= H) continue;
                struct RTCRayHit *r = &rays[n];
                float o[3], d[3];
                pgt_facade_camera_ray(job->cam, x, y, o, d);
                memset(r, 0, sizeof *r);
                r->ray.org_x = o[0], r->ray.org_y = o[1], r->ray.org_z = o[2];
                r->ray.dir_x = d[0], r->ray.dir_y = d[1], r->ray.dir_z = d[2];
                r->ray.tnear = 0.0f, r->ray.tfar = INFINITY, r->ray.mask = 0xFFFFFFFFu;
                r->hit.geomID = RTC_INVALID_GEOMETRY_ID;
                r->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                px[2u * n] = x, px[2u * n + 1u] = y;
                ++n;
            }
        rtcIntersect1M(job->scene, &ctx, rays, n, sizeof *rays);
        for (uint32_t k = 0; k < n; ++k)
            store(job, px[2u * k], px[2u * k + 1u], rays[k].ray.tfar, rays[k].hit.geomID,
                  rays[k].hit.primID, rays[k].hit.u, rays[k].hit.v);
    }
}

pgt_result pgt_facade_embree_trace(pgt_facade_embree *e, const pgt_facade_camera *cam,
                                   pgt_facade_embree_mode mode, pgt_facade_embree_hits *out,
                                   double *ms, pgt_error *err) {
    if (out->width != cam->width || out->height != cam->height)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "embree check: hits of %u x %u for a camera of %u x %u", out->width,
                             out->height, cam->width, cam->height);
    trace_job *job = calloc(1, sizeof *job);
    if (!job) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "embree check: out of memory");
    job->scene = (RTCScene)e->scene;
    job->cam = cam;
    job->out = out;
    job->tiles_x = (cam->width + TILE - 1u) / TILE;
    job->coherent = mode != PGT_FACADE_EMBREE_CHECK_RAYS;
    const uint32_t tiles_y = (cam->height + TILE - 1u) / TILE;
    const uint32_t workers = e->threads < PGT_MAX_THREADS ? e->threads : PGT_MAX_THREADS;
    pgt_result r = PGT_OK;
    if (mode == PGT_FACADE_EMBREE_STREAMS)
        for (uint32_t w = 0; w < workers; ++w) {
            /* rays then their pixel coordinates */
            const size_t n = (size_t)job->tiles_x * 16u;
            job->stream[w] = aligned_alloc(
                64, ((n * sizeof(struct RTCRayHit) + n * 2u * sizeof(uint32_t)) + 63u) / 64u * 64u);
            if (!job->stream[w]) {
                r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "embree check: out of memory");
                goto done;
            }
        }
    const double t0 = pgt_cli_now_ms();
    pgt_parallel_for_items(tiles_y, job->tiles_x * 16u, workers,
                           mode == PGT_FACADE_EMBREE_STREAMS ? trace_streams : trace_packets, job);
    if (ms) *ms = pgt_cli_now_ms() - t0;
    r = status((RTCDevice)e->device, e->monitor, "tracing", err);
done:
    for (uint32_t w = 0; w < PGT_MAX_THREADS; ++w) free(job->stream[w]);
    free(job);
    return r;
}

/* ---- comparison ---- */

typedef struct rect_key {
    uint32_t facade, node, kind, surface;
} rect_key;

static int key_cmp(const void *a_, const void *b_) {
    const rect_key *a = a_, *b = b_;
    if (a->facade != b->facade) return a->facade < b->facade ? -1 : 1;
    if (a->node != b->node) return a->node < b->node ? -1 : 1;
    if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
    if (a->surface != b->surface) return a->surface < b->surface ? -1 : 1;
    return 0;
}

static double seg_dist(const double p[3], const float *a, const float *b) {
    double ab[3], ap[3], t = 0.0, l2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        ab[k] = (double)b[k] - a[k], ap[k] = p[k] - a[k];
        t += ab[k] * ap[k], l2 += ab[k] * ab[k];
    }
    t = l2 > 0.0 ? fmin(1.0, fmax(0.0, t / l2)) : 0.0;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double q = ap[k] - t * ab[k];
        d2 += q * q;
    }
    return sqrt(d2);
}

/* An edge of the explicit mesh by its corners' positions, the lexicographically smaller first
 * (the triangles of one rectangle or roof have vertices of their own or shared: positions, not
 * indices, tell a shared edge). */
typedef struct pos_edge {
    const float *a, *b;
    int inner; /* shared by two triangles of the surface (surface_edges) */
} pos_edge;

static int pos_cmp(const float *a, const float *b) {
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int edge_cmp(const void *x, const void *y) {
    const pos_edge *e = x, *f = y;
    const int c = pos_cmp(e->a, f->a);
    return c ? c : pos_cmp(e->b, f->b);
}

/* The edges of the surface made of triangles tris[0 .. n) into out (at most 3n edges): first
 * its boundary, the edges no two of them share (a rectangle's 4 sides, a roof's outline), then
 * its inner edges, each once (a rectangle's diagonal, the inner edges of a roof's ear clipping).
 * Returns the boundary's count; *inner gets the inner edges' count. */
static uint32_t surface_edges(const pgt_facade_mesh *m, const uint32_t *tris, uint32_t n,
                              pos_edge *out, uint32_t *inner) {
    uint32_t e = 0;
    for (uint32_t a = 0; a < n; ++a)
        for (uint32_t k = 0; k < 3; ++k) {
            const float *p0 = m->positions + 3u * (size_t)m->indices[3u * (size_t)tris[a] + k];
            const float *p1 =
                m->positions + 3u * (size_t)m->indices[3u * (size_t)tris[a] + (k + 1u) % 3u];
            const int swap = pos_cmp(p0, p1) > 0;
            out[e].a = swap ? p1 : p0, out[e].b = swap ? p0 : p1;
            e++;
        }
    qsort(out, e, sizeof *out, edge_cmp);
    /* each edge once (u <= k: the writes never pass the reads), then the boundary's in front */
    uint32_t u = 0;
    for (uint32_t k = 0; k < e;) {
        uint32_t r = k + 1;
        while (r < e && !edge_cmp(&out[k], &out[r])) r++;
        out[u] = out[k], out[u].inner = r > k + 1, u++;
        k = r;
    }
    uint32_t b = 0, s = u;
    while (b < s)
        if (!out[b].inner)
            b++;
        else {
            const pos_edge t = out[b];
            out[b] = out[--s], out[s] = t;
        }
    *inner = u - b;
    return b;
}

/* Distance from p to the nearest of n edges. */
static double edges_dist(const pos_edge *edges, uint32_t n, const double p[3]) {
    double best = INFINITY;
    for (uint32_t k = 0; k < n; ++k) best = fmin(best, seg_dist(p, edges[k].a, edges[k].b));
    return best;
}

/* Distance from p to triangle (a, b, c) (the closest point by the triangle's Voronoi regions,
 * Ericson, Real-Time Collision Detection 5.1.5), in double. */
static double tri_dist(const double p[3], const float *fa, const float *fb, const float *fc) {
    double a[3], ab[3], ac[3], ap[3], q[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = fa[k], ab[k] = (double)fb[k] - fa[k], ac[k] = (double)fc[k] - fa[k];
        ap[k] = p[k] - a[k];
    }
    const double d1 = ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2];
    const double d2 = ac[0] * ap[0] + ac[1] * ap[1] + ac[2] * ap[2];
    const double aa = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    const double cc = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
    const double bc = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
    const double den = aa * cc - bc * bc;
    double v = den > 0.0 ? (cc * d1 - bc * d2) / den : -1.0;
    double w = den > 0.0 ? (aa * d2 - bc * d1) / den : -1.0;
    if (v >= 0.0 && w >= 0.0 && v + w <= 1.0) { /* inside: the plane's distance */
        for (int k = 0; k < 3; ++k) q[k] = a[k] + v * ab[k] + w * ac[k] - p[k];
        return sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    }
    /* outside (or degenerate): the nearest of the three edges */
    return fmin(seg_dist(p, fa, fb), fmin(seg_dist(p, fb, fc), seg_dist(p, fc, fa)));
}

/* A disagreement being explained: its keys, their triangles (tris[first .. + n) of the
 * comparison's list, every one: a roof has as many as its footprint's corners less 2), their
 * boundary (edges[efirst .. + en)) and their inner edges (the next ein). */
typedef struct wanted {
    rect_key key;
    uint32_t first, n, efirst, en, ein;
} wanted;

static int wanted_cmp(const void *a, const void *b) {
    return key_cmp(&((const wanted *)a)->key, &((const wanted *)b)->key);
}

/* Counts each wanted key's triangles into w[].n (from 0); with tris, also lists them at
 * tris[w.first ..] (w[].n reset first: the second pass of a count-then-fill). */
static void key_triangles(const pgt_facade_mesh *mesh, wanted *w, size_t wn, uint32_t *tris) {
    for (size_t k = 0; k < wn; ++k) w[k].n = 0;
    for (uint32_t tri = 0; tri < mesh->triangle_count; ++tri) {
        wanted probe;
        probe.key =
            (rect_key){mesh->facade[tri], mesh->node[tri], mesh->kind[tri], mesh->surface[tri]};
        wanted *hit = bsearch(&probe, w, wn, sizeof *w, wanted_cmp);
        if (!hit) continue;
        if (tris) tris[hit->first + hit->n] = tri;
        hit->n++;
    }
}

/* How far along the ray (o, d) a hit at depth t on triangle tri's plane may move when the plane
 * moves PGT_FACADE_CHECK_PLANE_EPS float epsilons of the coordinates' magnitude (the largest
 * |coordinate| of o and the hit) along its normal: that distance / |cos a|, a the angle between
 * the ray and the normal (INFINITY for a ray in the plane; 0 for a degenerate triangle). The
 * rounding of either side's coordinates moves a hit this much in depth, and along the surface:
 * at street level, nearly parallel to a wall, it passes the relative tolerances. */
static double plane_slack(const pgt_facade_mesh *mesh, uint32_t tri, const float o[3],
                          const float d[3], double t) {
    const uint32_t *v = mesh->indices + 3u * (size_t)tri;
    const float *a = mesh->positions + 3u * (size_t)v[0], *b = mesh->positions + 3u * (size_t)v[1],
                *c = mesh->positions + 3u * (size_t)v[2];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) e1[k] = (double)b[k] - a[k], e2[k] = (double)c[k] - a[k];
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    double nn = 0.0, dd = 0.0, nd = 0.0, mag = 0.0;
    for (int k = 0; k < 3; ++k) {
        nn += n[k] * n[k], dd += (double)d[k] * d[k], nd += n[k] * d[k];
        mag = fmax(mag, fmax(fabs((double)o[k]), fabs((double)o[k] + t * d[k])));
    }
    if (!(nn > 0.0 && dd > 0.0)) return 0.0;
    const double cos_a = fabs(nd) / sqrt(nn * dd);
    const double along = PGT_FACADE_CHECK_PLANE_EPS * FLT_EPSILON * mag;
    return cos_a > 0.0 ? along / cos_a : INFINITY;
}

/* plane_slack of pixel (x, y)'s ray. */
static double pixel_slack(const pgt_facade_mesh *mesh, const pgt_facade_camera *cam, uint32_t tri,
                          uint32_t x, uint32_t y, double t) {
    float o[3], d[3];
    pgt_facade_camera_ray(cam, x, y, o, d);
    return plane_slack(mesh, tri, o, d, t);
}

int pgt_facade_embree_compare(const pgt_facade_mesh *mesh, const pgt_facade_camera *cam,
                              const pgt_facade_frame *frame, const pgt_facade_embree_hits *hits,
                              pgt_facade_check *out) {
    memset(out, 0, sizeof *out);
    const uint32_t W = frame->width, H = frame->height;
    const size_t n = (size_t)W * H;
    out->pixels = n;
    size_t *bad = NULL, bad_n = 0, bad_cap = 0;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t of = frame->facade[i], et = hits->tri[i];
        if (of == PGT_NONE && et == PGT_NONE) {
            out->agree++, out->both_miss++;
            continue;
        }
        if (of != PGT_NONE && et != PGT_NONE) {
            const double t = frame->depth[i], te = hits->t[i], dt = fabs(t - te);
            if (mesh->facade[et] == of && mesh->node[et] == frame->node[i] &&
                mesh->kind[et] == (uint32_t)frame->terminal[i] &&
                mesh->surface[et] == frame->surface[i] &&
                (dt <= PGT_FACADE_CHECK_DEPTH_TOL_REL * t ||
                 dt <= pixel_slack(mesh, cam, et, (uint32_t)(i % W), (uint32_t)(i / W), t))) {
                out->agree++;
                out->max_abs_dt = fmax(out->max_abs_dt, dt);
                out->max_rel_dt = fmax(out->max_rel_dt, dt / t);
                continue;
            }
        }
        if (bad_n == bad_cap) {
            bad_cap = bad_cap ? 2u * bad_cap : 64u;
            size_t *b = realloc(bad, bad_cap * sizeof *b);
            if (!b) { /* cannot explain them: every one counts as far from an edge */
                free(bad);
                bad = NULL, bad_cap = bad_n = 0;
                out->disagree = n - out->agree;
                goto finish;
            }
            bad = b;
        }
        bad[bad_n++] = i;
    }
    out->disagree = bad_n;
    if (bad_n) {
        /* the rectangles of both sides of every disagreement, found in one pass over the mesh */
        wanted *w = calloc(2u * bad_n, sizeof *w);
        size_t wn = 0;
        if (!w) {
            free(bad);
            goto finish;
        }
        for (size_t b = 0; b < bad_n; ++b) {
            const size_t i = bad[b];
            if (frame->facade[i] != PGT_NONE)
                w[wn++].key = (rect_key){frame->facade[i], frame->node[i],
                                         (uint32_t)frame->terminal[i], frame->surface[i]};
            const uint32_t et = hits->tri[i];
            if (et != PGT_NONE)
                w[wn++].key =
                    (rect_key){mesh->facade[et], mesh->node[et], mesh->kind[et], mesh->surface[et]};
        }
        qsort(w, wn, sizeof *w, wanted_cmp);
        size_t u = 0;
        for (size_t k = 0; k < wn; ++k)
            if (u == 0 || key_cmp(&w[u - 1].key, &w[k].key)) w[u++] = w[k];
        wn = u;
        /* their triangles, counted, then listed (CSR), and each key's boundary once */
        key_triangles(mesh, w, wn, NULL);
        size_t total = 0;
        for (size_t k = 0; k < wn; ++k) w[k].first = (uint32_t)total, total += w[k].n;
        uint32_t *tris = malloc((total ? total : 1u) * sizeof *tris);
        pos_edge *edges = malloc((total ? 3u * total : 1u) * sizeof *edges);
        if (!tris || !edges) { /* cannot explain them: every one counts as far from an edge */
            free(tris);
            free(edges);
            free(w);
            free(bad);
            goto finish;
        }
        key_triangles(mesh, w, wn, tris);
        for (size_t k = 0, e = 0; k < wn; ++k) {
            w[k].efirst = (uint32_t)e;
            w[k].en = surface_edges(mesh, tris + w[k].first, w[k].n, edges + e, &w[k].ein);
            e += w[k].en + w[k].ein;
        }
        for (size_t b = 0; b < bad_n; ++b) {
            const size_t i = bad[b];
            const uint32_t x = (uint32_t)(i % W), y = (uint32_t)(i / W);
            float o[3], d[3];
            pgt_facade_camera_ray(cam, x, y, o, d);
            pgt_facade_check_pixel px;
            memset(&px, 0, sizeof px);
            px.x = x, px.y = y;
            px.edge[0] = px.edge[1] = px.inner = INFINITY;
            px.facade[0] = px.facade[1] = PGT_NONE;
            px.t[0] = frame->depth[i], px.t[1] = hits->t[i];
            /* both hit at one distance, different rectangles: a tie when the rectangle ours
             * names passes through the point Embree hit (two faces in one place; a label of
             * ours that names no face there, or a face behind or before Embree's, is no tie) */
            /* float rounding's reach along the ray on the plane Embree hit (plane_slack) */
            const double slack1 =
                hits->tri[i] != PGT_NONE ? plane_slack(mesh, hits->tri[i], o, d, hits->t[i]) : 0.0;
            const int tie_depth = frame->facade[i] != PGT_NONE && hits->tri[i] != PGT_NONE &&
                                  fabs((double)px.t[0] - px.t[1]) <=
                                      fmax(PGT_FACADE_CHECK_DEPTH_TOL_REL * px.t[0], slack1);
            /* the edge distances (relative to t) within which a disagreement is rounding */
            double tol[2] = {PGT_FACADE_CHECK_EDGE_EPS_REL, PGT_FACADE_CHECK_EDGE_EPS_REL};
            const wanted *ours = NULL;
            double on = INFINITY; /* from Embree's hit point to the rectangle ours names */
            if (frame->facade[i] != PGT_NONE) {
                wanted probe;
                probe.key = (rect_key){frame->facade[i], frame->node[i],
                                       (uint32_t)frame->terminal[i], frame->surface[i]};
                px.facade[0] = probe.key.facade, px.node[0] = probe.key.node;
                px.kind[0] = probe.key.kind, px.surface[0] = probe.key.surface;
                const wanted *r = bsearch(&probe, w, wn, sizeof *w, wanted_cmp);
                const double t = frame->depth[i];
                double p[3];
                for (int k = 0; k < 3; ++k) p[k] = (double)o[k] + t * (double)d[k];
                if (r && r->n) {
                    px.edge[0] = (float)(edges_dist(edges + r->efirst, r->en, p) / t);
                    const double slack0 = plane_slack(mesh, tris[r->first], o, d, t);
                    tol[0] = fmax(tol[0], slack0 / t);
                    /* Embree's ray went on past the rectangle ours hit (a miss, or a hit
                     * behind it): through the crack along an edge between two of its
                     * triangles when ours' point lies on one */
                    const int passed =
                        hits->tri[i] == PGT_NONE ||
                        hits->t[i] > t + fmax(PGT_FACADE_CHECK_DEPTH_TOL_REL * t, slack0);
                    if (passed && r->ein)
                        px.inner = (float)(edges_dist(edges + r->efirst + r->en, r->ein, p) / t);
                }
                ours = r;
            }
            const uint32_t et = hits->tri[i];
            if (et != PGT_NONE) {
                wanted probe;
                probe.key =
                    (rect_key){mesh->facade[et], mesh->node[et], mesh->kind[et], mesh->surface[et]};
                px.facade[1] = probe.key.facade, px.node[1] = probe.key.node;
                px.kind[1] = probe.key.kind, px.surface[1] = probe.key.surface;
                const wanted *r = bsearch(&probe, w, wn, sizeof *w, wanted_cmp);
                const uint32_t *tv = mesh->indices + 3u * (size_t)et;
                const double bu = hits->u[i], bv = hits->v[i], b0 = 1.0 - bu - bv;
                double p[3];
                for (int k = 0; k < 3; ++k)
                    p[k] = b0 * mesh->positions[3u * (size_t)tv[0] + k] +
                           bu * mesh->positions[3u * (size_t)tv[1] + k] +
                           bv * mesh->positions[3u * (size_t)tv[2] + k];
                if (r && r->n)
                    px.edge[1] = (float)(edges_dist(edges + r->efirst, r->en, p) / hits->t[i]);
                tol[1] = fmax(tol[1], slack1 / hits->t[i]);
                for (uint32_t k = 0; tie_depth && ours && k < ours->n; ++k) {
                    const uint32_t *ov = mesh->indices + 3u * (size_t)tris[ours->first + k];
                    on = fmin(on, tri_dist(p, mesh->positions + 3u * (size_t)ov[0],
                                           mesh->positions + 3u * (size_t)ov[1],
                                           mesh->positions + 3u * (size_t)ov[2]));
                }
            }
            const int tie = tie_depth && on <= PGT_FACADE_CHECK_TIE_TOL_REL * px.t[1];
            if (tie)
                out->ties++;
            else if (px.edge[0] <= tol[0] || px.edge[1] <= tol[1])
                out->near_edge++;
            else if (px.inner <= tol[0])
                out->near_edge++, out->crack++;
            else if (out->reported < PGT_FACADE_CHECK_MAX_REPORTED)
                out->far[out->reported++] = px;
        }
        free(w);
        free(tris);
        free(edges);
    }
    free(bad);
finish:
    out->agreement_pct = n ? 100.0 * (double)out->agree / (double)n : 100.0;
    return out->disagree == out->near_edge + out->ties &&
           100.0 * (double)(out->agree + out->ties) >= PGT_FACADE_CHECK_MIN_AGREEMENT * (double)n;
}

/* ---- PLY ---- */

size_t pgt_facade_mesh_bytes(const pgt_facade_mesh *m) {
    return 3u * (size_t)m->vertex_count * sizeof(float) +
           7u * (size_t)m->triangle_count * sizeof(uint32_t);
}

uint32_t pgt_facade_twin_max_triangles(int with_embree, uint64_t *available) {
    const uint64_t avail = pgt_cli_available_bytes();
    if (available) *available = avail;
    if (avail == 0) return PGT_FACADE_MAX_TRIANGLES;
    const double per = PGT_FACADE_MESH_BYTES_PER_TRIANGLE +
                       (with_embree ? PGT_FACADE_EMBREE_BYTES_PER_TRIANGLE : 0u);
    const double n = floor((double)avail * PGT_FACADE_TWIN_MEMORY_SHARE / per);
    return n >= (double)PGT_FACADE_MAX_TRIANGLES ? PGT_FACADE_MAX_TRIANGLES
                                                 : (n < 1.0 ? 1u : (uint32_t)n);
}

const char *pgt_facade_twin_limit_why(char *buf, size_t size, uint64_t available, int with_embree) {
    buf[0] = 0;
    char mem[32];
    if (available)
        snprintf(buf, size,
                 " (what fits in %.0f %% of the %s of memory available%s; pgt facade "
                 "--max-triangles sets another limit)",
                 100.0 * PGT_FACADE_TWIN_MEMORY_SHARE,
                 pgt_cli_bytes_text(mem, sizeof mem, available),
                 with_embree ? " with Embree's scene of it" : "");
    return buf;
}

pgt_result pgt_facade_mesh_write_ply(const pgt_facade_mesh *m, const char *path, pgt_error *err) {
    const uint32_t one = 1;
    uint8_t little;
    memcpy(&little, &one, 1);
    if (!little)
        return pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                             "%s: writing PLY needs a little-endian host", path);
    char tmp[4200];
    FILE *f = pgt_cli_tmp_open(path, tmp, sizeof tmp);
    if (!f) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\ncomment pgt facade --explicit: every terminal "
            "of every facade (paper 003)\nelement vertex %u\nproperty float x\nproperty float "
            "y\nproperty float z\nelement face %u\nproperty list uchar uint vertex_indices\n"
            "property uint facade\nproperty uint node\nproperty uint kind\nproperty uint "
            "surface\nend_header\n",
            m->vertex_count, m->triangle_count);
    fwrite(m->positions, sizeof(float), 3u * (size_t)m->vertex_count, f);
    uint8_t rec[29];
    rec[0] = 3;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
        memcpy(rec + 1, m->indices + 3u * (size_t)t, 12);
        memcpy(rec + 13, &m->facade[t], 4);
        memcpy(rec + 17, &m->node[t], 4);
        memcpy(rec + 21, &m->kind[t], 4);
        memcpy(rec + 25, &m->surface[t], 4);
        fwrite(rec, 1, sizeof rec, f);
    }
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad || pgt_replace_file(tmp, path) != 0) {
        const int e = errno;
        remove(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot write: %s", path, strerror(e));
    }
    return PGT_OK;
}
