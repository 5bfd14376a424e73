/* pgt harness: 8-bit PNG reading and writing (libpng), for figures, masks and debug pictures.
 *
 * Pixels are interleaved, rows top to bottom, `channels` bytes per pixel: 1 gray, 2 gray+alpha,
 * 3 RGB, 4 RGBA. The reader never aborts on a bad file: it returns a pgt_result code and a
 * message naming the file. The writer writes PATH.tmp.PID beside the target and renames it. */
#ifndef PGT_PNG_IO_H
#define PGT_PNG_IO_H

#include <stdint.h>

#include "pgt/image.h"

/* Largest width or height read or written: the image module's limit, so every picture of an
 * atlas fits, and a hostile 16-byte IHDR cannot ask for gigabytes. */
#define PGT_PNG_MAX_SIDE PGT_IMAGE_MAX_SIDE

/* The 8-bit sRGB code of a linear value (the sRGB transfer function, rounded to nearest): 0 at
 * or below 0 and for NaN, 255 at or above 1. For pictures rendered in linear light. */
uint8_t pgt_png_linear_to_srgb8(float c);

/* Writes an 8-bit PNG (colour type from `channels`, 1..4; zlib level 6, no interlacing).
 * Bad arguments are PGT_ERROR_INVALID_ARGUMENT (a side of 0, channels outside 1..4, NULL
 * pixels), a side above PGT_PNG_MAX_SIDE PGT_ERROR_LIMIT, both before anything is written;
 * a failed write or rename PGT_ERROR_IO naming PATH (the temporary file is removed). */
pgt_result pgt_png_write(const char *path, uint32_t w, uint32_t h, uint32_t channels,
                         const uint8_t *pixels, pgt_error *err);

/* Reads any PNG as 8 bits per channel: palette images become RGB (RGBA with a tRNS chunk),
 * gray below 8 bits is scaled to 8, tRNS becomes an alpha channel, 16-bit samples are rounded
 * to 8 (v * 255 / 65535), interlaced images are de-interlaced; samples are kept as stored
 * (no gamma or colour-profile conversion). *pixels is malloc'd (free() it).
 * On failure the outputs are 0 / NULL. Codes:
 * - PGT_ERROR_IO: cannot open or read (or a directory); PGT_ERROR_EMPTY: a file of 0 bytes;
 * - PGT_ERROR_PARSE: not a PNG (signature), a CRC error in a critical chunk, bad zlib data, or
 *   anything else libpng rejects;
 * - PGT_ERROR_TRUNCATED: the file ends before IEND;
 * - PGT_ERROR_LIMIT: a side above PGT_PNG_MAX_SIDE;
 * - PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_png_read(const char *path, uint32_t *w, uint32_t *h, uint32_t *channels,
                        uint8_t **pixels, pgt_error *err);

/* Writes `count` (1..4) channels of img, picked by name (channel_names NULL: the first `count`
 * channels), as a PNG of `count` channels, mapping [lo, hi] linearly to [0, 255] with clamping
 * and rounding to nearest; NaN maps to 0. lo > hi inverts the map (e.g. depth, near = white).
 * A missing channel name, lo == hi or a non-finite bound is PGT_ERROR_INVALID_ARGUMENT. */
pgt_result pgt_png_from_image(const char *path, const pgt_image *img,
                              const char *const *channel_names, uint32_t count, float lo, float hi,
                              pgt_error *err);

#endif
