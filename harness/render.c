/* pgt harness: the figure ray tracer on Embree 3 (render.h says what the picture is).
 *
 * Embree 3 API: rtcNewDevice / rtcNewScene / rtcNewGeometry (RTC_GEOMETRY_TYPE_TRIANGLE) with
 * the meshes' arrays shared (rtcSetSharedGeometryBuffer), rtcCommitScene, then rtcIntersect1
 * and rtcOccluded1 per ray from pgt_parallel_for_items over image rows. Errors Embree reports
 * through its device error callback become the first pgt error message. */
#include "render.h"

#include <assert.h>
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/image.h"
#include "pgt/parallel.h"
#include "png_io.h"

#define RENDER_PI 3.14159265358979323846

/* ---- small vector helpers (double: camera set-up only) ---- */

static void d3_sub(const float a[3], const float b[3], double out[3]) {
    for (int k = 0; k < 3; ++k) out[k] = (double)a[k] - (double)b[k];
}

static double d3_dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void d3_cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double d3_normalize(double a[3]) {
    const double len = sqrt(d3_dot(a, a));
    if (len > 0.0)
        for (int k = 0; k < 3; ++k) a[k] /= len;
    return len;
}

/* ---- camera ---- */

pgt_result pgt_render_camera_check(const pgt_render_camera *cam, pgt_error *err) {
    const float *vals[3] = {cam->eye, cam->at, cam->up};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(vals[i][k]))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "camera: a coordinate is not a finite number");
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 3; ++k)
            if (fabsf(vals[i][k]) > PGT_RENDER_MAX_EYE)
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "camera: the %s's coordinate %g is beyond +-%g (Embree's "
                                     "rays start within 1.8e18)",
                                     i ? "look-at point" : "eye", (double)vals[i][k],
                                     (double)PGT_RENDER_MAX_EYE);
    if (!isfinite(cam->fov_deg) || !(cam->fov_deg > 0.0f) || !(cam->fov_deg < 180.0f))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: the field of view %g is not in (0, 180) degrees",
                             (double)cam->fov_deg);
    double w[3], up[3] = {cam->up[0], cam->up[1], cam->up[2]}, c[3];
    d3_sub(cam->eye, cam->at, w);
    if (!(d3_normalize(w) > 0.0))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: the eye is at the look-at point");
    if (!(d3_normalize(up) > 0.0))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "camera: the up vector is zero");
    d3_cross(up, w, c);
    if (!(sqrt(d3_dot(c, c)) >= PGT_RENDER_MIN_UP_SINE))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: the up vector is parallel to the view direction");
    return PGT_OK;
}

/* Orthonormal camera frame: u right, v up, w back toward the viewer (render.h). */
static void camera_frame(const pgt_render_camera *cam, double u[3], double v[3], double w[3]) {
    double up[3] = {cam->up[0], cam->up[1], cam->up[2]};
    d3_sub(cam->eye, cam->at, w);
    d3_normalize(w);
    d3_cross(up, w, u);
    d3_normalize(u);
    d3_cross(w, u, v);
}

/* Union bounding box of the meshes' vertices; 0 when there are none. */
static int scene_bounds(const pgt_render_mesh *meshes, uint32_t count, double lo[3], double hi[3]) {
    int any = 0;
    for (int k = 0; k < 3; ++k) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t i = 0; i < count; ++i) {
        const pgt_mesh *m = meshes[i].mesh;
        for (uint32_t j = 0; j < m->vertex_count; ++j)
            for (int k = 0; k < 3; ++k) {
                const double x = m->positions[3u * j + k];
                if (x < lo[k]) lo[k] = x;
                if (x > hi[k]) hi[k] = x;
            }
        any |= m->vertex_count > 0;
    }
    return any;
}

