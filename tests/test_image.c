/* pgt tests: float images and their files (ref_cpu/src/image*.c, harness/png_io.c).
 *
 * EXR: bit-exact round trips of several channel sets (negative zero, denormals, FLT_MAX,
 * infinities, NaN payloads, random bit patterns), lookup by name (OpenEXR sorts channels),
 * HALF / UINT / tiled / offset-window / decreasing-y files written here through the OpenEXR C
 * API in every lossless compression, every truncation of valid files, random mutations (run
 * under ASan+UBSan), and the malformed corpus (tests/data/malformed_images, listed with expected
 * codes in its MANIFEST). PNG: round trips of 1-4 channels; 16-bit, palette, low-bit-depth,
 * tRNS and interlaced files written here with libpng; every truncation; mutations with their
 * CRCs repaired so they reach the decoder; float images mapped to 8 bits. Atomic writes. */
#include <dirent.h>
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenEXR/openexr.h>
#include <png.h>
#include <zlib.h>

#include <pgt/image.h>

#include "png_io.h"
#include "test_scratch.h"
#include "test_util.h"

/* ---- helpers ---- */

static uint64_t rng_state;
static uint32_t rnd(void) {
    /* splitmix64: the tests need reproducible bytes, not quality */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (uint32_t)((z ^ (z >> 31)) >> 32);
}

static float from_bits(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof(f));
    return f;
}

static int save_file(const char *path, const void *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t put = size ? fwrite(data, 1, size, f) : 0;
    return (fclose(f) == 0 && put == size) ? 0 : -1;
}

static int image_is_zero(const pgt_image *img) {
    static const pgt_image zero;
    return memcmp(img, &zero, sizeof(zero)) == 0;
}

/* Same size, same channel names (in any order) and every plane the same bits. */
static int same_image(const pgt_image *a, const pgt_image *b) {
    if (a->width != b->width || a->height != b->height || a->channel_count != b->channel_count)
        return 0;
    size_t plane = (size_t)a->width * a->height * sizeof(float);
    for (uint32_t c = 0; c < a->channel_count; ++c) {
        int32_t k = pgt_image_find_channel(b, a->names[c]);
        if (k < 0 || memcmp(pgt_image_plane(a, c), pgt_image_plane(b, (uint32_t)k), plane) != 0)
            return 0;
    }
    return 1;
}

static void scratch_make(void) { scratch_make_for("image"); }

/* Reads from memory with garbage in *out first, so that "zeroed on failure" is really tested. */
static pgt_result read_mem(pgt_image *out, const void *data, size_t size, const char *name,
                           pgt_error *err) {
    memset(out, 0xAB, sizeof(*out));
    pgt_error_clear(err);
    return pgt_image_read_exr_memory(out, data, size, name, err);
}

static pgt_result read_png(const char *path, uint32_t *w, uint32_t *h, uint32_t *c, uint8_t **px,
                           pgt_error *err) {
    *w = *h = *c = 77;
    *px = (uint8_t *)err; /* any non-NULL value: the reader must reset it */
    pgt_error_clear(err);
    return pgt_png_read(path, w, h, c, px, err);
}

/* Every float the tests care about, then random bit patterns (every exponent and NaN payload). */
static void fill_values(pgt_image *img) {
    static const uint32_t special[] = {
        0x00000000u, 0x80000000u, 0x3f800000u, 0xbf800000u, /* 0, -0, 1, -1 */
        0x00800000u, 0x80800000u,                           /* FLT_MIN, -FLT_MIN */
        0x00000001u, 0x80000001u, 0x000116c2u, 0x807fffffu, /* denormals */
        0x7f7fffffu, 0xff7fffffu, 0x7149f2cau, 0xff6d8ab4u, /* FLT_MAX, -FLT_MAX, 1e30, -3.16e38 */
        0x7f800000u, 0xff800000u,                           /* +-inf */
        0x7fc12345u, 0xffc00001u, 0x7f800001u, 0x7fbfffffu, /* quiet and signalling NaNs */
    };
    size_t n = (size_t)img->width * img->height * img->channel_count;
    for (size_t i = 0; i < n; ++i)
        img->data[i] = from_bits(i < sizeof(special) / sizeof(special[0]) ? special[i] : rnd());
}

/* ---- EXR through pgt ---- */

static void test_exr_round_trip(void) {
    static const char *const set1[] = {"Y"};
    static const char *const set3[] = {"R", "G", "B"};
    static const char *const set5[] = {"R", "G", "B", "A", "depth"};
    static const char *const set11[] = {"P.x",  "P.y",  "P.z",   "N.x",  "N.y",  "N.z",
                                        "uv.u", "uv.v", "chart", "mask", "depth"};
    static const char *const set_long[] = {"a_channel_name_of_31_characters", "x"};
    char many_names[PGT_IMAGE_MAX_CHANNELS][8];
    const char *set64[PGT_IMAGE_MAX_CHANNELS];
    for (uint32_t c = 0; c < PGT_IMAGE_MAX_CHANNELS; ++c) {
        snprintf(many_names[c], sizeof(many_names[c]), "c%02u", 63 - c);
        set64[c] = many_names[c];
    }
    const struct {
        const char *const *names;
        uint32_t channels, w, h;
    } sets[] = {
        {set1, 1, 1, 1},   {set3, 3, 37, 23},     {set5, 5, 64, 17}, {set11, 11, 129, 40},
        {set64, 64, 5, 3}, {set_long, 2, 300, 1}, {set1, 1, 1, 100},
    };
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 7;
    for (size_t s = 0; s < sizeof(sets) / sizeof(sets[0]); ++s) {
        pgt_image img, back;
        pgt_error err;
        pgt_error_clear(&err);
        REQUIRE(pgt_image_create(&img, sets[s].w, sets[s].h, sets[s].channels, sets[s].names,
                                 &err) == PGT_OK);
        fill_values(&img);
        const char *path = scratch_path("round.exr");
        pgt_result r = pgt_image_write_exr(&img, path, &err);
        CHECK_MSG(r == PGT_OK, "set %zu: %s", s, err.message);
        CHECK(scratch_count() == 1); /* no temporary file left behind */
        r = pgt_image_read_exr(&back, path, &err);
        CHECK_MSG(r == PGT_OK, "set %zu: %s", s, err.message);
        if (r == PGT_OK) {
            CHECK_MSG(same_image(&img, &back), "set %zu: not bit-exact", s);
            /* OpenEXR stores the channels sorted by name. */
            for (uint32_t c = 1; c < back.channel_count; ++c)
                CHECK(strcmp(back.names[c - 1], back.names[c]) < 0);
        }
        pgt_image_destroy(&back);
        pgt_image_destroy(&img);
    }
    scratch_remove();
}

/* The chunks compressed on several threads: the file has the same bytes for any thread count
 * (chunks are compressed independently and written in order) and reads back bit-exact. Sizes:
 * a partial last chunk (100 rows = 6 x 16 + 4), exactly one chunk, fewer rows than threads. */
static void test_exr_threads(void) {
    static const char *const names[] = {"P.x",   "P.y",  "P.z",   "N.x",   "N.y", "N.z",
                                        "chart", "kind", "ptr.u", "ptr.v", "rot"};
    const struct { uint32_t w, h, channels; } sets[] = {{257, 100, 11}, {40, 16, 3}, {3, 2, 1}};
    static const uint32_t threads[] = {2, 3, 8};
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 11;
    for (size_t s = 0; s < sizeof(sets) / sizeof(sets[0]); ++s) {
        pgt_image img, back;
        pgt_error err;
        pgt_error_clear(&err);
        REQUIRE(pgt_image_create(&img, sets[s].w, sets[s].h, sets[s].channels, names, &err) ==
                PGT_OK);
        fill_values(&img);
        /* half the planes smooth, so that ZIP compresses some chunks and stores others raw */
        for (uint32_t c = 0; c < img.channel_count; c += 2)
            for (uint32_t i = 0; i < img.width * img.height; ++i)
                pgt_image_plane(&img, c)[i] = (float)(i % img.width) * 0.25f + (float)c;
        char ref_path[512];
        snprintf(ref_path, sizeof(ref_path), "%s", scratch_path("one.exr"));
        REQUIRE(pgt_image_write_exr_threads(&img, ref_path, 1, &err) == PGT_OK);
        size_t ref_size = 0;
        unsigned char *ref = load_file(ref_path, &ref_size);
        REQUIRE(ref != NULL);
        for (size_t t = 0; t < sizeof(threads) / sizeof(threads[0]); ++t) {
            const char *path = scratch_path("many.exr");
            pgt_result r = pgt_image_write_exr_threads(&img, path, threads[t], &err);
            CHECK_MSG(r == PGT_OK, "set %zu, %u threads: %s", s, threads[t], err.message);
            size_t size = 0;
            unsigned char *bytes = load_file(path, &size);
            CHECK_MSG(bytes && size == ref_size && memcmp(bytes, ref, size) == 0,
                      "set %zu: %u threads write other bytes than one", s, threads[t]);
            free(bytes);
            r = pgt_image_read_exr(&back, path, &err);
            CHECK_MSG(r == PGT_OK, "set %zu: %s", s, err.message);
            if (r == PGT_OK) {
                CHECK_MSG(same_image(&img, &back), "set %zu, %u threads: not bit-exact", s,
                          threads[t]);
                pgt_image_destroy(&back);
            }
        }
        CHECK(scratch_count() == 2); /* no temporary file left behind */
        free(ref);
        pgt_image_destroy(&img);
    }
    scratch_remove();
}

