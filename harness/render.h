/* pgt harness: a small ray tracer for paper figures (meshes such as ivy on a surface, paper 000
 * Fig. 1 and 10), on Embree 3 (one RTCScene, one triangle geometry per mesh, rtcIntersect1 and
 * rtcOccluded1 per ray; figures, not benchmarks).
 *
 * The picture: a pinhole camera; per pixel an N x N regular grid of subpixel samples (no jitter,
 * so the bytes do not depend on the thread count); per sample the closest hit, its geometric
 * normal turned to face the viewer (two-sided), Lambert shading under one directional key light
 * fixed relative to the camera plus an ambient term, one shadow ray toward the key light; the
 * samples are averaged in linear light and the mean is encoded to 8-bit sRGB.
 *
 *   linear = albedo * (PGT_RENDER_AMBIENT + PGT_RENDER_KEY * max(0, n . l) * visible)
 *
 * Camera convention (right-handed): w = normalize(eye - at) points back toward the viewer,
 * u = normalize(up x w) to the right, v = w x u up in the picture. Pixel (x, y) has column x to
 * the right and row y downward; the sample at image-plane position (px, py), in pixels from the
 * top-left corner, looks along normalize(-w + sx * u + sy * v) with
 *   sx = (2 px / W - 1) * tan(fov / 2) * W / H,   sy = (1 - 2 py / H) * tan(fov / 2),
 * so fov is the vertical field of view and pixels are square. */
#ifndef PGT_RENDER_H
#define PGT_RENDER_H

#include <stdint.h>

#include "pgt/mesh.h"
#include "pgt/progress.h"
#include "pgt/result.h"

/* Shading constants. The key light comes from above-left of the camera and a little from behind
 * it, so what the camera sees is lit: its direction toward the light, in camera coordinates
 * (right u, up v, back w) before normalisation, is (KEY_RIGHT, KEY_UP, KEY_BACK). A surface
 * facing the camera gets n . l = 2 / sqrt(6) = 0.816. */
#define PGT_RENDER_AMBIENT 0.25f /* fill light: faces turned away from the key are not black */
#define PGT_RENDER_KEY 0.75f     /* key light; AMBIENT + KEY = 1: a lit face shows its albedo */
#define PGT_RENDER_KEY_RIGHT (-1.0)
#define PGT_RENDER_KEY_UP 1.0
#define PGT_RENDER_KEY_BACK 2.0

/* Default subpixel grid side (2 x 2 = 4 samples per pixel) and the largest allowed (16 x 16). */
#define PGT_RENDER_DEFAULT_SPP 2u
#define PGT_RENDER_MAX_SPP 16u

/* Vertical field of view of the automatic camera, degrees, and how much room it leaves around
 * the bounding sphere (5 %). */
#define PGT_RENDER_AUTO_FOV 35.0f
#define PGT_RENDER_AUTO_MARGIN 1.05

/* Shadow rays start at the hit point (from its barycentrics) and ignore hits nearer than this
 * (tnear), relative to the scene extent (the larger of the bounding-box diagonal and the largest
 * absolute coordinate): hit points carry float rounding of a few ulps of that extent (~1e-7
 * relative), so 1e-4 keeps a surface from shadowing itself except where the light grazes it
 * (n . l below ~1e-3, where the key light adds almost nothing), while occluders nearer than 1e-4
 * of the scene cast no shadow. */
#define PGT_RENDER_SHADOW_OFFSET_REL 1e-4f

/* Largest |coordinate| of a mesh vertex and of the camera's eye and look-at point. Embree
 * (3.13, assertions on in Debian's build) aborts on a ray whose origin lies beyond about 1.8e18
 * (ray.valid()); the automatic camera stands a few bounding radii away (PGT_RENDER_AUTO_FOV),
 * so meshes within 1e15 keep it far inside, and an explicit eye within 1e17 too. */
#define PGT_RENDER_MAX_COORD 1e15f
#define PGT_RENDER_MAX_EYE 1e17f

/* A camera is degenerate when the sine of the angle between up and the view direction is below
 * this (the right vector would be rounding noise; 1e-6 rad is far below any intended camera). */
#define PGT_RENDER_MIN_UP_SINE 1e-6

/* One mesh of the scene. Positions and indices are shared with Embree, never modified.
 * positions_padded: nonzero when mesh->positions has room for at least one more float after
 * its 3 * vertex_count (pgt_render_pad_positions makes that room); Embree reads every vertex
 * with a 16-byte load, so unpadded positions are copied once into a padded Embree buffer,
 * padded ones are used in place. Indices are always used in place. */
