#version 450
/* pgt: marching on a geometry-image atlas in GLSL, a port of pgt_march_step in ref_cpu/src/march.c
 * (the specification: paper 000, sec. 5, 5.1, 5.2, and march.h's rules beyond the paper: the
 * remaining length in 3D, the Jacobian rotation, no bounce), by way of its OpenCL port
 * gpu_cl/kernels/march.cl: every function below has the reference function of the same name and
 * does the same float operations in the same order, so that a walker's state after a step is the
 * reference's to the bit. Every float that an operation produces is `precise` (no contraction into
 * fused multiply-adds, no reassociation); 3-vectors are vec3 whose componentwise operations are
 * the reference's loops over three floats. Not ported: the CPU's cache requests (no effect on
 * results) and the condition callback (a host function; pgt_vk_march refuses it). The cosine and
 * sine of each texel's rot come from the host (rotcs, pgt_gpu_march_prepare).
 *
 * GLSL has no pointers: the atlas view and the walkers are storage buffers (march_vk_layout.h),
 * the parameters push constants, and out-parameters are copied back whether or not the callee
 * wrote them, so a result the reference leaves untouched on failure goes through a local here.
 * The uint16 fields (jump u and v, rings) are read from their 32-bit words. One invocation is one
 * walker. */
#include "march_vk_layout.h"

layout(local_size_x = PGT_GPU_MARCH_GROUP_SIZE) in;

layout(push_constant) uniform Push {
    pgt_gpu_march_params p;
};

/* pgt_march_texel and pgt_march_state as the host's arrays hold them (std430: 16 and 36 bytes). */
struct mc_texel {
    float x, y, z;
    uint code;
};
struct mc_state {
    float x, y, dx, dy;
    uint chart, from;
    float in_dx, in_dy;
    uint bounces;
};
/* A jump record read out of its words. */
struct mc_jump {
    uint u, v;
    float rot;
};

layout(std430, set = 0, binding = PGT_VK_M_CODES) readonly buffer Codes { uint codes[]; };
layout(std430, set = 0, binding = PGT_VK_M_TEXELS) readonly buffer Texels { mc_texel texels[]; };
layout(std430, set = 0, binding = PGT_VK_M_JUMPS) readonly buffer Jumps { uvec2 jump_words[]; };
layout(std430, set = 0, binding = PGT_VK_M_RINGS) readonly buffer Rings { uint ring_words[]; };
layout(std430, set = 0, binding = PGT_VK_M_ROTCS) readonly buffer Rotcs { vec2 rotcs[]; };
layout(std430, set = 0, binding = PGT_VK_M_MASK) readonly buffer Mask { float mask[]; };
layout(std430, set = 0, binding = PGT_VK_M_STATES) buffer States { mc_state states[]; };
layout(std430, set = 0, binding = PGT_VK_M_REC_STATES) buffer RecStates { mc_state rec_states[]; };
layout(std430, set = 0, binding = PGT_VK_M_REC_EVENTS) buffer RecEvents { uint rec_events[]; };
layout(std430, set = 0, binding = PGT_VK_M_TAKEN) buffer Taken { uint taken[]; };

#define MC_NONE 0xFFFFFFFFu
#define MC_KIND_BACKGROUND 0u
#define MC_KIND_INNER 1u
#define MC_KIND_INDIRECTION 2u
#define MC_KIND_DEAD_END 3u
#define MC_CODE(kind, chart) ((kind) | (((chart) + 1u) << 2))
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

const int mc_ring_dx[8] = int[8](-1, 0, 1, -1, 1, -1, 0, 1);
const int mc_ring_dy[8] = int[8](-1, -1, -1, 0, 0, 1, 1, 1);

float mc_infinity() { return uintBitsToFloat(0x7F800000u); }

uint ring_of(uint t) { return (ring_words[t >> 1] >> ((t & 1u) * 16u)) & 0xFFFFu; }

mc_jump jump_of(uint t) {
    const uvec2 w = jump_words[t];
    return mc_jump(w.x & 0xFFFFu, w.x >> 16, uintBitsToFloat(w.y));
}

