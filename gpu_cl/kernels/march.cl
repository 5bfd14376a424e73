/* pgt: marching on a geometry-image atlas in OpenCL C 1.2, a port of pgt_march_step in
 * ref_cpu/src/march.c (the specification: paper 000, sec. 5, 5.1, 5.2, and march.h's rules
 * beyond the paper: the remaining length in 3D, the Jacobian rotation, no bounce). Every
 * function below has the reference function of the same name and does the same float
 * operations in the same order (contraction off, division and sqrt correctly rounded on devices
 * that offer it), so that a walker's state after a step is the reference's to the bit. Not
 * ported: the CPU's cache requests (no effect on results) and the condition callback (a host
 * function; pgt_cl_march refuses it). The cosine and sine of each indirection texel's rot come
 * from the host (rotcs), computed with the reference's own cosf and sinf, whose last bit an
 * OpenCL cos may not match.
 *
 * The program is this file after gpu_shared/lang.h, gpu_shared/march_event.h, the reference's
 * ref_cpu/src/vec3_internal.h (dot3 and cross3, the reference's own source) and march_layout.h,
 * concatenated at build time (see ../CMakeLists.txt), which turns the #include below into a
 * comment. One work item is one walker. */

#include "vec3_internal.h"

#pragma OPENCL FP_CONTRACT OFF

#define MC_NONE 0xFFFFFFFFu
#define MC_KIND_BACKGROUND 0u
#define MC_KIND_INNER 1u
#define MC_KIND_INDIRECTION 2u
#define MC_KIND_DEAD_END 3u
#define MC_CODE(kind, chart) ((uint)(kind) | ((uint)((chart) + 1u) << 2))
#define MC_INNER 0u
#define MC_JUMP 1u
#define MC_SEARCH 2u
#define MC_STOP 3u
#define MC_STOP_NONE 0u
#define MC_STOP_DEAD_END 1u
#define MC_STOP_NO_INDIRECTION 2u
#define MC_STOP_TOO_MANY_JUMPS 3u
#define MC_STOP_REJECTED 4u
#define MC_STOP_BOUNCE 5u

/* pgt_march_texel, pgt_march_jump and pgt_march_state, as the host's arrays hold them. */
typedef struct mc_texel {
    float x, y, z;
    uint code;
} mc_texel;
typedef struct mc_jump {
    ushort u, v;
    float rot;
} mc_jump;
typedef struct mc_state {
    float x, y, dx, dy;
    uint chart, from;
    float in_dx, in_dy;
    uint bounces;
} mc_state;

/* pgt_march_atlas as the kernel reads it, plus the call's parameters. */
typedef struct mc_atlas {
    pgt_gpu_march_params p;
    __global const uint *codes;
    __global const mc_texel *texels;
    __global const mc_jump *jumps;
    __global const ushort *rings;
    __global const float2 *rotcs; /* (cosf(rot), sinf(rot)) of every texel's jump record */
    __global const float *mask;   /* when p.flags has PGT_GPU_MARCH_MASK */
} mc_atlas;

__constant int mc_ring_dx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
__constant int mc_ring_dy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};

static inline uint ring_neighbour(uint w, uint x, uint y, uint k) {
    return (y + (uint)mc_ring_dy[k]) * w + x + (uint)mc_ring_dx[k];
}

static inline uint lowest_bit(uint m) { return 31u - clz(m & (0u - m)); }

static inline uint texel_at(const mc_atlas *a, float x, float y) {
    const float fw = (float)a->p.width, fh = (float)a->p.height;
    if (!(x >= 0.0f && y >= 0.0f && x < fw && y < fh)) return MC_NONE;
    return (uint)y * a->p.width + (uint)x;
}

static inline uint code_of(const mc_atlas *a, uint t) { return t == MC_NONE ? 0u : a->codes[t]; }

static inline void pos3(const mc_atlas *a, uint t, float p[3]) {
    p[0] = a->texels[t].x, p[1] = a->texels[t].y, p[2] = a->texels[t].z;
}

static inline uint pointer_of(const mc_atlas *a, uint t) {
    return (uint)a->jumps[t].v * a->p.width + a->jumps[t].u;
}

