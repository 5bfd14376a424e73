/* pgt: sqrt(3) subdivision in OpenCL C 1.2, a port of the general path of ref_cpu/src/sqrt3.c
 * (the specification: Kobbelt 2000; paper 004, Algorithm 2 and 4.2.2 / Algorithm 3). Every
 * function below has the reference function of the same name and does the same float
 * operations in the same order, so that the output is the reference's element by element.
 *
 * The program is this file after gpu_shared/lang.h, gpu_shared/sqrt3_layout.h and sqrt3_cl.h
 * (concatenated at build time, see ../CMakeLists.txt): it includes nothing itself.
 *
 * Per step the host runs: s3_classify -> s3_scan (levels) -> s3_scan_add (levels) when the step
 * is not uniform, then s3_vertices and s3_faces; or, on a uniform step of a mesh without border,
 * s3_vertices_closed and s3_faces_closed (the reference's closed fast path, same bytes). Buffers
 * are the flat arrays of sqrt3_layout.h; a buffer a step does not use is bound to a 4-byte
 * placeholder and not read. */

/* The reference is built with -ffp-contract=off: a fused a * b + c rounds once where the
 * reference rounds twice, so contraction would change the last bit. */
#pragma OPENCL FP_CONTRACT OFF

/* Everything a helper needs to know about the step: its parameters and the classification. */
typedef struct s3_step {
    pgt_s3_params p;
    __global const uint *kind;     /* F, when !p.is_uniform */
    __global const uint *bslot;    /* F, when !p.is_uniform */
    __global const uint *pt_off;   /* F, when !p.is_uniform */
    __global const uint *face_off; /* F, when !p.is_uniform */
} s3_step;

static inline uint s3_next(uint h) { return h % 3u == 2u ? h - 2u : h + 1u; }
static inline uint s3_prev(uint h) { return h % 3u == 0u ? h + 2u : h - 1u; }

/* A uniform step has every face a centroid face emitting one point and three triangles: its
 * offsets are f and 3f and the classification arrays are not read. */
static inline uint s3_kind(const s3_step *s, uint f) {
    return s->p.is_uniform ? PGT_S3_KIND_CENTROID : s->kind[f];
}
static inline uint s3_tri_base(const s3_step *s, uint f) {
    return s->p.is_uniform ? 3u * f : s->face_off[f];
}
static inline uint s3_point(const s3_step *s, uint f) {
    return s->p.V + (s->p.is_uniform ? f : s->pt_off[f]);
}

/* Corner c of border face f starts h_1, the half-edge after its border half-edge (at b0). */
static inline int s3_is_h1(const s3_step *s, uint f, uint c) {
    return c == (s->bslot[f] + 1u) % 3u;
}

/* Output vertex of face(h)'s new point on h's side; h is not the border half-edge of its face. */
static uint s3_Q(const s3_step *s, uint h) {
    const uint f = h / 3u, base = s3_point(s, f);
    if (s3_kind(s, f) == PGT_S3_KIND_CENTROID) return base;
    return s3_is_h1(s, f, h % 3u) ? base + 1u : base;
}

/* Output half-edge e of the triangle emitted in slot c of face f. */
static inline uint s3_out_he(const s3_step *s, uint f, uint c, uint e) {
    return 3u * (s3_tri_base(s, f) + c) + e;
}

/* Incoming border half-edge (x -> a) at the vertex a where border half-edge hb (a -> b) starts. */
static uint s3_border_incoming(__global const uint *opp, uint hb) {
    uint h = hb;
    for (;;) {
        const uint o = opp[s3_prev(h)];
        if (o == PGT_GPU_NONE) return s3_prev(h);
        h = o;
    }
}

/* Outgoing border half-edge (b -> y) at the vertex b where border half-edge hb (a -> b) ends. */
static uint s3_border_outgoing_after(__global const uint *opp, uint hb) {
    uint h = s3_next(hb);
    for (;;) {
        const uint o = opp[h];
        if (o == PGT_GPU_NONE) return h;
        h = s3_next(o);
    }
}

/* ---- pass 1: classify faces, and the counts the scan turns into offsets --------------------- */

