/* pgt: the layout of one CGA split along one axis (paper 003 sections 3 and 6.1; issue 6 item 1).
 *
 * This work is based on:
 *   Paper 003, sec. 3 (the facade grammar F, GF, G, FL in the notation of CGA shape [13]) and
 *   sec. 6.1 ("for each split operation, the generated blocks are represented by intervals": the
 *   grammar is an implicit hierarchical space partition; Algorithm 1 needs the child whose
 *   interval holds the ray's entry point, getSplitIndex(p), and that child's exit).
 *   CityEngine's CGA reference (the split operation; the "Subdivision split" help page with its
 *   worked examples on scopes of length 5 and 10) where the paper is silent.
 *
 * A split cuts a scope of length L along its axis into children [start, end), in part order. The
 * input is the evaluated parts (kind, size) and, optionally, one repeat group: a contiguous run
 * parts[group_first .. +group_count) that repeats (`{ ... }*`; `split(x){ ... }*` is the group of
 * every part). Part indices in the output refer to that flat array: the expander flattens a
 * grammar REPEAT part into it. A child records the part it instantiates and, for group parts,
 * the repetition (0 for the other parts).
 *
 * Semantics (CityEngine's documented behaviour unless the last column says otherwise):
 *
 * | case                     | layout                                  | CityEngine / choice    |
 * | ------------------------ | --------------------------------------- | ---------------------- |
 * | absolute `s`             | exactly s                               | as CityEngine          |
 * | size <= 0, NaN, infinite | no child, takes no room                 | as CityEngine (<= 0)   |
 * | parts past L             | the one crossing L ends at L, the rest  | as CityEngine ("Yellow |
 * |                          | are dropped; a sum below L leaves       | has length 1 instead   |
 * |                          | [sum, L) without a child                | of 2", 3+1=4 of 5)     |
 * | floating `~s`, no group  | all floating parts scaled by one factor | as CityEngine ("weighed|
 * |                          | to fill L - absolutes - relatives; none | proportionally"; Blue  |
 * |                          | left: no floating child                 | not generated)         |
 * | relative `'r`            | r * L (a fraction of the scope's        | as CityEngine ("size * |
 * |                          | length, whatever the other parts)       | current scope size")   |
 * | repeat group with a      | n = max(1, round(A / g)) (halves up),   | as CityEngine ("best   |
 * | floating part            | A = L - the parts outside the group, g  | number of repetitions, |
 * | relative in the split)   | = the group's nominal length; floating  | least stretching"; the |
 * |                          | parts scaled so that n repetitions fill | ~2.1 in 10 -> 5 x 2    |
 * |                          | A exactly; n lowered to floor(A / a) if | example); the lowering |
 * |                          | its absolute parts (length a) would not | is a CHOICE            |
 * |                          | fit n times                             |                        |
 * | repeat group without     | n = floor(A / g) (within                | as CityEngine ("as     |
 * | floating parts           | PGT_SPLIT_FIT_TOL): as often as it fits | often as it fits the   |
 * |                          | completely; [n g, A) is left empty      | scope completely")     |
 * | parts outside a group    | nominal sizes: the group adapts, the    | CHOICE (CityEngine is  |
 * |                          | floating parts outside it do not        | silent)                |
 * | repeat fits zero times   | A <= 0, floor(A / g) = 0 or             | CHOICE for the         |
 * |                          | floor(A / a) = 0: no repetition, the    | floating case          |
 * |                          | outside parts still laid out            |                        |
 * | nothing fits             | L <= 0 or not finite: zero children     |                        |
 *
 * Repeat count, in detail: n = round(A / g) is the nearest whole number of repetitions to A / g;
 * CityEngine's reference asks for the "best number of repetitions, least stretching" without a
 * formula, and round is not the least stretching in every case: ~2 in 2.9 gives 1 x 2.9 (+45 %)
 * where 2 x 1.45 (-27.5 %) stretches less (a review's example). Kept as round, the rule this
 * table states and every shipped figure was made with; a least-stretch rule would pick between
 * floor(q) and ceil(q) by |A / n - g| (or by |log(A / (n g))|).
 *
 * Relative, in detail: CityEngine's reference says "the new shape's size will be size * current
 * scope size", so split(x){2 : A | '0.5 : B} on 10 gives B = 5, and relative parts summing to 1
 * next to absolute ones overflow the scope and are cut at its end like absolute parts.
 *
 * Numbers. Everything is float32 in the order written (-ffp-contract=off), so a GPU port that
 * writes the same operations gets the same bits. No boundary is accumulated over repetitions:
 * repetition i starts at group_start + i * period (two roundings, no drift over 10^6 repeats) and
 * a part inside it at that base plus its offset in the repetition (offsets are accumulated over
 * the group's few parts), clamped to the next repetition's base; the end of one child is
 * computed by the same expression as the start of the next, so children tile without gaps or
 * overlaps bit for bit, and materialised intervals, pgt_split_child_get and pgt_split_child_at
 * agree exactly. Parts outside the group are accumulated from 0 (prefix) or from the group's end
 * (suffix); a boundary within PGT_SPLIT_SNAP_REL * L of L is set to L, so layouts meant to fill
 * (floating parts, shares summing to 1) end at L exactly. Rare rounding can leave a repeated
 * child of zero width (never returned by pgt_split_child_at).
 *
 * Queries do not materialise the children: pgt_split_build resolves the parts once into a
 * pgt_split_plan plus one pgt_split_slot per part (caller-owned, no allocation anywhere here),
 * then pgt_split_child_at finds the child holding a coordinate in O(1) for the repetition (a
 * division, corrected by at most a step or two against the rounded bases) plus O(log parts) by
 * binary search, and pgt_split_child_get returns child k the same way (Algorithm 1 steps to index
 * +- 1). No recursion. */
