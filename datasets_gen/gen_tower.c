/* pgt datasets: a twisted elliptic tower of quads with UVs in metres and normals, for facades on
 * generic meshes (paper 003 sec. 10, Fig. 12). See gen.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"

/* Quads around and up at most: a tower of 4096 x 4096 quads is far past any figure. */
#define TOWER_MAX_SIDE 4096u
/* Simpson intervals per radian of the arc-length integral: the error is far below float32's
 * rounding of the UVs for any ellipse of aspect up to 10. */
#define TOWER_SIMPSON_PER_RAD 512.0

static const double PI = 3.14159265358979323846;

/* Arc length of the ellipse (ax cos a, az sin a) from angle 0 to a (negative for a < 0). */
static double arc(double ax, double az, double a) {
    const int n = 2 * (int)ceil(fabs(a) * TOWER_SIMPSON_PER_RAD * 0.5 + 1.0);
    const double h = a / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double x = h * i, s = sin(x), c = cos(x);
        const double f = sqrt(ax * ax * s * s + az * az * c * c);
        sum += (i == 0 || i == n) ? f : (i % 2 ? 4.0 * f : 2.0 * f);
    }
    return sum * h / 3.0;
}

pgt_result pgt_gen_tower(pgt_facade_quads *out, double ax, double az, double height,
                         double twist_deg, uint32_t segments, uint32_t rows, pgt_error *err) {
    memset(out, 0, sizeof *out);
    /* at least 1e-3: float positions and the normal's squared length stay far from underflow
     * (1e-300 wrote 0 positions and NaN normals) */
    if (!(ax >= 1e-3 && az >= 1e-3 && height >= 1e-3 && ax <= 1e4 && az <= 1e4 && height <= 1e4))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_tower: semi-axes %g, %g and height %g must be in [1e-3, 1e4]",
                             ax, az, height);
    if (!(fabs(twist_deg) <= 90.0))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_tower: twist %g degrees, expected |twist| <= 90", twist_deg);
    if (segments < 3 || rows < 1 || segments > TOWER_MAX_SIDE || rows > TOWER_MAX_SIDE)
        return pgt_error_set(err,
                             segments > TOWER_MAX_SIDE || rows > TOWER_MAX_SIDE
                                 ? PGT_ERROR_LIMIT
                                 : PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_tower: %u segments and %u rows, expected 3 to %u and 1 to %u",
                             segments, rows, TOWER_MAX_SIDE, TOWER_MAX_SIDE);
    const uint32_t cols = segments + 1u, V = cols * (rows + 1u), Q = segments * rows;
    out->positions = malloc((size_t)V * 3u * sizeof(float));
    out->normals = malloc((size_t)V * 3u * sizeof(float));
    out->uvs = malloc((size_t)V * 2u * sizeof(float));
    out->indices = malloc((size_t)Q * 4u * sizeof(uint32_t));
    if (!out->positions || !out->normals || !out->uvs || !out->indices) {
        pgt_facade_quads_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_gen_tower: out of memory");
    }
    out->vertex_count = V, out->quad_count = Q;
    const double twist = twist_deg * PI / 180.0;
    for (uint32_t j = 0; j <= rows; ++j) {
        const double y = height * j / rows, phi = twist * y / height;
        const double s0 = arc(ax, az, phi);
        for (uint32_t k = 0; k <= segments; ++k) {
            const uint32_t v = j * cols + k;
            const double a = phi - 2.0 * PI * k / segments;
            const double c = cos(a), s = sin(a);
            const double nx = az * c, nz = ax * s, nl = sqrt(nx * nx + nz * nz);
            out->positions[3u * v] = (float)(ax * c);
            out->positions[3u * v + 1u] = (float)y;
            out->positions[3u * v + 2u] = (float)(az * s);
            out->normals[3u * v] = (float)(nx / nl);
            out->normals[3u * v + 1u] = 0.0f;
            out->normals[3u * v + 2u] = (float)(nz / nl);
            out->uvs[2u * v] = (float)(s0 - arc(ax, az, a));
            out->uvs[2u * v + 1u] = (float)y;
        }
    }
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t k = 0; k < segments; ++k) {
            uint32_t *q = out->indices + 4u * (j * segments + k);
            q[0] = j * cols + k, q[1] = j * cols + k + 1u;
            q[2] = (j + 1u) * cols + k + 1u, q[3] = (j + 1u) * cols + k;
        }
    return PGT_OK;
}
