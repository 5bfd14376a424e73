/* pgt: the layout of one CGA split (split.h; paper 003 sections 3 and 6.1, CityEngine's split).
 *
 * One function, run(), resolves the sizes, chooses the repetitions and walks the boundaries; it
 * fills the plan and slots (pgt_split_build) or writes the children (pgt_split_layout) with the
 * same float operations in the same order, so both give the same bits. The queries recompute a
 * boundary with the same expressions from the plan and the slots. */
#include "pgt/split.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "pgt/grammar.h"

_Static_assert(PGT_SPLIT_ABSOLUTE == (int)PGT_GRAMMAR_PART_ABSOLUTE &&
                   PGT_SPLIT_RELATIVE == (int)PGT_GRAMMAR_PART_RELATIVE &&
                   PGT_SPLIT_FLOATING == (int)PGT_GRAMMAR_PART_FLOATING,
               "split kinds are the grammar's part kinds");

/* The factors that turn a part's evaluated size into its length. */
typedef struct resolve {
    float rel_base;    /* R: the scope's length L, for relative parts */
    float float_out;   /* factor of floating parts outside the group (1: nominal) */
    float float_group; /* factor of floating parts inside the group (1: nominal) */
} resolve;

static int active(const pgt_split_part *p) { return isfinite(p->size) && p->size > 0.0f; }

/* The length of a part: 0 means no child (split.h's table). */
static float resolve_size(const resolve *r, const pgt_split_part *p, int in_group) {
    if (!active(p)) return 0.0f;
    float s = 0.0f;
    switch (p->kind) {
    case PGT_SPLIT_ABSOLUTE:
        s = p->size;
        break;
    case PGT_SPLIT_RELATIVE:
        s = p->size * r->rel_base;
        break;
    case PGT_SPLIT_FLOATING:
        s = p->size * (in_group ? r->float_group : r->float_out);
        break;
    default:
        assert(!"unknown split part kind");
        return 0.0f;
    }
    return isfinite(s) && s > 0.0f ? s : 0.0f;
}

/* The end of a part of length s starting at x, on a scope ending at L: parts past L are cut at
 * L (CityEngine), and a boundary within the snap distance of L is L (split.h, Numbers). */
static float advance(float x, float s, float L, float snap_from) {
    if (!(s > 0.0f)) return x;
    const float e = x + s;
    return e >= snap_from ? L : e;
}

/* Where repetition i starts (i == n: where the group ends): no accumulation over repetitions. */
static float rep_base(const pgt_split_plan *p, uint32_t i) {
    if (i >= p->repetitions) return p->group_end;
    const float b = p->group_start + (float)i * p->period;
    return b < p->group_end ? b : p->group_end;
}

/* The boundary at offset o inside repetition i: offsets at the group's end are the next
 * repetition's base, so consecutive repetitions share their boundary bit for bit. */
static float group_boundary(const pgt_split_plan *p, uint32_t i, float o) {
    const float next = rep_base(p, i + 1);
    if (o >= p->group_span) return next;
    const float x = rep_base(p, i) + o;
    return x < next ? x : next;
}

static void emit(pgt_split_child *dst, uint32_t capacity, uint32_t index, float start, float end,
                 uint32_t part, uint32_t repetition) {
    if (index >= capacity) return;
    dst[index].start = start;
    dst[index].end = end;
    dst[index].part = part;
    dst[index].repetition = repetition;
}

/* Lays out parts[begin .. end) one after the other from x; returns where they end. Fills their
 * slots, writes their children from index *next on, and counts them into *children. */
static float walk(const resolve *r, const pgt_split_part *parts, uint32_t begin, uint32_t end,
                  float x, float L, float snap_from, pgt_split_slot *slots, pgt_split_child *dst,
                  uint32_t capacity, uint32_t *next, uint32_t *children) {
    for (uint32_t k = begin; k < end; ++k) {
        const float e = advance(x, resolve_size(r, &parts[k], 0), L, snap_from);
        const uint32_t is_child = e > x;
        if (slots) {
            slots[k].start = x;
            slots[k].end = e;
            slots[k].rank = *children;
            slots[k].is_child = is_child;
        }
        if (is_child) {
            emit(dst, capacity, (*next)++, x, e, k, 0);
            (*children)++;
        }
        x = e;
    }
    return x;
}

