/* pgt: OpenEXR reading and writing through the OpenEXR 3.1 C API (OpenEXRCore).
 *
 * Based on the OpenEXR file layout (openexr.com, "OpenEXR File Layout"): the magic number
 * 76 2f 31 01, a version field, the header attributes, an offset table of one uint64 per chunk,
 * then the chunks (scanline blocks of 16 rows for ZIP, or tiles). OpenEXRCore parses and decodes;
 * this file adds what pgt needs around it: declared sizes checked against the PGT_IMAGE_MAX_*
 * limits and the offset table and every chunk against the file size before anything large is
 * allocated, the library's errors mapped to pgt_result codes with messages naming the file, and
 * the write-to-a-temporary-file-then-rename rule of every pgt writer.
 *
 * All I/O goes through our own read/write callbacks (pread/pwrite on our descriptor, or memcpy
 * from memory), so the library never opens, truncates or deletes a file itself. */
#include "pgt/image.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

#include "pgt/parallel.h"

#include "image_internal.h"

static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};

/* One file or memory buffer being read or written, and what went wrong with it. */
typedef struct exr_stream {
    const char *name;         /* the path (or the memory reader's name), for messages */
    int fd;                   /* -1 when reading from memory */
    const unsigned char *mem; /* memory reading */
    uint64_t size;            /* reading: bytes in the file, fixed when it was opened */
    _Atomic int io_errno;     /* the first failed read or write, 0 if none */
    int chunks_checked;       /* reading: check_chunks found every chunk inside the file */
    uint64_t packed_bytes;    /* reading (chunks_checked): the chunks' packed sizes, summed, or
                                 when a chunk's offset or size is not one a chunk can have, the
                                 bytes after the offset table (all the chunks can hold) */
    int packed_is_sum;        /* packed_bytes is the sum of the chunks' sizes */
    const char *compression;  /* reading: the file's compression, once the header is read */
    char lib_msg[256];        /* the library's last error message */
    /* a decoding worker's stream, for its messages: the stream the library reads through,
     * whose io_errno counts (NULL: this one) */
    const struct exr_stream *io;
} exr_stream;

/* The first failed read or write of the file behind s, 0 if none. */
static int stream_errno(const exr_stream *s) { return (s->io ? s->io : s)->io_errno; }

/* Records errno e as the stream's first failure (reads may run on several threads). */
static void stream_fail(exr_stream *s, int e) {
    int none = 0;
    atomic_compare_exchange_strong(&s->io_errno, &none, e);
}

/* OpenEXRCore reports errors through a callback, sometimes while it holds its context lock, so
 * the callback must not call back into the library (exr_get_user_data would take that lock
 * again). It finds the stream of the call in progress through this thread-local pointer. */
static _Thread_local exr_stream *current_stream;

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
    (void)ctxt;
    (void)code;
    exr_stream *s = current_stream;
    if (s) snprintf(s->lib_msg, sizeof(s->lib_msg), "%s", msg ? msg : "");
}

static int64_t stream_read(exr_const_context_t ctxt, void *userdata, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    (void)ctxt;
    (void)error_cb;
    exr_stream *s = userdata;
    if (offset >= s->size) return 0;
    uint64_t n = s->size - offset < sz ? s->size - offset : sz;
    if (s->fd < 0) {
        memcpy(buffer, s->mem + offset, (size_t)n);
        return (int64_t)n;
    }
    uint64_t done = 0;
    while (done < n) {
        ssize_t got =
            pread(s->fd, (char *)buffer + done, (size_t)(n - done), (off_t)(offset + done));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) {
            stream_fail(s, errno);
            return -1;
        }
        if (got == 0) break; /* the file shrank since we measured it: a short read */
        done += (uint64_t)got;
    }
    return (int64_t)done;
}

static int64_t stream_size(exr_const_context_t ctxt, void *userdata) {
    (void)ctxt;
    return (int64_t)((exr_stream *)userdata)->size;
}

static int64_t stream_write(exr_const_context_t ctxt, void *userdata, const void *buffer,
                            uint64_t sz, uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    (void)ctxt;
    (void)error_cb;
    exr_stream *s = userdata;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t put =
            pwrite(s->fd, (const char *)buffer + done, (size_t)(sz - done), (off_t)(offset + done));
        if (put < 0 && errno == EINTR) continue;
        if (put <= 0) {
            stream_fail(s, put < 0 ? errno : EIO);
            return -1;
        }
        done += (uint64_t)put;
    }
    return (int64_t)done;
}

static exr_context_initializer_t stream_initializer(exr_stream *s) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = s;
    init.read_fn = stream_read;
    init.size_fn = stream_size;
    init.write_fn = stream_write;
    /* A damaged offset table is an error, not something to guess around by scanning chunks. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    return init;
}

/* ---- chunks on several threads (reading and writing) ---- */

/* A worker of a pass over chunks: the stream that the library's messages of its calls go to
 * (on_exr_error finds it through current_stream; its `io` is the file's stream, whose io_errno
 * counts) and its first failing chunk. The pass's job keeps the worker's pipeline and why it
 * failed. */
typedef struct exr_worker {
    exr_stream msg;
    uint32_t failed_chunk; /* UINT32_MAX while none failed */
} exr_worker;

/* Does chunk `chunk` on worker `worker` of `job`; 0 when it failed. */
typedef int (*exr_chunk_fn)(void *job, uint32_t worker, uint32_t chunk);

typedef struct exr_chunk_pass {
    exr_chunk_fn fn;
    void *job;
    exr_worker *workers;
} exr_chunk_pass;

static void chunk_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const exr_chunk_pass *p = vctx;
    exr_worker *w = &p->workers[worker];
    exr_stream *const caller = current_stream; /* the caller's thread runs a range too */
    current_stream = &w->msg;
    for (uint32_t i = begin; i < end && w->failed_chunk == UINT32_MAX; ++i) {
        w->msg.lib_msg[0] = '\0';
        if (!p->fn(p->job, worker, i)) w->failed_chunk = i;
    }
    current_stream = caller;
}

/* Runs fn over chunks [0, count), each weighing `weight` pixels, on the `count_workers` workers
 * w (messages named after stream s), each until its first failure. Returns the worker whose
 * failing chunk is the lowest, -1 when none failed: a worker takes its blocks in increasing
 * order and skips only chunks after its failure, so that is the chunk a serial pass stops at. */