static void position_rim(const mc_atlas *a, float x, float y, int i0, int j0, float fx, float fy,
                         float out_p[3]) {
    const int w = (int)a->p.width, tx = (int)x, ty = (int)y;
    const uint m = a->rings[ty * w + tx], block = (m & 0x0Fu) | (m & 0xF0u) << 1 | 0x10u;
    const float wx[2] = {1.0f - fx, fx}, wy[2] = {1.0f - fy, fy};
    float sum = 0.0f, p[3] = {0.0f, 0.0f, 0.0f};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int xi = i0 + i, yj = j0 + j;
            if (!(block >> ((yj - ty + 1) * 3 + xi - tx + 1) & 1u)) continue;
            const mc_texel q = a->texels[yj * w + xi];
            const float wq = wx[i] * wy[j];
            p[0] += wq * q.x, p[1] += wq * q.y, p[2] += wq * q.z;
            sum += wq;
        }
    for (int k = 0; k < 3; ++k) out_p[k] = p[k] / sum;
}

static void march_position(const mc_atlas *a, float x, float y, float out_p[3]) {
    const uint w = a->p.width;
    const int i0 = (int)(x + 0.5f) - 1, j0 = (int)(y + 0.5f) - 1;
    const float fx = x - 0.5f - (float)i0, fy = y - 0.5f - (float)j0;
    if (i0 >= 0 && j0 >= 0 && (uint)i0 + 1u < w && (uint)j0 + 1u < a->p.height) {
        const uint b = (uint)j0 * w + (uint)i0;
        const mc_texel q0 = a->texels[b], q1 = a->texels[b + 1u], q2 = a->texels[b + w],
                       q3 = a->texels[b + w + 1u];
        const uint c = q0.code;
        if ((c & 3u) == MC_KIND_INNER && q1.code == c && q2.code == c && q3.code == c) {
            const float w00 = (1.0f - fx) * (1.0f - fy), w10 = fx * (1.0f - fy),
                        w01 = (1.0f - fx) * fy, w11 = fx * fy;
            out_p[0] = w00 * q0.x + w10 * q1.x + w01 * q2.x + w11 * q3.x;
            out_p[1] = w00 * q0.y + w10 * q1.y + w01 * q2.y + w11 * q3.y;
            out_p[2] = w00 * q0.z + w10 * q1.z + w01 * q2.z + w11 * q3.z;
            return;
        }
    }
    position_rim(a, x, y, i0, j0, fx, fy, out_p);
}

static int texel_jacobian(const mc_atlas *a, uint t, float ex[3], float ey[3]) {
    const uint w = a->p.width, m = a->rings[t];
    const uint left = (m >> 3) & 1u, right = (m >> 4) & 1u, up = (m >> 1) & 1u,
               down = (m >> 6) & 1u;
    if (!(left | right) || !(up | down)) return 0;
    const mc_texel x0 = a->texels[t - left], x1 = a->texels[t + right],
                   y0 = a->texels[t - up * w], y1 = a->texels[t + down * w];
    const float ix = (left & right) ? 0.5f : 1.0f, iy = (up & down) ? 0.5f : 1.0f;
    ex[0] = (x1.x - x0.x) * ix, ex[1] = (x1.y - x0.y) * ix, ex[2] = (x1.z - x0.z) * ix;
    ey[0] = (y1.x - y0.x) * iy, ey[1] = (y1.y - y0.y) * iy, ey[2] = (y1.z - y0.z) * iy;
    return 1;
}

static inline void texel_motion(const float ex[3], const float ey[3], float dx, float dy,
                                float out_v[3]) {
    for (int k = 0; k < 3; ++k) out_v[k] = ex[k] * dx + ey[k] * dy;
}

