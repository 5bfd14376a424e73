/* pgt: declarations every sqrt(3) shader shares: the push constants, the storage buffers (the
 * flat arrays of gpu_shared/sqrt3_layout.h, bindings from s3_vk_layout.h) and the half-edge
 * helpers of ref_cpu/src/sqrt3.c. A shader only binds what it uses (glslc -O drops the rest). */
#include "s3_vk_layout.h"

layout(local_size_x = PGT_S3_GROUP_SIZE) in;

layout(push_constant) uniform Push {
    pgt_vk_s3_push pc;
};

layout(std430, set = 0, binding = PGT_VK_B_POS_IN) readonly buffer PosIn { float pos_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_IDX_IN) readonly buffer IdxIn { uint idx_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_OPP_IN) readonly buffer OppIn { uint opp_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_VH_IN) readonly buffer VhIn { uint vh_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_PROT_IN) readonly buffer ProtIn { uint prot_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_PARENT_IN) readonly buffer ParentIn { uint parent_in[]; };
layout(std430, set = 0, binding = PGT_VK_B_KIND) buffer Kind { uint kind[]; };
layout(std430, set = 0, binding = PGT_VK_B_BSLOT) buffer Bslot { uint bslot[]; };
layout(std430, set = 0, binding = PGT_VK_B_PT_OFF) buffer PtOff { uint pt_off[]; };
layout(std430, set = 0, binding = PGT_VK_B_FACE_OFF) buffer FaceOff { uint face_off[]; };
layout(std430, set = 0, binding = PGT_VK_B_ALPHA) readonly buffer Alpha { float alpha[]; };
layout(std430, set = 0, binding = PGT_VK_B_POS_OUT) writeonly buffer PosOut { float pos_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_IDX_OUT) writeonly buffer IdxOut { uint idx_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_OPP_OUT) writeonly buffer OppOut { uint opp_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_VH_OUT) writeonly buffer VhOut { uint vh_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_PROT_OUT) writeonly buffer ProtOut { uint prot_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_PARENT_OUT) writeonly buffer ParentOut { uint parent_out[]; };
layout(std430, set = 0, binding = PGT_VK_B_SUMS) buffer Sums { uvec2 sums[]; };
layout(std430, set = 0, binding = PGT_VK_B_FAULT) buffer Fault { uint fault[]; };

/* The element this invocation handles (a pass may be dispatched in ranges: first, count). */
bool s3_item(out uint i) {
    i = pc.s3.first + gl_GlobalInvocationID.x;
    return gl_GlobalInvocationID.x < pc.s3.count;
}

uint he_next(uint h) { return h % 3u == 2u ? h - 2u : h + 1u; }
uint he_prev(uint h) { return h % 3u == 0u ? h + 2u : h - 1u; }

vec3 load_pos(uint v) { return vec3(pos_in[3u * v], pos_in[3u * v + 1u], pos_in[3u * v + 2u]); }

void store_pos(uint v, vec3 p) {
    uint i = 3u * v - pc.pos_base;
    pos_out[i] = p.x;
    pos_out[i + 1u] = p.y;
    pos_out[i + 2u] = p.z;
}

/* Per-face facts of a step (s3_kind, s3_tri_base, s3_point of the reference): a uniform step has
 * every face a centroid face with offsets f and 3f, and does not bind kind, pt_off, face_off. */
uint s3_kind(uint f) { return pc.s3.is_uniform != 0u ? PGT_S3_KIND_CENTROID : kind[f]; }
uint s3_tri_base(uint f) { return pc.s3.is_uniform != 0u ? 3u * f : face_off[f]; }
uint s3_point(uint f) { return pc.s3.V + (pc.s3.is_uniform != 0u ? f : pt_off[f]); }

/* Output half-edge e of the triangle emitted in slot c of face f. */
uint s3_out_he(uint f, uint c, uint e) { return 3u * (s3_tri_base(f) + c) + e; }

/* A fan walk of `element` in pass `pass` (0 vertices, 1 faces) reached pc.walk_budget
 * iterations and stopped (s3_vk_layout.h: lavapipe's loop limit): record it for the host, which
 * then refuses the call. The first pass to stop keeps the code; its smallest element wins. */
void s3_walk_stopped(uint pass, uint element) {
    const uint code = 1u + 2u * pc.level + pass;
    const uint was = atomicCompSwap(fault[PGT_VK_FAULT_CODE], 0u, code);
    if (was == 0u || was == code) atomicMin(fault[PGT_VK_FAULT_ELEMENT], element);
}