static int32_t run_chunks(exr_worker *w, uint32_t count_workers, const exr_stream *s,
                          uint32_t count, uint32_t weight, exr_chunk_fn fn, void *job) {
    for (uint32_t i = 0; i < count_workers; ++i) {
        w[i].msg.name = s->name;
        w[i].msg.fd = s->fd;
        w[i].msg.size = s->size;
        w[i].msg.chunks_checked = s->chunks_checked;
        w[i].msg.compression = s->compression;
        w[i].msg.io = s;
        w[i].failed_chunk = UINT32_MAX;
    }
    exr_chunk_pass p = {fn, job, w};
    pgt_parallel_for_items(count, weight, count_workers, chunk_range, &p);
    int32_t failed = -1;
    for (uint32_t i = 0; i < count_workers; ++i)
        if (w[i].failed_chunk != UINT32_MAX &&
            (failed < 0 || w[i].failed_chunk < w[failed].failed_chunk))
            failed = (int32_t)i;
    return failed;
}

/* ---- reading ---- */

/* Maps a failed library call while reading. A short read (the library asked for bytes past the
 * end of the file) is truncation, unless check_chunks has seen every chunk inside the file: then
 * the library read past a chunk because the chunk lies about its size, a parse error. A failed
 * read of our own descriptor is I/O; everything the library rejects as malformed is a parse
 * error. */
static pgt_result read_fail(exr_stream *s, exr_result_t rv, const char *what, pgt_error *err) {
    if (stream_errno(s))
        return pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", s->name,
                             strerror(stream_errno(s)));
    pgt_result code = PGT_ERROR_PARSE;
    if (rv == EXR_ERR_OUT_OF_MEMORY)
        code = PGT_ERROR_OUT_OF_MEMORY;
    else if (rv == EXR_ERR_READ_IO && !s->chunks_checked)
        code = PGT_ERROR_TRUNCATED;
    else if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED)
        code = PGT_ERROR_UNSUPPORTED;
    const char *msg = s->lib_msg[0] ? s->lib_msg : exr_get_default_error_message(rv);
    if (code == PGT_ERROR_UNSUPPORTED && s->compression)
        return pgt_error_set(err, code,
                             "%s: %s: this OpenEXR C library cannot decode %s "
                             "compression (%s)",
                             s->name, what, s->compression, msg);
    return pgt_error_set(err, code, "%s: %s: %s (OpenEXR %s)", s->name, what, msg,
                         exr_get_error_code_as_string(rv));
}

static const char *compression_name(exr_compression_t c) {
    static const char *const names[] = {"no",    "RLE", "ZIPS", "ZIP",  "PIZ",
                                        "PXR24", "B44", "B44A", "DWAA", "DWAB"};
    return (unsigned)c < sizeof(names) / sizeof(names[0]) ? names[c] : "unknown";
}

#define READ_CALL(call, what)                                                                      \
    do {                                                                                           \
        s->lib_msg[0] = '\0';                                                                      \
        exr_result_t rv_ = (call);                                                                 \
        if (rv_ != EXR_ERR_SUCCESS) return read_fail(s, rv_, what, err);                           \
    } while (0)

/* Values in one tile (clipped to the image) at most: the decode's buffers stay under 512 MB
 * beside the image, while a whole 4096^2 RGBA image in one tile (2^26 values) still reads. */
#define EXR_MAX_TILE_VALUES (1u << 26)

typedef struct exr_layout {
    int32_t min_x, min_y; /* data window origin */
    uint32_t width, height, channels;
    int tiled;
    uint32_t tile_w, tile_h;
    int32_t scanlines_per_chunk;
    uint32_t chunk_pixels; /* a chunk's pixels at most: a tile or a block of rows, clipped to the
                            * image (a file may declare them far larger) */
    int32_t chunks;
    exr_compression_t compression;
} exr_layout;

/* ---- telling a short file from a malformed one ----
 *
 * OpenEXRCore reports a header that ends early as a bad header, and a chunk past the end of the
 * file as a corrupt chunk leader. pgt calls both "truncated", so before the library sees the
 * file we walk its structure ourselves, as the file layout defines it: after the magic number
 * and the version field, each header is a list of attributes (name NUL, type NUL, int32 size,
 * value) ended by an empty name; a multi-part file ends its list of headers with an empty header.
 * Then comes one offset table of uint64 per chunk, and each chunk starts with a leader (scanline:
 * int32 y, int32 size; tile: 4 int32 coordinates, int32 size). Anything that is not short but
 * odd is left for the library to judge. */

/* Little-endian integers, byte by byte (independent of the host). */
static uint64_t le_u64(const unsigned char *p) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}
static int32_t le_i32(const unsigned char *p) {
    uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    return (int32_t)v; /* two's complement on every host pgt builds on */
}

typedef struct scan_cursor {
    exr_stream *s;
    uint64_t pos;
    unsigned char buf[4096];
    uint64_t buf_start;
    size_t buf_len;
} scan_cursor;

/* 1: a byte, 0: the end of the file, -1: a read error. */
static int scan_byte(scan_cursor *c, unsigned char *out) {
    if (c->pos < c->buf_start || c->pos >= c->buf_start + c->buf_len) {
        int64_t got = stream_read(NULL, c->s, c->buf, sizeof(c->buf), c->pos, NULL);
        if (got < 0) return -1;
        c->buf_start = c->pos;
        c->buf_len = (size_t)got;
        if (got == 0) return 0;
    }
    *out = c->buf[c->pos++ - c->buf_start];
    return 1;
}

/* A NUL-terminated name of at most 255 characters, copied to out (256 bytes) when out is not
 * NULL. 1: read (*len its length), 0: the file ended, -1: a read error, -2: malformed (too
 * long). */
static int scan_name(scan_cursor *c, size_t *len, char *out) {
    for (size_t n = 0; n < 256; ++n) {
        unsigned char b = 0;
        int got = scan_byte(c, &b);
        if (got <= 0) return got;
        if (out) out[n] = (char)b;
        if (b == 0) {
            *len = n;
            return 1;
        }
    }
    return -2;
}

/* The first name that a channel list (a chlist value of size bytes at c->pos: entries of a name
 * and 16 bytes, ended by an empty name) holds twice, into dup (256 bytes); 1 when there is one,
 * else 0 (also when the list is malformed: the library says how). *count gets the number of
 * entries; names are compared among the first PGT_IMAGE_MAX_CHANNELS only (a longer list is
 * refused whatever its names). OpenEXRCore drops a list with a repeated name and reports
 * "'channels' attribute not found". */
