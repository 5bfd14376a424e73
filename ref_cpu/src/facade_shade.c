/* pgt: fine detail of facade terminals in terminal space (paper 003 sec. 6.3-6.4): procedural
 * materials as height fields, normal mapping, relief mapping with self-shadowing in the relief.
 *
 * Terminal space. A terminal's rectangle is axis-aligned in facade space; its terminal space
 * (t_T, b_T, n_T) is the rectangle's two in-plane axes and its normal turned towards the ray
 * (6.3: "for parametric surface sets the terminal space is" the partial derivatives of the
 * surface). The pattern coordinates (u, v) are facade-space coordinates in metres, v up on
 * vertical surfaces: (x, y) on z-facing rectangles, (z, y) on x-facing ones, (x, z) on
 * horizontal ones, so bricks run on across neighbouring terminals of one wall.
 *
 * Height fields h(u, v) in [0, 1] (1 = the macroscopic surface, 0 = the bottom of the relief,
 * depth D below it): bricks (running bond, 24 x 6.5 cm with 1 cm joints, D = 1.2 cm) on walls and
 * reveals, stone blocks (60 x 30 cm, 1 cm joints, D = 0.8 cm) on ledges, sills and slabs, vertical
 * planks (12 cm, D = 0.4 cm) on doors; glass, frames and railings are smooth.
 *
 * Relief mapping (Policarpo et al. 2005, the paper's [16, 15]): from the macroscopic hit the ray
 * goes on below the surface; linear search in RELIEF_LINEAR steps over the depth range, then
 * RELIEF_BINARY bisections. Self-shadowing: from the relief hit towards the light, the same
 * linear search: a height above the ray on the way out shadows it. */
#include <math.h>

#include "facade_internal.h"

#define RELIEF_LINEAR 24u
#define RELIEF_BINARY 6u
#define RELIEF_SHADOW_STEPS 16u
/* A grazing ray crosses the relief layer over a long way: the search stops after this many
 * metres along the surface (the relief then ends where it stops). */
#define RELIEF_MAX_TRAVEL 0.5f
/* Central differences of h for normals (metres): a fifth of a joint. */
#define RELIEF_GRAD_EPS 0.002f
/* A point this far (metres) below the height field still counts as on it when a shadow ray
 * leaves the relief: the height field's own float rounding at the start point. */
#define RELIEF_SHADOW_BIAS 1e-5f

static float smooth01(float x) {
    x = x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
    return x * x * (3.0f - 2.0f * x);
}

/* Distance to the nearest joint of a running-bond grid of w x hgt cells (odd rows offset by
 * half a cell), in metres. */
static float min2(float a, float b) { return a < b ? a : b; }

static float joint_distance(float u, float v, float w, float hgt, int bond) {
    const float row = floorf(v / hgt);
    const float fv = v - row * hgt;
    const int odd = (int)((int64_t)row & 1); /* |v| is metres on a facade: row fits */
    const float uu = u + (bond && odd ? 0.5f * w : 0.0f);
    const float fu = uu - floorf(uu / w) * w;
    return min2(min2(fu, w - fu), min2(fv, hgt - fv));
}

uint32_t facade_material(uint32_t kind, uint32_t surface) {
    /* geometry images carry no pattern (their triangles are not axis-aligned) */
    switch (kind) {
    case PGT_FACADE_WALL:
        return FACADE_MAT_BRICK;
    case PGT_FACADE_WINDOW:
        return surface <= 3u || (surface >= 17u && surface <= 20u) || surface >= 22u
                   ? FACADE_MAT_BRICK
               : surface <= 9u ? FACADE_MAT_STONE
                               : FACADE_MAT_NONE;
    case PGT_FACADE_DOOR:
        return surface <= 2u || (surface >= 9u && surface <= 11u) ? FACADE_MAT_BRICK
               : surface == 12u                                   ? FACADE_MAT_WOOD
                                                                  : FACADE_MAT_NONE;
    case PGT_FACADE_LEDGE:
        return FACADE_MAT_STONE;
    case PGT_FACADE_BALCONY:
        return surface <= 4u ? FACADE_MAT_STONE : FACADE_MAT_NONE;
    default:
        return FACADE_MAT_NONE;
    }
}

float facade_relief_depth(uint32_t material) {
    static const float depth[FACADE_MAT_COUNT] = {0.0f, 0.012f, 0.008f, 0.004f};
    return material < FACADE_MAT_COUNT ? depth[material] : 0.0f;
}

