/* pgt: sqrt(3) pass 4, per face of the step's input (s3_faces of ref_cpu/src/sqrt3.c without
 * UVs and labels): its new points, its triangles after the edge flips, their protected flags and
 * parents, and with adjacency their opposite half-edges and the new points' outgoing half-edges.
 *
 * The triangle emitted for half-edge h = a -> b of face f after the flip is (a, Q(opp h), Q(h)),
 * Q(h) being f's new point on h's side (the centroid, or on a trisected border face the
 * trisection point next to h's non-apex end). Positions: the reference's float operations in its
 * order, `precise` (no contraction). */
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s3_common.glsl"

/* Corner c of border face f starts h_1, the half-edge after its border half-edge (at b0). */
bool s3_is_h1(uint f, uint c) { return c == (bslot[f] + 1u) % 3u; }

/* Output vertex of face(h)'s new point on h's side; h is not the border half-edge of its face. */
uint s3_Q(uint h) {
    const uint f = h / 3u, base = s3_point(f);
    if (s3_kind(f) == PGT_S3_KIND_CENTROID) return base;
    /* h_1 starts at b0: E_b = base + 1; h_2 starts at the apex: E_a = base. */
    return s3_is_h1(f, h % 3u) ? base + 1u : base;
}

/* The fan walks below load once per step, the loop testing the loaded value: lavapipe (Mesa
 * 22.3, LLVM 15) returned wrong half-edges for some invocations of the shorter form
 * `while (opp_in[x(h)] != NONE) h = y(opp_in[x(h)]);` (measured on grid_16x16, k = 2). */

/* Both stop after pc.walk_budget iterations (lavapipe's loop limit, s3_vk_layout.h), recording
 * face f; the host then refuses the call. The vertices pass before them walks every fan of this
 * level whole, so it has recorded such a fan first: the stop here only bounds the loops. */

/* Incoming border half-edge (x -> a) at the vertex a where the border half-edge hb starts. */
uint s3_border_incoming(uint hb) {
    uint h = hb, o = opp_in[he_prev(hb)], walked = 0u;
    while (o != PGT_GPU_NONE) {
        if (++walked == pc.walk_budget) {
            s3_walk_stopped(1u, hb / 3u);
            break;
        }
        h = o;
        o = opp_in[he_prev(h)];
    }
    return he_prev(h);
}

/* Outgoing border half-edge (b -> y) at the vertex b where the border half-edge hb ends. */
uint s3_border_outgoing_after(uint hb) {
    uint h = he_next(hb), o = opp_in[h], walked = 0u;
    while (o != PGT_GPU_NONE) {
        if (++walked == pc.walk_budget) {
            s3_walk_stopped(1u, hb / 3u);
            break;
        }
        h = he_next(o);
        o = opp_in[h];
    }
    return h;
}

void emit(uint t, uint a, uint b, uint c) {
    const uint i = 3u * t - pc.idx_base;
    idx_out[i] = a;
    idx_out[i + 1u] = b;
    idx_out[i + 2u] = c;
}

void emit_opp(uint t, uint e0, uint e1, uint e2) {
    const uint i = 3u * t - pc.opp_base;
    opp_out[i] = e0;
    opp_out[i + 1u] = e1;
    opp_out[i + 2u] = e2;
}

/* What the triangles of a subdivided face need to know about the neighbour across h (s3_nb). */
struct s3_nb {
    uint o;       /* opposite half-edge, or NONE */
    bool flip;    /* the edge is flipped (the neighbour exists and is subdivided) */
    uint q_opp;   /* Q(o) when flipped */
    uint e0;      /* output partner of edge a -> Q(o) (flipped) or a -> b (not flipped) */
    uint e1_flip; /* output partner of edge Q(o) -> Q(h) when flipped: T(o).e1 */
    uint e2_next; /* output partner of the next half-edge's triangle's edge Q -> b */
};