static int scan_duplicate_channel(scan_cursor *c, int32_t size, char *dup, uint32_t *count) {
    enum { MAX_NAMES = PGT_IMAGE_MAX_CHANNELS };
    *count = 0;
    char(*names)[256] = malloc(MAX_NAMES * sizeof *names), other[256];
    if (!names) return 0;
    const uint64_t end = c->pos + (uint64_t)size;
    int found = 0;
    for (uint32_t n = 0; c->pos < end; ++n) {
        size_t len = 0;
        char *name = n < MAX_NAMES ? names[n] : other;
        if (scan_name(c, &len, name) != 1 || len == 0 || c->pos + 16u > end) break;
        ++*count;
        for (uint32_t k = 0; n < MAX_NAMES && k < n && !found; ++k)
            if (!strcmp(names[k], name)) found = 1, memcpy(dup, name, len + 1);
        c->pos += 16u; /* pixel type, pLinear, reserved, x and y sampling */
    }
    free(names);
    return found;
}

/* Sets *header_end to the offset just past the headers, or 0 when they look malformed (the
 * library then says how), and *multipart to the version field's multipart flag (its chunks
 * start with a part number). Returns PGT_ERROR_TRUNCATED when the file ends inside them. */
static pgt_result scan_headers(exr_stream *s, uint64_t *header_end, int *multipart_out,
                               pgt_error *err) {
    *header_end = 0;
    *multipart_out = 0;
    scan_cursor c;
    memset(&c, 0, sizeof(c));
    c.s = s;
    unsigned char version[8];
    if (stream_read(NULL, s, version, 8, 0, NULL) != 8)
        return stream_errno(s) ? PGT_OK
                               : pgt_error_set(err, PGT_ERROR_TRUNCATED,
                                               "%s: the file ends in its version field", s->name);
    const int multipart = (version[5] & 0x10) != 0; /* version flag bit 12 */
    *multipart_out = multipart;
    c.pos = 8;
    for (int part = 0, attr = 0;;) {
        size_t len = 0;
        char attr_name[256], type_name[256];
        int got = scan_name(&c, &len, attr_name); /* an attribute's name, or a header's end */
        if (got == 1 && len == 0) {
            if (!multipart || attr == 0) {
                *header_end = c.pos;
                return PGT_OK;
            }
            part++; /* the next part's header */
            attr = 0;
            continue;
        }
        if (got == 1) got = scan_name(&c, &len, type_name); /* its type */
        unsigned char size[4];
        for (int i = 0; i < 4 && got == 1; ++i) got = scan_byte(&c, &size[i]);
        if (got == 1 && le_i32(size) < 0) got = -2;
        const uint64_t next = c.pos + (uint64_t)(got == 1 ? le_i32(size) : 0);
        if (got == 1 && next > s->size) got = 0; /* its value */
        if (got == 1 && !strcmp(attr_name, "channels") && !strcmp(type_name, "chlist")) {
            char dup[256];
            uint32_t count = 0;
            const int found = scan_duplicate_channel(&c, le_i32(size), dup, &count);
            if (count > PGT_IMAGE_MAX_CHANNELS) /* as read_layout says it, before the library */
                return pgt_error_set(err, PGT_ERROR_LIMIT, "%s: %u channels exceed the limit of %u",
                                     s->name, count, PGT_IMAGE_MAX_CHANNELS);
            if (found)
                return pgt_error_set(err, PGT_ERROR_PARSE, "%s: two channels named '%s'", s->name,
                                     dup);
        }
        c.pos = next;
        if (got == 0)
            return pgt_error_set(err, PGT_ERROR_TRUNCATED,
                                 "%s: the file ends in its header (part %d, attribute %d)", s->name,
                                 part, attr);
        if (got < 0) return PGT_OK; /* a read error or an odd header: the library says which */
        attr++;
    }
}

/* The offset table and every chunk leader lie inside the file (a leader: the part number in a
 * multipart file, then y or the tile's four numbers, then the packed size). */
static pgt_result check_chunks(exr_stream *s, uint64_t header_end, int32_t chunks, int tiled,
                               int multipart, pgt_error *err) {
    const uint64_t table_end = header_end + (uint64_t)chunks * 8u;
    if (table_end > s->size)
        return pgt_error_set(err, PGT_ERROR_TRUNCATED,
                             "%s: the file ends in its offset table (%d chunks need bytes "
                             "%llu-%llu, the file holds %llu)",
                             s->name, chunks, (unsigned long long)header_end,
                             (unsigned long long)table_end, (unsigned long long)s->size);
    const uint64_t leader = (tiled ? 20u : 8u) + (multipart ? 4u : 0u);
    unsigned char entry[8], lead[24];
    uint64_t packed_sum = 0;
    int all = 1;
    for (int32_t i = 0; i < chunks; ++i) {
        if (stream_read(NULL, s, entry, 8, header_end + 8u * (uint64_t)i, NULL) != 8)
            return PGT_OK; /* a read error: the library will meet it too */
        uint64_t at = le_u64(entry);
        if (at < table_end) { /* not a place a chunk can start: the library's to judge */
            all = 0;
            continue;
        }
        if (at > s->size || s->size - at < leader)
            return pgt_error_set(err, PGT_ERROR_TRUNCATED,
                                 "%s: chunk %d starts at byte %llu but the file ends before its "
                                 "leader (%llu bytes)",
                                 s->name, i, (unsigned long long)at, (unsigned long long)s->size);
        if (stream_read(NULL, s, lead, (uint64_t)leader, at, NULL) != (int64_t)leader)
            return PGT_OK;
        int32_t packed = le_i32(lead + leader - 4);
        if (packed >= 0)
            packed_sum += (uint64_t)packed;
        else
            all = 0;
        if (packed >= 0 && (uint64_t)packed > s->size - at - leader)
            return pgt_error_set(err, PGT_ERROR_TRUNCATED,
                                 "%s: chunk %d needs bytes %llu-%llu but the file holds %llu",
                                 s->name, i, (unsigned long long)at,
                                 (unsigned long long)(at + leader + (uint64_t)packed),
                                 (unsigned long long)s->size);
    }
    s->chunks_checked = 1;
    /* an offset or size the library will refuse still leaves the pixels no more than the rest
     * of the file (a 0 here once skipped the bound below: 512 chunks of packed size 0 had a 1 GiB
     * image allocated before the library refused them) */
    s->packed_is_sum = all;
    s->packed_bytes = all ? packed_sum : s->size - table_end;
    return PGT_OK;
}

/* B44 and B44A pack a 4x4 block of HALF values (32 bytes) into 14 bytes, or 3 when the block
 * is flat (B44A), and store FLOAT and UINT channels as they are: at most 32/3, rounded up. */
#define EXR_B44_MAX_RATIO 11u
/* PIZ's last stage is OpenEXR's 16-bit Huffman code: a code is at least 1 bit, and its run code
 * (at least 1 bit, then an 8-bit count) repeats the previous value up to 255 times, so 9 bits
 * give at most 255 values of 16 bits (453.3:1; its encoder sends a value, the run code and the
 * count, 10 bits for 256 values: 409.6:1 on a constant image). The wavelet and the value table
 * before it keep the size. */