__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_classify(const pgt_s3_params p, const uint flags, __global const uint *opp,
            __global const uint *prot, __global uint *kind, __global uint *bslot,
            __global uint *pt_count, __global uint *tri_count) {
    if (get_global_id(0) >= p.count) return;
    const uint f = p.first + (uint)get_global_id(0);
    uint k = PGT_S3_KIND_CENTROID, b = 0u;
    if ((flags & PGT_CL_S3_PROT) && prot[f]) {
        k = PGT_S3_KIND_PROTECTED;
    } else if (p.even) {
        /* After an odd iteration a subdivided face has at most one border edge. */
        for (uint c = 0u; c < 3u; ++c)
            if (opp[3u * f + c] == PGT_GPU_NONE) k = PGT_S3_KIND_BORDER, b = c;
    }
    kind[f] = k;
    bslot[f] = b;
    pt_count[f] = k; /* PGT_S3_KIND_* equals the number of new points */
    tri_count[f] = k == PGT_S3_KIND_PROTECTED ? 1u : 3u;
}

/* ---- pass 2: exclusive prefix sums of two arrays at once ------------------------------------ */

/* Scans a[off + 0 .. n) and b[off + 0 .. n) in place, block by block (PGT_CL_S3_SCAN_BLOCK
 * elements a work-group), and writes each block's totals to a[sum_off + group], b[sum_off +
 * group]. The host scans those sums the same way and adds them back (s3_scan_add). */
