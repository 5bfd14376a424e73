/* pgt: the channel contract of an atlas image (atlas.h). */
#include "pgt/atlas.h"

pgt_result pgt_atlas_channels_find(const pgt_image *atlas, const char *what,
                                   pgt_atlas_channels *out, pgt_error *err) {
    static const char *const names[PGT_ATLAS_CHANNEL_COUNT] = PGT_ATLAS_CHANNEL_NAMES;
    uint32_t *slots[PGT_ATLAS_CHANNEL_COUNT] = {&out->px,    &out->py,    &out->pz,    &out->nx,
                                                &out->ny,    &out->nz,    &out->chart, &out->kind,
                                                &out->ptr_u, &out->ptr_v, &out->rot};
    if (!what) what = "atlas";
    for (uint32_t i = 0; i < PGT_ATLAS_CHANNEL_COUNT; ++i) {
        const int32_t c = atlas ? pgt_image_find_channel(atlas, names[i]) : -1;
        if (c < 0)
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s: not an atlas: no channel '%s'", what,
                                 names[i]);
        *slots[i] = (uint32_t)c;
    }
    /* the integer channels: a file may store them as HALF, which holds whole numbers exactly
     * only up to 2048 (an id above it was rounded when written: charts 2049 and 2050 merge) */
    const uint32_t ids[4] = {out->chart, out->kind, out->ptr_u, out->ptr_v};
    for (uint32_t k = 0; atlas->half && k < 4; ++k) {
        if (!atlas->half[ids[k]]) continue;
        const float *v = pgt_image_plane(atlas, ids[k]);
        const size_t n = (size_t)atlas->width * atlas->height;
        for (size_t i = 0; i < n; ++i)
            if (v[i] > 2048.0f)
                return pgt_error_set(err, PGT_ERROR_PARSE,
                                     "%s: channel '%s' is stored as HALF, which holds whole "
                                     "numbers exactly only up to 2048, and texel (%zu, %zu) has "
                                     "%g: write it as FLOAT or UINT",
                                     what, atlas->names[ids[k]], i % atlas->width, i / atlas->width,
                                     (double)v[i]);
    }
    return PGT_OK;
}