#define EXR_PIZ_MAX_RATIO 454u

/* The most a chunk's bytes expand under a compression, 0 when no simple bound holds (DWA's
 * lossy coding: run lengths inside deflate): NONE stores the pixels, RLE codes a run of up to
 * 128 bytes in 2, ZIP and ZIPS are deflate (at most 1032:1), PXR24 deflates 3 of a float's 4
 * bytes, B44 and PIZ as above. */
static uint64_t max_expansion(exr_compression_t c) {
    switch (c) {
    case EXR_COMPRESSION_NONE:
        return 1u;
    case EXR_COMPRESSION_RLE:
        return 64u;
    case EXR_COMPRESSION_ZIPS:
    case EXR_COMPRESSION_ZIP:
        return PGT_IMAGE_DEFLATE_MAX_RATIO;
    case EXR_COMPRESSION_PXR24:
        return PGT_IMAGE_DEFLATE_MAX_RATIO * 4u / 3u;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A:
        return EXR_B44_MAX_RATIO;
    case EXR_COMPRESSION_PIZ:
        return EXR_PIZ_MAX_RATIO;
    default:
        return 0u;
    }
}

/* Everything checked before the pixels are allocated. */
static pgt_result read_layout(exr_context_t ctxt, exr_stream *s, exr_layout *lay,
                              const exr_attr_chlist_t **out_ch, pgt_error *err) {
    const char *name = s->name;
    int parts = 0;
    READ_CALL(exr_get_count(ctxt, &parts), "header");
    if (parts != 1)
        return pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                             "%s: a multi-part file of %d parts (pgt reads single-part files)",
                             name, parts);
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    READ_CALL(exr_get_storage(ctxt, 0, &storage), "header");
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        return pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                             "%s: deep data (pgt reads flat scanline and tiled images)", name);
    lay->tiled = storage == EXR_STORAGE_TILED;

    exr_attr_box2i_t dw;
    READ_CALL(exr_get_data_window(ctxt, 0, &dw), "header");
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    if (w < 1 || h < 1)
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s: empty or inverted data window (%d, %d)-(%d, %d)", name, dw.min.x,
                             dw.min.y, dw.max.x, dw.max.y);
    if (w > PGT_IMAGE_MAX_SIDE || h > PGT_IMAGE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: data window of %lld x %lld pixels exceeds the limit of %u per "
                             "side",
                             name, (long long)w, (long long)h, PGT_IMAGE_MAX_SIDE);
    lay->min_x = dw.min.x;
    lay->min_y = dw.min.y;
    lay->width = (uint32_t)w;
    lay->height = (uint32_t)h;

    const exr_attr_chlist_t *ch = NULL;
    READ_CALL(exr_get_channels(ctxt, 0, &ch), "header");
    if (!ch || ch->num_channels < 1)
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s: no channels", name);
    if ((uint32_t)ch->num_channels > PGT_IMAGE_MAX_CHANNELS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "%s: %d channels exceed the limit of %u", name,
                             ch->num_channels, PGT_IMAGE_MAX_CHANNELS);
    lay->channels = (uint32_t)ch->num_channels;
    for (int c = 0; c < ch->num_channels; ++c) {
        const exr_attr_chlist_entry_t *e = &ch->entries[c];
        const char *cn = e->name.str ? e->name.str : "";
        if (e->name.length < 1 || !e->name.str)
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s: channel %d has no name", name, c);
        if ((uint32_t)e->name.length >= PGT_IMAGE_NAME_SIZE)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "%s: channel name '%.40s' is %d characters long (pgt keeps up to "
                                 "%u)",
                                 name, cn, (int)e->name.length, PGT_IMAGE_NAME_SIZE - 1);
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return pgt_error_set(
                err, PGT_ERROR_UNSUPPORTED,
                "%s: channel '%s' is subsampled %d x %d (pgt reads full-resolution "
                "channels only)",
                name, cn, (int)e->x_sampling, (int)e->y_sampling);
        if (e->pixel_type != EXR_PIXEL_UINT && e->pixel_type != EXR_PIXEL_HALF &&
            e->pixel_type != EXR_PIXEL_FLOAT)
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s: channel '%s' has pixel type %d", name,
                                 cn, (int)e->pixel_type);
        for (int d = 0; d < c; ++d)
            if (strcmp(ch->entries[d].name.str, cn) == 0)
                return pgt_error_set(err, PGT_ERROR_PARSE, "%s: two channels named '%s'", name, cn);
    }
    if ((uint64_t)lay->width * lay->height * lay->channels > PGT_IMAGE_MAX_VALUES)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s: %u x %u pixels x %u channels exceed the limit of %u values", name,
                             lay->width, lay->height, lay->channels, PGT_IMAGE_MAX_VALUES);

    /* OpenEXR 3.1 takes any compression byte, and a chunk stored raw never meets it. */
    READ_CALL(exr_get_compression(ctxt, 0, &lay->compression), "header");
    if (lay->compression < EXR_COMPRESSION_NONE || lay->compression >= EXR_COMPRESSION_LAST_TYPE)
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s: unknown compression %d", name,
                             (int)lay->compression);
    s->compression = compression_name(lay->compression);
    int32_t chunks = 0;
    READ_CALL(exr_get_chunk_count(ctxt, 0, &chunks), "header");
    if (chunks < 1) return pgt_error_set(err, PGT_ERROR_PARSE, "%s: no chunks", name);
    lay->chunks = chunks;
    if (lay->tiled) {
        uint32_t tw = 0, th = 0;
        exr_tile_level_mode_t level = EXR_TILE_LAST_TYPE;
        exr_tile_round_mode_t round = EXR_TILE_ROUND_LAST_TYPE;
        READ_CALL(exr_get_tile_descriptor(ctxt, 0, &tw, &th, &level, &round), "header");
        if (tw < 1 || th < 1)
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s: tiles of %u x %u pixels", name, tw, th);
        lay->tile_w = tw;
        lay->tile_h = th;
        /* the library decodes a tile through buffers of its (clipped) size, twice over: one
         * tile of a whole 2^28-value image took 3 GB */
        const uint64_t tile_pixels =
            (uint64_t)(tw < lay->width ? tw : lay->width) * (th < lay->height ? th : lay->height);
        if (tile_pixels * lay->channels > EXR_MAX_TILE_VALUES)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "%s: tiles of %u x %u pixels x %u channels exceed the limit of "
                                 "%u values a tile",
                                 name, tw, th, lay->channels, EXR_MAX_TILE_VALUES);
        lay->chunk_pixels = (uint32_t)tile_pixels;
        int32_t lw = 0, lh = 0;
        READ_CALL(exr_get_level_sizes(ctxt, 0, 0, 0, &lw, &lh), "header");
        if ((int64_t)lw != w || (int64_t)lh != h)
            return pgt_error_set(err, PGT_ERROR_PARSE,
                                 "%s: level 0 is %d x %d but the data window %lld x %lld", name, lw,
                                 lh, (long long)w, (long long)h);
    } else {
        READ_CALL(exr_get_scanlines_per_chunk(ctxt, 0, &lay->scanlines_per_chunk), "header");
        if (lay->scanlines_per_chunk < 1)
            return pgt_error_set(err, PGT_ERROR_PARSE, "%s: %d scanlines per chunk", name,
                                 lay->scanlines_per_chunk);
        const uint32_t rows = (uint32_t)lay->scanlines_per_chunk;
        lay->chunk_pixels = (rows < lay->height ? rows : lay->height) * lay->width;
    }
    *out_ch = ch;
    return PGT_OK;
}

