/* pgt harness: PNG reading and writing with libpng 1.6.
 *
 * libpng reports an error by longjmp to the setjmp of the call in progress (libpng manual,
 * "Setjmp/longjmp issues"). Each setjmp sits in a small *_body function whose locals are not
 * touched after the jump; everything that must survive it (allocations, what went wrong) lives
 * in a png_job reached through a pointer, so the C rule that non-volatile locals modified
 * between setjmp and longjmp are indeterminate (C11 7.13.2.1) never applies. */
#include "png_io.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The compression level of written files: zlib's default, a good size for little time. */
#define PGT_PNG_ZLIB_LEVEL 6

typedef struct png_job {
    FILE *f;
    int eof;      /* a read met the end of the file */
    int io_errno; /* a read or write failed */
    int limit;    /* the image is larger than PGT_PNG_MAX_SIDE */
    int oom;      /* our allocation failed */
    int too_big;  /* the header declares more pixels than the file's bytes can hold */
    uint64_t file_bytes; /* reading a regular file: its size, else 0 */
    uint32_t w, h, channels;
    uint8_t *pixels; /* reading: the result, freed on failure */
    png_bytep *rows; /* reading: row pointers into pixels */
    char msg[200];   /* libpng's error message */
} png_job;

static void on_png_error(png_structp png, png_const_charp msg) {
    png_job *job = png_get_error_ptr(png);
    snprintf(job->msg, sizeof(job->msg), "%s", msg ? msg : "");
    png_longjmp(png, 1);
}

/* Warnings (an ancillary chunk with a bad CRC, a known-incorrect sRGB profile) are not failures,
 * and the harness prints nothing it was not asked for. */
static void on_png_warning(png_structp png, png_const_charp msg) {
    (void)png;
    (void)msg;
}

/* ---- reading ---- */

static void read_bytes(png_structp png, png_bytep out, size_t n) {
    png_job *job = png_get_io_ptr(png);
    if (fread(out, 1, n, job->f) == n) return;
    if (ferror(job->f)) {
        job->io_errno = errno ? errno : EIO;
        png_error(png, "read error");
    }
    job->eof = 1;
    png_error(png, "the file ends before its IEND chunk");
}

static int read_body(png_structp png, png_infop info, png_job *job) {
    if (setjmp(png_jmpbuf(png))) return -1;
    png_set_read_fn(png, job, read_bytes);
    png_set_sig_bytes(png, 8);
    /* libpng's own default limit is 10^6 per side; ours is smaller and has its own error code,
     * so let libpng accept any size the format allows and check after the header. */
    png_set_user_limits(png, 0x7fffffffu, 0x7fffffffu);
    png_read_info(png, info);
    job->w = png_get_image_width(png, info);
    job->h = png_get_image_height(png, info);
    if (job->w > PGT_PNG_MAX_SIDE || job->h > PGT_PNG_MAX_SIDE) {
        job->limit = 1;
        return -1;
    }
    /* deflate expands at most 1032 times: a header declaring more rows of bytes than that of
     * the file's size is refused before the pixels are allocated (a 69-byte file declaring
     * 16384^2 RGBA pixels reserved 1 GiB) */
    const uint64_t raw = ((uint64_t)png_get_rowbytes(png, info) + 1u) * job->h;
    if (job->file_bytes &&
        raw > PGT_IMAGE_DEFLATE_MAX_RATIO * job->file_bytes + PGT_IMAGE_EXPANSION_SLACK) {
        job->too_big = 1;
        return -1;
    }
    int color = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    if (depth == 16) png_set_scale_16(png); /* rounds; png_set_strip_16 would truncate */
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    job->channels = png_get_channels(png, info);
    if (png_get_bit_depth(png, info) != 8 || job->channels < 1 || job->channels > 4 ||
        png_get_rowbytes(png, info) != (size_t)job->w * job->channels)
        png_error(png, "unexpected pixel layout after expansion to 8 bits");
    size_t row = (size_t)job->w * job->channels;
    job->pixels = malloc(row * job->h);
    job->rows = malloc(sizeof(png_bytep) * job->h);
    if (!job->pixels || !job->rows) {
        job->oom = 1;
        png_error(png, "out of memory");
    }
    for (uint32_t y = 0; y < job->h; ++y) job->rows[y] = job->pixels + row * y;
    png_read_image(png, job->rows);
    png_read_end(png, NULL); /* the chunks after IDAT, their CRCs, and IEND */
    return 0;
}

