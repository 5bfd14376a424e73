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
    return PGT_OK;
}
