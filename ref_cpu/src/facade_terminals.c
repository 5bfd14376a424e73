/* pgt: the facade terminals as parametric surface sets (paper 003 sec. 6.2.1, Fig. 7).
 *
 * Every terminal is a set of axis-aligned rectangles in facade space, built here once for the
 * ray test and the explicit expansion alike. Within the scope [0, w] x [0, h] (block-local X, Y;
 * Z out of the wall), with sizes clamped to be >= 0:
 *
 * Window(m, f, fd, r, sh, sd): the frame's outer rectangle is [m, w - m] x [m + sh, h - m]; the
 * opening is that rectangle shrunk by f; the sill is the box [m, w - m] x [m, m + sh] x [0, sd];
 * the frame is a ring protruding to z = fd; the opening's reveal goes from z = fd back to z = -r
 * where the glass is. The wall (z = 0) covers the rest of the scope. Surfaces (ids):
 *   0-3 wall strips (bottom, top, left, right); 4 sill front; 5 sill bottom; 6, 7 sill sides;
 *   8 the sill's top where the frame does not sit on it (sd > fd); 9 the frame's underside where
 *   it overhangs the sill (fd > sd); 10-13 frame front bars (bottom, top, left, right); 14-16
 *   frame outer sides (top, left, right); 17-20 reveal (bottom, top, left, right); 21 glass;
 *   22 the sill's back and 23-26 the frame bars' backs, in the wall plane (see "Closed").
 * The opening must be non-empty (w - 2 m - 2 f > 0 and h - 2 m - sh - 2 f > 0), else Wall().
 *
 * Door(m, f, fd, r): the same without sill and bottom margin, the opening down to Y = 0.
 *   0-2 wall (top, left, right); 3-5 frame front bars (top, left, right); 6-8 frame outer sides
 *   (top, left, right); 9-11 reveal (top, left, right); 12 door leaf at z = -r; 13 threshold
 *   (Y = 0, z in [-r, 0]: the floor of the recess, else a ray looking down into it leaks out);
 *   14-16 the frame bars' backs.
 *   Needs w - 2 m - 2 f > 0 and h - m - f > 0, else Wall().
 *
 * Ledge(d): the box [0, w] x [0, h] x [0, d]: 0 front, 1 top, 2 bottom, 3 left, 4 right, 5 back.
 *
 * Balcony(d, s, rl): the slab [i, w - i] x [0, s] x [0, d] (0 front, 1 top, 2 bottom, 3 left,
 *   4 right) and a railing of height rl on it: 5 front panel at z = d, 6 left and 7 right
 *   panels; s and s + rl are clamped to h; i = BALCONY_INSET w keeps its sides off the scope's
 *   edges, where a neighbour's box side would be coplanar with a railing panel (two surfaces
 *   in one place: which one a ray hits would be a coin toss). No wall: a Window in the same
 *   scope gives it.
 *
 * Closed. The wall plane z = 0 is closed behind every protruding solid (sill, frame, ledge): a
 * ray from inside a building (buildings have no roofs) meets a back face before it could reach
 * the inside of a solid, where two terminals touch (a pillar standing on a ledge) and their
 * coplanar faces would make the nearest hit a coin toss. A back is emitted only when its solid
 * has depth; else the front face itself lies in the wall plane.
 *
 * Rectangles of zero area (a frame of depth 0 has no sides) keep their id with hi[0] = lo[0]. */
#include <math.h>

#include "pgt/facade.h"
#include "pgt/grammar.h"

/* A balcony leaves this share of its scope's width free on each side. */
#define BALCONY_INSET 0.05f

typedef struct qbuf {
    pgt_facade_quad *q;
    uint32_t n;
    float x0, y0; /* the scope's origin on the facade */
} qbuf;

static float nonneg(float v) { return v > 0.0f ? v : 0.0f; /* NaN too */ }

/* Surface ids are the order of the calls below. A rectangle of zero area stays in the list with
 * hi[0] = lo[0], so that the ids never shift; the ray test and the explicit expansion skip it. */
