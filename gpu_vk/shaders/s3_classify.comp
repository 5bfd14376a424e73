/* pgt: sqrt(3) pass 1, classify faces (s3_classify of ref_cpu/src/sqrt3.c): per face of the
 * step's input, its kind (protected / centroid / border-trisected) and border corner. */
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s3_common.glsl"

void main() {
    uint f;
    if (!s3_item(f)) return;
    uint k = PGT_S3_KIND_CENTROID, slot = 0u;
    if (prot_in[f] != 0u) {
        k = PGT_S3_KIND_PROTECTED;
    } else if (pc.s3.even != 0u) {
        /* After an odd iteration a subdivided face has at most one border edge. */
        for (uint c = 0u; c < 3u; ++c)
            if (opp_in[3u * f + c] == PGT_GPU_NONE) k = PGT_S3_KIND_BORDER, slot = c;
    }
    kind[f] = k;
    bslot[f] = slot;
}