uint ring_neighbour(uint w, uint x, uint y, uint k) {
    return (y + uint(mc_ring_dy[k])) * w + x + uint(mc_ring_dx[k]);
}

uint lowest_bit(uint m) { return uint(findLSB(m)); }

uint texel_at(float x, float y) {
    const float fw = float(p.width), fh = float(p.height);
    if (!(x >= 0.0 && y >= 0.0 && x < fw && y < fh)) return MC_NONE;
    return uint(y) * p.width + uint(x);
}

uint code_of(uint t) { return t == MC_NONE ? 0u : codes[t]; }

vec3 pos3(uint t) { return vec3(texels[t].x, texels[t].y, texels[t].z); }

uint pointer_of(uint t) {
    const mc_jump j = jump_of(t);
    return j.v * p.width + j.u;
}

float dot3(vec3 a, vec3 b) {
    precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
    return r;
}

vec3 cross3(vec3 a, vec3 b) {
    precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return r;
}

vec3 position_rim(float x, float y, int i0, int j0, float fx, float fy) {
    const int w = int(p.width), tx = int(x), ty = int(y);
    const uint m = ring_of(uint(ty * w + tx)), block = (m & 0x0Fu) | ((m & 0xF0u) << 1) | 0x10u;
    precise float wx[2] = float[2](1.0 - fx, fx), wy[2] = float[2](1.0 - fy, fy);
    precise float sum = 0.0;
    precise vec3 q3 = vec3(0.0);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int xi = i0 + i, yj = j0 + j;
            if (((block >> uint((yj - ty + 1) * 3 + xi - tx + 1)) & 1u) == 0u) continue;
            const mc_texel q = texels[yj * w + xi];
            precise float wq = wx[i] * wy[j];
            q3 += wq * vec3(q.x, q.y, q.z);
            sum += wq;
        }
    precise vec3 r = q3 / sum;
    return r;
}

vec3 march_position(float x, float y) {
    const uint w = p.width;
    const int i0 = int(x + 0.5) - 1, j0 = int(y + 0.5) - 1;
    precise float fx = x - 0.5 - float(i0), fy = y - 0.5 - float(j0);
    if (i0 >= 0 && j0 >= 0 && uint(i0) + 1u < w && uint(j0) + 1u < p.height) {
        const uint b = uint(j0) * w + uint(i0);
        const mc_texel q0 = texels[b], q1 = texels[b + 1u], q2 = texels[b + w],
                       q3 = texels[b + w + 1u];
        const uint c = q0.code;
        if ((c & 3u) == MC_KIND_INNER && q1.code == c && q2.code == c && q3.code == c) {
            precise float w00 = (1.0 - fx) * (1.0 - fy), w10 = fx * (1.0 - fy),
                          w01 = (1.0 - fx) * fy, w11 = fx * fy;
            precise vec3 r = w00 * vec3(q0.x, q0.y, q0.z) + w10 * vec3(q1.x, q1.y, q1.z) +
                             w01 * vec3(q2.x, q2.y, q2.z) + w11 * vec3(q3.x, q3.y, q3.z);
            return r;
        }
    }
    return position_rim(x, y, i0, j0, fx, fy);
}

bool texel_jacobian(uint t, out vec3 ex, out vec3 ey) {
    const uint w = p.width, m = ring_of(t);
    const uint left = (m >> 3) & 1u, right = (m >> 4) & 1u, up = (m >> 1) & 1u,
               down = (m >> 6) & 1u;
    ex = vec3(0.0), ey = vec3(0.0);
    if ((left | right) == 0u || (up | down) == 0u) return false;
    const mc_texel x0 = texels[t - left], x1 = texels[t + right], y0 = texels[t - up * w],
                   y1 = texels[t + down * w];
    precise float ix = (left & right) != 0u ? 0.5 : 1.0, iy = (up & down) != 0u ? 0.5 : 1.0;
    precise vec3 a = (vec3(x1.x, x1.y, x1.z) - vec3(x0.x, x0.y, x0.z)) * ix;
    precise vec3 b = (vec3(y1.x, y1.y, y1.z) - vec3(y0.x, y0.y, y0.z)) * iy;
    ex = a, ey = b;
    return true;
}

