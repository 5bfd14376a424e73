/* pgt: flat float images with named channels, and OpenEXR reading and writing.
 *
 * One image type serves geometry-image atlases (P.x P.y P.z N.x ... chart), masks and rendered
 * frames (R G B depth). Storage is planar float32, the layout a GPU backend uploads as one buffer:
 * channel c, row y (top to bottom, as EXR and PNG store rows), column x is
 *     data[((size_t)c * height + y) * width + x].
 *
 * The EXR reader validates everything: a malformed, truncated or hostile file returns a
 * pgt_result code and a message that names the file; nothing aborts, and declared sizes are
 * checked against the limits below and against the file size before the pixels are allocated.
 * The writer writes to a temporary file beside the target and renames it into place. */
#ifndef PGT_IMAGE_H
#define PGT_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes of a channel name including its NUL: 31 characters, the length OpenEXR allows without
 * its "long names" flag, so every name we write is readable by every EXR reader. */
#define PGT_IMAGE_NAME_SIZE 32u

/* Largest width or height: 16384 covers every atlas and frame the papers use (their largest
 * geometry images are 2048^2) with room to spare. */
#define PGT_IMAGE_MAX_SIDE 16384u

/* Most channels: a geometry image with position, normal, UV, tangent, chart and masks has ~16. */
#define PGT_IMAGE_MAX_CHANNELS 64u

/* Most floats in one image (width * height * channels): 2^28 = 1 GiB of pixel data. Without it a
 * 300-byte ZIP-compressed EXR could declare 16384^2 x 64 channels and ask for 64 GiB. */
#define PGT_IMAGE_MAX_VALUES (1u << 28)

/* The most a deflate (zlib) stream expands: a 258-byte match from about 2 bits, 1032 to 1. The
 * PNG and EXR readers refuse a header declaring more pixel bytes than this times the compressed
 * bytes (plus PGT_IMAGE_EXPANSION_SLACK: filter bytes, chunk headers, RLE's counts) before the
 * pixels are allocated. */
#define PGT_IMAGE_DEFLATE_MAX_RATIO 1032u
#define PGT_IMAGE_EXPANSION_SLACK 4096u

typedef struct pgt_image {
    uint32_t width, height, channel_count;
    char (*names)[PGT_IMAGE_NAME_SIZE]; /* channel_count NUL-terminated names */
    float *data;                        /* channel_count planes of height rows of width floats */
    /* channel_count flags, 1 where the file stored the channel as HALF (whole numbers exact
     * only up to 2048), set by the EXR readers; NULL for an image made in memory */
    uint8_t *half;
} pgt_image;

/* Allocates an image with every value 0.0f. names may be NULL (all names empty, for the caller
 * to fill) or hold channel_count names, each non-empty, at most 31 characters and unique.
 * A zero size is PGT_ERROR_INVALID_ARGUMENT, a size above the limits PGT_ERROR_LIMIT.
 * *out is overwritten; on failure it is left zeroed. */
pgt_result pgt_image_create(pgt_image *out, uint32_t width, uint32_t height, uint32_t channel_count,
                            const char *const *names, pgt_error *err);

/* pgt_image_create without the zeroing: the values are undefined until written. For a producer
 * that writes every value of every plane (the atlas builder: 44 MB at 1024^2, whose zeroing is a
 * serial pass of several ms in front of a parallel one that overwrites it all). On Linux a large
 * image is backed by transparent huge pages where the system allows (ref_cpu/src/alloc_internal.h
 * for the threshold and the measurements). */
pgt_result pgt_image_create_unset(pgt_image *out, uint32_t width, uint32_t height,
                                  uint32_t channel_count, const char *const *names, pgt_error *err);

/* Frees the arrays and zeroes the struct; NULL or a zeroed image is a no-op. */
void pgt_image_destroy(pgt_image *img);

/* Index of the channel called `name` (exact, case-sensitive), or -1. OpenEXR stores channels
 * sorted by name, so a channel read from a file must be looked up by name, never by position. */
