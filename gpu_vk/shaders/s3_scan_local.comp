/* pgt: sqrt(3) pass 2a, the work-group step of the exclusive prefix sums of what each face emits
 * (points = its kind value, triangles = 1 if protected else 3).
 *
 * Level 0 reads kind[] and writes each face's offsets within its work-group into pt_off[] and
 * face_off[]; level l > 0 scans the work-group totals of level l - 1 in place in sums[]. Each
 * work-group's total goes to sums[scan_out + group]; the level of one group holds the grand
 * totals. s3_scan_add then adds the scanned totals back, level by level. */
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s3_common.glsl"

shared uvec2 part[PGT_S3_GROUP_SIZE];

void main() {
    uint i;
    const bool live = s3_item(i);
    const uint lid = gl_LocalInvocationID.x;
    uvec2 v = uvec2(0u);
    if (live) {
        if (pc.scan_level == 0u) {
            uint k = kind[i];
            v = uvec2(k, k == PGT_S3_KIND_PROTECTED ? 1u : 3u); /* KIND_* = points emitted */
        } else {
            v = sums[pc.scan_in + i];
        }
    }
    /* Inclusive Hillis-Steele scan of the group; every invocation reaches every barrier. */
    part[lid] = v;
    memoryBarrierShared();
    barrier();
    for (uint d = 1u; d < PGT_S3_GROUP_SIZE; d <<= 1u) {
        uvec2 t = lid >= d ? part[lid - d] : uvec2(0u);
        memoryBarrierShared();
        barrier();
        part[lid] += t;
        memoryBarrierShared();
        barrier();
    }
    const uvec2 excl = part[lid] - v;
    if (live) {
        if (pc.scan_level == 0u) {
            pt_off[i] = excl.x;
            face_off[i] = excl.y;
        } else {
            sums[pc.scan_in + i] = excl;
        }
    }
    /* i / group size is this work-group's index in the level (first is a multiple of it). */
    if (lid == PGT_S3_GROUP_SIZE - 1u) sums[pc.scan_out + i / PGT_S3_GROUP_SIZE] = part[lid];
}