void pgt_render_auto_camera(const pgt_render_mesh *meshes, uint32_t count, double az_deg,
                            double el_deg, int up_axis, double aspect, pgt_render_camera *out) {
    assert(count >= 1 && up_axis >= 0 && up_axis <= 2 && aspect > 0.0);
    assert(isfinite(az_deg) && isfinite(el_deg) && fabs(el_deg) < 90.0);
    double lo[3], hi[3], centre[3], radius = 0.0;
    const int any = scene_bounds(meshes, count, lo, hi);
    assert(any);
    (void)any;
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5 * (lo[k] + hi[k]);
        radius += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    radius = 0.5 * sqrt(radius);
    if (!(radius > 0.0)) radius = 1.0;
    /* azimuth 0 direction r and the direction s it turns toward, right-handed about the axis */
    static const double ref[3][3] = {{0, 1, 0}, {0, 0, 1}, {0, -1, 0}};
    static const double side[3][3] = {{0, 0, 1}, {1, 0, 0}, {1, 0, 0}};
    const double az = az_deg * RENDER_PI / 180.0, el = el_deg * RENDER_PI / 180.0;
    double dir[3];
    for (int k = 0; k < 3; ++k)
        dir[k] = cos(el) * (cos(az) * ref[up_axis][k] + sin(az) * side[up_axis][k]) +
                 (k == up_axis ? sin(el) : 0.0);
    const double half_v = 0.5 * PGT_RENDER_AUTO_FOV * RENDER_PI / 180.0;
    double half = half_v;
    if (aspect < 1.0) half = atan(aspect * tan(half_v)); /* the horizontal angle is narrower */
    const double dist = PGT_RENDER_AUTO_MARGIN * radius / sin(half);
    for (int k = 0; k < 3; ++k) {
        out->at[k] = (float)centre[k];
        out->eye[k] = (float)(centre[k] + dist * dir[k]);
        out->up[k] = k == up_axis ? 1.0f : 0.0f;
    }
    out->fov_deg = PGT_RENDER_AUTO_FOV;
}

/* PGT_ERROR_INVALID_ARGUMENT for a coordinate beyond PGT_RENDER_MAX_COORD (or not finite);
 * the message starts with prefix ("" or "render: mesh 2: "). */
static pgt_result check_coordinates(const pgt_mesh *mesh, const char *prefix, pgt_error *err) {
    float c = 0.0f;
    const uint32_t v = pgt_mesh_far_vertex(mesh, PGT_RENDER_MAX_COORD, &c);
    if (v == PGT_NONE) return PGT_OK;
    return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                         "%svertex %u (0-based): coordinate %g is beyond +-%g (Embree's rays must "
                         "start within 1.8e18; scale the mesh down)",
                         prefix, v, (double)c, (double)PGT_RENDER_MAX_COORD);
}

pgt_result pgt_render_pad_positions(pgt_mesh *mesh, pgt_error *err) {
    const size_t n = 3u * (size_t)mesh->vertex_count;
    const pgt_result r = check_coordinates(mesh, "", err);
    if (r != PGT_OK) return r;
    float *p = realloc(mesh->positions, (n + 1u) * sizeof(float));
    if (!p)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "render: out of memory padding %u vertices", mesh->vertex_count);
    p[n] = 0.0f;
    mesh->positions = p;
    return PGT_OK;
}

/* ---- Embree errors ---- */

typedef struct embree_errors {
    pthread_mutex_t lock;
    int set;
    char message[PGT_ERROR_MESSAGE_SIZE];
} embree_errors;

static const char *rtc_error_name(enum RTCError code) {
    switch (code) {
    case RTC_ERROR_NONE:
        return "none";
    case RTC_ERROR_INVALID_ARGUMENT:
        return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
        return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
        return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
        return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
        return "cancelled";
    default:
        return "unknown error";
    }
}

/* Embree's device error callback: may run on any thread; keeps the first message. */
static void on_embree_error(void *user, enum RTCError code, const char *str) {
    embree_errors *e = user;
    pthread_mutex_lock(&e->lock);
    if (!e->set) {
        e->set = 1;
        snprintf(e->message, sizeof e->message, "embree: %s: %s", rtc_error_name(code),
                 str ? str : "");
    }
    pthread_mutex_unlock(&e->lock);
}

/* PGT_ERROR_BACKEND with Embree's first message when the callback fired or the device holds
 * an error code (rtcGetDeviceError also clears it), else PGT_OK. */
static pgt_result embree_status(RTCDevice dev, embree_errors *e, const char *what, pgt_error *err) {
    const enum RTCError code = rtcGetDeviceError(dev);
    pthread_mutex_lock(&e->lock);
    const int set = e->set;
    pthread_mutex_unlock(&e->lock);
    if (set) return pgt_error_set(err, PGT_ERROR_BACKEND, "%s (%s)", e->message, what);
    if (code != RTC_ERROR_NONE)
        return pgt_error_set(err, PGT_ERROR_BACKEND, "embree: %s (%s)", rtc_error_name(code), what);
    return PGT_OK;
}

/* ---- tracing ---- */

