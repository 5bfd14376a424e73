/* pgt: procedural input meshes (see gen.h for the contract, README.md for the constructions).
 *
 * Everything is computed in double and rounded to float32 once, when stored; randomness is
 * pgt_rng_* keyed by (seed, stream, element index) only. */
#include "gen.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/rng.h>

/* M_PI is not strict C11. */
#define GEN_PI 3.14159265358979323846

/* Counts are checked in 64 bits against the mesh limit before anything is allocated. */
static pgt_result check_sizes(const char *fn, uint64_t vertices, uint64_t faces, pgt_error *err) {
    if (vertices > PGT_MESH_MAX_ELEMENTS || faces > PGT_MESH_MAX_ELEMENTS)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: %llu vertices and %llu faces exceed the limit of %u elements",
                             fn, (unsigned long long)vertices, (unsigned long long)faces,
                             PGT_MESH_MAX_ELEMENTS);
    return PGT_OK;
}

static void store3(float *dst, double x, double y, double z) {
    dst[0] = (float)x;
    dst[1] = (float)y;
    dst[2] = (float)z;
}

static void store_tri(uint32_t *dst, uint32_t a, uint32_t b, uint32_t c) {
    dst[0] = a;
    dst[1] = b;
    dst[2] = c;
}

/* ---------------------------------------------------------------------------------------------
 * Icosphere */

typedef struct gen_edge_key {
    uint64_t key; /* min vertex << 32 | max vertex */
    uint32_t half_edge;
} gen_edge_key;

static int compare_edge_key(const void *pa, const void *pb) {
    const gen_edge_key *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->half_edge < b->half_edge ? -1 : a->half_edge > b->half_edge;
}

static void normalize3(double *p) {
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    p[0] /= len;
    p[1] /= len;
    p[2] /= len;
}

pgt_result pgt_gen_icosphere(pgt_mesh *out, uint32_t level, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (level > PGT_GEN_ICOSPHERE_MAX_LEVEL)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "pgt_gen_icosphere: level %u exceeds the maximum %u (20 * 4^level "
                             "faces must stay within %u)",
                             level, PGT_GEN_ICOSPHERE_MAX_LEVEL, PGT_MESH_MAX_ELEMENTS);
    const uint64_t pow4 = (uint64_t)1 << (2 * level);
    const uint64_t final_v = 10 * pow4 + 2, final_f = 20 * pow4;
    pgt_result r = check_sizes("pgt_gen_icosphere", final_v, final_f, err);
    if (r != PGT_OK) return r;

    /* The icosahedron (+-1, +-phi, 0) and cyclic permutations, phi = (1 + sqrt 5) / 2 written
     * to more digits than double holds; faces CCW seen from outside. */
#define GEN_PHI 1.61803398874989484820
    static const double ico_v[12][3] = {
        {-1, GEN_PHI, 0}, {1, GEN_PHI, 0},  {-1, -GEN_PHI, 0}, {1, -GEN_PHI, 0},
        {0, -1, GEN_PHI}, {0, 1, GEN_PHI},  {0, -1, -GEN_PHI}, {0, 1, -GEN_PHI},
        {GEN_PHI, 0, -1}, {GEN_PHI, 0, 1},  {-GEN_PHI, 0, -1}, {-GEN_PHI, 0, 1}};