/* Decodes one chunk into columns [x0, x0 + width) and rows [y0, y0 + height) of every plane. */
static pgt_result decode_chunk(exr_context_t ctxt, exr_stream *s, const exr_layout *lay,
                               const exr_chunk_info_t *ci, uint32_t x0, uint32_t y0, pgt_image *img,
                               exr_decode_pipeline_t *dec, int *dec_live, pgt_error *err) {
    const char *name = s->name;
    if (ci->width < 1 || ci->height < 1 || (uint64_t)x0 + (uint64_t)ci->width > img->width ||
        (uint64_t)y0 + (uint64_t)ci->height > img->height)
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s: chunk %d of %d x %d pixels at (%u, %u) lies outside the %u x "
                             "%u data window",
                             name, ci->idx, ci->width, ci->height, x0, y0, img->width, img->height);
    if (ci->data_offset > s->size || ci->packed_size > s->size - ci->data_offset)
        return pgt_error_set(
            err, PGT_ERROR_TRUNCATED,
            "%s: chunk %d (rows %u-%u) needs bytes %llu-%llu but the file holds "
            "%llu bytes",
            name, ci->idx, y0, y0 + (uint32_t)ci->height - 1, (unsigned long long)ci->data_offset,
            (unsigned long long)(ci->data_offset + ci->packed_size), (unsigned long long)s->size);
    /* An uncompressed chunk holds exactly its pixels (OpenEXR 3.1 would read past a short one
     * into the next chunk). */
    if (lay->compression == EXR_COMPRESSION_NONE && ci->packed_size != ci->unpacked_size)
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s: uncompressed chunk %d holds %llu bytes, not the %llu its "
                             "pixels need",
                             name, ci->idx, (unsigned long long)ci->packed_size,
                             (unsigned long long)ci->unpacked_size);
    /* failures name the chunk and its pixels */
    char what[96];
    snprintf(what, sizeof(what), "pixel data of chunk %d (%d x %d pixels at %u, %u)", ci->idx,
             ci->width, ci->height, x0, y0);
    if (*dec_live) {
        READ_CALL(exr_decoding_update(ctxt, 0, ci, dec), what);
    } else {
        *dec_live = 1; /* exr_decoding_destroy also frees what a failed initialize left */
        READ_CALL(exr_decoding_initialize(ctxt, 0, ci, dec), what);
    }
    if ((uint32_t)dec->channel_count != img->channel_count)
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s: chunk %d decodes %d channels, not %u", name,
                             ci->idx, dec->channel_count, img->channel_count);
    for (int c = 0; c < dec->channel_count; ++c) {
        exr_coding_channel_info_t *cc = &dec->channels[c];
        if (cc->width != ci->width || cc->height != ci->height)
            return pgt_error_set(err, PGT_ERROR_PARSE,
                                 "%s: chunk %d: channel %d is %d x %d, not %d x %d", name, ci->idx,
                                 c, cc->width, cc->height, ci->width, ci->height);
        /* The library converts HALF and UINT to FLOAT while it unpacks. */
        cc->decode_to_ptr =
            (uint8_t *)(pgt_image_plane(img, (uint32_t)c) + (size_t)y0 * img->width + x0);
        cc->user_pixel_stride = (int32_t)sizeof(float);
        cc->user_line_stride = (int32_t)(sizeof(float) * img->width);
        cc->user_data_type = EXR_PIXEL_FLOAT;
        cc->user_bytes_per_element = (int16_t)sizeof(float);
    }
    /* Chosen again for every chunk: the pointers moved, and the choice is cheap. */
    READ_CALL(exr_decoding_choose_default_routines(ctxt, 0, dec), what);
    s->lib_msg[0] = '\0';
    const exr_result_t rv = exr_decoding_run(ctxt, 0, dec);
    /* OpenEXRCore 3.1's B44 decoder says "out of memory" for a chunk shorter than its data
     * needs; the buffers of a decode are bounded by the image's size, checked above: a
     * corrupt chunk */
    if (rv == EXR_ERR_OUT_OF_MEMORY && !stream_errno(s))
        return pgt_error_set(err, PGT_ERROR_PARSE, "%s: %s: %s (OpenEXR %s: a corrupt chunk)",
                             s->name, what,
                             s->lib_msg[0] ? s->lib_msg : exr_get_default_error_message(rv),
                             exr_get_error_code_as_string(rv));
    if (rv != EXR_ERR_SUCCESS) return read_fail(s, rv, what, err);
    return PGT_OK;
}

/* A chunk to decode: its library record and where its pixels go. */
typedef struct exr_chunk_in {
    exr_chunk_info_t ci;
    uint32_t x0, y0;
} exr_chunk_in;

/* A worker's decode pipeline (one per thread on the shared context) and its failure. */
typedef struct exr_decoder {
    exr_decode_pipeline_t dec;
    int live;
    pgt_error err;
} exr_decoder;

typedef struct exr_decode_job {
    exr_context_t ctxt;
    const exr_layout *lay;
    const exr_chunk_in *chunks;
    pgt_image *img;
    exr_worker *workers;
    exr_decoder *dec; /* per worker */
} exr_decode_job;

static int decode_one(void *vjob, uint32_t worker, uint32_t i) {
    const exr_decode_job *j = vjob;
    exr_decoder *d = &j->dec[worker];
    const exr_chunk_in *c = &j->chunks[i];
    return decode_chunk(j->ctxt, &j->workers[worker].msg, j->lay, &c->ci, c->x0, c->y0, j->img,
                        &d->dec, &d->live, &d->err) == PGT_OK;
}

/* The chunks' records in file order (serially: the library's lookups of the offset table),
 * then their pixels decoded on up to `threads` threads, each chunk on its own. Errors are those
 * of a serial read: the first failing chunk's, a record's or its decoding's. */
