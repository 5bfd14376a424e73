/* pgt harness: the Embree cross-check of per-pixel procedural facades (issue 6 item 9).
 *
 * The explicit twin of a facade scene (pgt_facade_explicit: every terminal's rectangles as two
 * triangles each) goes into an Embree 3 scene (one triangle geometry sharing the mesh's vertex
 * and index arrays, RTC_BUILD_QUALITY_HIGH, no robust or compact flag: Embree at its fastest).
 * The rays are exactly pgt_facade_render's: pgt_facade_camera_ray per pixel centre. Embree
 * traces them on the same number of threads (pgt_parallel_for over rows of 4 x 4 pixel tiles)
 * either as rtcIntersect16 packets of one tile each or as rtcIntersect1M streams of a tile row
 * with RTC_INTERSECT_CONTEXT_FLAG_COHERENT. Measured on 2 threads (results/facade.csv) neither
 * mode wins consistently (within ~15 % of each other, each faster on some rows), so pgt bench
 * facade times both and reports the faster; pgt facade uses packets unless told otherwise.
 *
 * Comparison per pixel with a rendered frame (frame.facade, node, terminal, surface, depth):
 * agreement is both missing, or both hitting the same (facade, node, kind, surface) at distances
 * t (ours) and t' (Embree) with |t - t'| <= PGT_FACADE_CHECK_DEPTH_TOL_REL * t. Both hitting at
 * such distances but naming different rectangles is a tie when the rectangle ours names passes
 * through Embree's hit point as well (within PGT_FACADE_CHECK_TIE_TOL_REL * t, in the explicit
 * mesh): the ray meets two coincident faces at one point and which one a nearest-hit query
 * names is float rounding on both sides (on a
 * generic mesh, --mesh, the terminals of neighbouring quads that protrude or recede past the
 * quad's sides overlap: tower quads 1.7 cm wide give thousands). Ties are counted apart and
 * do not fail the check. A disagreement is "near an edge" when the hit point of either side lies
 * within PGT_FACADE_CHECK_EDGE_EPS_REL
 * * t of the boundary of the rectangle it hit (the rectangle found as its two triangles in the
 * explicit mesh; the shared diagonal is not a boundary): there one float rounding decides which
 * of two touching or overlapping rectangles a ray meets first. It is near an edge as well (and
 * counted as a crack) when Embree's ray went on past the rectangle ours hit, and ours' hit point
 * lies within that distance of an edge between two of its triangles (a rectangle's diagonal, a
 * roof's inner edges): Embree without RTC_SCENE_FLAG_ROBUST is not watertight, and a ray through
 * a shared edge can miss both triangles (a 1000-building city at 3840 x 2160 had one such ray,
 * through a roof's diagonal, and failed the check). The robust flag closes these cracks, but it
 * changes what is timed against ours: measured on pgt bench facade's cities (2 runs each), BVH
 * builds 1.5-3 times faster in 2-21 % less memory, rays 0-15 % (median 5 %) slower.
 *
 * At grazing angles the three distances (depth of agreeing hits, edge distances, "went on past")
 * also accept what float rounding of the coordinates reaches along the ray: PGT_FACADE_CHECK_
 * PLANE_EPS epsilons of the coordinates' magnitude along the surface's normal, over the cosine
 * of the angle between the ray and the normal (plane_slack in facade_embree.c). */
#ifndef PGT_FACADE_EMBREE_H
#define PGT_FACADE_EMBREE_H

#include <stddef.h>
#include <stdint.h>

#include "pgt/facade.h"
#include "pgt/progress.h"
#include "pgt/result.h"

/* Relative depth tolerance of agreeing hits. Both sides intersect the same float rectangles:
 * ours in facade space (one transform of the ray: origin and direction each rounded, ~1e-7 of
 * the coordinates' magnitude), Embree in world space on rounded vertices (the same order). At a
 * grazing angle a the depth error grows as 1 / cos(a); 1e-4 covers angles up to ~89.5 degrees
 * at city coordinates of ~1000 with t ~ 100 (measured maximum in the tests: see
 * test_facade_embree). */
#define PGT_FACADE_CHECK_DEPTH_TOL_REL 1e-4
/* ... or, when the depths differ by more, agreeing hits when they lie within this many float
 * epsilons of the coordinates' magnitude (the largest |coordinate| of the eye and the hit) of
 * one another along the surface's normal: at street level the depth error is absolute and grows
 * as 1 / cos(a), past the relative bound at small t (a door 5.5 m away at 89.4 degrees: 1.5 mm,
 * 2.7e-4 t, but 1.5e-5 m along the normal, 0.4 epsilons of its coordinates of ~300; a window at
 * 89.87 degrees, 15 m: 5.4 mm, 0.3 epsilons). 4 leaves room for the few roundings of each side
 * and still refuses a surface 0.14 mm off at coordinates of 300. */