#undef GEN_PHI
    static const uint8_t ico_f[20][3] = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

    double *pos = malloc((size_t)final_v * 3 * sizeof(double));
    uint32_t *tri = malloc((size_t)final_f * 3 * sizeof(uint32_t));
    uint32_t *next = level ? malloc((size_t)final_f * 3 * sizeof(uint32_t)) : NULL;
    /* Half-edges of the last level before the final one: 3 * final_f / 4. */
    const size_t max_half_edges = level ? (size_t)(final_f / 4) * 3 : 1;
    gen_edge_key *edges = level ? malloc(max_half_edges * sizeof(gen_edge_key)) : NULL;
    uint32_t *mid = level ? malloc(max_half_edges * sizeof(uint32_t)) : NULL;
    if (!pos || !tri || (level && (!next || !edges || !mid))) {
        free(pos);
        free(tri);
        free(next);
        free(edges);
        free(mid);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "pgt_gen_icosphere: out of memory for level %u", level);
    }

    for (int v = 0; v < 12; ++v) {
        for (int k = 0; k < 3; ++k) pos[3 * v + k] = ico_v[v][k];
        normalize3(pos + 3 * v);
    }
    for (int f = 0; f < 20; ++f)
        for (int c = 0; c < 3; ++c) tri[3 * f + c] = ico_f[f][c];

    uint32_t vcount = 12, fcount = 20;
    for (uint32_t l = 0; l < level; ++l) {
        const uint32_t hcount = 3 * fcount;
        for (uint32_t h = 0; h < hcount; ++h) {
            uint32_t a = tri[h], b = tri[h - h % 3 + (h % 3 + 1) % 3];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            edges[h].key = (uint64_t)lo << 32 | hi;
            edges[h].half_edge = h;
        }
        qsort(edges, hcount, sizeof(*edges), compare_edge_key);
        /* One new vertex per distinct edge, numbered in edge-key order. */
        for (uint32_t i = 0; i < hcount; ++i) {
            if (i == 0 || edges[i].key != edges[i - 1].key) {
                uint32_t a = (uint32_t)(edges[i].key >> 32), b = (uint32_t)edges[i].key;
                double *p = pos + 3 * (size_t)vcount;
                for (int k = 0; k < 3; ++k)
                    p[k] = 0.5 * (pos[3 * (size_t)a + k] + pos[3 * (size_t)b + k]);
                normalize3(p);
                vcount++;
            }
            mid[edges[i].half_edge] = vcount - 1;
        }
        /* 1-to-4: three corner triangles and the middle one, all keeping the parent's winding. */
        for (uint32_t f = 0; f < fcount; ++f) {
            uint32_t a = tri[3 * f], b = tri[3 * f + 1], c = tri[3 * f + 2];
            uint32_t ab = mid[3 * f], bc = mid[3 * f + 1], ca = mid[3 * f + 2];
            uint32_t *t = next + 12 * (size_t)f;
            store_tri(t, a, ab, ca);
            store_tri(t + 3, ab, b, bc);
            store_tri(t + 6, ca, bc, c);
            store_tri(t + 9, ab, bc, ca);
        }
        uint32_t *swap = tri;
        tri = next;
        next = swap;
        fcount *= 4;
    }
    assert(vcount == final_v && fcount == final_f);

    r = pgt_mesh_create(out, vcount, fcount, 0, 0, err);
    if (r == PGT_OK) {
        for (size_t i = 0; i < (size_t)vcount * 3; ++i) out->positions[i] = (float)pos[i];
        memcpy(out->indices, tri, (size_t)fcount * 3 * sizeof(uint32_t));
    }
    free(pos);
    free(tri);
    free(next);
    free(edges);
    free(mid);
    return r;
}

/* ---------------------------------------------------------------------------------------------
 * Torus */

static pgt_result check_torus(const char *fn, double R, double r, uint32_t nu, uint32_t nv,
                              pgt_error *err) {
    if (!isfinite(R) || !isfinite(r) || !(r > 0.0) || !(r < R))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: radii R = %g, r = %g must be finite with 0 < r < R", fn, R, r);
    if (nu < 3 || nv < 3)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: nu = %u and nv = %u must both be at least 3", fn, nu, nv);
    return check_sizes(fn, (uint64_t)nu * nv, 2 * (uint64_t)nu * nv, err);
}