s3_nb s3_neighbour(uint h) {
    s3_nb nb;
    const uint f = h / 3u, c = h % 3u, o = opp_in[h];
    nb.o = o;
    nb.flip = false;
    nb.q_opp = PGT_GPU_NONE;
    nb.e1_flip = PGT_GPU_NONE;
    nb.e0 = PGT_GPU_NONE;
    nb.e2_next = s3_out_he(f, c, 1u); /* not flipped: this triangle's side b -> Q(h) */
    if (o == PGT_GPU_NONE) return nb;
    const uint g = o / 3u, gc = o % 3u, kg = s3_kind(g);
    if (kg == PGT_S3_KIND_PROTECTED) {
        nb.e0 = s3_out_he(g, 0u, gc); /* the protected neighbour's own half-edge */
        return nb;
    }
    const uint gbase = 3u * s3_tri_base(g);
    nb.flip = true;
    nb.e1_flip = gbase + 3u * gc + 1u;
    nb.e2_next = gbase + 3u * gc; /* T(o).e0 runs b -> Q(h) */
    if (kg == PGT_S3_KIND_CENTROID) {
        nb.q_opp = s3_point(g);
        nb.e0 = gbase + 3u * (gc == 2u ? 0u : gc + 1u) + 2u;
        return nb;
    }
    nb.q_opp = s3_Q(o);
    if (s3_is_h1(g, gc)) /* o is h_1 of a border face: its middle triangle */
        nb.e0 = s3_out_he(g, bslot[g], 1u);
    /* else o is h_2 of a border face: a -> Q(o) is the first third of the trisected border */
    return nb;
}

/* The triangle of half-edge h (a -> b) of subdivided face f, in slot h % 3; nb describes h's
 * neighbour, pnb that of prev(h). */
void s3_face_triangle(uint h, uint q, s3_nb nb, s3_nb pnb) {
    const uint f = h / 3u, c = h % 3u, t = s3_tri_base(f) + c;
    const bool border_face = s3_kind(f) == PGT_S3_KIND_BORDER;
    emit(t, idx_in[h], nb.flip ? nb.q_opp : idx_in[he_next(h)], q);
    if (pc.s3.with_adj == 0u) return;
    uint e1, e2;
    /* e1: Q(o) -> Q(h) when flipped, else b -> Q(h) */
    if (nb.flip)
        e1 = nb.e1_flip;
    else if (!border_face)
        e1 = s3_out_he(f, (c + 1u) % 3u, 2u);
    else if (s3_is_h1(f, c)) /* h_1: A -> E_b is the middle triangle's e1 */
        e1 = s3_out_he(f, bslot[f], 1u);
    else /* h_2: a0 -> E_a lies on the border */
        e1 = PGT_GPU_NONE;
    /* e2: Q(h) -> a */
    if (!border_face)
        e2 = pnb.e2_next;
    else if (s3_is_h1(f, c)) /* h_1: E_b -> b0 lies on the border */
        e2 = PGT_GPU_NONE;
    else /* h_2: E_a -> A is the middle triangle's e2 */
        e2 = s3_out_he(f, bslot[f], 2u);
    emit_opp(t, nb.e0, e1, e2);
}

