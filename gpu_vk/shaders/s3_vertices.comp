/* pgt: sqrt(3) pass 3, old vertices (s3_vertices of ref_cpu/src/sqrt3.c without UVs): the new
 * position (eq. 4.1-4.2, or Kobbelt's border mask on even iterations) and, with adjacency, one
 * outgoing half-edge of the vertex in the next level.
 *
 * The float operations are the reference's, in its order, and `precise` forbids contracting
 * them into fused multiply-adds, so positions are bit-equal where the device's float ops are
 * IEEE. */
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s3_common.glsl"

void main() {
    uint v;
    if (!s3_item(v)) return;
    const vec3 pv = load_pos(v);
    const uint h0 = vh_in[v];
    if (h0 == PGT_GPU_NONE) {
        store_pos(v, pv);
        if (pc.s3.with_adj != 0u) vh_out[v - pc.vh_base] = PGT_GPU_NONE;
        return;
    }
    /* Sum the neighbours walking forward round the fan from h0; an interior vertex comes back to
     * h0. A border vertex meets the border: its sum must start at its fan start (its outgoing
     * border half-edge), so walk back to it and sum again from there unless h0 was it. */
    precise vec3 sum = vec3(0.0);
    uint n = 0u, last = h0, first = h0;
    bool touch_prot = false, border = false, stopped = false;
    while (true) {
        sum = vec3(0.0);
        n = 0u;
        touch_prot = false;
        uint h = first, hn;
        while (true) {
            sum += load_pos(idx_in[he_next(h)]);
            n++;
            touch_prot = touch_prot || prot_in[h / 3u] != 0u;
            last = h;
            hn = opp_in[he_prev(h)];
            if (hn == PGT_GPU_NONE || hn == first) break;
            if (n == pc.walk_budget) { /* lavapipe's loop limit (s3_vk_layout.h) */
                stopped = true;
                break;
            }
            h = hn;
        }
        if (stopped || hn != PGT_GPU_NONE || border) break;
        border = true;
        /* one load per step (see s3_border_incoming in s3_faces.comp) */
        uint start = h0, o = opp_in[h0], walked = 0u;
        while (o != PGT_GPU_NONE) {
            if (++walked == pc.walk_budget) {
                stopped = true;
                break;
            }
            start = he_next(o);
            o = opp_in[start];
        }
        if (stopped || start == first) break;
        first = start;
    }
    /* the results of a stopped walk are wrong; the host refuses the call */
    if (stopped) s3_walk_stopped(0u, v);
    const uint hin = he_prev(last); /* on a border: the incoming border half-edge */
    if (border) {
        sum += load_pos(idx_in[hin]);
        n++;
    }
    vec3 po = pv;
    if (!touch_prot) {
        if (!border) {
            /* eq. 4.1: (1 - alpha_n) V + alpha_n / n sum V_i; the table covers every valence a
             * call meets (the host sizes it from the input) */
            const float a = alpha[min(n, pc.s3.alpha_count - 1u)];
            precise const float w = a / float(n);
            precise vec3 relaxed = (1.0 - a) * pv + w * sum;
            po = relaxed;
        } else if (pc.s3.even != 0u) {
            /* Kobbelt's border vertex mask (4 P_prev + 19 P + 4 P_next) / 27 */
            const vec3 pp = load_pos(idx_in[hin]);
            const vec3 pn = load_pos(idx_in[he_next(first)]);
            precise vec3 moved = (4.0 * pp + 19.0 * pv + 4.0 * pn) / 27.0;
            po = moved;
        }
    }
    store_pos(v, po);
    if (pc.s3.with_adj != 0u) {
        /* An output half-edge leaving v: from the triangle of a half-edge leaving v that is not a
         * trisected border half-edge (the fan's last one on a border). */
        const uint hc = border ? last : h0, f = hc / 3u;
        vh_out[v - pc.vh_base] = s3_kind(f) == PGT_S3_KIND_PROTECTED ? s3_out_he(f, 0u, hc % 3u)
                                                                     : s3_out_he(f, hc % 3u, 0u);
    }
}