/* Shared by the plain and noisy tori: amplitude 0 means no displacement and no draws. */
static pgt_result build_torus(pgt_mesh *out, double R, double r, uint32_t nu, uint32_t nv,
                              uint32_t seed, double amplitude, pgt_error *err) {
    pgt_result res = pgt_mesh_create(out, nu * nv, 2 * nu * nv, 0, 0, err);
    if (res != PGT_OK) return res;
    for (uint32_t i = 0; i < nu; ++i) {
        const double u = 2.0 * GEN_PI * (double)i / (double)nu;
        const double cu = cos(u), su = sin(u);
        for (uint32_t j = 0; j < nv; ++j) {
            const double v = 2.0 * GEN_PI * (double)j / (double)nv;
            const uint32_t k = i * nv + j;
            /* Moving along the outward normal (cos v cos u, cos v sin u, sin v) by d is the same
             * as using tube radius r + d at this vertex. */
            double rr = r;
            if (amplitude != 0.0)
                rr += amplitude * (2.0 * pgt_rng_double(seed, PGT_GEN_STREAM_NOISY_TORUS, k) - 1.0);
            const double ring = R + rr * cos(v);
            store3(out->positions + 3 * (size_t)k, ring * cu, ring * su, rr * sin(v));
        }
    }
    /* d(p)/du x d(p)/dv points outward, so (i,j) (i+1,j) (i+1,j+1) (i,j+1) is CCW outside. */
    for (uint32_t i = 0; i < nu; ++i) {
        const uint32_t i1 = (i + 1) % nu;
        for (uint32_t j = 0; j < nv; ++j) {
            const uint32_t j1 = (j + 1) % nv;
            const uint32_t a = i * nv + j, b = i1 * nv + j, c = i1 * nv + j1, d = i * nv + j1;
            uint32_t *t = out->indices + 6 * (size_t)(i * nv + j);
            store_tri(t, a, b, c);
            store_tri(t + 3, a, c, d);
        }
    }
    return PGT_OK;
}

pgt_result pgt_gen_torus(pgt_mesh *out, double R, double r, uint32_t nu, uint32_t nv,
                         pgt_error *err) {
    memset(out, 0, sizeof(*out));
    pgt_result res = check_torus("pgt_gen_torus", R, r, nu, nv, err);
    if (res != PGT_OK) return res;
    return build_torus(out, R, r, nu, nv, 0, 0.0, err);
}

pgt_result pgt_gen_noisy_torus(pgt_mesh *out, double R, double r, uint32_t nu, uint32_t nv,
                               uint32_t seed, double amplitude, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    pgt_result res = check_torus("pgt_gen_noisy_torus", R, r, nu, nv, err);
    if (res != PGT_OK) return res;
    if (!isfinite(amplitude) || !(amplitude >= 0.0) || !(amplitude < r) || !(r + amplitude < R))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_noisy_torus: amplitude = %g must be finite with "
                             "0 <= amplitude < r = %g and r + amplitude < R = %g",
                             amplitude, r, R);
    return build_torus(out, R, r, nu, nv, seed, amplitude, err);
}

pgt_result pgt_gen_bench_torus_size(uint32_t faces_target, uint32_t *out_nu, uint32_t *out_nv,
                                    pgt_error *err) {
    *out_nu = *out_nv = 0;
    if (faces_target < 18)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_bench_torus: faces_target = %u must be at least 18 (3 x 3 "
                             "quads)",
                             faces_target);
    if (faces_target > PGT_MESH_MAX_ELEMENTS)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "pgt_gen_bench_torus: faces_target = %u exceeds the limit of %u",
                             faces_target, PGT_MESH_MAX_ELEMENTS);
    /* nu : nv = 5 : 4 and nu * nv = quads: nv = sqrt(0.8 quads), then nu = quads / nv. */
    const double quads = (double)(faces_target / 2);
    double nv = floor(sqrt(0.8 * quads) + 0.5);
    if (nv < 3.0) nv = 3.0;
    double nu = floor(quads / nv + 0.5);
    if (nu < 3.0) nu = 3.0;
    pgt_result r = check_sizes("pgt_gen_bench_torus", (uint64_t)nu * (uint64_t)nv,
                               2 * (uint64_t)nu * (uint64_t)nv, err);
    if (r != PGT_OK) return r;
    *out_nu = (uint32_t)nu;
    *out_nv = (uint32_t)nv;
    return PGT_OK;
}

pgt_result pgt_gen_bench_torus(pgt_mesh *out, uint32_t faces_target, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    uint32_t nu, nv;
    pgt_result r = pgt_gen_bench_torus_size(faces_target, &nu, &nv, err);
    if (r != PGT_OK) return r;
    return pgt_gen_torus(out, 1.0, 0.4, nu, nv, err);
}

/* ---------------------------------------------------------------------------------------------
 * Grid */