void main() {
    uint f;
    if (!s3_item(f)) return;
    const uint kf = s3_kind(f), base_t = s3_tri_base(f), np = s3_point(f);
    const uint nt = kf == PGT_S3_KIND_PROTECTED ? 1u : 3u;
    const uint par = pc.parent_mode == PGT_VK_PARENT_IDENTITY ? f
                     : pc.parent_mode == PGT_VK_PARENT_READ   ? parent_in[f]
                                                              : 0u;
    for (uint i = 0u; i < nt; ++i) {
        if (pc.write_prot != 0u)
            prot_out[base_t + i - pc.prot_base] = kf == PGT_S3_KIND_PROTECTED ? 1u : 0u;
        if (pc.parent_mode != PGT_VK_PARENT_NONE) parent_out[base_t + i - pc.parent_base] = par;
    }
    if (kf == PGT_S3_KIND_PROTECTED) {
        emit(base_t, idx_in[3u * f], idx_in[3u * f + 1u], idx_in[3u * f + 2u]);
        if (pc.s3.with_adj != 0u) {
            uint e[3];
            for (uint c = 0u; c < 3u; ++c) {
                const uint o = opp_in[3u * f + c];
                e[c] = o == PGT_GPU_NONE                               ? PGT_GPU_NONE
                       : s3_kind(o / 3u) == PGT_S3_KIND_PROTECTED ? s3_out_he(o / 3u, 0u, o % 3u)
                                                                  : s3_out_he(o / 3u, o % 3u, 0u);
            }
            emit_opp(base_t, e[0], e[1], e[2]);
        }
        return;
    }
    const s3_nb nb0 = s3_neighbour(3u * f), nb1 = s3_neighbour(3u * f + 1u),
                nb2 = s3_neighbour(3u * f + 2u);
    if (kf == PGT_S3_KIND_CENTROID) {
        /* step (1): the face point at the centroid */
        const vec3 p0 = load_pos(idx_in[3u * f]), p1 = load_pos(idx_in[3u * f + 1u]),
                   p2 = load_pos(idx_in[3u * f + 2u]);
        precise vec3 q = (p0 + p1 + p2) / 3.0;
        store_pos(np, q);
        if (pc.s3.with_adj != 0u) vh_out[np - pc.vh_base] = s3_out_he(f, 0u, 2u);
        s3_face_triangle(3u * f, np, nb0, nb2);
        s3_face_triangle(3u * f + 1u, np, nb1, nb0);
        s3_face_triangle(3u * f + 2u, np, nb2, nb1);
        return;
    }
    /* Border face on an even iteration: trisect the border edge a0 -> b0 with Kobbelt's
     * (1, 16, 10) / 27 masks, apex A, triangles (a0 E_a A) (E_a E_b A) (E_b b0 A) before the flips
     * of the two inner edges. */
    const uint sb = bslot[f], hb = 3u * f + sb;
    const uint a0 = idx_in[hb], b0 = idx_in[he_next(hb)], apex = idx_in[he_prev(hb)];
    const uint a0o = idx_in[s3_border_incoming(hb)];
    const uint b0o = idx_in[he_next(s3_border_outgoing_after(hb))];
    const vec3 pa = load_pos(a0), pb = load_pos(b0), pao = load_pos(a0o), pbo = load_pos(b0o);
    precise vec3 ea = (pao + 16.0 * pa + 10.0 * pb) / 27.0;
    precise vec3 eb = (10.0 * pa + 16.0 * pb + pbo) / 27.0;
    store_pos(np, ea);
    store_pos(np + 1u, eb);
    const uint tm = base_t + sb;
    emit(tm, np, np + 1u, apex);
    if (pc.s3.with_adj != 0u) {
        const uint h2 = 3u * f + (sb + 2u) % 3u;
        const s3_nb nbn = sb == 0u ? nb1 : sb == 1u ? nb2 : nb0; /* nb[(sb + 1) % 3] */
        /* A -> E_b: T(opp h_1).e0 or T(h_1).e1 */
        emit_opp(tm, PGT_GPU_NONE, nbn.e2_next, s3_out_he(f, h2 % 3u, 2u));
        vh_out[np - pc.vh_base] = s3_out_he(f, sb, 0u);
        vh_out[np + 1u - pc.vh_base] = s3_out_he(f, sb, 1u);
    }
    if (sb != 0u) s3_face_triangle(3u * f, s3_Q(3u * f), nb0, nb2);
    if (sb != 1u) s3_face_triangle(3u * f + 1u, s3_Q(3u * f + 1u), nb1, nb0);
    if (sb != 2u) s3_face_triangle(3u * f + 2u, s3_Q(3u * f + 2u), nb2, nb1);
}
