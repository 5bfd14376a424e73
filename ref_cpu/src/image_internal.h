/* pgt: private helpers shared by image.c and image_exr.c. */
#ifndef PGT_IMAGE_INTERNAL_H
#define PGT_IMAGE_INTERNAL_H

#include "pgt/image.h"

/* Zero sizes are PGT_ERROR_INVALID_ARGUMENT, sizes above the PGT_IMAGE_MAX_* limits
 * PGT_ERROR_LIMIT; `what` (a path, or "image create") starts the message. */
pgt_result pgt_image_check_size(uint32_t width, uint32_t height, uint32_t channel_count,
                                const char *what, pgt_error *err);

/* Every name non-NULL, non-empty, NUL-terminated within PGT_IMAGE_NAME_SIZE bytes and unique;
 * else PGT_ERROR_INVALID_ARGUMENT. */
pgt_result pgt_image_check_names(const char *const *names, uint32_t count, const char *what,
                                 pgt_error *err);

#endif