pgt_result pgt_png_read(const char *path, uint32_t *w, uint32_t *h, uint32_t *channels,
                        uint8_t **pixels, pgt_error *err) {
    *w = *h = *channels = 0;
    *pixels = NULL;
    if (!path || !path[0])
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "PNG read: no path");
    FILE *f = fopen(path, "rb");
    if (!f) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    const int have_st = fstat(fileno(f), &st) == 0;
    if (have_st && S_ISDIR(st.st_mode)) {
        fclose(f);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot read: is a directory", path);
    }
    const uint64_t file_bytes = have_st && S_ISREG(st.st_mode) ? (uint64_t)st.st_size : 0u;
    png_byte sig[8];
    size_t n = fread(sig, 1, sizeof(sig), f);
    pgt_result r = PGT_OK;
    if (ferror(f))
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(errno));
    else if (n == 0)
        r = pgt_error_set(err, PGT_ERROR_EMPTY, "%s: empty file", path);
    else if (png_sig_cmp(sig, 0, n) != 0)
        r = pgt_error_set(err, PGT_ERROR_PARSE, "%s: not a PNG file (no PNG signature)", path);
    else if (n < sizeof(sig))
        r = pgt_error_set(err, PGT_ERROR_TRUNCATED, "%s: the file ends in its signature", path);
    if (r != PGT_OK) {
        fclose(f);
        return r;
    }

    png_job job;
    memset(&job, 0, sizeof(job));
    job.f = f;
    job.file_bytes = file_bytes;
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int rc = png && info ? read_body(png, info, &job) : (job.oom = 1, -1);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    free(job.rows);
    if (rc == 0) {
        *w = job.w;
        *h = job.h;
        *channels = job.channels;
        *pixels = job.pixels;
        return PGT_OK;
    }
    free(job.pixels);
    if (job.too_big)
        return pgt_error_set(err, PGT_ERROR_TRUNCATED,
                             "%s: declares %u x %u pixels, more than its %llu bytes can hold "
                             "(deflate expands at most %u times)",
                             path, job.w, job.h, (unsigned long long)file_bytes,
                             (unsigned)PGT_IMAGE_DEFLATE_MAX_RATIO);
    if (job.limit)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: %u x %u pixels exceed the limit of %u per side", path, job.w,
                             job.h, PGT_PNG_MAX_SIDE);
    if (job.io_errno)
        return pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(job.io_errno));
    if (job.oom)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %u x %u pixels",
                             path, job.w, job.h);
    if (job.eof) return pgt_error_set(err, PGT_ERROR_TRUNCATED, "%s: %s", path, job.msg);
    return pgt_error_set(err, PGT_ERROR_PARSE, "%s: %s", path, job.msg);
}

/* ---- writing ---- */

static void write_bytes(png_structp png, png_bytep data, size_t n) {
    png_job *job = png_get_io_ptr(png);
    if (fwrite(data, 1, n, job->f) == n) return;
    job->io_errno = errno ? errno : EIO;
    png_error(png, "write error");
}

static void flush_bytes(png_structp png) {
    png_job *job = png_get_io_ptr(png);
    if (fflush(job->f) == 0) return;
    job->io_errno = errno ? errno : EIO;
    png_error(png, "write error");
}