pgt_result pgt_gen_grid(pgt_mesh *out, uint32_t nx, uint32_t ny, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (nx < 1 || ny < 1)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_grid: nx = %u and ny = %u must both be at least 1", nx, ny);
    pgt_result r = check_sizes("pgt_gen_grid", ((uint64_t)nx + 1) * ((uint64_t)ny + 1),
                               2 * (uint64_t)nx * ny, err);
    if (r != PGT_OK) return r;
    r = pgt_mesh_create(out, (nx + 1) * (ny + 1), 2 * nx * ny, 1, 0, err);
    if (r != PGT_OK) return r;
    const uint32_t w = nx + 1;
    for (uint32_t j = 0; j <= ny; ++j)
        for (uint32_t i = 0; i <= nx; ++i)
            store3(out->positions + 3 * ((size_t)j * w + i), (double)i / nx, (double)j / ny, 0.0);
    for (uint32_t j = 0; j < ny; ++j)
        for (uint32_t i = 0; i < nx; ++i) {
            const uint32_t a = j * w + i, b = a + 1, c = a + w + 1, d = a + w;
            uint32_t *t = out->indices + 6 * ((size_t)j * nx + i);
            if ((i + j) % 2 == 0) {
                store_tri(t, a, b, c);
                store_tri(t + 3, a, c, d);
            } else {
                store_tri(t, a, b, d);
                store_tri(t + 3, b, c, d);
            }
        }
    /* UVs are the float x, y of the corner (the same rounding as the positions). */
    for (size_t corner = 0; corner < (size_t)out->face_count * 3; ++corner) {
        const float *p = out->positions + 3 * (size_t)out->indices[corner];
        out->uvs[2 * corner] = p[0];
        out->uvs[2 * corner + 1] = p[1];
    }
    return PGT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Jagged hemisphere */

pgt_result pgt_gen_hemisphere_jagged(pgt_mesh *out, uint32_t rings, uint32_t segments,
                                     uint32_t seed, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (rings < 2 || segments < 3)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_hemisphere_jagged: rings = %u must be at least 2 and "
                             "segments = %u at least 3",
                             rings, segments);
    const uint64_t vcount = 1 + (uint64_t)rings * segments;
    const uint64_t full = (uint64_t)segments * (2 * (uint64_t)rings - 1);
    const uint32_t cuts = segments / 2;
    pgt_result r = check_sizes("pgt_gen_hemisphere_jagged", vcount, full, err);
    if (r != PGT_OK) return r;
    r = pgt_mesh_create(out, (uint32_t)vcount, (uint32_t)(full - cuts), 0, 0, err);
    if (r != PGT_OK) return r;

    const double dtheta = 0.5 * GEN_PI / rings;
    store3(out->positions, 0.0, 0.0, 1.0);
    for (uint32_t k = 1; k <= rings; ++k)
        for (uint32_t s = 0; s < segments; ++s) {
            double theta = dtheta * k;
            if (k == rings && s % 2 == 1) {
                /* Raised rim vertex: between 1/4 and 3/4 of the way up to the ring above. */
                const double h = pgt_rng_double(seed, PGT_GEN_STREAM_JAGGED_HEIGHT, s);
                theta = 0.5 * GEN_PI - dtheta * (0.25 + 0.5 * h);
            }
            const double phi = 2.0 * GEN_PI * (double)s / (double)segments;
            store3(out->positions + 3 * (1 + (size_t)(k - 1) * segments + s),
                   sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
        }

    /* Which rim quads lose their rim triangle: one of each pair (2t, 2t+1). */
    uint8_t *cut = calloc(segments, 1);
    if (!cut) {
        pgt_mesh_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "pgt_gen_hemisphere_jagged: out of memory");
    }
    for (uint32_t t = 0; t < cuts; ++t)
        cut[2 * t + (uint32_t)(pgt_rng_u64(seed, PGT_GEN_STREAM_JAGGED_CUT, t) & 1u)] = 1;

    uint32_t *tri = out->indices;
    /* Pole fan: seen from above, increasing azimuth is counter-clockwise. */
    for (uint32_t s = 0; s < segments; ++s) {
        store_tri(tri, 0, 1 + s, 1 + (s + 1) % segments);
        tri += 3;
    }
    /* Bands between ring k and the ring k+1 below it; quad a (ring k), b, c (ring k+1), d. */
    for (uint32_t k = 1; k < rings; ++k) {
        const uint32_t up = 1 + (k - 1) * segments, down = up + segments;
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t s1 = (s + 1) % segments;
            const uint32_t a = up + s, b = down + s, c = down + s1, d = up + s1;
            if (!(k + 1 == rings && cut[s])) {
                store_tri(tri, a, b, c);
                tri += 3;
            }
            store_tri(tri, a, c, d);
            tri += 3;
        }
    }
    assert(tri == out->indices + 3 * (size_t)out->face_count);
    free(cut);
    return PGT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Cube sphere */