typedef struct trace_job {
    RTCScene scene;
    pgt_progress *progress; /* rows done (NULL: none) */
    uint8_t *out;
    uint32_t w, h, n; /* n x n samples per pixel */
    int shadows;
    float eye[3], u[3], v[3], w_axis[3]; /* camera frame */
    float tan_y, tan_x;                  /* image-plane half extents at distance 1 */
    float light[3];                      /* toward the key light, world, unit length */
    float eps;                           /* shadow ray tnear */
    float background[3];                 /* linear */
    const float (*albedo)[3];            /* per geometry id */
    const pgt_render_mesh *meshes;       /* geometry id = mesh index */
    uint64_t rays[PGT_MAX_THREADS];      /* per worker */
} trace_job;

static float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

/* Linear radiance of one sample ray from the eye through image-plane point (px, py). */
static void shade_sample(trace_job *job, struct RTCIntersectContext *ctx, float px, float py,
                         float rgb[3], uint64_t *rays) {
    const float sx = (2.0f * px / (float)job->w - 1.0f) * job->tan_x;
    const float sy = (1.0f - 2.0f * py / (float)job->h) * job->tan_y;
    float d[3];
    for (int k = 0; k < 3; ++k) d[k] = -job->w_axis[k] + sx * job->u[k] + sy * job->v[k];
    const float dl = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) d[k] /= dl;

    struct RTCRayHit rh;
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = job->eye[0], rh.ray.org_y = job->eye[1], rh.ray.org_z = job->eye[2];
    rh.ray.dir_x = d[0], rh.ray.dir_y = d[1], rh.ray.dir_z = d[2];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(job->scene, ctx, &rh);
    ++*rays;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        for (int k = 0; k < 3; ++k) rgb[k] = job->background[k];
        return;
    }
    float n[3] = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    /* Ng is the unnormalised cross product of two edges: its square overflows float for edges
     * beyond ~3e9 and underflows below ~1e-10, so the length is taken in double (the shading
     * does not depend on the mesh's scale) */
    const double nd[3] = {n[0], n[1], n[2]};
    const double nl = sqrt(d3_dot(nd, nd));
    const float flip = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) > 0.0f ? -1.0f : 1.0f;
    for (int k = 0; k < 3; ++k) n[k] = (float)(flip * nd[k] / nl); /* two-sided: face the viewer */
    float lambert = n[0] * job->light[0] + n[1] * job->light[1] + n[2] * job->light[2];
    if (!(lambert > 0.0f)) lambert = 0.0f;
    if (lambert > 0.0f && job->shadows) {
        /* the hit point from its barycentrics: rounded like the scene's coordinates, however
         * far the eye is (eye + t d would carry the eye's distance in its rounding) */
        const pgt_mesh *m = job->meshes[rh.hit.geomID].mesh;
        const uint32_t *tri = &m->indices[3u * (size_t)rh.hit.primID];
        const float *p0 = &m->positions[3u * (size_t)tri[0]];
        const float *p1 = &m->positions[3u * (size_t)tri[1]];
        const float *p2 = &m->positions[3u * (size_t)tri[2]];
        const float b0 = 1.0f - rh.hit.u - rh.hit.v;
        struct RTCRay sr;
        memset(&sr, 0, sizeof sr);
        sr.org_x = b0 * p0[0] + rh.hit.u * p1[0] + rh.hit.v * p2[0];
        sr.org_y = b0 * p0[1] + rh.hit.u * p1[1] + rh.hit.v * p2[1];
        sr.org_z = b0 * p0[2] + rh.hit.u * p1[2] + rh.hit.v * p2[2];
        sr.dir_x = job->light[0], sr.dir_y = job->light[1], sr.dir_z = job->light[2];
        sr.tnear = job->eps;
        sr.tfar = INFINITY;
        sr.mask = 0xFFFFFFFFu;
        rtcOccluded1(job->scene, ctx, &sr);
        ++*rays;
        if (sr.tfar < 0.0f) lambert = 0.0f; /* Embree sets tfar to -inf on a hit */
    }
    const float *a = job->albedo[rh.hit.geomID];
    const float light = PGT_RENDER_AMBIENT + PGT_RENDER_KEY * lambert;
    for (int k = 0; k < 3; ++k) rgb[k] = a[k] * light;
}