vec3 texel_motion(vec3 ex, vec3 ey, float dx, float dy) {
    precise vec3 v = ex * dx + ey * dy;
    return v;
}

float norm3(vec3 v) {
    precise float r = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return r;
}

bool transport_direction(vec3 sx_in, vec3 sy_in, vec3 rx_in, vec3 ry_in, float dx, float dy,
                         out float out_dx, out float out_dy) {
    precise vec3 sx = sx_in, sy = sy_in, rx = rx_in, ry = ry_in;
    precise float m = 0.0;
    out_dx = 0.0, out_dy = 0.0;
    for (int i = 0; i < 3; ++i)
        m = max(m, max(max(abs(sx[i]), abs(sy[i])), max(abs(rx[i]), abs(ry[i]))));
    if (!(m > 0.0) || isinf(m) || isnan(m)) return false;
    if (m < p.jacobian_scale_min || m > p.jacobian_scale_max) sx /= m, sy /= m, rx /= m, ry /= m;
    precise vec3 v = texel_motion(sx, sy, dx, dy);
    precise vec3 ns = cross3(sx, sy), nr = cross3(rx, ry);
    precise float ls = sqrt(dot3(ns, ns)), lr = sqrt(dot3(nr, nr));
    if (!(ls > 0.0) || !(lr > 0.0)) return false;
    ns /= ls, nr /= lr;
    precise float c = dot3(ns, nr);
    if (!(c > 0.0)) return false;
    precise vec3 k = cross3(ns, nr), kv = cross3(k, v);
    precise float kk = dot3(k, v) / (1.0 + c);
    precise vec3 t = c * v + kv + kk * k;
    precise float a11 = dot3(rx, rx), a12 = dot3(rx, ry), a22 = dot3(ry, ry);
    precise float b1 = dot3(rx, t), b2 = dot3(ry, t), det = a11 * a22 - a12 * a12;
    precise float least = p.min_jacobian_sine2 * a11 * a22;
    if (!(det > least)) return false;
    precise float ex = (a22 * b1 - a12 * b2) / det, ey = (a11 * b2 - a12 * b1) / det;
    precise float l = sqrt(ex * ex + ey * ey);
    if (!(l > 0.0)) return false;
    precise float ox = ex / l, oy = ey / l;
    out_dx = ox, out_dy = oy;
    return true;
}

uint search_xy(uint chart, float x0, float y0, float x1, float y1, out uint out_x,
               out uint out_y) {
    const uint tag = chart + 1u;
    precise float lo = 0.0, hi = 1.0;
    out_x = 0u, out_y = 0u;
    for (uint i = 0u; i < PGT_GPU_MARCH_SEARCH_ITERATIONS; ++i) {
        precise float m = 0.5 * (lo + hi);
        precise float x = x0 + (x1 - x0) * m, y = y0 + (y1 - y0) * m;
        const uint t = texel_at(x, y);
        const uint c = code_of(t);
        if ((c >> 2) != tag) {
            hi = m;
        } else if ((c & 3u) == MC_KIND_INNER) {
            lo = m;
        } else {
            out_x = uint(x), out_y = uint(y);
            return t;
        }
    }
    return MC_NONE;
}

uint nearest_inner(float x, float y, uint px, uint py, out uint out_x, out uint out_y) {
    const uint w = p.width, ring = ring_of(py * w + px) & 0xFFu;
    uint m = (ring & PGT_GPU_MARCH_RING_EDGES) != 0u ? ring & PGT_GPU_MARCH_RING_EDGES : ring;
    uint near = MC_NONE, bx = 0u, by = 0u;
    precise float near_e2 = mc_infinity();
    for (; m != 0u; m &= m - 1u) {
        const uint k = lowest_bit(m);
        const uint nx = px + uint(mc_ring_dx[k]), ny = py + uint(mc_ring_dy[k]);
        precise float ex = float(nx) + 0.5 - x, ey = float(ny) + 0.5 - y;
        precise float e2 = ex * ex + ey * ey;
        if (e2 < near_e2) near = ny * w + nx, near_e2 = e2, bx = nx, by = ny;
    }
    out_x = bx, out_y = by;
    return near;
}