#define PGT_FACADE_CHECK_PLANE_EPS 4.0
/* Disagreements within this distance (relative to t) of a rectangle's boundary are rounding:
 * a pixel's footprint at 512 pixels and 45 degrees is ~1.6e-3 t, float coordinates of a city
 * ~1e-7 of 1000 = 1e-4 absolute; 1e-4 t is a tenth of a pixel at 512^2 and well above the
 * rounding at every t > 1. */
#define PGT_FACADE_CHECK_EDGE_EPS_REL 1e-4
/* A tie's faces must meet Embree's hit point within this distance (relative to t): coincident
 * faces built through different facade frames differ by the float rounding of their
 * coordinates, ~1e-7 of magnitudes up to ~1000 m at t >= 10 m (measured ties: at most 2.2e-7 t
 * apart along the ray on the thin towers of the CLI tests); parallel faces farther apart are
 * two faces, and ours naming the one behind is a failure (0.2 mm behind at t = 3 m, 6.7e-5 t,
 * passed as a tie with the depth tolerance). */
#define PGT_FACADE_CHECK_TIE_TOL_REL 1e-5
/* The agreement the check demands (percent), as the issue states it. */
#define PGT_FACADE_CHECK_MIN_AGREEMENT 99.99

typedef enum pgt_facade_embree_mode {
    PGT_FACADE_EMBREE_PACKETS = 0, /* rtcIntersect16, one 4 x 4 tile per packet, coherent flag */
    PGT_FACADE_EMBREE_STREAMS = 1, /* rtcIntersect1M of a tile row, coherent flag */
    /* The rays the check compares: packets as above with the incoherent flag. With the coherent
     * flag Embree 3.13's packet and stream traversal missed hits that rtcIntersect1 finds: an
     * eye at street level inside a building, 0.52 m behind a window's frame (a back face,
     * cos 0.99998, 0.018 m inside its edge), missed by 59 rays as packets and 43 as streams of
     * one frame (a 248-building city, seed 31, camera 340,2,286,118,13,98,0,1,0,78), found by
     * every one without the flag. The coherent modes are timed (faster on small scenes: 77 against
     * 58 Mrays/s on 25 buildings at 1280x720); the check traces once more without it. */
    PGT_FACADE_EMBREE_CHECK_RAYS = 2
} pgt_facade_embree_mode;
#define PGT_FACADE_EMBREE_DEFAULT_MODE PGT_FACADE_EMBREE_PACKETS

/* An Embree scene of an explicit facade mesh (opaque Embree handles). */
typedef struct pgt_facade_embree {
    void *device, *scene; /* RTCDevice, RTCScene */
    const pgt_facade_mesh *mesh;
    float *vertices; /* padded copy of mesh->positions (Embree reads 16 bytes a vertex) */
    uint32_t threads;
    double build_ms;     /* device, geometry and BVH build */
    size_t embree_bytes; /* peak bytes Embree reported (rtcSetDeviceMemoryMonitorFunction) */
    size_t buffer_bytes; /* the vertex and index buffers it reads */
    void *monitor;       /* the memory counter */
} pgt_facade_embree;

/* Builds the scene on `threads` threads. The mesh must outlive e. PGT_ERROR_BACKEND with
 * Embree's first message. A mesh without triangles gives a scene without geometry (every ray
 * misses). progress (NULL: none) gets the stage "Embree's BVH" in triangles, from Embree's
 * build progress (rtcSetSceneProgressMonitorFunction). */
pgt_result pgt_facade_embree_create(pgt_facade_embree *e, const pgt_facade_mesh *mesh,
                                    uint32_t threads, pgt_progress *progress, pgt_error *err);
void pgt_facade_embree_destroy(pgt_facade_embree *e);

/* Embree's hits of one frame: per pixel (row-major, y = 0 at the top). */
typedef struct pgt_facade_embree_hits {
    uint32_t width, height;
    float *t;      /* INFINITY on a miss */
    uint32_t *tri; /* triangle, PGT_NONE on a miss */
    float *u, *v;  /* barycentrics of the hit */
} pgt_facade_embree_hits;

pgt_result pgt_facade_embree_hits_create(pgt_facade_embree_hits *h, uint32_t width, uint32_t height,
                                         pgt_error *err);