static int write_body(png_structp png, png_infop info, png_job *job, const uint8_t *pixels) {
    static const int color_types[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                       PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    if (setjmp(png_jmpbuf(png))) return -1;
    png_set_write_fn(png, job, write_bytes, flush_bytes);
    png_set_IHDR(png, info, job->w, job->h, 8, color_types[job->channels - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, PGT_PNG_ZLIB_LEVEL);
    png_write_info(png, info);
    const size_t row = (size_t)job->w * job->channels;
    for (uint32_t y = 0; y < job->h; ++y) png_write_row(png, pixels + row * y);
    png_write_end(png, NULL);
    return 0;
}

uint8_t pgt_png_linear_to_srgb8(float c) {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)(255.0f * s + 0.5f);
}

pgt_result pgt_png_write(const char *path, uint32_t w, uint32_t h, uint32_t channels,
                         const uint8_t *pixels, pgt_error *err) {
    if (!path || !path[0])
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "PNG write: no path");
    if (w == 0 || h == 0 || channels < 1 || channels > 4 || !pixels)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: cannot write %u x %u pixels of %u channels%s", path, w, h,
                             channels, pixels ? "" : " from NULL");
    if (w > PGT_PNG_MAX_SIDE || h > PGT_PNG_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: %u x %u pixels exceed the limit of %u per side", path, w, h,
                             PGT_PNG_MAX_SIDE);

    /* PATH.tmp.PID in the same folder, so rename() replaces the target atomically. */
    size_t tmp_size = strlen(path) + 32;
    char *tmp = malloc(tmp_size);
    if (!tmp) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    pgt_tmp_name(tmp, tmp_size, path);
    png_job job;
    memset(&job, 0, sizeof(job));
    job.w = w;
    job.h = h;
    job.channels = channels;
    job.f = fopen(tmp, "wb");
    if (!job.f) {
        int e = errno;
        free(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot create a temporary file beside it: %s",
                             path, strerror(e));
    }
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int rc = png && info ? write_body(png, info, &job, pixels) : (job.oom = 1, -1);
    png_destroy_write_struct(&png, &info);
    int closed = fclose(job.f);
    pgt_result r = PGT_OK;
    if (rc != 0 && job.oom)
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    else if (rc != 0 && job.io_errno)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: write error: %s", path, strerror(job.io_errno));
    else if (rc != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: %s", path, job.msg);
    else if (closed != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: write error: %s", path, strerror(errno));
    else if (pgt_replace_file(tmp, path) != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot move the written file into place: %s",
                          path, strerror(errno));
    if (r != PGT_OK) remove(tmp);
    free(tmp);
    return r;
}

/* ---- float images as pictures ---- */

static uint8_t to_byte(float v, double lo, double hi) {
    double t = ((double)v - lo) / (hi - lo);
    if (!(t > 0.0)) return 0; /* also NaN */
    if (t >= 1.0) return 255;
    return (uint8_t)(t * 255.0 + 0.5);
}

pgt_result pgt_png_from_image(const char *path, const pgt_image *img,
                              const char *const *channel_names, uint32_t count, float lo, float hi,
                              pgt_error *err) {
    const char *name = path && path[0] ? path : "PNG write";
    if (!img || !img->data || count < 1 || count > 4)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: need an image and 1 to 4 channels (got %u)", name, count);
    if (!isfinite(lo) || !isfinite(hi) || lo == hi)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: the range [%g, %g] cannot be mapped to 0..255", name, (double)lo,
                             (double)hi);
    uint32_t planes[4];
    for (uint32_t k = 0; k < count; ++k) {
        int32_t c = channel_names ? pgt_image_find_channel(img, channel_names[k]) : (int32_t)k;
        if (c < 0 || (uint32_t)c >= img->channel_count)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: the image has no channel '%s'", name,
                                 channel_names ? channel_names[k] : "?");
        planes[k] = (uint32_t)c;
    }
    size_t pixels = (size_t)img->width * img->height;
    uint8_t *buf = malloc(pixels * count + 1);
    if (!buf) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    for (uint32_t k = 0; k < count; ++k) {
        const float *plane = pgt_image_plane(img, planes[k]);
        for (size_t i = 0; i < pixels; ++i) buf[i * count + k] = to_byte(plane[i], lo, hi);
    }
    pgt_result r = pgt_png_write(path, img->width, img->height, count, buf, err);
    free(buf);
    return r;
}