static inline float norm3(const float v[3]) {
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static int transport_direction(const mc_atlas *a, const float sx_in[3], const float sy_in[3],
                               const float rx_in[3], const float ry_in[3], float dx, float dy,
                               float *out_dx, float *out_dy) {
    float sx[3], sy[3], rx[3], ry[3], m = 0.0f;
    for (int i = 0; i < 3; ++i) {
        sx[i] = sx_in[i], sy[i] = sy_in[i], rx[i] = rx_in[i], ry[i] = ry_in[i];
        m = fmax(m, fmax(fmax(fabs(sx[i]), fabs(sy[i])), fmax(fabs(rx[i]), fabs(ry[i]))));
    }
    if (!(m > 0.0f) || !isfinite(m)) return 0;
    if (m < a->p.jacobian_scale_min || m > a->p.jacobian_scale_max)
        for (int i = 0; i < 3; ++i) sx[i] /= m, sy[i] /= m, rx[i] /= m, ry[i] /= m;
    float ns[3], nr[3], v[3], k[3], kv[3], t[3];
    texel_motion(sx, sy, dx, dy, v);
    cross3(sx, sy, ns);
    cross3(rx, ry, nr);
    const float ls = sqrt(dot3(ns, ns)), lr = sqrt(dot3(nr, nr));
    if (!(ls > 0.0f) || !(lr > 0.0f)) return 0;
    for (int i = 0; i < 3; ++i) ns[i] /= ls, nr[i] /= lr;
    const float c = dot3(ns, nr);
    if (!(c > 0.0f)) return 0;
    cross3(ns, nr, k);
    cross3(k, v, kv);
    const float kk = dot3(k, v) / (1.0f + c);
    for (int i = 0; i < 3; ++i) t[i] = c * v[i] + kv[i] + kk * k[i];
    const float a11 = dot3(rx, rx), a12 = dot3(rx, ry), a22 = dot3(ry, ry);
    const float b1 = dot3(rx, t), b2 = dot3(ry, t), det = a11 * a22 - a12 * a12;
    if (!(det > a->p.min_jacobian_sine2 * a11 * a22)) return 0;
    const float ex = (a22 * b1 - a12 * b2) / det, ey = (a11 * b2 - a12 * b1) / det;
    const float l = sqrt(ex * ex + ey * ey);
    if (!(l > 0.0f)) return 0;
    *out_dx = ex / l, *out_dy = ey / l;
    return 1;
}

static uint search_xy(const mc_atlas *a, uint chart, float x0, float y0, float x1, float y1,
                      uint *out_x, uint *out_y) {
    const uint tag = chart + 1u;
    float lo = 0.0f, hi = 1.0f;
    for (uint i = 0; i < PGT_GPU_MARCH_SEARCH_ITERATIONS; ++i) {
        const float m = 0.5f * (lo + hi);
        const float x = x0 + (x1 - x0) * m, y = y0 + (y1 - y0) * m;
        const uint t = texel_at(a, x, y);
        const uint c = code_of(a, t);
        if ((c >> 2) != tag) {
            hi = m;
        } else if ((c & 3u) == MC_KIND_INNER) {
            lo = m;
        } else {
            *out_x = (uint)x, *out_y = (uint)y;
            return t;
        }
    }
    return MC_NONE;
}

static uint nearest_inner(const mc_atlas *a, float x, float y, uint px, uint py, uint *out_x,
                          uint *out_y) {
    const uint w = a->p.width, ring = a->rings[py * w + px] & 0xFFu;
    uint m = (ring & PGT_GPU_MARCH_RING_EDGES) ? ring & PGT_GPU_MARCH_RING_EDGES : ring;
    uint near = MC_NONE, bx = 0, by = 0;
    float near_e2 = INFINITY;
    for (; m; m &= m - 1u) {
        const uint k = lowest_bit(m);
        const uint nx = px + (uint)mc_ring_dx[k], ny = py + (uint)mc_ring_dy[k];
        const float ex = (float)nx + 0.5f - x, ey = (float)ny + 0.5f - y;
        const float e2 = ex * ex + ey * ey;
        if (e2 < near_e2) near = ny * w + nx, near_e2 = e2, bx = nx, by = ny;
    }
    *out_x = bx, *out_y = by;
    return near;
}

static void score_pointer(const mc_atlas *a, uint t, const float pc[3], const float r[3],
                          uint *best, float *best_score) {
    float q[3], c[3];
    pos3(a, pointer_of(a, t), q);
    for (int k = 0; k < 3; ++k) c[k] = q[k] - pc[k];
    const float len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(len > 0.0f)) return;
    const float score = (c[0] * r[0] + c[1] * r[1] + c[2] * r[2]) / len;
    if (score > *best_score) *best = t, *best_score = score;
}