void score_pointer(uint t, vec3 pc, vec3 r, inout uint best, inout float best_score) {
    precise vec3 c = pos3(pointer_of(t)) - pc;
    precise float len = sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
    if (!(len > 0.0)) return;
    precise float score = (c.x * r.x + c.y * r.y + c.z * r.z) / len;
    if (score > best_score) best = t, best_score = score;
}

uint pointer_candidates(uint chart, uint p0, uint nx0, uint ny0, out uint cand[9]) {
    const uint w = p.width, near = ny0 * w + nx0;
    uint n = 0u; /* cand[n] and above are never read */
    cand[n] = p0;
    n += codes[p0] == MC_CODE(MC_KIND_INDIRECTION, chart) ? 1u : 0u;
    const uint ox = p0 % w + 1u - nx0, oy = p0 / w + 1u - ny0, b = oy * 3u + ox;
    uint m = ring_of(near) >> 8;
    if (ox <= 2u && oy <= 2u && b != 4u) m &= ~(1u << (b > 4u ? b - 1u : b));
    for (; m != 0u; m &= m - 1u) cand[n++] = ring_neighbour(w, nx0, ny0, lowest_bit(m));
    return n;
}

uint best_pointer(uint chart, float x, float y, uint cur, uint p0, uint p0x, uint p0y) {
    uint nx0 = 0u, ny0 = 0u;
    const uint near = nearest_inner(x, y, p0x, p0y, nx0, ny0);
    if (near == MC_NONE || near == cur) return p0;
    const vec3 pc = pos3(cur);
    precise vec3 r = pos3(near) - pc;
    uint best = p0;
    float best_score = -mc_infinity();
    uint cand[9];
    const uint n = pointer_candidates(chart, p0, nx0, ny0, cand);
    for (uint k = 0u; k < n; ++k) score_pointer(cand[k], pc, r, best, best_score);
    return best;
}

/* jump_direction for the jump record jr of texel t (rotcs[t]: its rot's cosine and sine). */
bool jump_direction(mc_jump jr, uint t, bool has_src, vec3 sx, vec3 sy, float dx, float dy,
                    out float ndx, out float ndy, out vec3 rx, out vec3 ry) {
    const uint ref = jr.v * p.width + jr.u;
    const bool has_ref = texel_jacobian(ref, rx, ry);
    ndx = dx, ndy = dy;
    if ((p.flags & PGT_GPU_MARCH_NO_ROTATION) != 0u) return has_ref;
    float tdx, tdy;
    if ((p.flags & PGT_GPU_MARCH_JACOBIAN) != 0u && has_src && has_ref &&
        transport_direction(sx, sy, rx, ry, dx, dy, tdx, tdy)) {
        ndx = tdx, ndy = tdy;
        return has_ref;
    }
    if (jr.rot != 0.0) {
        const vec2 cs = rotcs[t];
        precise float a = cs.x * dx - cs.y * dy, b = cs.y * dx + cs.x * dy;
        ndx = a, ndy = b;
    }
    return has_ref;
}

bool bounces(uint from, uint u, uint v) {
    const uint w = p.width, f = from - 1u;
    if (f >= w * p.height) return false;
    const uint fx = f % w, fy = f / w;
    const uint ex = u > fx ? u - fx : fx - u, ey = v > fy ? v - fy : fy - v;
    return ex <= PGT_GPU_MARCH_BOUNCE_TEXELS && ey <= PGT_GPU_MARCH_BOUNCE_TEXELS &&
           codes[f] == codes[v * w + u];
}

uint unbounced_pointer(uint chart, float x, float y, uint cur, uint p0, uint p0x, uint p0y,
                       float dx, float dy, uint from) {
    const uint w = p.width;
    uint nx0 = 0u, ny0 = 0u, cand[9], n = 1u;
    const uint near = nearest_inner(x, y, p0x, p0y, nx0, ny0);
    cand[0] = p0;
    if (near != MC_NONE) n = pointer_candidates(chart, p0, nx0, ny0, cand);
    const bool has_r = near != MC_NONE && near != cur;
    vec3 pc = vec3(0.0), r = vec3(0.0);
    if (has_r) {
        pc = pos3(cur);
        precise vec3 d = pos3(near) - pc;
        r = d;
    }
    uint best = MC_NONE;
    float best_score = -mc_infinity();
    for (uint k = 0u; k < n; ++k) {
        const uint t = cand[k];
        const mc_jump j = jump_of(t);
        if (bounces(from, j.u, j.v)) continue;
        if (has_r) {
            score_pointer(t, pc, r, best, best_score);
            continue;
        }
        precise float ox = float(t % w) + 0.5 - x, oy = float(t / w) + 0.5 - y;
        precise float score = (ox * dx + oy * dy) / sqrt(ox * ox + oy * oy);
        if (score > best_score) best = t, best_score = score;
    }
    return best;
}