#ifndef PGT_SPLIT_H
#define PGT_SPLIT_H

#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Part kinds; the values equal pgt_grammar_part_kind's ABSOLUTE, RELATIVE and FLOATING. */
typedef enum pgt_split_kind {
    PGT_SPLIT_ABSOLUTE = 0, /* s: exactly s */
    PGT_SPLIT_RELATIVE = 1, /* 's: s times the scope's whole length (the table above) */
    PGT_SPLIT_FLOATING = 2  /* ~s: s, stretched or shrunk to fill */
} pgt_split_kind;

/* Children of one split, at most: the repetitions of a group are cut to fit (the plan's
 * PGT_SPLIT_CAPPED flag says so). 2^24 keeps the repetition index exact in float32 (i * period)
 * and every count well inside uint32 whatever the number of parts. */
#define PGT_SPLIT_MAX_CHILDREN (1u << 24)

/* A boundary at or beyond L - L * PGT_SPLIT_SNAP_REL is L. Accumulating k sizes rounds at most
 * k / 2 ulps of L away from the exact sum; 2^-16 (128 ulps at the top of L's binade) covers
 * splits of ~200 parts. The price: a child narrower than L / 65536 at the very end (0.2 mm on a
 * 13 m facade) merges into its neighbour. */
#define PGT_SPLIT_SNAP_REL (1.0f / 65536.0f)

/* A repetition fits when it overshoots the available length by less than this fraction of the
 * group's length: sizes written in decimal are not exact in binary (3 x 0.1f exceeds 0.3f), and
 * the user means them to fit. The overshoot is clipped from the last repetition. */
#define PGT_SPLIT_FIT_TOL 1e-4f

/* pgt_split_plan.flags */
#define PGT_SPLIT_CAPPED 1u /* the group would repeat past PGT_SPLIT_MAX_CHILDREN children */

/* One evaluated part. */
typedef struct pgt_split_part {
    uint32_t kind; /* pgt_split_kind */
    float size;    /* the evaluated size expression */
} pgt_split_part;

/* One child: the interval [start, end) on the axis (0 at the scope's start), the part it
 * instantiates (index into the parts array) and, for group parts, the repetition (else 0). */