/* The number of repetitions for quotient q = available / length, rounded (floating) or floored
 * (absolute) after PGT_SPLIT_FIT_TOL, at most cap; sets *capped when cut. */
static uint32_t repetitions(float q, int round_it, uint32_t cap, int *capped) {
    const float v = round_it ? floorf(q + 0.5f) : floorf(q + PGT_SPLIT_FIT_TOL);
    if (!(v >= 0.0f)) return 0; /* NaN cannot happen (q is finite or +inf), negative can */
    if (!(v < (float)cap)) {
        if (v > (float)cap) *capped = 1;
        return cap;
    }
    return (uint32_t)v;
}

static void run(pgt_split_plan *plan, pgt_split_slot *slots, pgt_split_child *dst,
                uint32_t capacity, const pgt_split_part *parts, uint32_t part_count,
                uint32_t group_first, uint32_t group_count, float length) {
    assert(part_count == 0 || parts);
    assert(group_count == 0 ||
           (group_first <= part_count && group_count <= part_count - group_first));
    memset(plan, 0, sizeof(*plan));
    if (group_count == 0) group_first = part_count;
    const uint32_t group_end = group_first + group_count;
    plan->part_count = part_count;
    plan->group_first = group_first;
    plan->group_count = group_count;
    if (slots) memset(slots, 0, (size_t)part_count * sizeof(*slots));
    if (!(length > 0.0f) || !isfinite(length)) return;
    const float L = length, snap_from = L - L * PGT_SPLIT_SNAP_REL;
    plan->length = L;

    /* Nominal sums over the active parts, a group's parts once. */
    float abs_sum = 0.0f, float_sum = 0.0f, rel_sum = 0.0f;
    for (uint32_t k = 0; k < part_count; ++k) {
        if (!active(&parts[k])) continue;
        if (parts[k].kind == PGT_SPLIT_ABSOLUTE) abs_sum += parts[k].size;
        if (parts[k].kind == PGT_SPLIT_FLOATING) float_sum += parts[k].size;
        if (parts[k].kind == PGT_SPLIT_RELATIVE) rel_sum += parts[k].size;
    }
    /* Relative parts are r times the scope's length (CityEngine: "size * current scope size").
     * Without a group, floating parts fill what the absolute and relative parts leave; with a
     * group, the group adapts instead. */
    resolve r = {L, 1.0f, 1.0f};
    if (group_count == 0 && float_sum > 0.0f) {
        const float left = L - abs_sum - rel_sum * L;
        r.float_out = left > 0.0f ? left / float_sum : 0.0f;
    }

    uint32_t next = 0; /* index of the next child written */
    float x = walk(&r, parts, 0, group_first, 0.0f, L, snap_from, slots, dst, capacity, &next,
                   &plan->prefix_children);
    plan->group_start = plan->group_end = x;

    if (group_count > 0) {
        /* Outside the group every part has its nominal size (float_out is 1 here). */
        float outside = 0.0f;
        for (uint32_t k = 0; k < part_count; ++k)
            if (k < group_first || k >= group_end) outside += resolve_size(&r, &parts[k], 0);
        const float avail = L - outside;
        float fixed = 0.0f, floating = 0.0f; /* one repetition: absolute and relative, floating */
        uint32_t active_parts = 0;
        for (uint32_t k = group_first; k < group_end; ++k) {
            const float s = resolve_size(&r, &parts[k], 1);
            if (!(s > 0.0f)) continue;
            active_parts++;
            if (parts[k].kind == PGT_SPLIT_FLOATING)
                floating += s;
            else
                fixed += s;
        }
        const float nominal = fixed + floating;
        const int stretch = floating > 0.0f;
        const uint32_t cap = active_parts ? PGT_SPLIT_MAX_CHILDREN / active_parts : 0;
        int capped = 0;
        uint32_t n = 0;
        if (avail > 0.0f && nominal > 0.0f && cap > 0) {
            if (stretch) {
                n = repetitions(avail / nominal, 1, cap, &capped);
                if (n < 1) n = 1;
                if (fixed > 0.0f) { /* the absolute parts must fit n times */
                    int unused = 0;
                    const uint32_t most = repetitions(avail / fixed, 0, cap, &unused);
                    if (most < n) n = most;
                }
            } else {
                n = repetitions(avail / nominal, 0, cap, &capped);
            }
        }
        if (capped) plan->flags |= PGT_SPLIT_CAPPED;
        plan->repetitions = n;
        if (n > 0) {
            float period = nominal;
            if (stretch) {
                period = avail / (float)n;
                const float left = period - fixed;
                r.float_group = left > 0.0f ? left / floating : 0.0f;
            }
            plan->period = period;
            /* The group's end: exactly A for a stretched group; n periods, clipped to A by
             * PGT_SPLIT_FIT_TOL, otherwise; never past L. */
            float g1 = stretch ? x + avail : x + (float)n * period;
            if (!stretch && g1 > x + avail) g1 = x + avail;
            if (g1 >= snap_from) g1 = L;
            plan->group_end = g1;
        }
        /* Offsets inside one repetition. */
        float o = 0.0f;
        uint32_t rank = 0;
        for (uint32_t k = group_first; k < group_end; ++k) {
            const float s = n > 0 ? resolve_size(&r, &parts[k], 1) : 0.0f;
            const float o1 = o + s;
            if (slots) {
                slots[k].start = o;
                slots[k].end = o1;
                slots[k].rank = rank;
                slots[k].is_child = s > 0.0f;
            }
            rank += s > 0.0f;
            o = o1;
        }
        plan->group_span = o;
        plan->group_children = rank;
        if (dst && capacity > next) {
            for (uint32_t i = 0; i < n && next < capacity; ++i) {
                float oi = 0.0f;
                for (uint32_t k = group_first; k < group_end; ++k) {
                    const float s = resolve_size(&r, &parts[k], 1);
                    const float o1 = oi + s;
                    if (s > 0.0f)
                        emit(dst, capacity, next++, group_boundary(plan, i, oi),
                             group_boundary(plan, i, o1), k, i);
                    oi = o1;
                }
            }
        }
        next = plan->prefix_children + n * plan->group_children;
        x = plan->group_end;
        /* After the group, floating parts keep their nominal size too. */
        walk(&r, parts, group_end, part_count, x, L, snap_from, slots, dst, capacity, &next,
             &plan->suffix_children);
    }
    plan->child_count =
        plan->prefix_children + plan->repetitions * plan->group_children + plan->suffix_children;
}