int32_t pgt_image_find_channel(const pgt_image *img, const char *name);

/* The plane of channel c (width * height floats, row-major). */
static inline float *pgt_image_plane(const pgt_image *img, uint32_t c) {
    return img->data + (size_t)c * img->height * img->width;
}

/* Writes a single-part scanline OpenEXR file: every channel as FLOAT (so values come back
 * bit-exact, negative zero, denormals, infinities and NaN payloads included), ZIP compression
 * (16 rows per chunk), data and display window (0, 0)-(width-1, height-1), INCREASING_Y.
 * Names must be non-empty, at most 31 characters and unique (else PGT_ERROR_INVALID_ARGUMENT,
 * before anything is written). The file is written to PATH.tmp.PID and renamed over PATH; on
 * any failure the temporary file is removed and PGT_ERROR_IO names PATH. */
pgt_result pgt_image_write_exr(const pgt_image *img, const char *path, pgt_error *err);

/* pgt_image_write_exr with the chunks packed and compressed on up to `threads` threads (0 means
 * 1), then written in file order: the same bytes for any thread count. Compression is most of a
 * write (a 1024^2 atlas of 11 channels: 44 MB of floats in 64 chunks). */
pgt_result pgt_image_write_exr_threads(const pgt_image *img, const char *path, uint32_t threads,
                                       pgt_error *err);

/* Reads a single-part scanline or tiled OpenEXR file (of a mip- or rip-mapped file the
 * full-resolution level) in any compression OpenEXRCore decodes (3.1: all but DWAA and DWAB),
 * with HALF, FLOAT or UINT channels, all converted to float (HALF exactly; UINT rounded to
 * nearest above 2^24). The image covers the data window; its origin and the display window are
 * not kept. Channels come in the file's order, which OpenEXR sorts by name. On failure *out is
 * zeroed.
 *
 * Error codes (every message starts with the path, or `name` for the memory reader):
 * - PGT_ERROR_IO: the file cannot be opened or read (or is a directory).
 * - PGT_ERROR_EMPTY: a file of 0 bytes.
 * - PGT_ERROR_PARSE: not an OpenEXR file (magic number), or a header or pixel data that
 *   OpenEXR rejects as malformed (bad attribute, corrupt chunk, inverted data window, ...).
 * - PGT_ERROR_TRUNCATED: the file ends inside its header, its offset table or a chunk, or its
 *   offset table points past the end, or its chunks hold fewer bytes than the pixels its header
 *   declares need under its compression's largest expansion (checked before the pixels are
 *   allocated, for every compression but DWAA and DWAB).
 * - PGT_ERROR_LIMIT: width or height above PGT_IMAGE_MAX_SIDE, more than PGT_IMAGE_MAX_CHANNELS
 *   channels, more than PGT_IMAGE_MAX_VALUES values, a tile of more than 2^26 values (clipped
 *   to the image), or a channel name longer than 31.
 * - PGT_ERROR_UNSUPPORTED: a file of two parts or more (one part with the multipart flag is
 *   read), a deep file, a subsampled channel, or a compression
 *   the library cannot decode (DWAA, DWAB with OpenEXR 3.1).
 * - PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_image_read_exr(pgt_image *out, const char *path, pgt_error *err);

/* pgt_image_read_exr with the chunks decoded on up to `threads` threads (0 means 1): the same
 * image and, for a damaged file, the same error as one thread (that of the first failing chunk
 * in file order). Decompression is most of a read (a 1024^2 atlas: 64 ZIP chunks, 44 MB). */
pgt_result pgt_image_read_exr_threads(pgt_image *out, const char *path, uint32_t threads,
                                      pgt_error *err);

/* The same from memory; `name` is used in messages in place of the path. */
pgt_result pgt_image_read_exr_memory(pgt_image *out, const void *data, size_t size,
                                     const char *name, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