static void test_exr_channel_lookup(void) {
    static const char *const names[] = {"depth", "B", "R", "G", "A", "N.x", "N.y", "P.z"};
    static const char *const sorted[] = {"A", "B", "G", "N.x", "N.y", "P.z", "R", "depth"};
    const uint32_t n = 8, w = 19, h = 21;
    pgt_image img, back;
    pgt_error err;
    pgt_error_clear(&err);
    REQUIRE(pgt_image_create(&img, w, h, n, names, &err) == PGT_OK);
    for (uint32_t c = 0; c < n; ++c)
        for (uint32_t i = 0; i < w * h; ++i) pgt_image_plane(&img, c)[i] = 1000.0f * c + i;
    for (uint32_t c = 0; c < n; ++c) CHECK(pgt_image_find_channel(&img, names[c]) == (int32_t)c);
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    const char *path = scratch_path("lookup.exr");
    REQUIRE(pgt_image_write_exr(&img, path, &err) == PGT_OK);
    REQUIRE(pgt_image_read_exr(&back, path, &err) == PGT_OK);
    REQUIRE(back.channel_count == n);
    for (uint32_t c = 0; c < n; ++c) {
        CHECK_MSG(strcmp(back.names[c], sorted[c]) == 0, "channel %u is '%s'", c, back.names[c]);
        int32_t k = pgt_image_find_channel(&back, names[c]);
        REQUIRE(k >= 0);
        CHECK(memcmp(pgt_image_plane(&back, (uint32_t)k), pgt_image_plane(&img, c),
                     (size_t)w * h * sizeof(float)) == 0);
        CHECK(pgt_image_plane(&back, (uint32_t)k)[5] == 1000.0f * c + 5);
    }
    CHECK(pgt_image_find_channel(&back, "missing") == -1);
    CHECK(pgt_image_find_channel(&back, "") == -1);
    CHECK(pgt_image_find_channel(&back, "r") == -1); /* case-sensitive */
    CHECK(pgt_image_find_channel(&back, "N") == -1); /* no prefix matches */
    CHECK(pgt_image_find_channel(&back, "depth_and_then_a_name_longer_than_31") == -1);
    CHECK(pgt_image_find_channel(&back, NULL) == -1);
    CHECK(pgt_image_find_channel(NULL, "R") == -1);
    pgt_image_destroy(&back);
    pgt_image_destroy(&img);
    scratch_remove();
}