static void trace_rows(void *ctx_, uint32_t begin, uint32_t end, uint32_t worker) {
    trace_job *job = ctx_;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    const uint32_t n = job->n;
    const float inv_n = 1.0f / (float)n, inv_count = 1.0f / (float)(n * n);
    uint64_t rays = 0;
    for (uint32_t y = begin; y < end; ++y) {
        uint8_t *row = job->out + (size_t)y * job->w * 3u;
        for (uint32_t x = 0; x < job->w; ++x) {
            float sum[3] = {0.0f, 0.0f, 0.0f};
            for (uint32_t j = 0; j < n; ++j)
                for (uint32_t i = 0; i < n; ++i) {
                    float c[3];
                    shade_sample(job, &ctx, (float)x + ((float)i + 0.5f) * inv_n,
                                 (float)y + ((float)j + 0.5f) * inv_n, c, &rays);
                    for (int k = 0; k < 3; ++k) sum[k] += c[k];
                }
            for (int k = 0; k < 3; ++k)
                row[3u * x + k] = pgt_png_linear_to_srgb8(sum[k] * inv_count);
        }
        pgt_progress_add(job->progress, 1);
    }
    job->rays[worker] += rays;
}

/* ---- the call ---- */

static pgt_result check_inputs(uint32_t w, uint32_t h, const pgt_render_mesh *meshes,
                               uint32_t count, const pgt_render_camera *cam,
                               const pgt_render_options *o, pgt_error *err) {
    if (w == 0 || h == 0 || w > PGT_IMAGE_MAX_SIDE || h > PGT_IMAGE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "render: image size %u x %u is not within 1 to %u per side", w, h,
                             PGT_IMAGE_MAX_SIDE);
    if (count == 0 || !meshes)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "render: no meshes");
    if (o->spp > PGT_RENDER_MAX_SPP || o->threads > PGT_MAX_THREADS)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "render: spp %u or threads %u out of range (at most %u and %u)",
                             o->spp, o->threads, PGT_RENDER_MAX_SPP, PGT_MAX_THREADS);
    if (o->background_set)
        for (int k = 0; k < 3; ++k)
            if (!(o->background[k] >= 0.0f && o->background[k] <= 1.0f))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "render: background colour not in [0, 1]");
    uint64_t vertices = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const pgt_mesh *m = meshes[i].mesh;
        if (!m || (m->vertex_count && !m->positions) || (m->face_count && !m->indices))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "render: mesh %u is missing", i);
        for (int k = 0; k < 3; ++k)
            if (!(meshes[i].rgb[k] >= 0.0f && meshes[i].rgb[k] <= 1.0f))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "render: mesh %u: colour component %g not in [0, 1]", i,
                                     (double)meshes[i].rgb[k]);
        char where[40];
        snprintf(where, sizeof where, "render: mesh %u: ", i);
        const pgt_result rc = check_coordinates(m, where, err);
        if (rc != PGT_OK) return rc;
        /* Embree reads indices unchecked: one pass here (about 1 ms per million triangles) */
        const uint32_t *ix = m->indices, V = m->vertex_count;
        for (size_t c = 0; c < 3u * (size_t)m->face_count; ++c)
            if (ix[c] >= V)
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "render: mesh %u: face %zu uses vertex %u of %u", i, c / 3u,
                                     ix[c], V);
        vertices += V;
    }
    if (vertices == 0)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "render: the meshes are empty");
    return pgt_render_camera_check(cam, err);
}