static uint pointer_candidates(const mc_atlas *a, uint chart, uint p0, uint nx0, uint ny0,
                               uint cand[9]) {
    const uint w = a->p.width, near = ny0 * w + nx0;
    uint n = 0;
    cand[n] = p0;
    n += a->codes[p0] == MC_CODE(MC_KIND_INDIRECTION, chart) ? 1u : 0u;
    const uint ox = p0 % w + 1u - nx0, oy = p0 / w + 1u - ny0, b = oy * 3u + ox;
    uint m = (uint)a->rings[near] >> 8;
    if (ox <= 2u && oy <= 2u && b != 4u) m &= ~(1u << (b > 4u ? b - 1u : b));
    for (; m; m &= m - 1u) cand[n++] = ring_neighbour(w, nx0, ny0, lowest_bit(m));
    return n;
}

static uint best_pointer(const mc_atlas *a, uint chart, float x, float y, uint cur, uint p0,
                         uint p0x, uint p0y) {
    uint nx0 = 0, ny0 = 0;
    const uint near = nearest_inner(a, x, y, p0x, p0y, &nx0, &ny0);
    if (near == MC_NONE || near == cur) return p0;
    float pc[3], pn[3], r[3];
    pos3(a, cur, pc);
    pos3(a, near, pn);
    for (int k = 0; k < 3; ++k) r[k] = pn[k] - pc[k];
    uint best = p0;
    float best_score = -INFINITY;
    uint cand[9];
    const uint n = pointer_candidates(a, chart, p0, nx0, ny0, cand);
    for (uint k = 0; k < n; ++k) score_pointer(a, cand[k], pc, r, &best, &best_score);
    return best;
}

/* jump_direction for the jump record jr of texel t (rotcs[t]: its rot's cosine and sine). */
static int jump_direction(const mc_atlas *a, mc_jump jr, uint t, int has_src, const float sx[3],
                          const float sy[3], float dx, float dy, float *ndx, float *ndy,
                          float rx[3], float ry[3]) {
    const uint ref = (uint)jr.v * a->p.width + jr.u;
    const int has_ref = texel_jacobian(a, ref, rx, ry);
    *ndx = dx, *ndy = dy;
    if (a->p.flags & PGT_GPU_MARCH_NO_ROTATION) return has_ref;
    if ((a->p.flags & PGT_GPU_MARCH_JACOBIAN) && has_src && has_ref &&
        transport_direction(a, sx, sy, rx, ry, dx, dy, ndx, ndy))
        return has_ref;
    if (jr.rot != 0.0f) {
        const float2 cs = a->rotcs[t];
        *ndx = cs.x * dx - cs.y * dy, *ndy = cs.y * dx + cs.x * dy;
    }
    return has_ref;
}

static inline int bounces(const mc_atlas *a, uint from, uint u, uint v) {
    const uint w = a->p.width, f = from - 1u;
    if (f >= w * a->p.height) return 0;
    const uint fx = f % w, fy = f / w;
    const uint ex = u > fx ? u - fx : fx - u, ey = v > fy ? v - fy : fy - v;
    return ex <= PGT_GPU_MARCH_BOUNCE_TEXELS && ey <= PGT_GPU_MARCH_BOUNCE_TEXELS &&
           a->codes[f] == a->codes[v * w + u];
}

