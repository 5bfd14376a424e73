/* pgt: float image allocation and channel lookup (file formats are in image_exr.c). */
#include "pgt/image.h"

#include <stdlib.h>
#include <string.h>

#include "alloc_internal.h"
#include "image_internal.h"

pgt_result pgt_image_check_size(uint32_t width, uint32_t height, uint32_t channel_count,
                                const char *what, pgt_error *err) {
    if (width == 0 || height == 0 || channel_count == 0)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: an image of %u x %u pixels and %u channels is empty", what, width,
                             height, channel_count);
    if (width > PGT_IMAGE_MAX_SIDE || height > PGT_IMAGE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: an image of %u x %u pixels exceeds the limit of %u per side",
                             what, width, height, PGT_IMAGE_MAX_SIDE);
    if (channel_count > PGT_IMAGE_MAX_CHANNELS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "%s: %u channels exceed the limit of %u", what,
                             channel_count, PGT_IMAGE_MAX_CHANNELS);
    if ((uint64_t)width * height * channel_count > PGT_IMAGE_MAX_VALUES)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: %u x %u pixels x %u channels exceed the limit of %u values", what,
                             width, height, channel_count, PGT_IMAGE_MAX_VALUES);
    return PGT_OK;
}

pgt_result pgt_image_check_names(const char *const *names, uint32_t count, const char *what,
                                 pgt_error *err) {
    for (uint32_t c = 0; c < count; ++c) {
        const char *n = names[c];
        if (!n || n[0] == '\0')
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: channel %u has no name",
                                 what, c);
        if (memchr(n, '\0', PGT_IMAGE_NAME_SIZE) == NULL)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: channel %u: the name '%.*s...' is longer than %u "
                                 "characters",
                                 what, c, 16, n, PGT_IMAGE_NAME_SIZE - 1);
        for (uint32_t d = 0; d < c; ++d)
            if (strcmp(names[d], n) == 0)
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "%s: channels %u and %u are both named '%s'", what, d, c, n);
    }
    return PGT_OK;
}

static pgt_result image_create(pgt_image *out, uint32_t width, uint32_t height,
                               uint32_t channel_count, const char *const *names, int zeroed,
                               pgt_error *err) {
    memset(out, 0, sizeof(*out));
    pgt_result r = pgt_image_check_size(width, height, channel_count, "image create", err);
    if (r != PGT_OK) return r;
    if (names && (r = pgt_image_check_names(names, channel_count, "image create", err)) != PGT_OK)
        return r;
    /* calloc: masks and accumulation targets start at 0.0f (all-zero bits) for free. */
    out->names = calloc(channel_count, sizeof(*out->names));
    const size_t values = (size_t)width * height * channel_count;
    out->data = zeroed ? calloc(values, sizeof(float)) : pgt_alloc_large(values * sizeof(float));
    if (!out->names || !out->data) {
        pgt_image_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "out of memory for an image of %u x %u pixels and %u channels", width,
                             height, channel_count);
    }
    if (names)
        for (uint32_t c = 0; c < channel_count; ++c)
            memcpy(out->names[c], names[c], strlen(names[c]) + 1);
    out->width = width;
    out->height = height;
    out->channel_count = channel_count;
    return PGT_OK;
}

pgt_result pgt_image_create(pgt_image *out, uint32_t width, uint32_t height, uint32_t channel_count,
                            const char *const *names, pgt_error *err) {
    return image_create(out, width, height, channel_count, names, 1, err);
}

pgt_result pgt_image_create_unset(pgt_image *out, uint32_t width, uint32_t height,
                                  uint32_t channel_count, const char *const *names,
                                  pgt_error *err) {
    return image_create(out, width, height, channel_count, names, 0, err);
}

void pgt_image_destroy(pgt_image *img) {
    if (!img) return;
    free(img->names);
    free(img->data);
    free(img->half);
    memset(img, 0, sizeof(*img));
}

int32_t pgt_image_find_channel(const pgt_image *img, const char *name) {
    if (!img || !img->names || !name) return -1;
    size_t n = strlen(name);
    if (n == 0 || n >= PGT_IMAGE_NAME_SIZE) return -1;
    for (uint32_t c = 0; c < img->channel_count; ++c)
        if (memcmp(img->names[c], name, n + 1) == 0) return (int32_t)c;
    return -1;
}