void pgt_facade_embree_hits_destroy(pgt_facade_embree_hits *h);

/* Traces one ray per pixel of cam (pgt_facade_camera_ray) on e->threads threads; *ms gets the
 * wall time of the trace (ray generation included, as in our frame). */
pgt_result pgt_facade_embree_trace(pgt_facade_embree *e, const pgt_facade_camera *cam,
                                   pgt_facade_embree_mode mode, pgt_facade_embree_hits *out,
                                   double *ms, pgt_error *err);

/* One pixel the check could not explain (for messages). */
typedef struct pgt_facade_check_pixel {
    uint32_t x, y;
    uint32_t facade[2], node[2], kind[2], surface[2]; /* ours, Embree's (PGT_NONE: miss) */
    float t[2];
    float edge[2]; /* distance to the rectangle's boundary / t; INFINITY when that side missed */
    float inner;   /* ours' hit point's distance to an edge inside its rectangle (between two of
                      its triangles in the explicit mesh) / t when Embree's ray went on past
                      that rectangle; else INFINITY */
} pgt_facade_check_pixel;

#define PGT_FACADE_CHECK_MAX_REPORTED 8u

typedef struct pgt_facade_check {
    uint64_t pixels, agree, both_miss;
    uint64_t disagree;  /* every pixel that does not agree, ties included */
    uint64_t ties;      /* both hit at the same distance (PGT_FACADE_CHECK_DEPTH_TOL_REL) but name
                           different rectangles, and ours passes through Embree's hit point
                           (PGT_FACADE_CHECK_TIE_TOL_REL): coincident faces, either is the
                           nearest hit */
    uint64_t near_edge; /* the other disagreements near an edge */
    uint64_t crack;     /* of those, the ones near an inner edge only (Embree's ray slipped
                           between two triangles of the rectangle ours hit) */
    double max_abs_dt, max_rel_dt; /* among agreeing hits */
    double agreement_pct;
    uint32_t reported;
    pgt_facade_check_pixel far[PGT_FACADE_CHECK_MAX_REPORTED]; /* first disagreements not near
                                                                  an edge */
} pgt_facade_check;

/* Compares a rendered frame with Embree's hits of the same camera. Nonzero return = the check
 * passes: every disagreement a tie or near an edge, and agreement with the ties counted in >=
 * PGT_FACADE_CHECK_MIN_AGREEMENT. */
int pgt_facade_embree_compare(const pgt_facade_mesh *mesh, const pgt_facade_camera *cam,
                              const pgt_facade_frame *frame, const pgt_facade_embree_hits *hits,
                              pgt_facade_check *out);

/* Writes the mesh as binary little-endian PLY: vertex x y z (float), face vertex_indices
 * (uchar count, uint) then facade, node, kind, surface (uint). Temporary file + rename. */
pgt_result pgt_facade_mesh_write_ply(const pgt_facade_mesh *m, const char *path, pgt_error *err);

/* Bytes of the mesh's arrays (positions, indices, per-triangle ids). */
size_t pgt_facade_mesh_bytes(const pgt_facade_mesh *m);

/* Share of the memory available at start (pgt_cli_available_bytes) that the explicit twin may
 * fill, with Embree's scene of it when it is built: the rest is for the frame, the scene, the
 * PLY writer and the system. The twin's arrays stay within their limit's capacity
 * (pgt_facade_explicit_limit), realloc's copy of one array apart. */
#define PGT_FACADE_TWIN_MEMORY_SHARE 0.75
/* Embree's bytes per triangle of the twin (its reported peak, the padded vertex copy and the index
 * buffer): 152-173 on the three cities of results/facade.csv; 200 leaves a margin. */
#define PGT_FACADE_EMBREE_BYTES_PER_TRIANGLE 200u

/* The most triangles the explicit twin may have so that it (and Embree's scene of it, when
 * with_embree) fits in PGT_FACADE_TWIN_MEMORY_SHARE of the memory available now, at most
 * PGT_FACADE_MAX_TRIANGLES (also when the memory cannot be read); *available gets the bytes
 * read (0: unknown). A grammar whose twin would be larger fails with a clear error instead of
 * exhausting the machine's memory. */
uint32_t pgt_facade_twin_max_triangles(int with_embree, uint64_t *available);
/* " (what fits in 3/4 of the X GiB of memory available...)": why that limit, for the message of
 * the error it gives (empty when available is 0). */
const char *pgt_facade_twin_limit_why(char *buf, size_t size, uint64_t available, int with_embree);

#endif