static uint unbounced_pointer(const mc_atlas *a, uint chart, float x, float y, uint cur, uint p0,
                              uint p0x, uint p0y, float dx, float dy, uint from) {
    const uint w = a->p.width;
    uint nx0 = 0, ny0 = 0, cand[9], n = 1;
    const uint near = nearest_inner(a, x, y, p0x, p0y, &nx0, &ny0);
    cand[0] = p0;
    if (near != MC_NONE) n = pointer_candidates(a, chart, p0, nx0, ny0, cand);
    const int has_r = near != MC_NONE && near != cur;
    float pc[3], r[3];
    if (has_r) {
        float pn[3];
        pos3(a, cur, pc);
        pos3(a, near, pn);
        for (int k = 0; k < 3; ++k) r[k] = pn[k] - pc[k];
    }
    uint best = MC_NONE;
    float best_score = -INFINITY;
    for (uint k = 0; k < n; ++k) {
        const uint t = cand[k];
        if (bounces(a, from, a->jumps[t].u, a->jumps[t].v)) continue;
        if (has_r) {
            score_pointer(a, t, pc, r, &best, &best_score);
            continue;
        }
        const float ox = (float)(t % w) + 0.5f - x, oy = (float)(t / w) + 0.5f - y;
        const float score = (ox * dx + oy * dy) / sqrt(ox * ox + oy * oy);
        if (score > best_score) best = t, best_score = score;
    }
    return best;
}

/* pgt_march_step with angle 0 (pgt_march_batch's steps); the stop reason goes to *why and the
 * chart crossings to *crossings. */
static uint march_step(const mc_atlas *a, mc_state *s, uint *why, uint *crossings) {
    *why = MC_STOP_NONE, *crossings = 0u;
    const float length = a->p.step_length;
    float dx = s->dx, dy = s->dy;
    float cx = s->x, cy = s->y, rem = length, idx = s->in_dx, idy = s->in_dy;
    uint chart = s->chart, jumps = 0, from = s->from, nb = s->bounces;
    uint event = MC_INNER;
    for (;;) {
        const float tx = cx + dx * rem, ty = cy + dy * rem;
        const uint td = texel_at(a, tx, ty), c = code_of(a, td), tag = chart + 1u;
        if (c == MC_CODE(MC_KIND_INNER, chart)) {
            cx = tx, cy = ty;
            break;
        }
        uint p0, p0x, p0y;
        if ((c >> 2) == tag) {
            if ((c & 3u) == MC_KIND_DEAD_END) return *why = MC_STOP_DEAD_END, MC_STOP;
            p0 = td, p0x = (uint)tx, p0y = (uint)ty;
            if (event == MC_INNER) event = MC_JUMP;
        } else {
            p0 = search_xy(a, chart, cx, cy, tx, ty, &p0x, &p0y);
            if (p0 == MC_NONE) return *why = MC_STOP_NO_INDIRECTION, MC_STOP;
            if ((a->codes[p0] & 3u) == MC_KIND_DEAD_END) return *why = MC_STOP_DEAD_END, MC_STOP;
            event = MC_SEARCH;
        }
        if (jumps == PGT_GPU_MARCH_MAX_JUMPS) return *why = MC_STOP_TOO_MANY_JUMPS, MC_STOP;
        jumps++;
        const uint w = a->p.width, scx = (uint)cx, scy = (uint)cy, src = scy * w + scx;
        const int best = !(a->p.flags & PGT_GPU_MARCH_NO_BEST_POINTER);
        uint pi = p0;
        if (best) pi = best_pointer(a, chart, cx, cy, src, p0, p0x, p0y);
        float sx[3], sy[3], rx[3], ry[3], ndx, ndy;
        const int has_src = texel_jacobian(a, src, sx, sy);
        int bounce = bounces(a, from, a->jumps[pi].u, a->jumps[pi].v);
        if (bounce && best && dx * idx + dy * idy > 0.0f) {
            const uint alt = unbounced_pointer(a, chart, cx, cy, src, p0, p0x, p0y, dx, dy, from);
            if (alt != MC_NONE) pi = alt, bounce = 0;
        }
        if (bounce && nb == PGT_GPU_MARCH_MAX_BOUNCES) return *why = MC_STOP_BOUNCE, MC_STOP;
        nb = bounce ? nb + 1u : 0u;
        const mc_jump jr = a->jumps[pi];
        const uint ref = (uint)jr.v * w + jr.u;
        const int has_ref = jump_direction(a, jr, pi, has_src, sx, sy, dx, dy, &ndx, &ndy, rx, ry);
        float rem_dst = 0.0f, rem_src = 0.0f;
        float v[3], vd[3];
        if (has_src) texel_motion(sx, sy, dx, dy, v);
        const float lv = has_src ? norm3(v) : 0.0f;
        if (lv > 0.0f) {
            float pc[3], pr[3];
            march_position(a, cx, cy, pc);
            pos3(a, ref, pr);
            const float dp[3] = {pr[0] - pc[0], pr[1] - pc[1], pr[2] - pc[2]};
            const float covered = dot3(dp, v) > 0.0f ? norm3(dp) : 0.0f, l3 = rem * lv;
            const float rem3 = covered >= l3 ? 0.0f : l3 - covered;
            rem_src = rem3 / lv;
            if (has_ref) texel_motion(rx, ry, ndx, ndy, vd);
            const float ld = has_ref ? norm3(vd) : 0.0f;
            if (!(ld > 0.0f))
                rem_dst = rem_src;
            else if (ld * a->p.max_length_ratio > lv)
                rem_dst = rem3 / ld;
            else
                rem_dst = rem_src * a->p.max_length_ratio;
        } else {
            const float ox = (float)p0x + 0.5f - cx, oy = (float)p0y + 0.5f - cy;
            rem_src = rem - (ox * dx + oy * dy);
            if (!(rem_src > 0.0f)) rem_src = 0.0f;
            rem_dst = rem_src;
        }
        if (rem_dst > a->p.max_length) rem_dst = a->p.max_length;
        *crossings = jumps; /* where the reference sets pgt_march_info.jumps */
        const float nl = sqrt(ndx * ndx + ndy * ndy);
        dx = ndx / nl, dy = ndy / nl;
        from = src + 1u, idx = dx, idy = dy;
        cx = (float)jr.u + 0.5f, cy = (float)jr.v + 0.5f;
        chart = (a->codes[ref] >> 2) - 1u;
        rem = rem_dst;
        if (!(rem > 0.0f)) break;
    }
    if (a->p.flags & PGT_GPU_MARCH_MASK) {
        const uint t = texel_at(a, cx, cy);
        if (a->mask[t] >= a->p.mask_threshold) return *why = MC_STOP_REJECTED, MC_STOP;
    }
    s->x = cx, s->y = cy, s->dx = dx, s->dy = dy, s->chart = chart;
    s->from = from, s->in_dx = idx, s->in_dy = idy, s->bounces = nb;
    return event;
}