typedef struct pgt_split_child {
    float start, end;
    uint32_t part;
    uint32_t repetition;
} pgt_split_child;

/* A resolved part. Outside the group, [start, end) is the child's interval on the axis (start ==
 * end when the part has no child); in the group, start and end are its offsets inside one
 * repetition before clamping. rank counts the children of the part's segment (before the group,
 * one repetition, after the group) that come before it; is_child is 1 when it makes a child. */
typedef struct pgt_split_slot {
    float start, end;
    uint32_t rank;
    uint32_t is_child;
} pgt_split_slot;

/* A resolved split: with its slots, everything the queries need. */
typedef struct pgt_split_plan {
    float length;                 /* L, or 0 when L was <= 0 or not finite */
    uint32_t part_count;          /* parts (and slots) */
    uint32_t group_first;         /* the repeat group, parts[group_first .. +group_count) */
    uint32_t group_count;         /* 0: no group (every part is "before the group") */
    uint32_t repetitions;         /* n; 0 without a group or when it fits zero times */
    float group_start, group_end; /* where the repetitions lie; equal when n == 0 */
    float period;                 /* length of one repetition */
    float group_span;             /* offset of the group's end inside a repetition */
    uint32_t prefix_children;     /* children of the parts before the group */
    uint32_t group_children;      /* children of one repetition */
    uint32_t suffix_children;     /* children of the parts after the group */
    uint32_t child_count;         /* prefix + repetitions * group + suffix */
    uint32_t flags;               /* PGT_SPLIT_CAPPED */
} pgt_split_plan;

/* Resolves a split: parts[0 .. part_count) with the repeat group parts[group_first ..
 * +group_count) (group_count 0: none; the group must lie inside the parts) on a scope of length
 * `length`. Writes *out_plan and, when out_slots is not NULL, out_slots[0 .. part_count). */
void pgt_split_build(pgt_split_plan *out_plan, pgt_split_slot *out_slots,
                     const pgt_split_part *parts, uint32_t part_count, uint32_t group_first,
                     uint32_t group_count, float length);

/* How many children the split makes (to size a buffer for pgt_split_layout). */
uint32_t pgt_split_count(const pgt_split_part *parts, uint32_t part_count, uint32_t group_first,
                         uint32_t group_count, float length);

/* Writes the children in order into dst[0 .. min(count, capacity)) and returns count, the
 * number of children (as pgt_split_count); dst may be NULL when capacity is 0. */
uint32_t pgt_split_layout(pgt_split_child *dst, uint32_t capacity, const pgt_split_part *parts,
                          uint32_t part_count, uint32_t group_first, uint32_t group_count,
                          float length);

/* Child `index` of a built split (the same bits as pgt_split_layout's dst[index]). Returns
 * index, or PGT_NONE (out untouched) when index >= child_count. O(log parts). */
uint32_t pgt_split_child_get(const pgt_split_plan *plan, const pgt_split_slot *slots,
                             uint32_t index, pgt_split_child *out);

/* The child holding coordinate t: with direction >= 0 the one with start <= t < end, with
 * direction < 0 the one with start < t <= end (a ray travelling towards -axis that enters at
 * t = L is in the last child, not outside). Returns its index and writes *out, or returns
 * PGT_NONE (out untouched) when no child holds t (t outside [0, L], in a gap, or NaN). O(1) for
 * the repetition plus O(log parts); nothing is materialised. */
uint32_t pgt_split_child_at(const pgt_split_plan *plan, const pgt_split_slot *slots, float t,
                            int direction, pgt_split_child *out);

/* pgt_split_child_at on children already materialised (start[k], end[k] of child k, as
 * pgt_split_layout or pgt_split_child_get give them, n of them): the same index for every t and
 * direction (tests/test_split.c checks both against the layout). A binary search over n; for a
 * caller that queries one split many times. */
uint32_t pgt_split_flat_at(const float *start, const float *end, uint32_t n, float t,
                           int direction);

#ifdef __cplusplus
}
#endif

#endif
