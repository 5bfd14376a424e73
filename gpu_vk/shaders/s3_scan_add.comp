/* pgt: sqrt(3) pass 2b: adds to each element of a scan level the exclusive sum of the
 * work-groups before its own (the scanned level above), making the level's prefix sums global.
 * Level 0 is pt_off[] and face_off[]; higher levels live in sums[]. */
#version 450
#extension GL_GOOGLE_include_directive : require
#include "s3_common.glsl"

void main() {
    uint i;
    if (!s3_item(i)) return;
    const uvec2 add = sums[pc.scan_out + i / PGT_S3_GROUP_SIZE];
    if (pc.scan_level == 0u) {
        pt_off[i] += add.x;
        face_off[i] += add.y;
    } else {
        sums[pc.scan_in + i] += add;
    }
}