pgt_result pgt_render(uint8_t *rgb_out, uint32_t w, uint32_t h, const pgt_render_mesh *meshes,
                      uint32_t count, const pgt_render_camera *cam, const pgt_render_options *o,
                      pgt_render_stats *out_stats, pgt_error *err) {
    static const pgt_render_options defaults;
    if (!o) o = &defaults;
    pgt_result r = check_inputs(w, h, meshes, count, cam, o, err);
    if (r != PGT_OK) return r;

    const double t0 = pgt_cli_now_ms();
    trace_job *job = calloc(1, sizeof *job);
    float(*albedo)[3] = malloc(count * sizeof *albedo);
    if (!job || !albedo) {
        free(job);
        free(albedo);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "render: out of memory");
    }
    embree_errors errors;
    memset(&errors, 0, sizeof errors);
    pthread_mutex_init(&errors.lock, NULL);

    const uint32_t threads = o->threads ? o->threads : pgt_cli_cpu_count();
    char config[64];
    snprintf(config, sizeof config, "threads=%u", threads);
    RTCDevice dev = rtcNewDevice(config);
    RTCScene scene = NULL;
    uint64_t triangles = 0;
    if (!dev) {
        r = pgt_error_set(err, PGT_ERROR_BACKEND, "embree: %s (rtcNewDevice)",
                          rtc_error_name(rtcGetDeviceError(NULL)));
        goto done;
    }
    rtcSetDeviceErrorFunction(dev, on_embree_error, &errors);
    scene = rtcNewScene(dev);
    if ((r = embree_status(dev, &errors, "rtcNewScene", err)) != PGT_OK) goto done;
    /* robust: no cracks between triangles for rays grazing a shared edge; compact: leaves hold
     * triangle indices into the shared vertex buffers instead of copies of the vertices (on a
     * 5.7M-triangle mesh: peak memory 311 instead of 647 MB, a sixth of the system time) */
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_COMPACT);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    for (uint32_t i = 0; i < count; ++i) {
        const pgt_mesh *m = meshes[i].mesh;
        for (int k = 0; k < 3; ++k) albedo[i][k] = meshes[i].rgb[k];
        if (m->face_count == 0) continue;
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (meshes[i].positions_padded) {
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       m->positions, 0, 3u * sizeof(float), m->vertex_count);
        } else {
            /* Embree pads its own buffers for the 16-byte loads: the one copy */
            float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                3u * sizeof(float), m->vertex_count);
            if (vb) memcpy(vb, m->positions, 3u * sizeof(float) * m->vertex_count);
        }
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m->indices, 0,
                                   3u * sizeof(uint32_t), m->face_count);
        rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(scene, g, i); /* geomID = mesh index: its albedo */
        rtcReleaseGeometry(g);
        if ((r = embree_status(dev, &errors, "mesh geometry", err)) != PGT_OK) goto done;
        triangles += m->face_count;
    }
    rtcCommitScene(scene);
    if ((r = embree_status(dev, &errors, "rtcCommitScene", err)) != PGT_OK) goto done;
    const double t1 = pgt_cli_now_ms();

    /* camera and light */
    double u[3], v[3], wa[3], lo[3], hi[3];
    camera_frame(cam, u, v, wa);
    double L[3];
    for (int k = 0; k < 3; ++k)
        L[k] = PGT_RENDER_KEY_RIGHT * u[k] + PGT_RENDER_KEY_UP * v[k] + PGT_RENDER_KEY_BACK * wa[k];
    d3_normalize(L);
    scene_bounds(meshes, count, lo, hi);
    double extent = 0.0, diag = 0.0;
    for (int k = 0; k < 3; ++k) {
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
        extent = fmax(extent, fmax(fabs(lo[k]), fabs(hi[k])));
    }
    extent = fmax(extent, sqrt(diag));
    job->scene = scene;
    job->out = rgb_out;
    job->w = w, job->h = h;
    job->n = o->spp ? o->spp : PGT_RENDER_DEFAULT_SPP;
    job->shadows = !o->no_shadows;
    for (int k = 0; k < 3; ++k) {
        job->eye[k] = cam->eye[k];
        job->u[k] = (float)u[k], job->v[k] = (float)v[k], job->w_axis[k] = (float)wa[k];
        job->light[k] = (float)L[k];
        job->background[k] = o->background_set ? srgb_to_linear(o->background[k]) : 1.0f;
    }
    const double tan_y = tan(0.5 * (double)cam->fov_deg * RENDER_PI / 180.0);
    job->tan_y = (float)tan_y;
    job->tan_x = (float)(tan_y * (double)w / (double)h);
    job->eps = PGT_RENDER_SHADOW_OFFSET_REL * (float)extent;
    job->albedo = (const float(*)[3])albedo;
    job->meshes = meshes;
    const uint32_t workers = threads < PGT_MAX_THREADS ? threads : PGT_MAX_THREADS;
    job->progress = o->progress;
    pgt_progress_stage(o->progress, "rays", h, "rows");
    pgt_parallel_for_items(h, w, workers, trace_rows, job);
    if ((r = embree_status(dev, &errors, "tracing", err)) != PGT_OK) goto done;
    if (out_stats) {
        out_stats->bvh_ms = t1 - t0;
        out_stats->trace_ms = pgt_cli_now_ms() - t1;
        out_stats->triangles = triangles;
        out_stats->rays = 0;
        for (uint32_t i = 0; i < PGT_MAX_THREADS; ++i) out_stats->rays += job->rays[i];
    }
done:
    if (scene) rtcReleaseScene(scene);
    if (dev) rtcReleaseDevice(dev);
    pthread_mutex_destroy(&errors.lock);
    free(albedo);
    free(job);
    return r;
}