/* Walker gid takes up to p.steps steps from states[gid] (it stops at its first STOP) and ends
 * there; taken[gid] gets the steps taken (a STOP is not one). With PGT_GPU_MARCH_RECORD, record
 * gid * steps + k gets the state after step k (unchanged on STOP) and its event word
 * (PGT_MARCH_EVENT_WORD); the records after a STOP repeat it. */
__kernel void march_walk(__global const uint *codes, __global const mc_texel *texels,
                         __global const mc_jump *jumps, __global const ushort *rings,
                         __global const float2 *rotcs, __global const float *mask,
                         const pgt_gpu_march_params p, __global mc_state *states,
                         __global mc_state *rec_states, __global uint *rec_events,
                         __global uint *taken) {
    const uint gid = p.first + (uint)get_global_id(0);
    if (gid >= p.count) return;
    const mc_atlas a = {p, codes, texels, jumps, rings, rotcs, mask};
    mc_state s = states[gid];
    uint k = 0;
    for (; k < p.steps; ++k) {
        uint why, crossings;
        const uint ev = march_step(&a, &s, &why, &crossings);
        if (p.flags & PGT_GPU_MARCH_RECORD) {
            const uint r = gid * p.steps + k;
            rec_states[r] = s;
            rec_events[r] = PGT_MARCH_EVENT_WORD(ev, why, crossings);
        }
        if (ev == MC_STOP) break;
    }
    states[gid] = s;
    taken[gid] = k;
    if ((p.flags & PGT_GPU_MARCH_RECORD) && k < p.steps) /* the records after a STOP repeat it */
        for (uint j = k + 1u; j < p.steps; ++j) {
            rec_states[gid * p.steps + j] = s;
            rec_events[gid * p.steps + j] = rec_events[gid * p.steps + k];
        }
}