static pgt_result read_pixels(exr_context_t ctxt, exr_stream *s, const exr_layout *lay,
                              pgt_image *img, uint32_t threads, pgt_error *err) {
    pgt_result r = PGT_OK;
    const uint32_t tiles_x = lay->tiled ? (lay->width - 1) / lay->tile_w + 1 : 1;
    const uint32_t tiles_y = lay->tiled ? (lay->height - 1) / lay->tile_h + 1 : 0;
    const uint32_t count =
        lay->tiled ? tiles_x * tiles_y
                   : (uint32_t)((lay->height + (uint32_t)lay->scanlines_per_chunk - 1u) /
                                (uint32_t)lay->scanlines_per_chunk);
    const uint32_t workers = pgt_parallel_workers(threads);
    exr_chunk_in *chunks = calloc(count ? count : 1u, sizeof(exr_chunk_in));
    exr_worker *w = calloc(workers, sizeof(exr_worker));
    exr_decoder *dec = calloc(workers, sizeof(exr_decoder));
    if (!chunks || !w || !dec) {
        free(chunks);
        free(w);
        free(dec);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (pixel data)",
                             s->name);
    }
    /* the records; n: how many are good, r: the failure of record n when n < count */
    pgt_error rec_err = {0};
    uint32_t n = 0;
    for (; n < count; ++n) {
        exr_chunk_in *c = &chunks[n];
        s->lib_msg[0] = '\0';
        exr_result_t rv;
        if (lay->tiled) {
            const uint32_t tx = n % tiles_x, ty = n / tiles_x;
            rv = exr_read_tile_chunk_info(ctxt, 0, (int)tx, (int)ty, 0, 0, &c->ci);
            if (rv != EXR_ERR_SUCCESS) {
                r = read_fail(s, rv, "chunk", &rec_err);
                break;
            }
            if (c->ci.width > (int32_t)lay->tile_w || c->ci.height > (int32_t)lay->tile_h) {
                r = pgt_error_set(&rec_err, PGT_ERROR_PARSE,
                                  "%s: tile (%u, %u) is %d x %d, larger than %u x %u", s->name, tx,
                                  ty, c->ci.width, c->ci.height, lay->tile_w, lay->tile_h);
                break;
            }
            c->x0 = tx * lay->tile_w, c->y0 = ty * lay->tile_h;
        } else {
            const int64_t y = (int64_t)lay->min_y + (int64_t)n * lay->scanlines_per_chunk;
            rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &c->ci);
            if (rv != EXR_ERR_SUCCESS) {
                r = read_fail(s, rv, "chunk", &rec_err);
                break;
            }
            if ((int64_t)c->ci.start_y != y || c->ci.width != (int32_t)lay->width) {
                r = pgt_error_set(&rec_err, PGT_ERROR_PARSE,
                                  "%s: the chunk for row %lld starts at row %d and is %d wide",
                                  s->name, (long long)y, c->ci.start_y, c->ci.width);
                break;
            }
            c->x0 = 0, c->y0 = (uint32_t)(y - lay->min_y);
        }
    }
    exr_decode_job job = {ctxt, lay, chunks, img, w, dec};
    /* a chunk weighs its pixels */
    const int32_t failed = run_chunks(w, workers, s, n, lay->chunk_pixels, decode_one, &job);
    if (failed >= 0)
        r = pgt_error_set(err, dec[failed].err.code, "%s", dec[failed].err.message);
    else if (r != PGT_OK)
        r = pgt_error_set(err, rec_err.code, "%s", rec_err.message);
    for (uint32_t i = 0; i < workers; ++i)
        if (dec[i].live) exr_decoding_destroy(ctxt, &dec[i].dec);
    free(chunks);
    free(w);
    free(dec);
    return r;
}

static pgt_result read_stream(pgt_image *out, exr_stream *s, uint32_t threads, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (s->size == 0) return pgt_error_set(err, PGT_ERROR_EMPTY, "%s: empty file", s->name);
    unsigned char head[4];
    size_t n = s->size < 4 ? (size_t)s->size : 4;
    if (stream_read(NULL, s, head, n, 0, NULL) != (int64_t)n)
        return pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", s->name,
                             strerror(stream_errno(s) ? stream_errno(s) : EIO));
    if (memcmp(head, exr_magic, n) != 0)
        return pgt_error_set(err, PGT_ERROR_PARSE,
                             "%s: not an OpenEXR file (it does not start with 76 2f 31 01)",
                             s->name);
    if (n < 4)
        return pgt_error_set(err, PGT_ERROR_TRUNCATED, "%s: the file ends in its magic number",
                             s->name);

    exr_context_initializer_t init = stream_initializer(s);
    exr_context_t ctxt = NULL;
    exr_layout lay;
    memset(&lay, 0, sizeof(lay));
    const exr_attr_chlist_t *ch = NULL;
    uint64_t header_end = 0;
    int multipart = 0;
    pgt_result r = scan_headers(s, &header_end, &multipart, err);
    if (r != PGT_OK) return r;
    current_stream = s;
    s->lib_msg[0] = '\0';
    exr_result_t rv = exr_start_read(&ctxt, s->name, &init);
    if (rv != EXR_ERR_SUCCESS) r = read_fail(s, rv, "header", err);
    /* Without EXR_CONTEXT_FLAG_STRICT_HEADER the library reports some bad attributes (an unknown
     * compression byte, ...) and carries on with a default; pgt does not guess. */
    if (r == PGT_OK && s->lib_msg[0])
        r = pgt_error_set(err, PGT_ERROR_PARSE, "%s: header: %s", s->name, s->lib_msg);
    if (r == PGT_OK) r = read_layout(ctxt, s, &lay, &ch, err);
    if (r == PGT_OK && header_end > 0)
        r = check_chunks(s, header_end, lay.chunks, lay.tiled, multipart, err);
    /* pixels the chunks cannot hold are refused before they are allocated (a 17 KB ZIP file
     * declaring 16384^2 floats reserved 1 GiB) */
    if (r == PGT_OK && s->chunks_checked && max_expansion(lay.compression)) {
        uint64_t pixel_bytes = 0;
        for (uint32_t c = 0; c < lay.channels; ++c)
            pixel_bytes += ch->entries[c].pixel_type == EXR_PIXEL_HALF ? 2u : 4u;
        const uint64_t need = pixel_bytes * lay.width * lay.height;
        if (need > max_expansion(lay.compression) * s->packed_bytes + PGT_IMAGE_EXPANSION_SLACK)
            r = pgt_error_set(
                err, PGT_ERROR_TRUNCATED,
                "%s: declares %u x %u pixels of %llu bytes each, more than %llu bytes %s can "
                "hold with %s compression (at most %llu times)",
                s->name, lay.width, lay.height, (unsigned long long)pixel_bytes,
                (unsigned long long)s->packed_bytes,
                s->packed_is_sum ? "of chunks" : "after its offset table", s->compression,
                (unsigned long long)max_expansion(lay.compression));
    }
    if (r == PGT_OK &&
        pgt_image_create(out, lay.width, lay.height, lay.channels, NULL, NULL) != PGT_OK)
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                          "%s: out of memory for %u x %u pixels and %u channels", s->name,
                          lay.width, lay.height, lay.channels);
    if (r == PGT_OK && !(out->half = calloc(lay.channels, 1)))
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", s->name);
    if (r == PGT_OK) {
        for (uint32_t c = 0; c < lay.channels; ++c) {
            memcpy(out->names[c], ch->entries[c].name.str, (size_t)ch->entries[c].name.length + 1);
            out->half[c] = ch->entries[c].pixel_type == EXR_PIXEL_HALF;
        }
        r = read_pixels(ctxt, s, &lay, out, threads, err);
    }
    if (ctxt) exr_finish(&ctxt);
    current_stream = NULL;
    if (r != PGT_OK) pgt_image_destroy(out);
    return r;
}