static void test_image_create_contract(void) {
    pgt_image img;
    pgt_error err;
    static const char *const dup[] = {"R", "G", "R"};
    static const char *const empty[] = {"R", ""};
    static const char *const long32[] = {"abcdefghijklmnopqrstuvwxyz012345"};
    const struct {
        uint32_t w, h, c;
        const char *const *names;
        pgt_result expect;
    } cases[] = {
        {0, 4, 1, NULL, PGT_ERROR_INVALID_ARGUMENT},
        {4, 0, 1, NULL, PGT_ERROR_INVALID_ARGUMENT},
        {4, 4, 0, NULL, PGT_ERROR_INVALID_ARGUMENT},
        {PGT_IMAGE_MAX_SIDE + 1, 1, 1, NULL, PGT_ERROR_LIMIT},
        {1, PGT_IMAGE_MAX_SIDE + 1, 1, NULL, PGT_ERROR_LIMIT},
        {1, 1, PGT_IMAGE_MAX_CHANNELS + 1, NULL, PGT_ERROR_LIMIT},
        {PGT_IMAGE_MAX_SIDE, PGT_IMAGE_MAX_SIDE, 2, NULL, PGT_ERROR_LIMIT},
        {4, 4, 3, dup, PGT_ERROR_INVALID_ARGUMENT},
        {4, 4, 2, empty, PGT_ERROR_INVALID_ARGUMENT},
        {4, 4, 1, long32, PGT_ERROR_INVALID_ARGUMENT},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
        memset(&img, 0xAB, sizeof(img));
        pgt_error_clear(&err);
        pgt_result r =
            pgt_image_create(&img, cases[i].w, cases[i].h, cases[i].c, cases[i].names, &err);
        CHECK_MSG(r == cases[i].expect, "case %zu: got %s (%s)", i, pgt_result_name(r),
                  err.message);
        CHECK(image_is_zero(&img) && err.message[0] != '\0');
    }
    /* NULL names: empty names, zeroed data; the writer refuses empty names. */
    REQUIRE(pgt_image_create(&img, 3, 2, 2, NULL, NULL) == PGT_OK);
    CHECK(img.names[0][0] == '\0' && img.names[1][0] == '\0');
    for (uint32_t i = 0; i < 12; ++i) CHECK(img.data[i] == 0.0f && !signbit(img.data[i]));
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    pgt_error_clear(&err);
    CHECK(pgt_image_write_exr(&img, scratch_path("x.exr"), &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, scratch_path("x.exr")) != NULL);
    snprintf(img.names[0], PGT_IMAGE_NAME_SIZE, "Z");
    snprintf(img.names[1], PGT_IMAGE_NAME_SIZE, "Z");
    CHECK(pgt_image_write_exr(&img, scratch_path("x.exr"), NULL) == PGT_ERROR_INVALID_ARGUMENT);
    memset(img.names[1], 'q', PGT_IMAGE_NAME_SIZE); /* no NUL at all */
    CHECK(pgt_image_write_exr(&img, scratch_path("x.exr"), NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_image_find_channel(&img, "qqq") == -1);
    CHECK(scratch_count() == 0);
    snprintf(img.names[1], PGT_IMAGE_NAME_SIZE, "W");
    CHECK(pgt_image_write_exr(&img, scratch_path("x.exr"), NULL) == PGT_OK);
    CHECK(pgt_image_write_exr(NULL, scratch_path("x.exr"), NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_image_write_exr(&img, NULL, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    pgt_image_destroy(&img);
    CHECK(image_is_zero(&img));
    pgt_image_destroy(&img); /* twice, and NULL: no-ops */
    pgt_image_destroy(NULL);
    CHECK(pgt_image_write_exr(&img, scratch_path("y.exr"), NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(scratch_count() == 1);
    scratch_remove();
}

/* ---- EXR written through the OpenEXR C API ---- */

typedef struct capi_channel {
    const char *name;
    exr_pixel_type_t type;
    const void *data; /* planar, width * height values of 2 (HALF) or 4 bytes */
} capi_channel;

typedef struct capi_file {
    int32_t min_x, min_y, w, h;
    exr_storage_t storage;
    uint32_t tile_w, tile_h;
    exr_compression_t compression;
    exr_lineorder_t order;
    int channel_count;
    capi_channel ch[4];
} capi_file;

/* Points every coding channel of a pipeline at the rectangle starting at pixel (x, y). */
static int capi_point(exr_encode_pipeline_t *enc, const capi_file *f, int32_t x, int32_t y) {
    for (int k = 0; k < enc->channel_count; ++k) {
        const capi_channel *c = NULL;
        for (int i = 0; i < f->channel_count; ++i)
            if (strcmp(f->ch[i].name, enc->channels[k].channel_name) == 0) c = &f->ch[i];
        if (!c) return -1;
        int bpe = c->type == EXR_PIXEL_HALF ? 2 : 4;
        enc->channels[k].encode_from_ptr =
            (const uint8_t *)c->data + ((size_t)y * (size_t)f->w + (size_t)x) * (size_t)bpe;
        enc->channels[k].user_pixel_stride = bpe;
        enc->channels[k].user_line_stride = bpe * f->w;
        enc->channels[k].user_data_type = (uint16_t)c->type;
        enc->channels[k].user_bytes_per_element = (int16_t)bpe;
    }
    return 0;
}

static int capi_write(const char *path, const capi_file *f) {
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    if (exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS) return -1;
    int part = 0, bad = 0;
    exr_attr_box2i_t dw;
    dw.min.x = f->min_x;
    dw.min.y = f->min_y;
    dw.max.x = f->min_x + f->w - 1;
    dw.max.y = f->min_y + f->h - 1;
    exr_attr_v2f_t center;
    center.x = center.y = 0.0f;
    bad |= exr_add_part(ctxt, NULL, f->storage, &part);
    bad |= exr_initialize_required_attr(ctxt, part, &dw, &dw, 1.0f, &center, 1.0f, f->order,
                                        f->compression);
    if (f->storage == EXR_STORAGE_TILED)
        bad |= exr_set_tile_descriptor(ctxt, part, f->tile_w, f->tile_h, EXR_TILE_ONE_LEVEL,
                                       EXR_TILE_ROUND_DOWN);
    for (int i = 0; i < f->channel_count; ++i)
        bad |= exr_add_channel(ctxt, part, f->ch[i].name, f->ch[i].type, EXR_PERCEPTUALLY_LINEAR, 1,
                               1);
    bad |= exr_write_header(ctxt);
    exr_encode_pipeline_t enc;
    memset(&enc, 0, sizeof(enc));
    int live = 0;
    exr_chunk_info_t ci;
    if (!bad && f->storage == EXR_STORAGE_TILED) {
        int tx_n = (f->w + (int)f->tile_w - 1) / (int)f->tile_w;
        int ty_n = (f->h + (int)f->tile_h - 1) / (int)f->tile_h;
        for (int ty = 0; ty < ty_n && !bad; ++ty)
            for (int tx = 0; tx < tx_n && !bad; ++tx) {
                bad |= exr_write_tile_chunk_info(ctxt, part, tx, ty, 0, 0, &ci);
                bad |= live ? exr_encoding_update(ctxt, part, &ci, &enc)
                            : exr_encoding_initialize(ctxt, part, &ci, &enc);
                live = 1;
                bad |= capi_point(&enc, f, tx * (int32_t)f->tile_w, ty * (int32_t)f->tile_h);
                bad |= exr_encoding_choose_default_routines(ctxt, part, &enc);
                bad |= exr_encoding_run(ctxt, part, &enc);
            }
    } else if (!bad) {
        int32_t lines = 1;
        bad |= exr_get_scanlines_per_chunk(ctxt, part, &lines);
        int chunks = (f->h + lines - 1) / lines;
        for (int k = 0; k < chunks && !bad; ++k) {
            int chunk = k;
            bad |= exr_write_scanline_chunk_info(ctxt, part, f->min_y + chunk * lines, &ci);
            bad |= live ? exr_encoding_update(ctxt, part, &ci, &enc)
                        : exr_encoding_initialize(ctxt, part, &ci, &enc);
            live = 1;
            bad |= capi_point(&enc, f, 0, chunk * lines);
            bad |= exr_encoding_choose_default_routines(ctxt, part, &enc);
            bad |= exr_encoding_run(ctxt, part, &enc);
        }
    }
    if (live) exr_encoding_destroy(ctxt, &enc);
    bad |= exr_finish(&ctxt);
    return bad ? -1 : 0;
}

/* IEEE 754 binary16 to float, from the definition (not from the library under test). */
static float half_to_float(uint16_t h) {
    int sign = h >> 15, exp = (h >> 10) & 31, mant = h & 1023;
    double v;
    if (exp == 0)
        v = ldexp(mant, -24);
    else if (exp == 31)
        v = mant ? NAN : INFINITY;
    else
        v = ldexp(1024 + mant, exp - 25);
    return (float)(sign ? -v : v);
}

/* Every HALF bit pattern, UINT values around 2^24 and 2^32, random FLOAT bits, in a 256 x 256
 * window that does not start at (0, 0), in every lossless compression and both line orders. */
static void test_exr_half_uint_float(void) {
    enum { W = 256, H = 256 };
    uint16_t *half = malloc(sizeof(uint16_t) * W * H);
    uint32_t *uints = malloc(sizeof(uint32_t) * W * H);
    float *floats = malloc(sizeof(float) * W * H);
    REQUIRE(half && uints && floats);
    static const uint32_t u_special[] = {0,           1,           255,        65535,
                                         16777216,    16777217,    16777219,   123456789,
                                         2147483647u, 2147483648u, 4294967295u};
    rng_state = 11;
    for (uint32_t i = 0; i < W * H; ++i) {
        half[i] = (uint16_t)i;
        uints[i] = i < sizeof(u_special) / sizeof(u_special[0]) ? u_special[i] : rnd();
        floats[i] = from_bits(rnd());
    }
    static const exr_compression_t comps[] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,
                                              EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
                                              EXR_COMPRESSION_PIZ};
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    for (size_t k = 0; k < 2 * sizeof(comps) / sizeof(comps[0]); ++k) {
        capi_file f = {-5,
                       10,
                       W,
                       H,
                       EXR_STORAGE_SCANLINE,
                       0,
                       0,
                       comps[k / 2],
                       k % 2 ? EXR_LINEORDER_DECREASING_Y : EXR_LINEORDER_INCREASING_Y,
                       3,
                       {{"half", EXR_PIXEL_HALF, half},
                        {"uint", EXR_PIXEL_UINT, uints},
                        {"float", EXR_PIXEL_FLOAT, floats}}};
        const char *path = scratch_path("capi.exr");
        REQUIRE(capi_write(path, &f) == 0);
        pgt_image img;
        pgt_error err;
        pgt_error_clear(&err);
        pgt_result r = pgt_image_read_exr(&img, path, &err);
        CHECK_MSG(r == PGT_OK, "compression %d: %s", (int)comps[k / 2], err.message);
        if (r != PGT_OK) continue;
        CHECK(img.width == W && img.height == H && img.channel_count == 3);
        int32_t ch = pgt_image_find_channel(&img, "half");
        int32_t cu = pgt_image_find_channel(&img, "uint");
        int32_t cf = pgt_image_find_channel(&img, "float");
        REQUIRE(ch >= 0 && cu >= 0 && cf >= 0);
        /* the stored types: only the HALF channel is flagged (pgt_image.half) */
        CHECK(img.half && img.half[ch] == 1 && img.half[cu] == 0 && img.half[cf] == 0);
        int bad_h = 0, bad_u = 0;
        for (uint32_t i = 0; i < W * H; ++i) {
            float want = half_to_float(half[i]), got = pgt_image_plane(&img, (uint32_t)ch)[i];
            if (isnan(want) ? !isnan(got) : memcmp(&want, &got, sizeof(float)) != 0) bad_h++;
            if (pgt_image_plane(&img, (uint32_t)cu)[i] != (float)uints[i]) bad_u++;
        }
        CHECK_MSG(bad_h == 0, "compression %d: %d HALF values differ", (int)comps[k / 2], bad_h);
        CHECK_MSG(bad_u == 0, "compression %d: %d UINT values differ", (int)comps[k / 2], bad_u);
        CHECK(memcmp(pgt_image_plane(&img, (uint32_t)cf), floats, sizeof(float) * W * H) == 0);
        pgt_image_destroy(&img);
    }
    free(half);
    free(uints);
    free(floats);
    scratch_remove();
}

/* The reader refuses a file whose chunks could not hold its pixels under their compression's
 * largest expansion (image_exr.c, max_expansion). The files that compress best, constant images
 * as OpenEXR's encoders write them, stay within those bounds: every compression with a bound
 * reads them back exactly (HALF 1.5 and FLOAT 1.5, which PXR24's 24-bit floats and B44's HALF
 * blocks keep). */
/* capi_write marks its channels perceptually linear (pLinear 1): B44 then codes HALF values
 * through its logarithmic table, and 1.5 comes back one HALF step (2^-10 at 1..2) below; two
 * steps allowed (with pLinear 0 the flat blocks come back exact). */
#define EXR_B44_HALF_TOL (2.0 / 1024.0)

static void test_exr_constant_images(void) {
    enum { W = 512, H = 512 };
    static uint16_t half[W * H];
    static float floats[W * H];
    for (int i = 0; i < W * H; ++i) half[i] = 0x3e00, floats[i] = 1.5f;
    static const exr_compression_t comps[] = {
        EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,   EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
        EXR_COMPRESSION_PIZ,  EXR_COMPRESSION_PXR24, EXR_COMPRESSION_B44,  EXR_COMPRESSION_B44A};
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    for (size_t k = 0; k < sizeof(comps) / sizeof(comps[0]); ++k)
        for (int with_float = 0; with_float < 2; ++with_float) {
            capi_file f = {0,
                           0,
                           W,
                           H,
                           EXR_STORAGE_SCANLINE,
                           0,
                           0,
                           comps[k],
                           EXR_LINEORDER_INCREASING_Y,
                           1 + with_float,
                           {{"Y", EXR_PIXEL_HALF, half}, {"Z", EXR_PIXEL_FLOAT, floats}}};
            const char *path = scratch_path("constant.exr");
            REQUIRE(capi_write(path, &f) == 0);
            size_t bytes = 0;
            free(load_file(path, &bytes));
            pgt_image img;
            pgt_error err;
            pgt_error_clear(&err);
            const pgt_result r = pgt_image_read_exr(&img, path, &err);
            printf("  constant %dx%d %s, compression %d: %zu bytes (%.0f:1)\n", W, H,
                   with_float ? "HALF + FLOAT" : "HALF", (int)comps[k], bytes,
                   (double)W * H * (with_float ? 6.0 : 2.0) / (double)bytes);
            CHECK_MSG(r == PGT_OK, "compression %d: %s", (int)comps[k], err.message);
            if (r != PGT_OK) continue;
            /* B44 is lossy on HALF channels (Y here): within EXR_B44_HALF_TOL */
            const int lossy = comps[k] == EXR_COMPRESSION_B44 || comps[k] == EXR_COMPRESSION_B44A;
            int bad = 0;
            for (uint32_t c = 0; c < img.channel_count; ++c) {
                const double tol = lossy && !strcmp(img.names[c], "Y") ? EXR_B44_HALF_TOL : 0.0;
                for (size_t i = 0; i < (size_t)W * H; ++i)
                    bad += fabs(pgt_image_plane(&img, c)[i] - 1.5) > tol;
            }
            CHECK_MSG(img.channel_count == (uint32_t)(1 + with_float) && bad == 0,
                      "compression %d: %d values differ", (int)comps[k], bad);
            pgt_image_destroy(&img);
        }
    scratch_remove();
}

/* A tiled file whose tiles do not divide the image (partial tiles right and bottom). */
static void test_exr_tiled(void) {
    enum { W = 37, H = 23 };
    uint16_t half[W * H];
    float floats[W * H];
    rng_state = 12;
    for (int i = 0; i < W * H; ++i) {
        half[i] = (uint16_t)(0x3c00 + (i & 1023)); /* 1 .. 2 */
        floats[i] = (float)i * 0.25f - 100.0f;
    }
    static const exr_compression_t comps[] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_ZIP,
                                              EXR_COMPRESSION_PIZ};
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    for (size_t k = 0; k < sizeof(comps) / sizeof(comps[0]); ++k) {
        capi_file f = {3,
                       -7,
                       W,
                       H,
                       EXR_STORAGE_TILED,
                       16,
                       8,
                       comps[k],
                       EXR_LINEORDER_INCREASING_Y,
                       2,
                       {{"Z", EXR_PIXEL_FLOAT, floats}, {"Y", EXR_PIXEL_HALF, half}}};
        const char *path = scratch_path("tiled.exr");
        REQUIRE(capi_write(path, &f) == 0);
        pgt_image img;
        pgt_error err;
        pgt_error_clear(&err);
        pgt_result r = pgt_image_read_exr(&img, path, &err);
        CHECK_MSG(r == PGT_OK, "%s", err.message);
        if (r != PGT_OK) continue;
        CHECK(img.width == W && img.height == H && img.channel_count == 2);
        CHECK(strcmp(img.names[0], "Y") == 0 && strcmp(img.names[1], "Z") == 0);
        int bad = 0;
        for (int i = 0; i < W * H; ++i)
            bad += pgt_image_plane(&img, 0)[i] != half_to_float(half[i]) ||
                   pgt_image_plane(&img, 1)[i] != floats[i];
        CHECK_MSG(bad == 0, "compression %d: %d values differ", (int)comps[k], bad);
        pgt_image_destroy(&img);
    }
    scratch_remove();
}

/* ---- truncations, mutations, the corpus ---- */

/* A small but real file of each kind the reader meets. */
static unsigned char *make_exr(int kind, size_t *size) {
    scratch_make();
    if (!scratch[0]) return NULL;
    const char *path = scratch_path("base.exr");
    enum { W = 37, H = 23 };
    static uint16_t half[W * H];
    static float floats[W * H];
    for (int i = 0; i < W * H; ++i) {
        half[i] = (uint16_t)(0x3800 + (i % 97));
        floats[i] = sinf((float)i * 0.1f);
    }
    int bad = 0;
    if (kind == 0) { /* pgt's own: ZIP, FLOAT, smooth enough to compress */
        static const char *const names[] = {"R", "G", "B", "depth"};
        pgt_image img;
        bad = pgt_image_create(&img, W, H, 4, names, NULL) != PGT_OK;
        if (!bad) {
            for (size_t i = 0; i < (size_t)W * H * 4; ++i) img.data[i] = (float)(i % 50) * 0.5f;
            bad = pgt_image_write_exr(&img, path, NULL) != PGT_OK;
            pgt_image_destroy(&img);
        }
    } else {
        static const exr_compression_t comps[] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_ZIP,
                                                  EXR_COMPRESSION_PIZ, EXR_COMPRESSION_RLE};
        capi_file f = {0,
                       0,
                       W,
                       H,
                       kind == 1 ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE,
                       8,
                       8,
                       comps[kind % 4],
                       EXR_LINEORDER_INCREASING_Y,
                       2,
                       {{"Y", EXR_PIXEL_HALF, half}, {"Z", EXR_PIXEL_FLOAT, floats}}};
        bad = capi_write(path, &f) != 0;
    }
    unsigned char *data = bad ? NULL : load_file(path, size);
    scratch_remove();
    return data;
}

static void test_exr_truncations(void) {
    for (int kind = 0; kind < 4; ++kind) {
        size_t size = 0;
        unsigned char *data = make_exr(kind, &size);
        REQUIRE(data != NULL && size > 100);
        pgt_image img;
        pgt_error err;
        REQUIRE(read_mem(&img, data, size, "whole.exr", &err) == PGT_OK);
        pgt_image_destroy(&img);
        int bad = 0;
        for (size_t len = 0; len < size; ++len) {
            pgt_result r = read_mem(&img, data, len, "cut.exr", &err);
            pgt_result want = len == 0 ? PGT_ERROR_EMPTY : PGT_ERROR_TRUNCATED;
            if (r != want || !image_is_zero(&img) || strncmp(err.message, "cut.exr: ", 9) != 0) {
                if (bad++ < 5)
                    fprintf(stderr, "  kind %d, %zu of %zu bytes: %s: %s\n", kind, len, size,
                            pgt_result_name(r), err.message);
            }
        }
        CHECK_MSG(bad == 0, "kind %d: %d truncations misreported", kind, bad);
        /* The same through files: the message names the path. */
        scratch_make();
        REQUIRE(scratch[0] != '\0');
        const size_t lens[] = {0, 3, 9, 100, size / 2, size - 1};
        for (size_t i = 0; i < sizeof(lens) / sizeof(lens[0]); ++i) {
            const char *path = scratch_path("cut.exr");
            REQUIRE(save_file(path, data, lens[i]) == 0);
            memset(&img, 0xAB, sizeof(img));
            pgt_error_clear(&err);
            pgt_result r = pgt_image_read_exr(&img, path, &err);
            CHECK(r == (lens[i] == 0 ? PGT_ERROR_EMPTY : PGT_ERROR_TRUNCATED));
            CHECK(image_is_zero(&img) && strstr(err.message, path) == err.message);
        }
        scratch_remove();
        free(data);
    }
}

/* Reads the file at path on one thread and on several: the same result code, the same message
 * (that of the first failing chunk in file order) and, when it reads, the same image. */
static int same_read_any_threads(const char *path) {
    pgt_image one, many;
    pgt_error e1, e4;
    pgt_error_clear(&e1), pgt_error_clear(&e4);
    const pgt_result r1 = pgt_image_read_exr_threads(&one, path, 1, &e1);
    const pgt_result r4 = pgt_image_read_exr_threads(&many, path, 4, &e4);
    int same = r1 == r4 && strcmp(e1.message, e4.message) == 0;
    if (same && r1 == PGT_OK) same = same_image(&one, &many);
    if (!same)
        fprintf(stderr, "  %s: one thread %s (%s), four %s (%s)\n", path, pgt_result_name(r1),
                e1.message, pgt_result_name(r4), e4.message);
    pgt_image_destroy(&one);
    pgt_image_destroy(&many);
    return same;
}

static void test_exr_garbage_and_mutations(void) {
    pgt_image img;
    pgt_error err;
    unsigned char buf[1024];
    rng_state = 42;
    for (int i = 0; i < 400; ++i) {
        size_t len = rnd() % sizeof(buf);
        for (size_t k = 0; k < len; ++k) buf[k] = (unsigned char)rnd();
        if (i % 2 && len >= 8) memcpy(buf, "\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
        pgt_result r = read_mem(&img, buf, len, "noise.exr", &err);
        CHECK(r != PGT_OK && image_is_zero(&img) && strstr(err.message, "noise.exr: "));
    }
    for (int kind = 0; kind < 4; ++kind) {
        size_t size = 0;
        unsigned char *data = make_exr(kind, &size);
        REQUIRE(data != NULL);
        unsigned char *copy = malloc(size);
        int ok = 0, failed = 0, differ = 0;
        scratch_make();
        REQUIRE(scratch[0] != '\0');
        for (int i = 0; i < 1500; ++i) {
            memcpy(copy, data, size);
            int changes = 1 + (int)(rnd() % 4);
            for (int c = 0; c < changes; ++c) {
                /* Half of the changes in the header and offset table, where parsing happens. */
                size_t span = rnd() % 2 ? size : (size < 400 ? size : 400);
                size_t at = rnd() % span;
                copy[at] = (unsigned char)(rnd() % 3 ? rnd() : copy[at] ^ (1u << (rnd() % 8)));
            }
            pgt_result r = read_mem(&img, copy, size, "mutant.exr", &err);
            /* every third mutant also from a file, decoded on one thread and on four */
            if (i % 3 == 0) {
                const char *path = scratch_path("mutant.exr");
                REQUIRE(save_file(path, copy, size) == 0);
                differ += !same_read_any_threads(path);
            }
            if (r == PGT_OK) {
                ok++;
                CHECK(img.width >= 1 && img.width <= PGT_IMAGE_MAX_SIDE && img.height >= 1 &&
                      img.channel_count >= 1 && img.data && img.names);
                pgt_image_destroy(&img);
            } else {
                failed++;
                CHECK(image_is_zero(&img) && strstr(err.message, "mutant.exr: "));
            }
        }
        printf("  exr kind %d (%zu bytes): %d mutants read, %d rejected\n", kind, size, ok, failed);
        CHECK_MSG(differ == 0, "kind %d: %d mutants read differently on four threads", kind,
                  differ);
        scratch_remove();
        free(copy);
        free(data);
    }
}

/* Damaged files large enough to decode on several threads (the pool takes 4096 pixels a thread
 * at least): pgt's ZIP scanlines (13 chunks), RLE scanlines (one row a chunk) and uncompressed
 * 16 x 16 tiles. Bytes changed past the header, in the offset table and chunks, so that some
 * chunks fail to decode: one thread and four give the same code, message and image. */
static void test_exr_threads_damaged(void) {
    enum { W = 160, H = 200 };
    static uint16_t half[W * H];
    static float floats[W * H];
    for (int i = 0; i < W * H; ++i) {
        half[i] = (uint16_t)(0x3800 + (i % 97));
        floats[i] = sinf((float)i * 0.01f);
    }
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 5;
    for (int kind = 0; kind < 3; ++kind) {
        const char *base = scratch_path("base.exr");
        if (kind == 0) {
            static const char *const names[] = {"R", "G", "B", "depth"};
            pgt_image img;
            REQUIRE(pgt_image_create(&img, W, H, 4, names, NULL) == PGT_OK);
            for (size_t i = 0; i < (size_t)W * H * 4; ++i) img.data[i] = (float)(i % 50) * 0.5f;
            REQUIRE(pgt_image_write_exr(&img, base, NULL) == PGT_OK);
            pgt_image_destroy(&img);
        } else {
            const capi_file f = {0,
                                 0,
                                 W,
                                 H,
                                 kind == 2 ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE,
                                 16,
                                 16,
                                 kind == 2 ? EXR_COMPRESSION_NONE : EXR_COMPRESSION_RLE,
                                 EXR_LINEORDER_INCREASING_Y,
                                 2,
                                 {{"Y", EXR_PIXEL_HALF, half}, {"Z", EXR_PIXEL_FLOAT, floats}}};
            REQUIRE(capi_write(base, &f) == 0);
        }
        size_t size = 0;
        unsigned char *data = load_file(base, &size);
        REQUIRE(data != NULL && size > 1000);
        CHECK(same_read_any_threads(base));
        unsigned char *copy = malloc(size);
        REQUIRE(copy != NULL);
        int differ = 0, failed = 0;
        for (int i = 0; i < 150; ++i) {
            memcpy(copy, data, size);
            const int changes = 1 + (int)(rnd() % 3);
            for (int c = 0; c < changes; ++c) {
                const size_t at = 400u + rnd() % (size - 400u); /* past the header */
                copy[at] = (unsigned char)(rnd() % 2 ? rnd() : copy[at] ^ (1u << (rnd() % 8)));
            }
            const char *path = scratch_path("damaged.exr");
            REQUIRE(save_file(path, copy, size) == 0);
            pgt_image img;
            pgt_error err;
            pgt_error_clear(&err);
            failed += pgt_image_read_exr(&img, path, &err) != PGT_OK;
            pgt_image_destroy(&img);
            differ += !same_read_any_threads(path);
        }
        printf("  kind %d (%zu bytes): %d of 150 damaged files rejected\n", kind, size, failed);
        CHECK_MSG(differ == 0, "kind %d: %d damaged files read differently on four threads", kind,
                  differ);
        CHECK(failed > 0); /* the error path was taken */
        free(copy);
        free(data);
    }
    scratch_remove();
}

static void test_malformed_corpus(void) {
    char path[512], line[512], fname[256], code[64];
    snprintf(path, sizeof(path), "%s/malformed_images/MANIFEST", PGT_TEST_DATA_DIR);
    FILE *f = fopen(path, "r");
    REQUIRE(f != NULL);
    int files = 0;
    while (fgets(line, sizeof(line), f)) {
        if (line[0] == '#' || line[0] == '\n') continue;
        REQUIRE(sscanf(line, "%255s %63s", fname, code) == 2);
        files++;
        snprintf(path, sizeof(path), "%s/malformed_images/%s", PGT_TEST_DATA_DIR, fname);
        pgt_error err;
        pgt_result r;
        int zeroed;
        if (strstr(fname, ".png")) {
            uint32_t w, h, c;
            uint8_t *px;
            r = read_png(path, &w, &h, &c, &px, &err);
            zeroed = w == 0 && h == 0 && c == 0 && px == NULL;
            if (r == PGT_OK) free(px);
        } else {
            pgt_image img;
            memset(&img, 0xAB, sizeof(img));
            pgt_error_clear(&err);
            r = pgt_image_read_exr(&img, path, &err);
            zeroed = image_is_zero(&img);
            if (r == PGT_OK) pgt_image_destroy(&img);
            CHECK_MSG(same_read_any_threads(path), "%s: read differently on four threads", fname);
            /* The memory reader shares the code path: same code, its name in the message. */
            size_t size = 0;
            unsigned char *data = load_file(path, &size);
            REQUIRE(data != NULL);
            pgt_error err2;
            pgt_result r2 = read_mem(&img, data, size, fname, &err2);
            CHECK_MSG(r2 == r && strncmp(err2.message, fname, strlen(fname)) == 0,
                      "%s: memory read gave %s (%s)", fname, pgt_result_name(r2), err2.message);
            if (r2 == PGT_OK) pgt_image_destroy(&img);
            free(data);
        }
        CHECK_MSG(strcmp(pgt_result_name(r), code) == 0, "%s: got %s, expected %s (%s)", fname,
                  pgt_result_name(r), code, err.message);
        CHECK_MSG(err.code == r, "%s: err.code %d", fname, (int)err.code);
        CHECK_MSG(zeroed, "%s: outputs not zeroed", fname);
        CHECK_MSG(strncmp(err.message, path, strlen(path)) == 0, "%s: message '%s'", fname,
                  err.message);
        CHECK_MSG(strchr(err.message, '\n') == NULL, "%s: message of two lines", fname);
    }
    fclose(f);
    CHECK(files >= 40);
    /* Every corpus file is in the manifest. */
    snprintf(path, sizeof(path), "%s/malformed_images", PGT_TEST_DATA_DIR);
    DIR *d = opendir(path);
    REQUIRE(d != NULL);
    int on_disk = 0;
    for (struct dirent *e; (e = readdir(d));) {
        const char *dot = strrchr(e->d_name, '.');
        if (dot && (!strcmp(dot, ".exr") || !strcmp(dot, ".png"))) on_disk++;
    }
    closedir(d);
    CHECK_MSG(on_disk == files, "%d image files on disk, %d in MANIFEST", on_disk, files);
}

/* Two channels of one name: OpenEXRCore drops the list ("'channels' attribute not found");
 * pgt's header scan names the channel, from a file and from memory, and counts a list longer
 * than pgt reads even when a name repeats. */
static void test_exr_duplicate_channel(void) {
    char path[512];
    snprintf(path, sizeof(path), "%s/malformed_images/exr_duplicate_channel.exr",
             PGT_TEST_DATA_DIR);
    pgt_image img;
    pgt_error err = {0};
    CHECK(pgt_image_read_exr(&img, path, &err) == PGT_ERROR_PARSE);
    char want[600];
    snprintf(want, sizeof want, "%s: two channels named 'R'", path);
    CHECK_MSG(!strcmp(err.message, want), "%s", err.message);
    size_t size = 0;
    unsigned char *data = load_file(path, &size);
    REQUIRE(data != NULL);
    pgt_error_clear(&err);
    CHECK(read_mem(&img, data, size, "dup.exr", &err) == PGT_ERROR_PARSE);
    CHECK_MSG(!strcmp(err.message, "dup.exr: two channels named 'R'"), "%s", err.message);
    free(data);
    /* seventy channels with a repeat past the 64th: the limit, with the list's true count */
    snprintf(path, sizeof(path), "%s/malformed_images/exr_many_channels_repeated.exr",
             PGT_TEST_DATA_DIR);
    pgt_error_clear(&err);
    CHECK(pgt_image_read_exr(&img, path, &err) == PGT_ERROR_LIMIT);
    snprintf(want, sizeof want, "%s: 70 channels exceed the limit of 64", path);
    CHECK_MSG(!strcmp(err.message, want), "%s", err.message);
}

/* Tiles may be larger than the image (OpenEXRCore clips them): a tile's pixel count in 32 bits
 * (2^31 here) wrapped the parallel decode's weights, and threads 1 and 2 read zeros or half of
 * the image (tests/data/valid_images, written by make_corpus.py: pixel y holds y % 7 + 1). */
/* Reads valid_images/NAME on `threads` threads; 0 (a failed check) when it cannot. */
static int read_valid(const char *name, uint32_t threads, pgt_image *img) {
    char path[512];
    snprintf(path, sizeof(path), "%s/valid_images/%s", PGT_TEST_DATA_DIR, name);
    pgt_error err = {0};
    const pgt_result r = pgt_image_read_exr_threads(img, path, threads, &err);
    CHECK_MSG(r == PGT_OK, "%s", err.message);
    return r == PGT_OK;
}

static void test_tiles_larger_than_image(void) {
    for (uint32_t threads = 1; threads <= 4; ++threads) {
        pgt_image img;
        if (!read_valid("tiles_larger_than_image.exr", threads, &img)) continue;
        CHECK(img.width == 1 && img.height == 16384 && img.channel_count == 1);
        uint32_t wrong = 0;
        for (uint32_t y = 0; y < img.height; ++y) wrong += img.data[y] != (float)(y % 7u + 1u);
        CHECK_MSG(wrong == 0, "%u threads: %u of 16384 pixels wrong", threads, wrong);
        pgt_image_destroy(&img);
    }
}

/* A multipart file of one part (pgt reads it; its chunk leaders start with a part number, which
 * the file-size checks before the library read as the row and refused the file as truncated):
 * pixel (x, y) holds 10 y + x + 1 (make_corpus.py). */
static void test_one_part_multipart(void) {
    for (uint32_t threads = 1; threads <= 2; ++threads) {
        pgt_image img;
        if (!read_valid("one_part_multipart.exr", threads, &img)) continue;
        CHECK(img.width == 4 && img.height == 3 && img.channel_count == 1);
        for (uint32_t i = 0; i < 12; ++i)
            CHECK(img.data[i] == (float)(10u * (i / 4u) + i % 4u + 1u));
        pgt_image_destroy(&img);
    }
}

/* ---- PNG ---- */

static void test_png_round_trip(void) {
    const uint32_t sizes[][2] = {{1, 1}, {37, 23}, {300, 2}, {2, 300}};
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    rng_state = 5;
    for (uint32_t ch = 1; ch <= 4; ++ch)
        for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); ++s) {
            const uint32_t w = sizes[s][0], h = sizes[s][1];
            size_t n = (size_t)w * h * ch;
            uint8_t *px = malloc(n);
            for (size_t i = 0; i < n; ++i) px[i] = (uint8_t)(s == 1 ? rnd() : i * 7);
            const char *path = scratch_path("round.png");
            pgt_error err;
            pgt_error_clear(&err);
            CHECK_MSG(pgt_png_write(path, w, h, ch, px, &err) == PGT_OK, "%s", err.message);
            CHECK(scratch_count() == 1);
            uint32_t rw, rh, rc;
            uint8_t *back;
            pgt_result r = read_png(path, &rw, &rh, &rc, &back, &err);
            CHECK_MSG(r == PGT_OK, "%s", err.message);
            if (r == PGT_OK) {
                CHECK(rw == w && rh == h && rc == ch && memcmp(back, px, n) == 0);
                free(back);
            }
            free(px);
        }
    scratch_remove();
}

/* A PNG written with libpng directly: rows are already packed as the bit depth needs. */
typedef struct raw_png {
    uint32_t w, h;
    int depth, color, interlace;
    const uint8_t *rows; /* h rows of row_bytes */
    size_t row_bytes;
    const png_color *palette;
    int palette_size;
    const uint8_t *trns; /* palette alpha, or NULL */
    int trns_count;
    const png_color_16 *trns_color; /* gray/RGB transparent colour, or NULL */
} raw_png;

static int write_raw_png(const char *path, const raw_png *p) {
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, p->w, p->h, p->depth, p->color, p->interlace,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (p->palette) png_set_PLTE(png, info, p->palette, p->palette_size);
    if (p->trns || p->trns_color) png_set_tRNS(png, info, p->trns, p->trns_count, p->trns_color);
    png_write_info(png, info);
    int passes = png_set_interlace_handling(png);
    for (int pass = 0; pass < passes; ++pass)
        for (uint32_t y = 0; y < p->h; ++y) png_write_row(png, p->rows + p->row_bytes * y);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return fclose(f) == 0 ? 0 : -1;
}

static void test_png_variants(void) {
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    const char *path = scratch_path("variant.png");
    pgt_error err;
    uint32_t w, h, c;
    uint8_t *px;
    rng_state = 9;

    /* 16-bit gray holding every value: rounded to 8 bits as v * 255 / 65535. */
    static uint8_t rows16[256 * 256 * 2];
    for (uint32_t v = 0; v < 65536; ++v) {
        rows16[2 * v] = (uint8_t)(v >> 8); /* PNG samples are big-endian */
        rows16[2 * v + 1] = (uint8_t)v;
    }
    raw_png g16 = {256,  256, 16,  PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, rows16, 512, NULL, 0,
                   NULL, 0,   NULL};
    REQUIRE(write_raw_png(path, &g16) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(w == 256 && h == 256 && c == 1);
    int bad = 0;
    for (uint32_t v = 0; v < 65536; ++v) bad += px[v] != (uint8_t)floor(v / 257.0 + 0.5);
    CHECK_MSG(bad == 0, "%d 16-bit values rounded differently", bad);
    free(px);

    /* 16-bit RGBA, interlaced. */
    enum { W = 37, H = 23 };
    static uint8_t rgba16[W * H * 8];
    for (size_t i = 0; i < sizeof(rgba16); ++i) rgba16[i] = (uint8_t)rnd();
    raw_png c16 = {
        W,    H, 16,  PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_ADAM7, rgba16, W * 8, NULL, 0,
        NULL, 0, NULL};
    REQUIRE(write_raw_png(path, &c16) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(w == W && h == H && c == 4);
    bad = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; ++i) {
        unsigned v = (unsigned)rgba16[2 * i] << 8 | rgba16[2 * i + 1];
        bad += px[i] != (uint8_t)floor(v / 257.0 + 0.5);
    }
    CHECK_MSG(bad == 0, "%d interlaced 16-bit RGBA values differ", bad);
    free(px);

    /* 8-bit palette without tRNS: RGB. 4-bit palette with a short tRNS: RGBA, alpha 255 past
     * the tRNS entries. */
    png_color pal[256];
    for (int i = 0; i < 256; ++i)
        pal[i] = (png_color){(png_byte)i, (png_byte)(255 - i), (png_byte)(i * 3)};
    static uint8_t idx8[W * H];
    for (size_t i = 0; i < sizeof(idx8); ++i) idx8[i] = (uint8_t)rnd();
    raw_png p8 = {W,    H, 8,   PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, idx8, W, pal, 256,
                  NULL, 0, NULL};
    REQUIRE(write_raw_png(path, &p8) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(w == W && h == H && c == 3);
    bad = 0;
    for (size_t i = 0; i < (size_t)W * H; ++i)
        bad += px[3 * i] != pal[idx8[i]].red || px[3 * i + 1] != pal[idx8[i]].green ||
               px[3 * i + 2] != pal[idx8[i]].blue;
    CHECK_MSG(bad == 0, "%d palette pixels differ", bad);
    free(px);

    static uint8_t idx4[H * ((W + 1) / 2)];
    uint8_t want4[W * H];
    memset(idx4, 0, sizeof(idx4));
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            uint8_t v = (uint8_t)(rnd() % 16);
            want4[y * W + x] = v;
            idx4[y * ((W + 1) / 2) + x / 2] |= (uint8_t)(x % 2 ? v : v << 4);
        }
    const uint8_t trns[5] = {0, 10, 128, 254, 255};
    raw_png p4 = {
        W,    H, 4,   PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_ADAM7, idx4, (W + 1) / 2, pal, 16,
        trns, 5, NULL};
    REQUIRE(write_raw_png(path, &p4) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(w == W && h == H && c == 4);
    bad = 0;
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        uint8_t v = want4[i];
        bad += px[4 * i] != pal[v].red || px[4 * i + 1] != pal[v].green ||
               px[4 * i + 2] != pal[v].blue || px[4 * i + 3] != (v < 5 ? trns[v] : 255);
    }
    CHECK_MSG(bad == 0, "%d 4-bit palette pixels with tRNS differ", bad);
    free(px);

    /* Gray at 1, 2 and 4 bits: scaled to 0..255. */
    for (int depth = 1; depth <= 4; depth *= 2) {
        const int per_byte = 8 / depth;
        const size_t row = (W + (size_t)per_byte - 1) / (size_t)per_byte;
        uint8_t packed[H * W];
        uint8_t want[W * H];
        memset(packed, 0, sizeof(packed));
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                unsigned v = rnd() % (1u << depth);
                want[y * W + x] = (uint8_t)(v * 255 / ((1u << depth) - 1));
                int shift = 8 - depth * (int)(x % (uint32_t)per_byte + 1);
                packed[y * row + x / (uint32_t)per_byte] |= (uint8_t)(v << shift);
            }
        raw_png g = {W,    H, depth, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, packed, row, NULL, 0,
                     NULL, 0, NULL};
        REQUIRE(write_raw_png(path, &g) == 0);
        REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
        CHECK(w == W && h == H && c == 1 && memcmp(px, want, sizeof(want)) == 0);
        free(px);
    }

    /* 8-bit gray with a transparent value: gray + alpha. */
    uint8_t gray[W * H];
    for (size_t i = 0; i < sizeof(gray); ++i) gray[i] = (uint8_t)(i % 11);
    png_color_16 key;
    memset(&key, 0, sizeof(key));
    key.gray = 7;
    raw_png gt = {W,    H, 8,   PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, gray, W, NULL, 0,
                  NULL, 0, &key};
    REQUIRE(write_raw_png(path, &gt) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(c == 2);
    bad = 0;
    for (size_t i = 0; i < sizeof(gray); ++i)
        bad += px[2 * i] != gray[i] || px[2 * i + 1] != (gray[i] == 7 ? 0 : 255);
    CHECK_MSG(bad == 0, "%d gray+tRNS pixels differ", bad);
    free(px);

    /* Interlaced 8-bit RGB reads the same as the pixels written. */
    uint8_t rgb[W * H * 3];
    for (size_t i = 0; i < sizeof(rgb); ++i) rgb[i] = (uint8_t)rnd();
    raw_png ri = {W,    H, 8,   PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7, rgb, W * 3, NULL, 0,
                  NULL, 0, NULL};
    REQUIRE(write_raw_png(path, &ri) == 0);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(c == 3 && memcmp(px, rgb, sizeof(rgb)) == 0);
    free(px);
    scratch_remove();
}

static void test_png_from_image(void) {
    static const char *const names[] = {"depth", "R", "G", "B", "A"};
    pgt_image img;
    REQUIRE(pgt_image_create(&img, 4, 2, 5, names, NULL) == PGT_OK);
    const float depth[8] = {-1.0f, 0.0f, 0.25f, 0.5f, 1.0f, 2.0f, NAN, INFINITY};
    memcpy(pgt_image_plane(&img, 0), depth, sizeof(depth));
    for (uint32_t c = 1; c < 5; ++c)
        for (uint32_t i = 0; i < 8; ++i) pgt_image_plane(&img, c)[i] = (float)(c * 10 + i);
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    const char *path = scratch_path("pic.png");
    pgt_error err;
    uint32_t w, h, c;
    uint8_t *px;

    static const char *const d[] = {"depth"};
    REQUIRE(pgt_png_from_image(path, &img, d, 1, 0.0f, 1.0f, &err) == PGT_OK);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    const uint8_t want[8] = {0, 0, 64, 128, 255, 255, 0, 255};
    CHECK(w == 4 && h == 2 && c == 1 && memcmp(px, want, 8) == 0);
    free(px);
    /* lo > hi inverts (near = white). */
    REQUIRE(pgt_png_from_image(path, &img, d, 1, 1.0f, 0.0f, &err) == PGT_OK);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    const uint8_t inv[8] = {255, 255, 191, 128, 0, 0, 0, 0};
    CHECK(memcmp(px, inv, 8) == 0);
    free(px);
    /* Four channels picked by name, interleaved in the order asked. */
    static const char *const abgr[] = {"A", "B", "G", "R"};
    REQUIRE(pgt_png_from_image(path, &img, abgr, 4, 0.0f, 255.0f, &err) == PGT_OK);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(c == 4 && px[0] == 40 && px[1] == 30 && px[2] == 20 && px[3] == 10 && px[31] == 17);
    free(px);
    /* NULL names: the first channels. */
    REQUIRE(pgt_png_from_image(path, &img, NULL, 2, 0.0f, 255.0f, &err) == PGT_OK);
    REQUIRE(read_png(path, &w, &h, &c, &px, &err) == PGT_OK);
    CHECK(c == 2 && px[0] == 0 && px[1] == 10 && px[15] == 17);
    free(px);
    /* Bad requests: nothing written. */
    const char *other = scratch_path("no.png");
    static const char *const missing[] = {"R", "Z"};
    pgt_error_clear(&err);
    CHECK(pgt_png_from_image(other, &img, missing, 2, 0, 1, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "'Z'") != NULL && strstr(err.message, other) != NULL);
    CHECK(pgt_png_from_image(other, &img, d, 1, 0.5f, 0.5f, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_from_image(other, &img, d, 1, 0.0f, NAN, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_from_image(other, &img, NULL, 5, 0, 1, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_from_image(other, &img, NULL, 0, 0, 1, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_from_image(other, NULL, NULL, 1, 0, 1, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(scratch_count() == 1);
    pgt_image_destroy(&img);
    scratch_remove();
}

/* Walks the chunks of a PNG and rewrites every CRC, so that a mutation reaches the decoder
 * instead of failing the CRC check. Stops at a length that runs past the end. */
static void fix_png_crcs(unsigned char *p, size_t size) {
    size_t at = 8;
    while (at + 12 <= size) {
        uint32_t len = (uint32_t)p[at] << 24 | (uint32_t)p[at + 1] << 16 |
                       (uint32_t)p[at + 2] << 8 | p[at + 3];
        if (len > size - at - 12) return;
        uLong crc = crc32(0L, p + at + 4, (uInt)len + 4);
        unsigned char *q = p + at + 8 + len;
        q[0] = (unsigned char)(crc >> 24);
        q[1] = (unsigned char)(crc >> 16);
        q[2] = (unsigned char)(crc >> 8);
        q[3] = (unsigned char)crc;
        at += 12 + len;
    }
}

static void test_png_truncations_and_mutations(void) {
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    enum { W = 16, H = 9 };
    uint8_t px[W * H * 4];
    rng_state = 77;
    for (size_t i = 0; i < sizeof(px); ++i) px[i] = (uint8_t)(i % 7 ? rnd() : 0);
    const char *base = scratch_path("base.png");
    REQUIRE(pgt_png_write(base, W, H, 4, px, NULL) == PGT_OK);
    size_t size = 0;
    unsigned char *data = load_file(base, &size);
    REQUIRE(data != NULL);
    const char *path = scratch_path("cut.png");
    pgt_error err;
    uint32_t w, h, c;
    uint8_t *out;
    int bad = 0;
    for (size_t len = 0; len < size; ++len) {
        REQUIRE(save_file(path, data, len) == 0);
        pgt_result r = read_png(path, &w, &h, &c, &out, &err);
        pgt_result want = len == 0 ? PGT_ERROR_EMPTY : PGT_ERROR_TRUNCATED;
        if (r != want || out != NULL || w || h || c || strstr(err.message, path) != err.message)
            if (bad++ < 5)
                fprintf(stderr, "  %zu of %zu bytes: %s: %s\n", len, size, pgt_result_name(r),
                        err.message);
        if (r == PGT_OK) free(out);
    }
    CHECK_MSG(bad == 0, "%d PNG truncations misreported", bad);

    int ok = 0, failed = 0;
    unsigned char *copy = malloc(size);
    for (int i = 0; i < 1500; ++i) {
        memcpy(copy, data, size);
        int changes = 1 + (int)(rnd() % 3);
        for (int k = 0; k < changes; ++k) {
            size_t span = rnd() % 2 ? size : 60; /* often in IHDR */
            size_t at = rnd() % span;
            copy[at] = (unsigned char)(rnd() % 2 ? rnd() : copy[at] ^ (1u << (rnd() % 8)));
        }
        if (i % 4) fix_png_crcs(copy, size);
        REQUIRE(save_file(path, copy, size) == 0);
        pgt_result r = read_png(path, &w, &h, &c, &out, &err);
        if (r == PGT_OK) {
            ok++;
            CHECK(w >= 1 && w <= PGT_PNG_MAX_SIDE && h >= 1 && h <= PGT_PNG_MAX_SIDE && c >= 1 &&
                  c <= 4 && out != NULL);
            free(out);
        } else {
            failed++;
            CHECK(out == NULL && w == 0 && strstr(err.message, path) == err.message);
        }
    }
    printf("  png (%zu bytes): %d mutants read, %d rejected\n", size, ok, failed);
    free(copy);
    free(data);
    scratch_remove();
}

/* ---- errors that are not about content ---- */

static void test_atomic_writes_and_paths(void) {
    scratch_make();
    REQUIRE(scratch[0] != '\0');
    static const char *const one[] = {"Y"};
    pgt_image a, b, back;
    REQUIRE(pgt_image_create(&a, 8, 4, 1, one, NULL) == PGT_OK);
    REQUIRE(pgt_image_create(&b, 3, 5, 1, one, NULL) == PGT_OK);
    uint8_t px[8 * 4 * 3] = {0};
    pgt_error err;
    char path[512];

    /* A folder that does not exist: IO, naming the path, nothing created. */
    snprintf(path, sizeof(path), "%s/no/such/dir/x.exr", scratch);
    pgt_error_clear(&err);
    CHECK(pgt_image_write_exr(&a, path, &err) == PGT_ERROR_IO && strstr(err.message, path));
    snprintf(path, sizeof(path), "%s/no/such/dir/x.png", scratch);
    pgt_error_clear(&err);
    CHECK(pgt_png_write(path, 8, 4, 3, px, &err) == PGT_ERROR_IO && strstr(err.message, path));
    CHECK(scratch_count() == 0);

    /* Over an existing file: replaced whole, no temporary file left. */
    snprintf(path, sizeof(path), "%s", scratch_path("r.exr"));
    CHECK(pgt_image_write_exr(&a, path, NULL) == PGT_OK);
    CHECK(pgt_image_write_exr(&b, path, NULL) == PGT_OK);
    CHECK(pgt_image_read_exr(&back, path, NULL) == PGT_OK && back.width == 3 && back.height == 5);
    pgt_image_destroy(&back);
    snprintf(path, sizeof(path), "%s", scratch_path("r.png"));
    CHECK(pgt_png_write(path, 8, 4, 3, px, NULL) == PGT_OK);
    CHECK(pgt_png_write(path, 2, 2, 1, px, NULL) == PGT_OK);
    uint32_t w, h, c;
    uint8_t *out;
    CHECK(read_png(path, &w, &h, &c, &out, &err) == PGT_OK && w == 2 && h == 2 && c == 1);
    free(out);
    CHECK(scratch_count() == 2);

    /* The target is a folder: rename fails, the temporary file is removed, the folder stays. */
    snprintf(path, sizeof(path), "%s", scratch_path("dir.exr"));
    REQUIRE(mkdir(path, 0755) == 0);
    pgt_error_clear(&err);
    CHECK(pgt_image_write_exr(&a, path, &err) == PGT_ERROR_IO && strstr(err.message, path));
    pgt_error_clear(&err);
    CHECK(pgt_png_write(path, 8, 4, 3, px, &err) == PGT_ERROR_IO && strstr(err.message, path));
    struct stat st;
    CHECK(stat(path, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(scratch_count() == 3);
    /* Reading a folder or a missing file: IO naming it. */
    pgt_error_clear(&err);
    CHECK(pgt_image_read_exr(&back, path, &err) == PGT_ERROR_IO && strstr(err.message, path));
    CHECK(image_is_zero(&back));
    pgt_error_clear(&err);
    CHECK(read_png(path, &w, &h, &c, &out, &err) == PGT_ERROR_IO && strstr(err.message, path));
    CHECK(out == NULL);
    pgt_error_clear(&err);
    CHECK(pgt_image_read_exr(&back, "/nonexistent/x.exr", &err) == PGT_ERROR_IO);
    CHECK(strstr(err.message, "/nonexistent/x.exr") != NULL);
    CHECK(read_png("/nonexistent/x.png", &w, &h, &c, &out, &err) == PGT_ERROR_IO);
    CHECK(pgt_image_read_exr(&back, NULL, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(read_mem(&back, NULL, 5, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(read_mem(&back, NULL, 0, NULL, &err) == PGT_ERROR_EMPTY);
    CHECK(strncmp(err.message, "<memory>: ", 10) == 0);

    /* PNG arguments refused before anything is written. */
    const char *bad = scratch_path("bad.png");
    CHECK(pgt_png_write(bad, 0, 4, 3, px, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_write(bad, 8, 4, 5, px, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_write(bad, 8, 4, 0, px, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_write(bad, 8, 4, 3, NULL, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_png_write(bad, PGT_PNG_MAX_SIDE + 1, 1, 1, px, NULL) == PGT_ERROR_LIMIT);
    CHECK(pgt_png_write(NULL, 8, 4, 3, px, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(scratch_count() == 3);

    pgt_image_destroy(&a);
    pgt_image_destroy(&b);
    scratch_remove();
}

static const pgt_test_case cases[] = {
    {"exr_round_trip", test_exr_round_trip},
    {"exr_threads", test_exr_threads},
    {"exr_channel_lookup", test_exr_channel_lookup},
    {"image_create_contract", test_image_create_contract},
    {"exr_half_uint_float", test_exr_half_uint_float},
    {"exr_tiled", test_exr_tiled},
    {"exr_constant_images", test_exr_constant_images},
    {"exr_truncations", test_exr_truncations},
    {"exr_garbage_and_mutations", test_exr_garbage_and_mutations},
    {"exr_threads_damaged", test_exr_threads_damaged},
    {"malformed_corpus", test_malformed_corpus},
    {"exr_duplicate_channel", test_exr_duplicate_channel},
    {"tiles_larger_than_image", test_tiles_larger_than_image},
    {"one_part_multipart", test_one_part_multipart},
    {"png_round_trip", test_png_round_trip},
    {"png_variants", test_png_variants},
    {"png_from_image", test_png_from_image},
    {"png_truncations_and_mutations", test_png_truncations_and_mutations},
    {"atomic_writes_and_paths", test_atomic_writes_and_paths},
};

PGT_TEST_MAIN(cases)