static void put(qbuf *b, uint32_t axis, float c, float lo0, float hi0, float lo1, float hi1) {
    pgt_facade_quad *q = &b->q[b->n++];
    /* block-local to facade space: X += x0 on the x axis, Y += y0 on the y axis */
    const float off[3] = {b->x0, b->y0, 0.0f};
    static const uint32_t other[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    q->axis = axis;
    q->c = c + off[axis];
    q->lo[0] = lo0 + off[other[axis][0]];
    q->hi[0] = hi0 + off[other[axis][0]];
    q->lo[1] = lo1 + off[other[axis][1]];
    q->hi[1] = hi1 + off[other[axis][1]];
    if (!(hi0 > lo0 && hi1 > lo1)) q->hi[0] = q->lo[0]; /* empty: skipped */
}

/* X = const, over Y and Z */
static void qx(qbuf *b, float x, float y0, float y1, float z0, float z1) {
    put(b, 0, x, y0, y1, z0, z1);
}
/* Y = const, over X and Z */
static void qy(qbuf *b, float y, float x0, float x1, float z0, float z1) {
    put(b, 1, y, x0, x1, z0, z1);
}
/* Z = const, over X and Y */
static void qz(qbuf *b, float z, float x0, float x1, float y0, float y1) {
    put(b, 2, z, x0, x1, y0, y1);
}

static uint32_t wall(qbuf *b, float w, float h) {
    qz(b, 0.0f, 0.0f, w, 0.0f, h);
    return b->n;
}

uint32_t pgt_facade_kind_of(uint32_t grammar_terminal) {
    switch (grammar_terminal) {
    case PGT_GRAMMAR_TERMINAL_WALL:
        return PGT_FACADE_WALL;
    case PGT_GRAMMAR_TERMINAL_WINDOW:
        return PGT_FACADE_WINDOW;
    case PGT_GRAMMAR_TERMINAL_DOOR:
        return PGT_FACADE_DOOR;
    case PGT_GRAMMAR_TERMINAL_LEDGE:
        return PGT_FACADE_LEDGE;
    case PGT_GRAMMAR_TERMINAL_BALCONY:
        return PGT_FACADE_BALCONY;
    case PGT_GRAMMAR_TERMINAL_MESH:
        return PGT_FACADE_MESH;
    default:
        return PGT_FACADE_MISS;
    }
}

uint32_t pgt_facade_terminal_quads(uint32_t kind, const float *args, uint32_t arg_count, float x0,
                                   float y0, float w, float h, pgt_facade_quad *out) {
    qbuf b = {out, 0, x0, y0};
    float a[6] = {0, 0, 0, 0, 0, 0};
    for (uint32_t k = 0; k < arg_count && k < 6; ++k) a[k] = nonneg(args[k]);
    w = nonneg(w), h = nonneg(h);
    switch (kind) {
    case PGT_FACADE_WINDOW: {
        const float m = a[0], f = a[1], fd = a[2], r = a[3], sh = a[4], sd = a[5];
        const float ox0 = m, ox1 = w - m, ys = m + sh, oy1 = h - m;
        const float ix0 = ox0 + f, ix1 = ox1 - f, iy0 = ys + f, iy1 = oy1 - f;
        if (!(ix1 > ix0 && iy1 > iy0)) return wall(&b, w, h);
        qz(&b, 0.0f, 0.0f, w, 0.0f, m);  /* 0 wall bottom */
        qz(&b, 0.0f, 0.0f, w, oy1, h);   /* 1 wall top */
        qz(&b, 0.0f, 0.0f, ox0, m, oy1); /* 2 wall left */
        qz(&b, 0.0f, ox1, w, m, oy1);    /* 3 wall right */
        qz(&b, sd, ox0, ox1, m, ys);     /* 4 sill front */
        qy(&b, m, ox0, ox1, 0.0f, sd);   /* 5 sill bottom */
        qx(&b, ox0, m, ys, 0.0f, sd);    /* 6 sill left */
        qx(&b, ox1, m, ys, 0.0f, sd);    /* 7 sill right */
        qy(&b, ys, ox0, ox1, fd, sd);    /* 8 sill top beyond the frame */
        qy(&b, ys, ox0, ox1, sd, fd);    /* 9 frame underside beyond the sill */
        qz(&b, fd, ox0, ox1, ys, iy0);   /* 10 frame bottom bar */
        qz(&b, fd, ox0, ox1, iy1, oy1);  /* 11 frame top bar */
        qz(&b, fd, ox0, ix0, iy0, iy1);  /* 12 frame left bar */
        qz(&b, fd, ix1, ox1, iy0, iy1);  /* 13 frame right bar */
        qy(&b, oy1, ox0, ox1, 0.0f, fd); /* 14 frame top side */
        qx(&b, ox0, ys, oy1, 0.0f, fd);  /* 15 frame left side */
        qx(&b, ox1, ys, oy1, 0.0f, fd);  /* 16 frame right side */
        qy(&b, iy0, ix0, ix1, -r, fd);   /* 17 reveal bottom */
        qy(&b, iy1, ix0, ix1, -r, fd);   /* 18 reveal top */
        qx(&b, ix0, iy0, iy1, -r, fd);   /* 19 reveal left */
        qx(&b, ix1, iy0, iy1, -r, fd);   /* 20 reveal right */
        qz(&b, -r, ix0, ix1, iy0, iy1);  /* 21 glass */
        /* backs in the wall plane, where the solids have depth (see the comment above) */
        const float sb = sd > 0.0f ? ox1 : ox0, fb = fd > 0.0f ? 1.0f : 0.0f;
        qz(&b, 0.0f, ox0, sb, m, ys);                        /* 22 sill back */
        qz(&b, 0.0f, ox0, ox0 + fb * (ox1 - ox0), ys, iy0);  /* 23 frame bottom bar back */
        qz(&b, 0.0f, ox0, ox0 + fb * (ox1 - ox0), iy1, oy1); /* 24 frame top bar back */
        qz(&b, 0.0f, ox0, ox0 + fb * (ix0 - ox0), iy0, iy1); /* 25 frame left bar back */
        qz(&b, 0.0f, ix1, ix1 + fb * (ox1 - ix1), iy0, iy1); /* 26 frame right bar back */
        return b.n;
    }
    case PGT_FACADE_DOOR: {
        const float m = a[0], f = a[1], fd = a[2], r = a[3];
        const float ox0 = m, ox1 = w - m, oy1 = h - m;
        const float ix0 = ox0 + f, ix1 = ox1 - f, iy1 = oy1 - f;
        if (!(ix1 > ix0 && iy1 > 0.0f)) return wall(&b, w, h);
        qz(&b, 0.0f, 0.0f, w, oy1, h);      /* 0 wall top */
        qz(&b, 0.0f, 0.0f, ox0, 0.0f, oy1); /* 1 wall left */
        qz(&b, 0.0f, ox1, w, 0.0f, oy1);    /* 2 wall right */
        qz(&b, fd, ox0, ox1, iy1, oy1);     /* 3 frame top bar */
        qz(&b, fd, ox0, ix0, 0.0f, iy1);    /* 4 frame left bar */
        qz(&b, fd, ix1, ox1, 0.0f, iy1);    /* 5 frame right bar */
        qy(&b, oy1, ox0, ox1, 0.0f, fd);    /* 6 frame top side */
        qx(&b, ox0, 0.0f, oy1, 0.0f, fd);   /* 7 frame left side */
        qx(&b, ox1, 0.0f, oy1, 0.0f, fd);   /* 8 frame right side */
        qy(&b, iy1, ix0, ix1, -r, fd);      /* 9 reveal top */
        qx(&b, ix0, 0.0f, iy1, -r, fd);     /* 10 reveal left */
        qx(&b, ix1, 0.0f, iy1, -r, fd);     /* 11 reveal right */
        qz(&b, -r, ix0, ix1, 0.0f, iy1);    /* 12 door leaf */
        qy(&b, 0.0f, ix0, ix1, -r, 0.0f);   /* 13 threshold */
        const float fb = fd > 0.0f ? 1.0f : 0.0f;
        qz(&b, 0.0f, ox0, ox0 + fb * (ox1 - ox0), iy1, oy1);  /* 14 frame top bar back */
        qz(&b, 0.0f, ox0, ox0 + fb * (ix0 - ox0), 0.0f, iy1); /* 15 frame left bar back */
        qz(&b, 0.0f, ix1, ix1 + fb * (ox1 - ix1), 0.0f, iy1); /* 16 frame right bar back */
        return b.n;
    }
    case PGT_FACADE_LEDGE: {
        const float d = a[0];
        qz(&b, d, 0.0f, w, 0.0f, h);                      /* 0 front */
        qy(&b, h, 0.0f, w, 0.0f, d);                      /* 1 top */
        qy(&b, 0.0f, 0.0f, w, 0.0f, d);                   /* 2 bottom */
        qx(&b, 0.0f, 0.0f, h, 0.0f, d);                   /* 3 left */
        qx(&b, w, 0.0f, h, 0.0f, d);                      /* 4 right */
        qz(&b, 0.0f, 0.0f, d > 0.0f ? w : 0.0f, 0.0f, h); /* 5 back */
        return b.n;
    }
    case PGT_FACADE_BALCONY: {
        const float d = a[0], s = fminf(a[1], h), top = fminf(a[1] + a[2], h);
        const float x0 = BALCONY_INSET * w, x1 = w - BALCONY_INSET * w;
        qz(&b, d, x0, x1, 0.0f, s);    /* 0 slab front */
        qy(&b, s, x0, x1, 0.0f, d);    /* 1 slab top */
        qy(&b, 0.0f, x0, x1, 0.0f, d); /* 2 slab bottom */
        qx(&b, x0, 0.0f, s, 0.0f, d);  /* 3 slab left */
        qx(&b, x1, 0.0f, s, 0.0f, d);  /* 4 slab right */
        qz(&b, d, x0, x1, s, top);     /* 5 railing front */
        qx(&b, x0, s, top, 0.0f, d);   /* 6 railing left */
        qx(&b, x1, s, top, 0.0f, d);   /* 7 railing right */
        return b.n;
    }
    case PGT_FACADE_WALL:
        return wall(&b, w, h);
    default:
        return 0;
    }
}