__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_scan(__global uint *a, __global uint *b, const uint off, const uint n, const uint sum_off) {
    __local uint la[PGT_CL_S3_SCAN_BLOCK], lb[PGT_CL_S3_SCAN_BLOCK];
    __local uint ta[PGT_S3_GROUP_SIZE], tb[PGT_S3_GROUP_SIZE];
    const uint lid = (uint)get_local_id(0), group = (uint)get_group_id(0);
    const uint base = group * PGT_CL_S3_SCAN_BLOCK;
    /* Coalesced loads: item lid reads elements lid, lid + 64, ... of the block. */
    for (uint i = 0u; i < PGT_CL_S3_SCAN_ITEMS; ++i) {
        const uint j = i * PGT_S3_GROUP_SIZE + lid, g = base + j;
        la[j] = g < n ? a[off + g] : 0u;
        lb[j] = g < n ? b[off + g] : 0u;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Each item scans its PGT_CL_S3_SCAN_ITEMS consecutive elements serially... */
    uint sa = 0u, sb = 0u;
    for (uint i = 0u; i < PGT_CL_S3_SCAN_ITEMS; ++i) {
        const uint j = lid * PGT_CL_S3_SCAN_ITEMS + i, xa = la[j], xb = lb[j];
        la[j] = sa, lb[j] = sb;
        sa += xa, sb += xb;
    }
    ta[lid] = sa, tb[lid] = sb;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* ...then the items' totals are scanned across the group (Hillis-Steele, inclusive). */
    for (uint d = 1u; d < PGT_S3_GROUP_SIZE; d <<= 1) {
        const uint xa = lid >= d ? ta[lid - d] : 0u, xb = lid >= d ? tb[lid - d] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        ta[lid] += xa, tb[lid] += xb;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    const uint ea = ta[lid] - sa, eb = tb[lid] - sb; /* exclusive: what the items before hold */
    for (uint i = 0u; i < PGT_CL_S3_SCAN_ITEMS; ++i) {
        const uint j = lid * PGT_CL_S3_SCAN_ITEMS + i;
        la[j] += ea, lb[j] += eb;
    }
    if (lid == PGT_S3_GROUP_SIZE - 1u) a[sum_off + group] = ta[lid], b[sum_off + group] = tb[lid];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint i = 0u; i < PGT_CL_S3_SCAN_ITEMS; ++i) {
        const uint j = i * PGT_S3_GROUP_SIZE + lid, g = base + j;
        if (g < n) a[off + g] = la[j], b[off + g] = lb[j];
    }
}

/* Adds the scanned block sums a[sum_off + block] to the elements of each block. */
__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_scan_add(__global uint *a, __global uint *b, const uint off, const uint n, const uint sum_off) {
    const uint g = (uint)get_global_id(0);
    if (g >= n) return;
    const uint block = g / PGT_CL_S3_SCAN_BLOCK;
    a[off + g] += a[sum_off + block];
    b[off + g] += b[sum_off + block];
}

/* ---- pass 3: old vertices (reference s3_vertices, without UVs) ------------------------------ */

__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_vertices(const pgt_s3_params p, const uint flags, __global const float *pos,
            __global const uint *idx, __global const uint *opp, __global const uint *vh,
            __global const uint *prot, __global const float *alpha, __global const uint *kind,
            __global const uint *face_off, __global float *out_pos, __global uint *out_vh) {
    if (get_global_id(0) >= p.count) return;
    const uint v = p.first + (uint)get_global_id(0);
    s3_step s; /* this pass reads kinds and triangle offsets only */
    s.p = p, s.kind = kind, s.bslot = 0, s.pt_off = 0, s.face_off = face_off;
    const float px = pos[3u * v], py = pos[3u * v + 1u], pz = pos[3u * v + 2u];
    float ox = px, oy = py, oz = pz;
    const uint h0 = vh[v];
    if (h0 == PGT_GPU_NONE) {
        out_pos[3u * v] = ox, out_pos[3u * v + 1u] = oy, out_pos[3u * v + 2u] = oz;
        if (p.with_adj) out_vh[v] = PGT_GPU_NONE;
        return;
    }
    /* Sum the neighbours walking forward round the fan from h0; an interior vertex comes back to
     * h0. A border vertex meets the border: its sum must start at its fan start (its outgoing
     * border half-edge), so walk back to it and sum again from there unless h0 was it. */
    float sx, sy, sz;
    uint n, last = h0, first = h0, hn;
    int touch_prot, border = 0;
    for (;;) {
        sx = sy = sz = 0.0f;
        n = 0u, touch_prot = 0;
        uint h = first;
        for (;;) {
            const uint w = idx[s3_next(h)];
            sx += pos[3u * w], sy += pos[3u * w + 1u], sz += pos[3u * w + 2u];
            n++;
            if (flags & PGT_CL_S3_PROT) touch_prot |= prot[h / 3u] != 0u;
            last = h;
            hn = opp[s3_prev(h)];
            if (hn == PGT_GPU_NONE || hn == first) break;
            h = hn;
        }
        if (hn != PGT_GPU_NONE || border) break;
        border = 1;
        uint start = h0;
        while (opp[start] != PGT_GPU_NONE) start = s3_next(opp[start]);
        if (start == first) break;
        first = start;
    }
    const uint hin = s3_prev(last); /* on a border: the incoming border half-edge */
    if (border) {
        const uint w = idx[hin];
        sx += pos[3u * w], sy += pos[3u * w + 1u], sz += pos[3u * w + 2u];
        n++;
    }
    if (!touch_prot) {
        if (!border) {
            /* eq. 4.1: (1 - alpha_n) V + alpha_n / n sum V_i. The host sizes the table for every
             * valence a call meets; a larger one would be a host bug, made visible as NaN. */
            const float a = n < p.alpha_count ? alpha[n] : NAN, w = a / (float)n;
            ox = (1.0f - a) * px + w * sx;
            oy = (1.0f - a) * py + w * sy;
            oz = (1.0f - a) * pz + w * sz;
        } else if (p.even) {
            /* Kobbelt's border vertex mask (4 P_prev + 19 P + 4 P_next) / 27 */
            const uint vp = idx[hin], vn = idx[s3_next(first)];
            ox = (4.0f * pos[3u * vp] + 19.0f * px + 4.0f * pos[3u * vn]) / 27.0f;
            oy = (4.0f * pos[3u * vp + 1u] + 19.0f * py + 4.0f * pos[3u * vn + 1u]) / 27.0f;
            oz = (4.0f * pos[3u * vp + 2u] + 19.0f * pz + 4.0f * pos[3u * vn + 2u]) / 27.0f;
        }
    }
    out_pos[3u * v] = ox, out_pos[3u * v + 1u] = oy, out_pos[3u * v + 2u] = oz;
    if (p.with_adj) {
        /* An output half-edge leaving v: from the triangle of a half-edge leaving v that is not a
         * trisected border half-edge (the fan's last one on a border). */
        const uint hc = border ? last : h0, f = hc / 3u;
        out_vh[v] = s3_kind(&s, f) == PGT_S3_KIND_PROTECTED ? s3_out_he(&s, f, 0u, hc % 3u)
                                                            : s3_out_he(&s, f, hc % 3u, 0u);
    }
}

/* ---- pass 4: new points and triangles (reference s3_faces, without UVs and labels) ---------- */

/* Where a step writes its output level. */
typedef struct s3_out {
    __global float *pos;
    __global uint *idx;
    __global uint *opp; /* when p.with_adj */
    __global uint *vh;  /* when p.with_adj */
} s3_out;

/* What the triangles of a subdivided face need to know about the neighbour across half-edge h. */
typedef struct s3_nb {
    uint o;       /* opposite half-edge, or PGT_GPU_NONE */
    int flip;     /* the edge is flipped (the neighbour exists and is subdivided) */
    uint q_opp;   /* Q(o) when flipped */
    uint e0;      /* output partner of edge a -> Q(o) (flipped) or a -> b (not flipped) */
    uint e1_flip; /* output partner of edge Q(o) -> Q(h) when flipped: T(o).e1 */
    uint e2_next; /* output partner of the next half-edge's triangle's edge Q -> b */
} s3_nb;

static s3_nb s3_neighbour(const s3_step *s, __global const uint *opp, uint h) {
    s3_nb nb;
    const uint f = h / 3u, c = h % 3u, o = opp[h];
    nb.o = o;
    nb.flip = 0;
    nb.q_opp = PGT_GPU_NONE;
    nb.e1_flip = PGT_GPU_NONE;
    nb.e0 = PGT_GPU_NONE;
    nb.e2_next = s3_out_he(s, f, c, 1u); /* not flipped: this triangle's side b -> Q(h) */
    if (o == PGT_GPU_NONE) return nb;
    const uint g = o / 3u, gc = o % 3u, kg = s3_kind(s, g);
    if (kg == PGT_S3_KIND_PROTECTED) {
        nb.e0 = s3_out_he(s, g, 0u, gc); /* the protected neighbour's own half-edge */
        return nb;
    }
    const uint gbase = 3u * s3_tri_base(s, g);
    nb.flip = 1;
    nb.e1_flip = gbase + 3u * gc + 1u;
    nb.e2_next = gbase + 3u * gc; /* T(o).e0 runs b -> Q(h) */
    if (kg == PGT_S3_KIND_CENTROID) {
        nb.q_opp = s3_point(s, g);
        nb.e0 = gbase + 3u * (gc == 2u ? 0u : gc + 1u) + 2u;
        return nb;
    }
    nb.q_opp = s3_Q(s, o);
    if (s3_is_h1(s, g, gc)) /* o is h_1 of a border face: its middle triangle */
        nb.e0 = s3_out_he(s, g, s->bslot[g], 1u);
    /* else o is h_2 of a border face: a -> Q(o) is the first third of the trisected border */
    return nb;
}

static inline void s3_emit(const s3_out *out, uint t, uint a, uint b, uint c) {
    out->idx[3u * t] = a, out->idx[3u * t + 1u] = b, out->idx[3u * t + 2u] = c;
}

/* The triangle of half-edge h (a -> b) of subdivided face f, in slot h % 3; nb describes h's
 * neighbour, pnb that of prev(h). */
static void s3_face_triangle(const s3_step *s, __global const uint *idx, const s3_out *out, uint h,
                             uint q, const s3_nb *nb, const s3_nb *pnb) {
    const uint f = h / 3u, c = h % 3u, t = s3_tri_base(s, f) + c;
    const int border_face = s3_kind(s, f) == PGT_S3_KIND_BORDER;
    s3_emit(out, t, idx[h], nb->flip ? nb->q_opp : idx[s3_next(h)], q);
    if (!s->p.with_adj) return;
    __global uint *oo = out->opp + 3u * t;
    oo[0] = nb->e0;
    /* e1: Q(o) -> Q(h) when flipped, else b -> Q(h) */
    if (nb->flip)
        oo[1] = nb->e1_flip;
    else if (!border_face)
        oo[1] = s3_out_he(s, f, (c + 1u) % 3u, 2u);
    else if (s3_is_h1(s, f, c)) /* h_1: A -> E_b is the middle triangle's e1 */
        oo[1] = s3_out_he(s, f, s->bslot[f], 1u);
    else /* h_2: a0 -> E_a lies on the border */
        oo[1] = PGT_GPU_NONE;
    /* e2: Q(h) -> a */
    if (!border_face)
        oo[2] = pnb->e2_next;
    else if (s3_is_h1(s, f, c)) /* h_1: E_b -> b0 lies on the border */
        oo[2] = PGT_GPU_NONE;
    else /* h_2: E_a -> A is the middle triangle's e2 */
        oo[2] = s3_out_he(s, f, s->bslot[f], 2u);
}

__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_faces(const pgt_s3_params p, const uint flags, __global const float *pos,
         __global const uint *idx, __global const uint *opp, __global const uint *parent,
         __global const uint *kind, __global const uint *bslot, __global const uint *pt_off,
         __global const uint *face_off, __global float *out_pos, __global uint *out_idx,
         __global uint *out_opp, __global uint *out_vh, __global uint *out_prot,
         __global uint *out_parent) {
    if (get_global_id(0) >= p.count) return;
    const uint f = p.first + (uint)get_global_id(0);
    s3_step s;
    s.p = p, s.kind = kind, s.bslot = bslot, s.pt_off = pt_off, s.face_off = face_off;
    s3_out out;
    out.pos = out_pos, out.idx = out_idx, out.opp = out_opp, out.vh = out_vh;
    const uint kf = s3_kind(&s, f), base_t = s3_tri_base(&s, f), np = s3_point(&s, f);
    const uint nt = kf == PGT_S3_KIND_PROTECTED ? 1u : 3u;
    for (uint i = 0u; i < nt; ++i) {
        if (flags & PGT_CL_S3_PROT) out_prot[base_t + i] = kf == PGT_S3_KIND_PROTECTED;
        if (flags & PGT_CL_S3_PARENT) out_parent[base_t + i] = parent[f];
    }
    if (kf == PGT_S3_KIND_PROTECTED) {
        s3_emit(&out, base_t, idx[3u * f], idx[3u * f + 1u], idx[3u * f + 2u]);
        if (p.with_adj)
            for (uint e = 0u; e < 3u; ++e) {
                const uint o = opp[3u * f + e];
                uint d;
                if (o == PGT_GPU_NONE)
                    d = PGT_GPU_NONE;
                else if (s3_kind(&s, o / 3u) == PGT_S3_KIND_PROTECTED)
                    d = s3_out_he(&s, o / 3u, 0u, o % 3u);
                else
                    d = s3_out_he(&s, o / 3u, o % 3u, 0u);
                out_opp[3u * base_t + e] = d;
            }
        return;
    }
    s3_nb nb[3];
    for (uint c = 0u; c < 3u; ++c) nb[c] = s3_neighbour(&s, opp, 3u * f + c);
    if (kf == PGT_S3_KIND_CENTROID) {
        /* step (1): the face point at the centroid */
        const uint i0 = idx[3u * f], i1 = idx[3u * f + 1u], i2 = idx[3u * f + 2u];
        for (uint k = 0u; k < 3u; ++k)
            out_pos[3u * np + k] = (pos[3u * i0 + k] + pos[3u * i1 + k] + pos[3u * i2 + k]) / 3.0f;
        if (p.with_adj) out_vh[np] = s3_out_he(&s, f, 0u, 2u);
        for (uint c = 0u; c < 3u; ++c)
            s3_face_triangle(&s, idx, &out, 3u * f + c, np, &nb[c], &nb[(c + 2u) % 3u]);
        return;
    }
    /* Border face on an even iteration: trisect the border edge a0 -> b0 with Kobbelt's
     * (1, 16, 10) / 27 masks, apex A, triangles (a0 E_a A) (E_a E_b A) (E_b b0 A) before the
     * flips of the two inner edges. */
    const uint sb = bslot[f], hb = 3u * f + sb;
    const uint a0 = idx[hb], b0 = idx[s3_next(hb)], apex = idx[s3_prev(hb)];
    const uint a0o = idx[s3_border_incoming(opp, hb)];
    const uint b0o = idx[s3_next(s3_border_outgoing_after(opp, hb))];
    for (uint k = 0u; k < 3u; ++k) {
        const float pa = pos[3u * a0 + k], pb = pos[3u * b0 + k];
        const float pao = pos[3u * a0o + k], pbo = pos[3u * b0o + k];
        out_pos[3u * np + k] = (pao + 16.0f * pa + 10.0f * pb) / 27.0f;
        out_pos[3u * (np + 1u) + k] = (10.0f * pa + 16.0f * pb + pbo) / 27.0f;
    }
    const uint tm = base_t + sb;
    s3_emit(&out, tm, np, np + 1u, apex);
    if (p.with_adj) {
        const uint h2 = 3u * f + (sb + 2u) % 3u;
        out_opp[3u * tm] = PGT_GPU_NONE;
        out_opp[3u * tm + 1u] = nb[(sb + 1u) % 3u].e2_next; /* A -> E_b */
        out_opp[3u * tm + 2u] = s3_out_he(&s, f, h2 % 3u, 2u);
        out_vh[np] = s3_out_he(&s, f, sb, 0u);
        out_vh[np + 1u] = s3_out_he(&s, f, sb, 1u);
    }
    for (uint c = 0u; c < 3u; ++c)
        if (c != sb)
            s3_face_triangle(&s, idx, &out, 3u * f + c, s3_Q(&s, 3u * f + c), &nb[c],
                             &nb[(c + 2u) % 3u]);
}

/* ---- closed uniform steps (no border half-edge, no protected face) ------------------------- */

/* Pass 3 of a closed uniform step (reference s3_vertices_closed): every vertex with a face is
 * interior and unprotected; same neighbours in the same order as s3_vertices, so the same bytes,
 * without the border and protection tests. */
__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_vertices_closed(const pgt_s3_params p, __global const float *pos, __global const uint *idx,
                   __global const uint *opp, __global const uint *vh, __global const float *alpha,
                   __global float *out_pos, __global uint *out_vh) {
    if (get_global_id(0) >= p.count) return;
    const uint v = p.first + (uint)get_global_id(0);
    const float px = pos[3u * v], py = pos[3u * v + 1u], pz = pos[3u * v + 2u];
    const uint h0 = vh[v];
    if (h0 == PGT_GPU_NONE) {
        out_pos[3u * v] = px, out_pos[3u * v + 1u] = py, out_pos[3u * v + 2u] = pz;
        if (p.with_adj) out_vh[v] = PGT_GPU_NONE;
        return;
    }
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;
    uint n = 0u, h = h0;
    do {
        const uint w = idx[s3_next(h)];
        sx += pos[3u * w], sy += pos[3u * w + 1u], sz += pos[3u * w + 2u];
        n++;
        h = opp[s3_prev(h)];
    } while (h != h0);
    const float a = n < p.alpha_count ? alpha[n] : NAN, w = a / (float)n;
    out_pos[3u * v] = (1.0f - a) * px + w * sx;
    out_pos[3u * v + 1u] = (1.0f - a) * py + w * sy;
    out_pos[3u * v + 2u] = (1.0f - a) * pz + w * sz;
    if (p.with_adj) out_vh[v] = 3u * h0; /* T(h0).e0: face h0 / 3 emits at 3 (h0 / 3) + h0 % 3 */
}

/* Pass 4 of a closed uniform step (reference s3_faces_closed): every neighbour is a centroid
 * face, face f's point and triangles sit at V + f and 3f, and the triangle of half-edge
 * h = a -> b is (a, Q(opp h), Q(h)): index arithmetic only. */
__kernel __attribute__((reqd_work_group_size(PGT_S3_GROUP_SIZE, 1, 1))) void
s3_faces_closed(const pgt_s3_params p, const uint flags, __global const float *pos,
                __global const uint *idx, __global const uint *opp, __global const uint *parent,
                __global float *out_pos, __global uint *out_idx, __global uint *out_opp,
                __global uint *out_vh, __global uint *out_parent) {
    if (get_global_id(0) >= p.count) return;
    const uint f = p.first + (uint)get_global_id(0);
    const uint V = p.V, np = V + f;
    const uint i0 = idx[3u * f], i1 = idx[3u * f + 1u], i2 = idx[3u * f + 2u];
    const uint o0 = opp[3u * f], o1 = opp[3u * f + 1u], o2 = opp[3u * f + 2u];
    for (uint k = 0u; k < 3u; ++k)
        out_pos[3u * np + k] = (pos[3u * i0 + k] + pos[3u * i1 + k] + pos[3u * i2 + k]) / 3.0f;
    __global uint *o = out_idx + 9u * f;
    o[0] = i0, o[1] = V + o0 / 3u, o[2] = np;
    o[3] = i1, o[4] = V + o1 / 3u, o[5] = np;
    o[6] = i2, o[7] = V + o2 / 3u, o[8] = np;
    if (flags & PGT_CL_S3_PARENT) {
        const uint pf = parent[f];
        out_parent[3u * f] = pf, out_parent[3u * f + 1u] = pf, out_parent[3u * f + 2u] = pf;
    }
    if (!p.with_adj) return;
    out_vh[np] = 9u * f + 2u;
    __global uint *oo = out_opp + 9u * f;
    /* T(h).e0 pairs with T(next(o)).e2, T(h).e1 with T(o).e1, T(h).e2 with T(opp(prev h)).e0 */
    oo[0] = 3u * s3_next(o0) + 2u, oo[1] = 3u * o0 + 1u, oo[2] = 3u * o2;
    oo[3] = 3u * s3_next(o1) + 2u, oo[4] = 3u * o1 + 1u, oo[5] = 3u * o0;
    oo[6] = 3u * s3_next(o2) + 2u, oo[7] = 3u * o2 + 1u, oo[8] = 3u * o1;
}