typedef struct pgt_render_mesh {
    const pgt_mesh *mesh;
    float rgb[3]; /* linear diffuse albedo, each in [0, 1] */
    int positions_padded;
} pgt_render_mesh;

/* Eye and look-at point in the meshes' units, up direction (any length, not parallel to the view
 * direction), vertical field of view in degrees, in (0, 180). */
typedef struct pgt_render_camera {
    float eye[3], at[3], up[3], fov_deg;
} pgt_render_camera;

/* Zero-initialised options are the defaults. */
typedef struct pgt_render_options {
    uint32_t spp;        /* subpixel grid side N (N x N samples per pixel), 1 to
                            PGT_RENDER_MAX_SPP; 0: PGT_RENDER_DEFAULT_SPP */
    uint32_t threads;    /* worker threads for the BVH build and the trace, up to
                            PGT_MAX_THREADS; 0: every CPU */
    int no_shadows;      /* nonzero: no shadow rays (the key light reaches every surface) */
    int background_set;  /* zero: white background */
    float background[3]; /* the background as it appears in the PNG (sRGB-encoded, in [0, 1]) */
    pgt_progress *progress; /* NULL, or the stages "BVH" and "rays" (in image rows) */
} pgt_render_options;

/* What a render took (milliseconds of wall time) and what it drew. */
typedef struct pgt_render_stats {
    double bvh_ms;   /* Embree device, geometries and BVH build */
    double trace_ms; /* primary and shadow rays, shading, encoding */
    uint64_t triangles;
    uint64_t rays; /* primary plus shadow rays */
} pgt_render_stats;

/* Ray traces `count` meshes into rgb_out, w * h pixels of 3 bytes (R, G, B), rows top to bottom.
 * o may be NULL (defaults); out_stats may be NULL. The bytes depend only on the inputs, not on
 * the thread count. Errors (nothing is written to out_stats; rgb_out is unspecified):
 * - PGT_ERROR_INVALID_ARGUMENT: w or h 0 or above PGT_IMAGE_MAX_SIDE, count 0, a NULL mesh, a
 *   colour outside [0, 1] or not finite, a triangle index >= its mesh's vertex count, spp or
 *   threads out of range, a degenerate camera (pgt_render_camera_check's message);
 * - PGT_ERROR_OUT_OF_MEMORY;
 * - PGT_ERROR_BACKEND: Embree reported an error ("embree: CODE: message", the first one). */
pgt_result pgt_render(uint8_t *rgb_out, uint32_t w, uint32_t h, const pgt_render_mesh *meshes,
                      uint32_t count, const pgt_render_camera *cam, const pgt_render_options *o,
                      pgt_render_stats *out_stats, pgt_error *err);

/* PGT_OK when cam can render, else PGT_ERROR_INVALID_ARGUMENT with a message starting "camera:"
 * naming the problem: a value that is not finite, the eye at the look-at point, up of length 0
 * or parallel to the view direction (PGT_RENDER_MIN_UP_SINE), fov not in (0, 180). */
pgt_result pgt_render_camera_check(const pgt_render_camera *cam, pgt_error *err);

/* The automatic framing: looks at the centre of the union bounding box of the meshes' vertices
 * from azimuth az_deg and elevation el_deg (degrees) around the axis up_axis (0 x, 1 y, 2 z), at
 * the distance where the bounding sphere (half the box diagonal) fills the field of view
 * PGT_RENDER_AUTO_FOV (vertical, or horizontal when the picture is taller than wide, from
 * aspect = width / height) with PGT_RENDER_AUTO_MARGIN around it. Azimuth 0 looks from the +z
 * side for up y, from -y for up z, from +y for up x, and grows counter-clockwise seen from the
 * up axis (right-hand rule); elevation 90 would look down the up axis. The camera's up is the
 * axis. A scene of one point gets a bounding radius of 1. Inputs are the caller's contract
 * (finite angles, |el_deg| < 90, aspect > 0, count >= 1, meshes with vertices): asserts. */
void pgt_render_auto_camera(const pgt_render_mesh *meshes, uint32_t count, double az_deg,
                            double el_deg, int up_axis, double aspect, pgt_render_camera *out);

/* Grows mesh->positions by one float (set to 0) so Embree can share it (positions_padded = 1).
 * realloc: usually in place or a remap, at most one copy. PGT_ERROR_OUT_OF_MEMORY leaves the
 * mesh unchanged; a coordinate beyond +-PGT_RENDER_MAX_COORD is PGT_ERROR_INVALID_ARGUMENT
 * (pgt_render refuses it too), before the automatic camera is placed from the meshes. */
pgt_result pgt_render_pad_positions(pgt_mesh *mesh, pgt_error *err);

#endif