pgt_result pgt_image_read_exr_memory(pgt_image *out, const void *data, size_t size,
                                     const char *name, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (!name || !name[0]) name = "<memory>";
    if (!data && size > 0)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: NULL data of %zu bytes", name,
                             size);
    exr_stream s;
    memset(&s, 0, sizeof(s));
    s.name = name;
    s.fd = -1;
    s.mem = data;
    s.size = size;
    return read_stream(out, &s, 1u, err);
}

pgt_result pgt_image_read_exr(pgt_image *out, const char *path, pgt_error *err) {
    return pgt_image_read_exr_threads(out, path, 1u, err);
}

pgt_result pgt_image_read_exr_threads(pgt_image *out, const char *path, uint32_t threads,
                                      pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (!path || !path[0])
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "EXR read: no path");
    exr_stream s;
    memset(&s, 0, sizeof(s));
    s.name = path;
    /* O_NONBLOCK: a fifo without a writer would block the open itself, before the check
     * below refuses it (reads of a regular file are not affected) */
    s.fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (s.fd < 0)
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    pgt_result r;
    if (fstat(s.fd, &st) != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot stat: %s", path, strerror(errno));
    else if (S_ISDIR(st.st_mode))
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot read: is a directory", path);
    else if (!S_ISREG(st.st_mode))
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot read: not a regular file", path);
    else {
        s.size = (uint64_t)st.st_size;
        r = read_stream(out, &s, threads, err);
    }
    close(s.fd);
    return r;
}

/* ---- writing ---- */

static pgt_result write_fail(const exr_stream *s, exr_result_t rv, const char *what,
                             pgt_error *err) {
    if (stream_errno(s))
        return pgt_error_set(err, PGT_ERROR_IO, "%s: write error: %s", s->name,
                             strerror(stream_errno(s)));
    const char *msg = s->lib_msg[0] ? s->lib_msg : exr_get_default_error_message(rv);
    return pgt_error_set(err, rv == EXR_ERR_OUT_OF_MEMORY ? PGT_ERROR_OUT_OF_MEMORY : PGT_ERROR_IO,
                         "%s: %s: %s (OpenEXR %s)", s->name, what, msg,
                         exr_get_error_code_as_string(rv));
}

#define WRITE_CALL(call, what)                                                                     \
    do {                                                                                           \
        s->lib_msg[0] = '\0';                                                                      \
        exr_result_t rv_ = (call);                                                                 \
        if (rv_ != EXR_ERR_SUCCESS) return write_fail(s, rv_, what, err);                          \
    } while (0)

/* zlib level of the ZIP chunks we write. Level 1 writes a 1024^2 11-channel atlas several times
 * faster than the library's default and the files stay readable by every EXR reader (the level
 * is not stored: decoding is the same inflate); spot.obj's atlas: 2.0 s -> 0.57 s, 14.7 -> 14.9 MB.
 */
#ifndef PGT_EXR_ZIP_LEVEL
#define PGT_EXR_ZIP_LEVEL 1
#endif

/* A chunk of rows compressed by a worker, kept until it is written in file order. */
typedef struct exr_chunk_out {
    void *data;
    uint64_t size;
} exr_chunk_out;

/* A worker's encode pipeline (OpenEXRCore: one per thread, all on one context) and its
 * failure. */
typedef struct exr_encoder {
    exr_encode_pipeline_t enc;
    int live;
    exr_result_t rv;
} exr_encoder;

typedef struct exr_encode_job {
    exr_context_t ctxt;
    int part;
    int32_t lines; /* rows per chunk */
    const pgt_image *img;
    exr_chunk_out *chunks;
    exr_encoder *enc; /* per worker */
} exr_encode_job;

/* The pipeline's last stage: instead of writing the chunk (the file takes chunks only in
 * order), keep a copy of what would be written. */
static exr_result_t keep_chunk(exr_encode_pipeline_t *enc) {
    exr_chunk_out *out = enc->encoding_user_data;
    out->data = malloc(enc->compressed_bytes ? enc->compressed_bytes : 1u);
    if (!out->data) return EXR_ERR_OUT_OF_MEMORY;
    if (enc->compressed_bytes) memcpy(out->data, enc->compressed_buffer, enc->compressed_bytes);
    out->size = enc->compressed_bytes;
    return EXR_ERR_SUCCESS;
}

/* Nothing to wait for: write_pixels writes the kept chunks in order once all are done. */
static exr_result_t no_wait(exr_encode_pipeline_t *enc) {
    (void)enc;
    return EXR_ERR_SUCCESS;
}