/* Face f of the lattice cube [0,n]^3: coordinate `axis` is fixed at 0 or n, grid coordinates
 * (a, b) run along axes u and v, chosen so that u x v is the outward normal (CCW grid cells). */
static const struct {
    uint8_t axis, at_n, u, v;
} cube_faces[6] = {
    {0, 1, 1, 2}, /* +x: y x z = +x */
    {0, 0, 2, 1}, /* -x: z x y = -x */
    {1, 1, 2, 0}, /* +y: z x x = +y */
    {1, 0, 0, 2}, /* -y: x x z = -y */
    {2, 1, 0, 1}, /* +z: x x y = +z */
    {2, 0, 1, 0}, /* -z: y x x = -z */
};

pgt_result pgt_gen_cube_sphere(pgt_mesh *out, uint32_t n, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (n < 1)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_cube_sphere: n = %u must be at least 1", n);
    const uint64_t n2 = (uint64_t)n * n;
    pgt_result r = check_sizes("pgt_gen_cube_sphere", 6 * n2 + 2, 12 * n2, err);
    if (r != PGT_OK) return r;
    const size_t side = (size_t)n + 1, per_face = side * side;
    uint32_t *index = malloc(6 * per_face * sizeof(uint32_t));
    if (!index)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_gen_cube_sphere: out of memory");
    r = pgt_mesh_create(out, (uint32_t)(6 * n2 + 2), (uint32_t)(12 * n2), 1, 1, err);
    if (r != PGT_OK) {
        free(index);
        return r;
    }

    /* Vertex numbering: faces in order, grid points b-major; a point already on an earlier face
     * (a cube edge or corner) reuses that face's index. */
    uint32_t vcount = 0;
    for (uint32_t f = 0; f < 6; ++f)
        for (uint32_t b = 0; b <= n; ++b)
            for (uint32_t a = 0; a <= n; ++a) {
                uint32_t xyz[3];
                xyz[cube_faces[f].axis] = cube_faces[f].at_n ? n : 0;
                xyz[cube_faces[f].u] = a;
                xyz[cube_faces[f].v] = b;
                uint32_t id = PGT_NONE;
                for (uint32_t g = 0; g < f && id == PGT_NONE; ++g)
                    if (xyz[cube_faces[g].axis] == (cube_faces[g].at_n ? n : 0))
                        id = index[g * per_face + xyz[cube_faces[g].v] * side +
                                   xyz[cube_faces[g].u]];
                if (id == PGT_NONE) {
                    id = vcount++;
                    double p[3];
                    for (int k = 0; k < 3; ++k) p[k] = 2.0 * (double)xyz[k] / (double)n - 1.0;
                    normalize3(p);
                    store3(out->positions + 3 * (size_t)id, p[0], p[1], p[2]);
                }
                index[f * per_face + b * side + a] = id;
            }
    assert(vcount == out->vertex_count);

    const double g = PGT_GEN_CUBE_SPHERE_GUTTER;
    const double chart_w = 1.0 / 3.0 - 2.0 * g, chart_h = 0.5 - 2.0 * g;
    size_t face = 0;
    for (uint32_t f = 0; f < 6; ++f) {
        const double u0 = (double)(f % 3) / 3.0 + g, v0 = (double)(f / 3) / 2.0 + g;
        for (uint32_t b = 0; b < n; ++b)
            for (uint32_t a = 0; a < n; ++a) {
                /* Cell corners in CCW order; the cell is split along (a,b)-(a+1,b+1). */
                const uint32_t ca[4] = {a, a + 1, a + 1, a}, cb[4] = {b, b, b + 1, b + 1};
                static const uint8_t split[2][3] = {{0, 1, 2}, {0, 2, 3}};
                for (int t = 0; t < 2; ++t, ++face) {
                    for (int c = 0; c < 3; ++c) {
                        const uint32_t pa = ca[split[t][c]], pb = cb[split[t][c]];
                        out->indices[3 * face + c] = index[f * per_face + pb * side + pa];
                        out->uvs[6 * face + 2 * c] =
                            (float)(u0 + chart_w * ((double)pa / (double)n));
                        out->uvs[6 * face + 2 * c + 1] =
                            (float)(v0 + chart_h * ((double)pb / (double)n));
                    }
                    out->labels[face] = (int32_t)f;
                }
            }
    }
    assert(face == out->face_count);
    free(index);
    return PGT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Default datasets */

typedef enum gen_kind {
    GEN_ICOSPHERE,
    GEN_TORUS,
    GEN_NOISY_TORUS,
    GEN_GRID,
    GEN_HEMISPHERE_JAGGED,
    GEN_CUBE_SPHERE
} gen_kind;

/* Small on purpose: tests run sqrt(3) up to k = 3 on each against CGAL. */
static const struct {
    const char *name;
    gen_kind kind;
    uint32_t a, b, seed;
    double R, r, amplitude;
} gen_defaults[] = {
    {"icosphere_l0", GEN_ICOSPHERE, 0, 0, 0, 0.0, 0.0, 0.0},
    {"icosphere_l1", GEN_ICOSPHERE, 1, 0, 0, 0.0, 0.0, 0.0},
    {"icosphere_l2", GEN_ICOSPHERE, 2, 0, 0, 0.0, 0.0, 0.0},
    {"icosphere_l3", GEN_ICOSPHERE, 3, 0, 0, 0.0, 0.0, 0.0},
    {"torus_32x16", GEN_TORUS, 32, 16, 0, 1.0, 0.4, 0.0},
    {"noisy_torus_48x24", GEN_NOISY_TORUS, 48, 24, 7, 1.0, 0.4, 0.02},
    {"grid_16x16", GEN_GRID, 16, 16, 0, 0.0, 0.0, 0.0},
    {"hemisphere_jagged_12x32", GEN_HEMISPHERE_JAGGED, 12, 32, 11, 0.0, 0.0, 0.0},
    {"cube_sphere_8", GEN_CUBE_SPHERE, 8, 0, 0, 0.0, 0.0, 0.0},
};

#define GEN_DEFAULT_COUNT ((uint32_t)(sizeof(gen_defaults) / sizeof(gen_defaults[0])))

uint32_t pgt_gen_default_count(void) { return GEN_DEFAULT_COUNT; }

const char *pgt_gen_default_name(uint32_t i) {
    return i < GEN_DEFAULT_COUNT ? gen_defaults[i].name : NULL;
}

uint32_t pgt_gen_default_find(const char *name) {
    for (uint32_t i = 0; name && i < GEN_DEFAULT_COUNT; ++i)
        if (strcmp(gen_defaults[i].name, name) == 0) return i;
    return PGT_NONE;
}

pgt_result pgt_gen_default(uint32_t i, pgt_mesh *out, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (i >= GEN_DEFAULT_COUNT)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_default: index %u is past the %u default datasets", i,
                             GEN_DEFAULT_COUNT);
    const uint32_t a = gen_defaults[i].a, b = gen_defaults[i].b, seed = gen_defaults[i].seed;
    switch (gen_defaults[i].kind) {
    case GEN_ICOSPHERE: return pgt_gen_icosphere(out, a, err);
    case GEN_TORUS: return pgt_gen_torus(out, gen_defaults[i].R, gen_defaults[i].r, a, b, err);
    case GEN_NOISY_TORUS:
        return pgt_gen_noisy_torus(out, gen_defaults[i].R, gen_defaults[i].r, a, b, seed,
                                   gen_defaults[i].amplitude, err);
    case GEN_GRID: return pgt_gen_grid(out, a, b, err);
    case GEN_HEMISPHERE_JAGGED: return pgt_gen_hemisphere_jagged(out, a, b, seed, err);
    case GEN_CUBE_SPHERE: return pgt_gen_cube_sphere(out, a, err);
    }
    assert(0 && "unknown default dataset kind");
    return PGT_ERROR_INVALID_ARGUMENT;
}