/* pgt_march_step with angle 0 (pgt_march_batch's steps); the stop reason goes to why and the
 * chart crossings to crossings. */
uint march_step(inout mc_state s, out uint why, out uint crossings) {
    why = MC_STOP_NONE, crossings = 0u;
    const float step_len = p.step_length;
    float dx = s.dx, dy = s.dy;
    float cx = s.x, cy = s.y, rem = step_len, idx = s.in_dx, idy = s.in_dy;
    uint chart = s.chart, jumps = 0u, from = s.from, nb = s.bounces;
    uint event = MC_INNER;
    for (;;) {
        precise float tx = cx + dx * rem, ty = cy + dy * rem;
        const uint td = texel_at(tx, ty), c = code_of(td), tag = chart + 1u;
        if (c == MC_CODE(MC_KIND_INNER, chart)) {
            cx = tx, cy = ty;
            break;
        }
        uint p0, p0x, p0y;
        if ((c >> 2) == tag) {
            if ((c & 3u) == MC_KIND_DEAD_END) {
                why = MC_STOP_DEAD_END;
                return MC_STOP;
            }
            p0 = td, p0x = uint(tx), p0y = uint(ty);
            if (event == MC_INNER) event = MC_JUMP;
        } else {
            p0 = search_xy(chart, cx, cy, tx, ty, p0x, p0y);
            if (p0 == MC_NONE) {
                why = MC_STOP_NO_INDIRECTION;
                return MC_STOP;
            }
            if ((codes[p0] & 3u) == MC_KIND_DEAD_END) {
                why = MC_STOP_DEAD_END;
                return MC_STOP;
            }
            event = MC_SEARCH;
        }
        if (jumps == PGT_GPU_MARCH_MAX_JUMPS) {
            why = MC_STOP_TOO_MANY_JUMPS;
            return MC_STOP;
        }
        jumps++;
        const uint w = p.width, scx = uint(cx), scy = uint(cy), src = scy * w + scx;
        const bool best = (p.flags & PGT_GPU_MARCH_NO_BEST_POINTER) == 0u;
        uint pi = p0;
        if (best) pi = best_pointer(chart, cx, cy, src, p0, p0x, p0y);
        vec3 sx, sy, rx, ry;
        float ndx, ndy;
        const bool has_src = texel_jacobian(src, sx, sy);
        mc_jump jp = jump_of(pi);
        bool bounce = bounces(from, jp.u, jp.v);
        precise float along = dx * idx + dy * idy;
        if (bounce && best && along > 0.0) {
            const uint alt = unbounced_pointer(chart, cx, cy, src, p0, p0x, p0y, dx, dy, from);
            if (alt != MC_NONE) pi = alt, bounce = false;
        }
        if (bounce && nb == PGT_GPU_MARCH_MAX_BOUNCES) {
            why = MC_STOP_BOUNCE;
            return MC_STOP;
        }
        nb = bounce ? nb + 1u : 0u;
        const mc_jump jr = jump_of(pi);
        const uint ref = jr.v * w + jr.u;
        const bool has_ref = jump_direction(jr, pi, has_src, sx, sy, dx, dy, ndx, ndy, rx, ry);
        precise float rem_dst = 0.0, rem_src = 0.0;
        vec3 v = vec3(0.0), vd = vec3(0.0);
        if (has_src) v = texel_motion(sx, sy, dx, dy);
        const float lv = has_src ? norm3(v) : 0.0;
        if (lv > 0.0) {
            const vec3 pc = march_position(cx, cy), pr = pos3(ref);
            precise vec3 dp = pr - pc;
            precise float covered = dot3(dp, v) > 0.0 ? norm3(dp) : 0.0, l3 = rem * lv;
            precise float rem3 = covered >= l3 ? 0.0 : l3 - covered;
            rem_src = rem3 / lv;
            if (has_ref) vd = texel_motion(rx, ry, ndx, ndy);
            const float ld = has_ref ? norm3(vd) : 0.0;
            precise float ld_ratio = ld * p.max_length_ratio;
            if (!(ld > 0.0))
                rem_dst = rem_src;
            else if (ld_ratio > lv)
                rem_dst = rem3 / ld;
            else
                rem_dst = rem_src * p.max_length_ratio;
        } else {
            precise float ox = float(p0x) + 0.5 - cx, oy = float(p0y) + 0.5 - cy;
            rem_src = rem - (ox * dx + oy * dy);
            if (!(rem_src > 0.0)) rem_src = 0.0;
            rem_dst = rem_src;
        }
        if (rem_dst > p.max_length) rem_dst = p.max_length;
        crossings = jumps; /* where the reference sets pgt_march_info.jumps */
        precise float nl = sqrt(ndx * ndx + ndy * ndy);
        precise float ux = ndx / nl, uy = ndy / nl;
        dx = ux, dy = uy;
        from = src + 1u, idx = dx, idy = dy;
        precise float lx = float(jr.u) + 0.5, ly = float(jr.v) + 0.5;
        cx = lx, cy = ly;
        chart = (codes[ref] >> 2) - 1u;
        rem = rem_dst;
        if (!(rem > 0.0)) break;
    }
    if ((p.flags & PGT_GPU_MARCH_MASK) != 0u) {
        const uint t = texel_at(cx, cy);
        if (mask[t] >= p.mask_threshold) {
            why = MC_STOP_REJECTED;
            return MC_STOP;
        }
    }
    s.x = cx, s.y = cy, s.dx = dx, s.dy = dy, s.chart = chart;
    s.from = from, s.in_dx = idx, s.in_dy = idy, s.bounces = nb;
    return event;
}