/* Packs and compresses chunk c (rows c * lines on) with worker e's pipeline. */
static exr_result_t encode_chunk(const exr_encode_job *j, exr_encoder *e, uint32_t c) {
    const pgt_image *img = j->img;
    const uint32_t y = c * (uint32_t)j->lines;
    exr_chunk_info_t ci;
    memset(&ci, 0, sizeof(ci));
    exr_result_t rv = exr_write_scanline_chunk_info(j->ctxt, j->part, (int)y, &ci);
    if (rv != EXR_ERR_SUCCESS) return rv;
    if (e->live) {
        rv = exr_encoding_update(j->ctxt, j->part, &ci, &e->enc);
    } else {
        e->live = 1;
        rv = exr_encoding_initialize(j->ctxt, j->part, &ci, &e->enc);
    }
    if (rv != EXR_ERR_SUCCESS) return rv;
    for (int k = 0; k < e->enc.channel_count; ++k) {
        exr_coding_channel_info_t *cc = &e->enc.channels[k];
        /* The library sorts channels by name: match them by name, not position. */
        const int32_t ch = pgt_image_find_channel(img, cc->channel_name);
        if (ch < 0) return EXR_ERR_UNKNOWN;
        cc->encode_from_ptr =
            (const uint8_t *)(pgt_image_plane(img, (uint32_t)ch) + (size_t)y * img->width);
        cc->user_pixel_stride = (int32_t)sizeof(float);
        cc->user_line_stride = (int32_t)(sizeof(float) * img->width);
        cc->user_data_type = EXR_PIXEL_FLOAT;
        cc->user_bytes_per_element = (int16_t)sizeof(float);
    }
    rv = exr_encoding_choose_default_routines(j->ctxt, j->part, &e->enc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    e->enc.yield_until_ready_fn = no_wait;
    e->enc.write_fn = keep_chunk;
    e->enc.encoding_user_data = &j->chunks[c];
    return exr_encoding_run(j->ctxt, j->part, &e->enc);
}

static int encode_one(void *vjob, uint32_t worker, uint32_t c) {
    const exr_encode_job *j = vjob;
    exr_encoder *e = &j->enc[worker];
    e->rv = encode_chunk(j, e, c);
    return e->rv == EXR_ERR_SUCCESS;
}

/* The header, then the chunks: packed and ZIP-compressed on up to `threads` threads (each
 * chunk on its own: the same bytes for any thread count), written in file order. */
static pgt_result write_pixels(exr_context_t ctxt, exr_stream *s, const pgt_image *img,
                               uint32_t threads, pgt_error *err) {
    int part = 0;
    WRITE_CALL(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), "header");
    WRITE_CALL(exr_initialize_required_attr_simple(ctxt, part, (int32_t)img->width,
                                                   (int32_t)img->height, EXR_COMPRESSION_ZIP),
               "header");
    WRITE_CALL(exr_set_zip_compression_level(ctxt, part, PGT_EXR_ZIP_LEVEL), "header");
    for (uint32_t c = 0; c < img->channel_count; ++c)
        WRITE_CALL(exr_add_channel(ctxt, part, img->names[c], EXR_PIXEL_FLOAT,
                                   EXR_PERCEPTUALLY_LINEAR, 1, 1),
                   "channel list");
    WRITE_CALL(exr_write_header(ctxt), "header");
    int32_t lines = 0;
    WRITE_CALL(exr_get_scanlines_per_chunk(ctxt, part, &lines), "header");
    if (lines < 1) return write_fail(s, EXR_ERR_UNKNOWN, "header", err);
    const uint32_t count = (img->height + (uint32_t)lines - 1u) / (uint32_t)lines;
    const uint32_t workers = pgt_parallel_workers(threads);
    exr_worker *w = calloc(workers, sizeof(exr_worker));
    exr_encode_job job = {ctxt,
                          part,
                          lines,
                          img,
                          calloc(count, sizeof(exr_chunk_out)),
                          calloc(workers, sizeof(exr_encoder))};
    pgt_result r = PGT_OK;
    if (!w || !job.chunks || !job.enc) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (pixel data)", s->name);
        goto done;
    }
    /* a chunk weighs its rows' pixels */
    const int32_t failed =
        run_chunks(w, workers, s, count, (uint32_t)lines * img->width, encode_one, &job);
    if (failed >= 0) {
        r = write_fail(&w[failed].msg, job.enc[failed].rv, "pixel data", err);
        goto done;
    }
    for (uint32_t c = 0; c < count && r == PGT_OK; ++c) {
        s->lib_msg[0] = '\0';
        const exr_result_t rv = exr_write_scanline_chunk(ctxt, part, (int)(c * (uint32_t)lines),
                                                         job.chunks[c].data, job.chunks[c].size);
        if (rv != EXR_ERR_SUCCESS) r = write_fail(s, rv, "pixel data", err);
    }
done:
    if (job.enc)
        for (uint32_t i = 0; i < workers; ++i)
            if (job.enc[i].live) exr_encoding_destroy(ctxt, &job.enc[i].enc);
    if (job.chunks)
        for (uint32_t c = 0; c < count; ++c) free(job.chunks[c].data);
    free(job.chunks);
    free(job.enc);
    free(w);
    return r;
}

pgt_result pgt_image_write_exr(const pgt_image *img, const char *path, pgt_error *err) {
    return pgt_image_write_exr_threads(img, path, 1u, err);
}

pgt_result pgt_image_write_exr_threads(const pgt_image *img, const char *path, uint32_t threads,
                                       pgt_error *err) {
    if (!img || !path || !path[0])
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "EXR write: NULL %s",
                             img ? "path" : "image");
    if (!img->data || !img->names)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: image has NULL arrays", path);
    pgt_result r = pgt_image_check_size(img->width, img->height, img->channel_count, path, err);
    if (r != PGT_OK) return r;
    const char *names[PGT_IMAGE_MAX_CHANNELS];
    for (uint32_t c = 0; c < img->channel_count; ++c) names[c] = img->names[c];
    r = pgt_image_check_names(names, img->channel_count, path, err);
    if (r != PGT_OK) return r;

    /* PATH.tmp.PID in the same folder, so rename() replaces the target atomically. */
    size_t tmp_size = strlen(path) + 32;
    char *tmp = malloc(tmp_size);
    if (!tmp) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    pgt_tmp_name(tmp, tmp_size, path);
    exr_stream s;
    memset(&s, 0, sizeof(s));
    s.name = path;
    s.fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (s.fd < 0) {
        int e = errno;
        free(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot create a temporary file beside it: %s",
                             path, strerror(e));
    }

    exr_context_initializer_t init = stream_initializer(&s);
    exr_context_t ctxt = NULL;
    current_stream = &s;
    s.lib_msg[0] = '\0';
    exr_result_t rv = exr_start_write(&ctxt, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) r = write_fail(&s, rv, "start", err);
    if (r == PGT_OK) r = write_pixels(ctxt, &s, img, threads, err);
    if (ctxt) {
        /* exr_finish writes the offset table. */
        s.lib_msg[0] = '\0';
        rv = exr_finish(&ctxt);
        if (rv != EXR_ERR_SUCCESS && r == PGT_OK) r = write_fail(&s, rv, "offset table", err);
    }
    current_stream = NULL;
    if (close(s.fd) != 0 && r == PGT_OK)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: write error: %s", path, strerror(errno));
    if (r == PGT_OK && pgt_replace_file(tmp, path) != 0)
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: cannot move the written file into place: %s",
                          path, strerror(errno));
    if (r != PGT_OK) remove(tmp);
    free(tmp);
    return r;
}