float facade_height(uint32_t material, float u, float v) {
    switch (material) {
    case FACADE_MAT_BRICK: /* joint half-width 5 mm, rounded over 4 mm */
        return smooth01((joint_distance(u, v, 0.25f, 0.075f, 1) - 0.005f) / 0.004f);
    case FACADE_MAT_STONE:
        return smooth01((joint_distance(u, v, 0.61f, 0.31f, 1) - 0.005f) / 0.006f);
    case FACADE_MAT_WOOD: {
        const float fu = u - floorf(u / 0.12f) * 0.12f;
        return smooth01((min2(fu, 0.12f - fu) - 0.003f) / 0.01f);
    }
    default:
        return 1.0f;
    }
}

/* The pattern axes of a rectangle with normal axis `axis`: (iu, iv) facade-space axes of u, v. */
static void uv_axes(uint32_t axis, uint32_t *iu, uint32_t *iv) {
    *iu = axis == 0 ? 2u : 0u;
    *iv = axis == 1 ? 2u : 1u;
}

void facade_detail(const facade_detail_in *in, facade_detail_out *out) {
    const uint32_t ax = in->axis;
    uint32_t iu, iv;
    uv_axes(ax, &iu, &iv);
    const float D = facade_relief_depth(in->material) * in->relief;
    /* n_T faces the ray */
    const float sg = in->v[ax] < 0.0f ? 1.0f : -1.0f;
    const float down = fabsf(in->v[ax]); /* depth gained per metre along the ray */
    float u = in->p[iu], v = in->p[iv], s_hit = 0.0f;
    if (D > 0.0f && down > 0.0f) {
        const float s_max = fminf(D / down, RELIEF_MAX_TRAVEL);
        float s0 = 0.0f, s1 = s_max;
        int found = 0;
        for (uint32_t i = 1; i <= RELIEF_LINEAR && !found; ++i) {
            const float s = s_max * (float)i / (float)RELIEF_LINEAR;
            const float depth = s * down;
            if (depth >=
                D * (1.0f - facade_height(in->material, u + s * in->v[iu], v + s * in->v[iv])))
                s1 = s, found = 1;
            else
                s0 = s;
        }
        for (uint32_t i = 0; i < RELIEF_BINARY && found; ++i) {
            const float s = 0.5f * (s0 + s1);
            if (s * down >=
                D * (1.0f - facade_height(in->material, u + s * in->v[iu], v + s * in->v[iv])))
                s1 = s;
            else
                s0 = s;
        }
        s_hit = s1;
        u += s_hit * in->v[iu], v += s_hit * in->v[iv];
    }
    out->s = s_hit;
    out->h = facade_height(in->material, u, v);
    /* normal: n_T - D' (h_u e_u + h_v e_v), D' the normal-mapping depth */
    const float Dn = facade_relief_depth(in->material) * fmaxf(in->normal, in->relief);
    float n[3] = {0.0f, 0.0f, 0.0f};
    n[ax] = sg;
    if (Dn > 0.0f) {
        const float e = RELIEF_GRAD_EPS;
        const float hu =
            (facade_height(in->material, u + e, v) - facade_height(in->material, u - e, v)) /
            (2.0f * e);
        const float hv =
            (facade_height(in->material, u, v + e) - facade_height(in->material, u, v - e)) /
            (2.0f * e);
        n[iu] -= Dn * hu, n[iv] -= Dn * hv;
    }
    const float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) out->n[k] = n[k] / l;
    /* self-shadowing in the relief: from the hit towards the light until the ray leaves the
     * layer */
    out->shadowed = 0;
    if (D > 0.0f && in->relief_shadows) {
        const float up = in->l[ax] * sg; /* height gained per metre towards the light */
        if (up <= 0.0f) {
            out->shadowed = 1;
        } else {
            const float depth0 = D * (1.0f - out->h);
            const float s_max = fminf(depth0 / up, RELIEF_MAX_TRAVEL);
            for (uint32_t i = 1; i < RELIEF_SHADOW_STEPS && depth0 > 0.0f; ++i) {
                const float s = s_max * (float)i / (float)RELIEF_SHADOW_STEPS;
                const float depth = depth0 - s * up;
                const float hh = facade_height(in->material, u + s * in->l[iu], v + s * in->l[iv]);
                if (depth > D * (1.0f - hh) + RELIEF_SHADOW_BIAS) {
                    out->shadowed = 1;
                    break;
                }
            }
        }
    }
}

float pgt_facade_pattern_height(uint32_t kind, uint32_t surface, float u, float v) {
    return facade_height(facade_material(kind, surface), u, v);
}

float pgt_facade_relief_depth(uint32_t kind, uint32_t surface) {
    return facade_relief_depth(facade_material(kind, surface));
}