/* Walker gid takes the steps [step_first, step_first + step_count) of its p.steps from
 * states[gid] (it stops at its first STOP) and ends there; taken[gid] gets the steps taken so far
 * (a STOP is not one). With PGT_GPU_MARCH_RECORD, record gid * steps + k gets the state after
 * step k (unchanged on STOP) and its event word (PGT_MARCH_EVENT_WORD); the records after a STOP
 * repeat it. The host runs a call's steps in dispatches of at most PGT_VK_MARCH_DISPATCH_STEPS
 * (lavapipe ends every loop of an invocation after 65535 iterations in all, see
 * march_vk_layout.h); a walker that stopped in an earlier dispatch (taken < step_first) only
 * repeats its STOP record over this one's steps. */
void main() {
    const uint gid = p.first + gl_GlobalInvocationID.x;
    if (gid >= p.count) return;
    const bool record = (p.flags & PGT_GPU_MARCH_RECORD) != 0u;
    const uint end = p.step_first + p.step_count, base = gid * p.steps;
    if (p.step_first > 0u && taken[gid] < p.step_first) { /* stopped before this dispatch */
        if (record) {
            const uint at = base + taken[gid];
            const mc_state s = rec_states[at];
            const uint word = rec_events[at];
            for (uint j = p.step_first; j < end; ++j) {
                rec_states[base + j] = s;
                rec_events[base + j] = word;
            }
        }
        return;
    }
    mc_state s = states[gid];
    uint k = p.step_first, word = 0u;
    for (; k < end; ++k) {
        uint why, crossings;
        const uint ev = march_step(s, why, crossings);
        word = PGT_MARCH_EVENT_WORD(ev, why, crossings);
        if (record) {
            rec_states[base + k] = s;
            rec_events[base + k] = word;
        }
        if (ev == MC_STOP) break;
    }
    states[gid] = s;
    taken[gid] = k;
    if (record && k < end) /* the records after a STOP repeat it */
        for (uint j = k + 1u; j < end; ++j) {
            rec_states[base + j] = s;
            rec_events[base + j] = word;
        }
}