void pgt_split_build(pgt_split_plan *out_plan, pgt_split_slot *out_slots,
                     const pgt_split_part *parts, uint32_t part_count, uint32_t group_first,
                     uint32_t group_count, float length) {
    run(out_plan, out_slots, NULL, 0, parts, part_count, group_first, group_count, length);
}

uint32_t pgt_split_count(const pgt_split_part *parts, uint32_t part_count, uint32_t group_first,
                         uint32_t group_count, float length) {
    pgt_split_plan plan;
    run(&plan, NULL, NULL, 0, parts, part_count, group_first, group_count, length);
    return plan.child_count;
}

uint32_t pgt_split_layout(pgt_split_child *dst, uint32_t capacity, const pgt_split_part *parts,
                          uint32_t part_count, uint32_t group_first, uint32_t group_count,
                          float length) {
    assert(capacity == 0 || dst);
    pgt_split_plan plan;
    run(&plan, NULL, dst, capacity, parts, part_count, group_first, group_count, length);
    return plan.child_count;
}

/* The last slot in [begin, end) whose rank is <= rank (ranks never decrease): the child of that
 * rank is the last slot holding it, since the slot after a child has a rank one higher. */
static uint32_t slot_of_rank(const pgt_split_slot *slots, uint32_t begin, uint32_t end,
                             uint32_t rank) {
    uint32_t lo = begin, hi = end; /* answer in [lo, hi) */
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (slots[mid].rank <= rank)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

uint32_t pgt_split_child_get(const pgt_split_plan *plan, const pgt_split_slot *slots,
                             uint32_t index, pgt_split_child *out) {
    if (index >= plan->child_count) return PGT_NONE;
    const uint32_t in_group = plan->repetitions * plan->group_children;
    uint32_t k, rep = 0;
    float start, end;
    if (index < plan->prefix_children) {
        k = slot_of_rank(slots, 0, plan->group_first, index);
        start = slots[k].start, end = slots[k].end;
    } else if (index - plan->prefix_children < in_group) {
        const uint32_t j = index - plan->prefix_children;
        rep = j / plan->group_children;
        k = slot_of_rank(slots, plan->group_first, plan->group_first + plan->group_count,
                         j % plan->group_children);
        start = group_boundary(plan, rep, slots[k].start);
        end = group_boundary(plan, rep, slots[k].end);
    } else {
        k = slot_of_rank(slots, plan->group_first + plan->group_count, plan->part_count,
                         index - plan->prefix_children - in_group);
        start = slots[k].start, end = slots[k].end;
    }
    assert(slots[k].is_child);
    out->start = start;
    out->end = end;
    out->part = k;
    out->repetition = rep;
    return index;
}

/* Whether boundary b is at or before t for the search: b <= t, or b < t going towards -axis. */
static int before(float b, float t, int neg) { return neg ? b < t : b <= t; }

/* The last slot in [begin, end) whose start is before t (begin - 1 when none): starts never
 * decrease. In the group, starts are offsets of repetition rep. */
static uint32_t slot_before(const pgt_split_plan *plan, const pgt_split_slot *slots, uint32_t begin,
                            uint32_t end, int grouped, uint32_t rep, float t, int neg) {
    uint32_t lo = begin, hi = end; /* the first slot not before t is in [lo, hi] */
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        const float s = grouped ? group_boundary(plan, rep, slots[mid].start) : slots[mid].start;
        if (before(s, t, neg))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo - 1; /* wraps to PGT_NONE-like when lo == begin == 0: the caller checks */
}

uint32_t pgt_split_child_at(const pgt_split_plan *plan, const pgt_split_slot *slots, float t,
                            int direction, pgt_split_child *out) {
    if (plan->child_count == 0 || isnan(t)) return PGT_NONE;
    const int neg = direction < 0;
    const uint32_t gf = plan->group_first, ge = gf + plan->group_count, n = plan->repetitions;
    uint32_t begin, end, offset, rep = 0;
    int grouped = 0;
    if (!before(plan->group_start, t, neg)) { /* before the group (everything without one) */
        begin = 0, end = gf, offset = 0;
    } else if (n > 0 && !before(plan->group_end, t, neg)) {
        /* The repetition from one division, then at most a step or two against the rounded
         * bases (group_start + i * period rounds, and i * period is clamped at the end). */
        const float u = (t - plan->group_start) / plan->period;
        rep = u >= (float)n ? n - 1 : u > 0.0f ? (uint32_t)u : 0;
        while (rep > 0 && !before(rep_base(plan, rep), t, neg)) rep--;
        while (rep + 1 < n && before(rep_base(plan, rep + 1), t, neg)) rep++;
        begin = gf, end = ge, grouped = 1;
        offset = plan->prefix_children + rep * plan->group_children;
    } else {
        begin = ge, end = plan->part_count;
        offset = plan->prefix_children + n * plan->group_children;
    }
    if (begin == end) return PGT_NONE;
    const uint32_t k = slot_before(plan, slots, begin, end, grouped, rep, t, neg);
    if (k == begin - 1u || !slots[k].is_child) return PGT_NONE;
    const float s = grouped ? group_boundary(plan, rep, slots[k].start) : slots[k].start;
    const float e = grouped ? group_boundary(plan, rep, slots[k].end) : slots[k].end;
    if (neg ? !(t <= e) : !(t < e)) return PGT_NONE;
    out->start = s;
    out->end = e;
    out->part = k;
    out->repetition = rep;
    return offset + slots[k].rank;
}

uint32_t pgt_split_flat_at(const float *start, const float *end, uint32_t n, float t,
                           int direction) {
    /* the first child ending after t (direction >= 0) or at or after t (< 0); children are
     * ordered and do not overlap, so only it can hold t. NaN fails every comparison: none. */
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2u;
        if (direction >= 0 ? end[mid] > t : end[mid] >= t)
            hi = mid;
        else
            lo = mid + 1u;
    }
    if (lo == n) return PGT_NONE;
    return (direction >= 0 ? start[lo] <= t : start[lo] < t) ? lo : PGT_NONE;
}
