/* pgt: the grammar parser and rule compiler (paper 000 sec. 7, "rule compiler"; sec. 5 and 8 for
 * Marching and the ivy; CGA/CityEngine for case/else, attr, NIL and split; grammars/README.md is
 * the language reference).
 *
 * Recursive descent over the token array of grammar_lex.c, emitting the flat arrays of
 * pgt_grammar directly: expressions become postfix code while they are parsed (their stack depth
 * is tracked at emission), and the items, sub-sequences and split parts of one sequence are
 * collected on scratch stacks and copied out when the sequence ends, so that every sequence's
 * items are contiguous although sequences nest. Rule calls are resolved after the whole file is
 * read (rules may be called before they are defined); params must be defined before use. The
 * recursion is bounded by PGT_GRAMMAR_MAX_NESTING (sequences) and PGT_GRAMMAR_MAX_EXPR_DEPTH
 * (expressions), so no input can exhaust the C stack. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grammar_internal.h"

/* The growing arrays: the compiled ones (copied into pgt_grammar by sync) and three scratch
 * stacks for the items, sub-sequences and parts of the sequences being parsed. */
enum {
    V_RULES,
    V_CASES,
    V_SEQUENCES,
    V_ITEMS,
    V_PARTS,
    V_ARGS,
    V_SUBS,
    V_EXPRS,
    V_CODE,
    V_CODE_POS,
    V_CONSTS,
    V_PARAMS,
    V_PARAM_VALUES,
    V_RULE_PARAMS,
    V_NAMES,
    V_SCRATCH_ITEMS,
    V_SCRATCH_SUBS,
    V_SCRATCH_PARTS,
    V_COUNT
};

static const size_t vec_elem[V_COUNT] = {
    sizeof(pgt_grammar_rule),
    sizeof(pgt_grammar_case),
    sizeof(pgt_grammar_sequence),
    sizeof(pgt_grammar_item),
    sizeof(pgt_grammar_part),
    sizeof(uint32_t),
    sizeof(uint32_t),
    sizeof(pgt_grammar_expr),
    sizeof(uint32_t),
    sizeof(pgt_grammar_pos),
    sizeof(float),
    sizeof(pgt_grammar_param),
    sizeof(float),
    sizeof(uint32_t),
    sizeof(char),
    sizeof(pgt_grammar_item),
    sizeof(uint32_t),
    sizeof(pgt_grammar_part),
};

typedef struct vec {
    void *data;
    uint32_t count, cap;
} vec;

/* Terminal shapes: name, arity, and which argument (if any) is a smoothness name. */
static const struct {
    const char *name;
    uint32_t id, arity, smooth_arg;
} terminals[] = {
    {"Bark", PGT_GRAMMAR_TERMINAL_BARK, 2, 1},
    {"Leaves", PGT_GRAMMAR_TERMINAL_LEAVES, 2, PGT_NONE},
    {"Wall", PGT_GRAMMAR_TERMINAL_WALL, 0, PGT_NONE},
    {"Window", PGT_GRAMMAR_TERMINAL_WINDOW, 6, PGT_NONE},
    {"Door", PGT_GRAMMAR_TERMINAL_DOOR, 4, PGT_NONE},
    {"Ledge", PGT_GRAMMAR_TERMINAL_LEDGE, 1, PGT_NONE},
    {"Balcony", PGT_GRAMMAR_TERMINAL_BALCONY, 3, PGT_NONE},
    {"Mesh", PGT_GRAMMAR_TERMINAL_MESH, 1, PGT_NONE},
};

/* Words that are not rule, param or parameter names. */
static const char *const keywords[] = {"param",  "attr",  "case", "else",    "NIL",     "Marching",
                                       "Branch", "split", "PI",   "context", "texCoord"};

typedef struct parser {
    const char *text, *file;
    gtoken *toks;
    uint32_t pos;
    pgt_grammar *g;
    pgt_error *err;
    vec v[V_COUNT];
    uint32_t nesting; /* sequences being parsed */
    uint32_t rule;    /* rule whose body is parsed, PGT_NONE in a param */
    uint32_t expr_depth, stack, max_stack, flags; /* of the expression being parsed */
} parser;

#define TRY(x)                                                                                     \
    do {                                                                                           \
        const pgt_result try_r_ = (x);                                                             \
        if (try_r_ != PGT_OK) return try_r_;                                                       \
    } while (0)

#define AT(p, k, type, i) (((type *)(p)->v[k].data)[i])

/* ---- errors ---- */

/* "FILE:LINE:COL: message" at a source position. */
static pgt_result fail_pos(parser *p, pgt_result code, uint32_t line, uint32_t col, const char *fmt,
                           va_list ap) {
    char msg[PGT_ERROR_MESSAGE_SIZE];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return pgt_error_set(p->err, code, "%s:%u:%u: %s", p->file, line, col, msg);
}

/* The same at token t. */
static pgt_result fail_at(parser *p, pgt_result code, const gtoken *t, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static pgt_result fail_at(parser *p, pgt_result code, const gtoken *t, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    const pgt_result r = fail_pos(p, code, t->line, t->col, fmt, ap);
    va_end(ap);
    return r;
}

/* The same at a rule's name. */
static pgt_result fail_rule(parser *p, const pgt_grammar_rule *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static pgt_result fail_rule(parser *p, const pgt_grammar_rule *r, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    const pgt_result r2 = fail_pos(p, PGT_ERROR_INVALID_ARGUMENT, r->line, r->col, fmt, ap);
    va_end(ap);
    return r2;
}

static const gtoken *peek(const parser *p) { return &p->toks[p->pos]; }
static const gtoken *prev(const parser *p) { return &p->toks[p->pos ? p->pos - 1 : 0]; }
static void advance(parser *p) {
    if (p->toks[p->pos].kind != GTOK_EOF) p->pos++;
}

/* "expected WHAT, found TOKEN" at the current token. */
static pgt_result expected(parser *p, const char *what) {
    char found[64];
    pgt_grammar_describe(p->text, peek(p), found, sizeof found);
    return fail_at(p, PGT_ERROR_PARSE, peek(p), "expected %s, found %s", what, found);
}

static pgt_result expect(parser *p, uint32_t kind, const char *what) {
    if (peek(p)->kind != kind) return expected(p, what);
    advance(p);
    return PGT_OK;
}

static pgt_result limit_error(parser *p, const gtoken *t, const char *name, uint32_t value) {
    return fail_at(p, PGT_ERROR_LIMIT, t, "more than %s (%u) here, expected a smaller grammar",
                   name, value);
}

/* ---- arrays ---- */

/* A zeroed new element of array k, or NULL (out of memory, error set). */
static void *push(parser *p, int k) {
    vec *a = &p->v[k];
    if (a->count == a->cap) {
        const uint32_t cap = a->cap ? 2 * a->cap : 64;
        void *d = realloc(a->data, (size_t)cap * vec_elem[k]);
        if (!d) {
            pgt_error_set(p->err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", p->file);
            return NULL;
        }
        a->data = d;
        a->cap = cap;
    }
    void *slot = (char *)a->data + (size_t)a->count++ * vec_elem[k];
    memset(slot, 0, vec_elem[k]);
    return slot;
}

/* Moves scratch[mark ..] to the end of array k; *first is where it starts there. */
static pgt_result flush(parser *p, int scratch, uint32_t mark, int k, uint32_t *first) {
    vec *s = &p->v[scratch];
    *first = p->v[k].count;
    for (uint32_t i = mark; i < s->count; ++i) {
        void *slot = push(p, k);
        if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
        memcpy(slot, (char *)s->data + (size_t)i * vec_elem[k], vec_elem[k]);
    }
    s->count = mark;
    return PGT_OK;
}

/* Points g's arrays at the parser's (pgt_grammar_run reads g while params are compiled). */
static void sync(parser *p) {
    pgt_grammar *g = p->g;
    g->rules = p->v[V_RULES].data, g->rule_count = p->v[V_RULES].count;
    g->cases = p->v[V_CASES].data, g->case_count = p->v[V_CASES].count;
    g->sequences = p->v[V_SEQUENCES].data, g->sequence_count = p->v[V_SEQUENCES].count;
    g->items = p->v[V_ITEMS].data, g->item_count = p->v[V_ITEMS].count;
    g->parts = p->v[V_PARTS].data, g->part_count = p->v[V_PARTS].count;
    g->args = p->v[V_ARGS].data, g->arg_count = p->v[V_ARGS].count;
    g->subs = p->v[V_SUBS].data, g->sub_count = p->v[V_SUBS].count;
    g->exprs = p->v[V_EXPRS].data, g->expr_count = p->v[V_EXPRS].count;
    g->code = p->v[V_CODE].data, g->code_count = p->v[V_CODE].count;
    g->code_pos = p->v[V_CODE_POS].data;
    g->consts = p->v[V_CONSTS].data, g->const_count = p->v[V_CONSTS].count;
    g->params = p->v[V_PARAMS].data, g->param_count = p->v[V_PARAMS].count;
    g->param_values = p->v[V_PARAM_VALUES].data;
    g->rule_params = p->v[V_RULE_PARAMS].data, g->rule_param_count = p->v[V_RULE_PARAMS].count;
    g->names = p->v[V_NAMES].data, g->names_size = p->v[V_NAMES].count;
}

/* Appends a NUL-terminated name to the pool; *offset is where it starts. */
static pgt_result add_name(parser *p, const char *s, size_t n, uint32_t *offset) {
    *offset = p->v[V_NAMES].count;
    for (size_t i = 0; i <= n; ++i) {
        char *c = push(p, V_NAMES);
        if (!c) return PGT_ERROR_OUT_OF_MEMORY;
        *c = i < n ? s[i] : '\0';
    }
    return PGT_OK;
}

/* ---- names ---- */

static const char *tok_text(const parser *p, const gtoken *t) { return p->text + t->offset; }

static int tok_is(const parser *p, const gtoken *t, const char *word) {
    return t->kind == GTOK_IDENT && strlen(word) == t->length &&
           memcmp(tok_text(p, t), word, t->length) == 0;
}

/* The pooled name at offset equals token t. */
static int name_is(const parser *p, uint32_t offset, const gtoken *t) {
    const char *s = (const char *)p->v[V_NAMES].data + offset;
    return strncmp(s, tok_text(p, t), t->length) == 0 && s[t->length] == '\0';
}

static uint32_t find_fn(const parser *p, const gtoken *t) {
    for (uint32_t k = 0; k < pgt_grammar_fn_count; ++k)
        if (tok_is(p, t, pgt_grammar_fns[k].name)) return k;
    return PGT_NONE;
}

static uint32_t find_terminal(const parser *p, const gtoken *t) {
    for (uint32_t k = 0; k < sizeof terminals / sizeof terminals[0]; ++k)
        if (tok_is(p, t, terminals[k].name)) return k;
    return PGT_NONE;
}

static int is_reserved(const parser *p, const gtoken *t) {
    for (size_t k = 0; k < sizeof keywords / sizeof keywords[0]; ++k)
        if (tok_is(p, t, keywords[k])) return 1;
    return find_fn(p, t) != PGT_NONE || find_terminal(p, t) != PGT_NONE;
}

static uint32_t find_rule(const parser *p, const gtoken *t) {
    for (uint32_t r = 0; r < p->v[V_RULES].count; ++r)
        if (name_is(p, AT(p, V_RULES, pgt_grammar_rule, r).name, t)) return r;
    return PGT_NONE;
}

static uint32_t find_param(const parser *p, const gtoken *t) {
    for (uint32_t k = 0; k < p->v[V_PARAMS].count; ++k)
        if (name_is(p, AT(p, V_PARAMS, pgt_grammar_param, k).name, t)) return k;
    return PGT_NONE;
}

static uint32_t find_rule_param(const parser *p, const gtoken *t) {
    if (p->rule == PGT_NONE) return PGT_NONE;
    const pgt_grammar_rule *r = &AT(p, V_RULES, pgt_grammar_rule, p->rule);
    for (uint32_t k = 0; k < r->param_count; ++k)
        if (name_is(p, AT(p, V_RULE_PARAMS, uint32_t, r->first_param + k), t)) return k;
    return PGT_NONE;
}

/* Keeps in *best the candidate closest to t (a "did you mean" for typos only: at most 2 edits,
 * and fewer than half the name's letters). */
static void closest(const parser *p, const gtoken *t, const char *cand, const char **best,
                    uint32_t *best_d) {
    const uint32_t d = pgt_grammar_distance(tok_text(p, t), t->length, cand, strlen(cand), 3);
    if (d <= 2 && 2 * d < t->length && d < *best_d) *best = cand, *best_d = d;
}

/* " (did you mean 'X'?)" or "". */
static void did_you_mean(const char *best, char *buf, size_t size) {
    if (best)
        snprintf(buf, size, " (did you mean '%s'?)", best);
    else
        buf[0] = '\0';
}

/* A new name for a rule, param or rule parameter: not a keyword or built-in. */
static pgt_result check_new_name(parser *p, const gtoken *t, const char *what) {
    if (t->kind != GTOK_IDENT) {
        char buf[64];
        snprintf(buf, sizeof buf, "a %s name", what);
        return expected(p, buf);
    }
    if (is_reserved(p, t))
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "found the built-in word '%.*s', expected a %s name (built-ins are "
                       "reserved)",
                       (int)t->length, tok_text(p, t), what);
    return PGT_OK;
}

/* ---- expressions ---- */

/* Appends one instruction; t is its token (code_pos: where its errors point). */
static pgt_result emit(parser *p, uint32_t op, uint32_t operand, const gtoken *t) {
    if (p->v[V_CODE].count >= PGT_GRAMMAR_MAX_CODE)
        return limit_error(p, prev(p), "PGT_GRAMMAR_MAX_CODE instruction words",
                           PGT_GRAMMAR_MAX_CODE);
    uint32_t *c = push(p, V_CODE);
    if (!c) return PGT_ERROR_OUT_OF_MEMORY;
    *c = op | operand << PGT_GRAMMAR_OP_BITS;
    pgt_grammar_pos *pos = push(p, V_CODE_POS);
    if (!pos) return PGT_ERROR_OUT_OF_MEMORY;
    *pos = (pgt_grammar_pos){t->line, t->col};
    p->stack = (uint32_t)((int)p->stack + pgt_grammar_op_effect(op));
    if (p->stack > p->max_stack) p->max_stack = p->stack;
    if (p->max_stack > PGT_GRAMMAR_VM_STACK)
        return fail_at(p, PGT_ERROR_LIMIT, prev(p),
                       "this expression needs more than PGT_GRAMMAR_VM_STACK (%u) stack entries "
                       "here, expected a flatter expression (nest fewer right operands)",
                       PGT_GRAMMAR_VM_STACK);
    return PGT_OK;
}

static pgt_result emit_const(parser *p, float value, const gtoken *t) {
    if (p->v[V_CONSTS].count >= PGT_GRAMMAR_MAX_CONSTS)
        return limit_error(p, prev(p), "PGT_GRAMMAR_MAX_CONSTS constants", PGT_GRAMMAR_MAX_CONSTS);
    float *c = push(p, V_CONSTS);
    if (!c) return PGT_ERROR_OUT_OF_MEMORY;
    *c = value;
    return emit(p, PGT_GRAMMAR_OP_CONST, p->v[V_CONSTS].count - 1, t);
}

static pgt_result enter_expr(parser *p) {
    if (++p->expr_depth > PGT_GRAMMAR_MAX_EXPR_DEPTH)
        return limit_error(p, peek(p), "PGT_GRAMMAR_MAX_EXPR_DEPTH nested expression levels",
                           PGT_GRAMMAR_MAX_EXPR_DEPTH);
    return PGT_OK;
}

static pgt_result parse_binary(parser *p, int min_prec);

/* '(' EXPR {',' EXPR} ')' of a function: exactly arity arguments. */
static pgt_result parse_fn_args(parser *p, const gtoken *name, uint32_t arity) {
    TRY(expect(p, GTOK_LPAREN, "'(' after a function name"));
    uint32_t n = 0;
    if (peek(p)->kind != GTOK_RPAREN) {
        for (;;) {
            TRY(parse_binary(p, 1));
            n++;
            if (peek(p)->kind != GTOK_COMMA) break;
            advance(p);
        }
    }
    TRY(expect(p, GTOK_RPAREN, "',' or ')' in the arguments of a function"));
    if (n != arity)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name, "%.*s takes %u argument%s, found %u",
                       (int)name->length, tok_text(p, name), arity, arity == 1 ? "" : "s", n);
    return PGT_OK;
}

/* context.NAME(texCoord) */
static pgt_result parse_context(parser *p, const gtoken *t) {
    if (p->rule == PGT_NONE)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "found 'context' in a param, expected a compile-time constant (params "
                       "cannot read contexts)");
    TRY(expect(p, GTOK_DOT, "'.' after 'context' (context.mask or context.density)"));
    const gtoken *name = peek(p);
    uint32_t id = PGT_NONE;
    for (uint32_t k = 0; k < PGT_GRAMMAR_CONTEXT_COUNT; ++k)
        if (tok_is(p, name, pgt_grammar_context_name(k))) id = k;
    if (id == PGT_NONE) {
        if (name->kind != GTOK_IDENT) return expected(p, "a context name: mask or density");
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name,
                       "found context.%.*s, expected a known context: mask or density",
                       (int)name->length, tok_text(p, name));
    }
    advance(p);
    TRY(expect(p, GTOK_LPAREN, "'(' after the context name"));
    if (!tok_is(p, peek(p), "texCoord"))
        return expected(p, "texCoord (the only argument of a context lookup)");
    advance(p);
    TRY(expect(p, GTOK_RPAREN, "')' after texCoord"));
    p->flags |= PGT_GRAMMAR_EXPR_CONTEXT;
    return emit(p, PGT_GRAMMAR_OP_CONTEXT, id, t);
}

static pgt_result parse_name_expr(parser *p) {
    const gtoken *t = peek(p);
    advance(p);
    if (tok_is(p, t, "PI")) return emit_const(p, 3.14159265358979323846f, t);
    if (tok_is(p, t, "texCoord"))
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "found texCoord as a value, expected it only as the argument of "
                       "context.mask(texCoord) or context.density(texCoord)");
    if (tok_is(p, t, "context")) return parse_context(p, t);
    const uint32_t fn = find_fn(p, t);
    if (fn != PGT_NONE) {
        if (pgt_grammar_fns[fn].op == PGT_GRAMMAR_OP_RAND) {
            if (p->rule == PGT_NONE)
                return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                               "found 'rand' in a param, expected a compile-time constant "
                               "(params cannot draw random numbers)");
            p->flags |= PGT_GRAMMAR_EXPR_RAND;
        }
        TRY(parse_fn_args(p, t, pgt_grammar_fns[fn].arity));
        return emit(p, pgt_grammar_fns[fn].op, 0, t);
    }
    const uint32_t arg = find_rule_param(p, t);
    if (arg != PGT_NONE) {
        p->flags |= PGT_GRAMMAR_EXPR_ARGS;
        return emit(p, PGT_GRAMMAR_OP_ARG, arg, t);
    }
    const uint32_t param = find_param(p, t);
    if (param != PGT_NONE) return emit(p, PGT_GRAMMAR_OP_PARAM, param, t);
    /* unknown: suggest a near name among what could stand here */
    const char *best = NULL;
    uint32_t best_d = 3;
    const char *names = p->v[V_NAMES].data;
    for (uint32_t k = 0; k < p->v[V_PARAMS].count; ++k)
        closest(p, t, names + AT(p, V_PARAMS, pgt_grammar_param, k).name, &best, &best_d);
    if (p->rule != PGT_NONE) {
        const pgt_grammar_rule *r = &AT(p, V_RULES, pgt_grammar_rule, p->rule);
        for (uint32_t k = 0; k < r->param_count; ++k)
            closest(p, t, names + AT(p, V_RULE_PARAMS, uint32_t, r->first_param + k), &best,
                    &best_d);
    }
    for (uint32_t k = 0; k < pgt_grammar_fn_count; ++k)
        closest(p, t, pgt_grammar_fns[k].name, &best, &best_d);
    char hint[PGT_GRAMMAR_MAX_NAME_CHARS + 32];
    did_you_mean(best, hint, sizeof hint);
    return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                   "unknown identifier '%.*s'%s, expected a number, PI, a function, rand, "
                   "context, a param defined above%s",
                   (int)t->length, tok_text(p, t), hint,
                   p->rule == PGT_NONE ? "" : " or a parameter of this rule");
}

static pgt_result parse_unary(parser *p) {
    const gtoken *t = peek(p);
    if (t->kind == GTOK_MINUS || t->kind == GTOK_NOT) {
        advance(p);
        TRY(enter_expr(p));
        TRY(parse_unary(p));
        p->expr_depth--;
        return emit(p, t->kind == GTOK_MINUS ? PGT_GRAMMAR_OP_NEG : PGT_GRAMMAR_OP_NOT, 0, t);
    }
    if (t->kind == GTOK_NUMBER) {
        advance(p);
        return emit_const(p, t->value, t);
    }
    if (t->kind == GTOK_LPAREN) {
        advance(p);
        TRY(parse_binary(p, 1));
        if (peek(p)->kind != GTOK_RPAREN) {
            char what[80];
            snprintf(what, sizeof what, "')' to close the '(' at %u:%u", t->line, t->col);
            return expected(p, what);
        }
        advance(p);
        return PGT_OK;
    }
    if (t->kind == GTOK_IDENT) return parse_name_expr(p);
    return expected(p, "an expression");
}

/* Binary operators with C's precedence (higher binds tighter), all left-associative. */
static int binary_prec(uint32_t kind, uint32_t *op) {
    static const struct {
        uint32_t kind, op;
        int prec;
    } ops[] = {
        {GTOK_OR, PGT_GRAMMAR_OP_OR, 1},       {GTOK_AND, PGT_GRAMMAR_OP_AND, 2},
        {GTOK_EQ, PGT_GRAMMAR_OP_EQ, 3},       {GTOK_NE, PGT_GRAMMAR_OP_NE, 3},
        {GTOK_LT, PGT_GRAMMAR_OP_LT, 4},       {GTOK_LE, PGT_GRAMMAR_OP_LE, 4},
        {GTOK_GT, PGT_GRAMMAR_OP_GT, 4},       {GTOK_GE, PGT_GRAMMAR_OP_GE, 4},
        {GTOK_PLUS, PGT_GRAMMAR_OP_ADD, 5},    {GTOK_MINUS, PGT_GRAMMAR_OP_SUB, 5},
        {GTOK_STAR, PGT_GRAMMAR_OP_MUL, 6},    {GTOK_SLASH, PGT_GRAMMAR_OP_DIV, 6},
        {GTOK_PERCENT, PGT_GRAMMAR_OP_MOD, 6},
    };
    for (size_t k = 0; k < sizeof ops / sizeof ops[0]; ++k)
        if (ops[k].kind == kind) {
            *op = ops[k].op;
            return ops[k].prec;
        }
    return 0;
}

static pgt_result parse_binary(parser *p, int min_prec) {
    TRY(enter_expr(p));
    TRY(parse_unary(p));
    for (;;) {
        uint32_t op = 0;
        const int prec = binary_prec(peek(p)->kind, &op);
        if (prec == 0 || prec < min_prec) break;
        const gtoken *optok = peek(p);
        advance(p);
        TRY(parse_binary(p, prec + 1));
        TRY(emit(p, op, 0, optok));
    }
    p->expr_depth--;
    return PGT_OK;
}

/* One whole expression starting at the current token; *out is its index. */
static pgt_result parse_expr(parser *p, uint32_t *out) {
    const gtoken *t = peek(p);
    if (p->v[V_EXPRS].count >= PGT_GRAMMAR_MAX_EXPRS)
        return limit_error(p, t, "PGT_GRAMMAR_MAX_EXPRS expressions", PGT_GRAMMAR_MAX_EXPRS);
    const uint32_t first = p->v[V_CODE].count;
    p->expr_depth = p->stack = p->max_stack = p->flags = 0;
    TRY(parse_binary(p, 1));
    pgt_grammar_expr *e = push(p, V_EXPRS);
    if (!e) return PGT_ERROR_OUT_OF_MEMORY;
    e->first_code = first;
    e->code_count = p->v[V_CODE].count - first;
    e->max_stack = p->max_stack;
    e->flags = p->flags ? p->flags : PGT_GRAMMAR_EXPR_CONSTANT;
    e->line = t->line;
    e->col = t->col;
    *out = p->v[V_EXPRS].count - 1;
    return PGT_OK;
}

/* An expression that is one constant (a smoothness name). */
static pgt_result const_expr(parser *p, float value, const gtoken *t, uint32_t *out) {
    if (p->v[V_EXPRS].count >= PGT_GRAMMAR_MAX_EXPRS)
        return limit_error(p, t, "PGT_GRAMMAR_MAX_EXPRS expressions", PGT_GRAMMAR_MAX_EXPRS);
    const uint32_t first = p->v[V_CODE].count;
    p->stack = p->max_stack = 0;
    TRY(emit_const(p, value, t));
    pgt_grammar_expr *e = push(p, V_EXPRS);
    if (!e) return PGT_ERROR_OUT_OF_MEMORY;
    *e = (pgt_grammar_expr){first, 1, 1, PGT_GRAMMAR_EXPR_CONSTANT, t->line, t->col};
    *out = p->v[V_EXPRS].count - 1;
    return PGT_OK;
}

/* The value of a constant expression now (params and Branch counts). */
static pgt_result eval_now(parser *p, uint32_t expr, const char *what, float *out) {
    sync(p);
    pgt_grammar_fault fault;
    if (pgt_grammar_run(p->g, expr, NULL, 0, NULL, 1, out, &fault) != PGT_OK) {
        uint32_t line, col;
        char detail[64];
        pgt_grammar_fault_place(p->g, expr, &fault, &line, &col, detail, sizeof detail);
        return pgt_error_set(p->err, PGT_ERROR_INVALID_ARGUMENT, "%s:%u:%u: %s %s%s", p->file, line,
                             col, what, fault.why, detail);
    }
    return PGT_OK;
}

/* ---- sequences and items ---- */

static pgt_result parse_seq(parser *p, uint32_t *out);

/* Is token i the start of a rule: Name --> or Name(...) --> ? */
static int rule_starts_at(const parser *p, uint32_t i) {
    const gtoken *t = &p->toks[i];
    if (t->kind != GTOK_IDENT) return 0;
    const gtoken *n = &p->toks[i + 1];
    if (n->kind == GTOK_ARROW) return 1;
    return n->kind == GTOK_LPAREN && n->match != PGT_NONE &&
           p->toks[n->match + 1].kind == GTOK_ARROW;
}

/* '(' [EXPR {',' EXPR}] ')' into args; *first, *count. With no '(' there are no arguments. */
static pgt_result parse_args(parser *p, uint32_t *first, uint32_t *count) {
    *first = p->v[V_ARGS].count;
    *count = 0;
    if (peek(p)->kind != GTOK_LPAREN) return PGT_OK;
    advance(p);
    if (peek(p)->kind == GTOK_RPAREN) {
        advance(p);
        return PGT_OK;
    }
    for (;;) {
        if (*count == PGT_GRAMMAR_MAX_RULE_PARAMS)
            return limit_error(p, peek(p), "PGT_GRAMMAR_MAX_RULE_PARAMS arguments",
                               PGT_GRAMMAR_MAX_RULE_PARAMS);
        uint32_t e = PGT_NONE;
        TRY(parse_expr(p, &e));
        uint32_t *slot = push(p, V_ARGS);
        if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
        *slot = e;
        ++*count;
        if (peek(p)->kind != GTOK_COMMA) break;
        advance(p);
    }
    return expect(p, GTOK_RPAREN, "',' or ')' in an argument list");
}

/* '{' SEQ {(',' | '|') SEQ} '}' of Marching (want = 2) or Branch (want = 0: any number). */
static pgt_result parse_successors(parser *p, const gtoken *at, uint32_t want, uint32_t *first,
                                   uint32_t *count) {
    const char *what = tok_is(p, at, "Marching") ? "Marching" : "Branch";
    if (peek(p)->kind != GTOK_LBRACE) {
        char buf[96];
        snprintf(buf, sizeof buf, "'{' and the successor sequences of %s", what);
        return expected(p, buf);
    }
    const gtoken *open = peek(p);
    advance(p);
    const uint32_t mark = p->v[V_SCRATCH_SUBS].count;
    for (;;) {
        uint32_t s = PGT_NONE;
        TRY(parse_seq(p, &s));
        uint32_t *slot = push(p, V_SCRATCH_SUBS);
        if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
        *slot = s;
        const uint32_t n = p->v[V_SCRATCH_SUBS].count - mark;
        const int sep = peek(p)->kind == GTOK_COMMA || peek(p)->kind == GTOK_BAR;
        if (want == 2 && n == 1 && !sep)
            return expected(p, "',' or '|' between the two successor sequences of Marching");
        if (want == 2 && n == 2 && sep)
            return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, peek(p),
                           "found a third successor sequence, expected exactly two for "
                           "Marching {TopSucc, ExtrudedSucc}");
        if (!sep) break;
        advance(p);
    }
    if (peek(p)->kind != GTOK_RBRACE) {
        char buf[128];
        snprintf(buf, sizeof buf, "'}' to close the successor sequences of %s opened at %u:%u",
                 what, open->line, open->col);
        return expected(p, buf);
    }
    advance(p);
    *count = p->v[V_SCRATCH_SUBS].count - mark;
    return flush(p, V_SCRATCH_SUBS, mark, V_SUBS, first);
}

static pgt_result parse_parts(parser *p, int in_repeat, uint32_t *first, uint32_t *count);

/* One split part: SIZE ':' SEQ, or a repeat group '{' PARTS '}' '*'. */
static pgt_result parse_part(parser *p, int in_repeat) {
    const gtoken *t = peek(p);
    pgt_grammar_part part = {PGT_GRAMMAR_PART_ABSOLUTE, PGT_NONE, PGT_NONE, 0, 0, t->line, t->col};
    if (t->kind == GTOK_LBRACE) {
        if (in_repeat)
            return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                           "found a repeat group inside a repeat group, expected a part "
                           "SIZE : SEQ (repeat groups do not nest)");
        advance(p);
        TRY(parse_parts(p, 1, &part.first_part, &part.part_count));
        TRY(expect(p, GTOK_RBRACE, "'|' or '}' in a repeat group"));
        TRY(expect(p, GTOK_STAR, "'*' after the '}' of a repeat group"));
        part.kind = PGT_GRAMMAR_PART_REPEAT;
    } else {
        if (t->kind == GTOK_RBRACE || t->kind == GTOK_BAR)
            return expected(p, "a split part (SIZE : SEQ or { ... }*)");
        if (t->kind == GTOK_QUOTE || t->kind == GTOK_TILDE) {
            part.kind =
                t->kind == GTOK_QUOTE ? PGT_GRAMMAR_PART_RELATIVE : PGT_GRAMMAR_PART_FLOATING;
            advance(p);
        }
        TRY(parse_expr(p, &part.size));
        TRY(expect(p, GTOK_COLON, "':' between a split size and its successors"));
        TRY(parse_seq(p, &part.sequence));
    }
    pgt_grammar_part *slot = push(p, V_SCRATCH_PARTS);
    if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
    *slot = part;
    return PGT_OK;
}

static pgt_result parse_parts(parser *p, int in_repeat, uint32_t *first, uint32_t *count) {
    const uint32_t mark = p->v[V_SCRATCH_PARTS].count;
    for (;;) {
        TRY(parse_part(p, in_repeat));
        if (peek(p)->kind != GTOK_BAR) break;
        advance(p);
    }
    *count = p->v[V_SCRATCH_PARTS].count - mark;
    return flush(p, V_SCRATCH_PARTS, mark, V_PARTS, first);
}

/* split '(' x|y|z ')' '{' PARTS '}' ['*'] */
static pgt_result parse_split(parser *p, pgt_grammar_item *it) {
    TRY(expect(p, GTOK_LPAREN, "'(' and the axis of split"));
    static const char *const axes[] = {"x", "y", "z"};
    for (uint32_t k = 0; k < 3; ++k)
        if (tok_is(p, peek(p), axes[k])) it->target = k;
    if (it->target == PGT_NONE) return expected(p, "the axis of split: x, y or z");
    advance(p);
    TRY(expect(p, GTOK_RPAREN, "')' after the axis of split"));
    const gtoken *open = peek(p);
    TRY(expect(p, GTOK_LBRACE, "'{' and the parts of split"));
    TRY(parse_parts(p, 0, &it->first_sub, &it->sub_count));
    if (peek(p)->kind != GTOK_RBRACE) {
        char buf[96];
        snprintf(buf, sizeof buf, "'|' or '}' to close the parts of split opened at %u:%u",
                 open->line, open->col);
        return expected(p, buf);
    }
    advance(p);
    if (peek(p)->kind != GTOK_STAR) return PGT_OK;
    /* split(a) { ... }* repeats all its parts: one repeat group holding them */
    for (uint32_t k = 0; k < it->sub_count; ++k)
        if (AT(p, V_PARTS, pgt_grammar_part, it->first_sub + k).kind == PGT_GRAMMAR_PART_REPEAT)
            return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, peek(p),
                           "found '*' after a split that holds a repeat group, expected no "
                           "'*' (repeat groups do not nest)");
    advance(p);
    pgt_grammar_part *group = push(p, V_PARTS);
    if (!group) return PGT_ERROR_OUT_OF_MEMORY;
    *group = (pgt_grammar_part){PGT_GRAMMAR_PART_REPEAT, PGT_NONE,   PGT_NONE, it->first_sub,
                                it->sub_count,           open->line, open->col};
    it->first_sub = p->v[V_PARTS].count - 1;
    it->sub_count = 1;
    return PGT_OK;
}

/* Bark(radius, C1), Leaves(density, size): arguments by the terminal table. */
static pgt_result parse_terminal(parser *p, uint32_t k, pgt_grammar_item *it) {
    const gtoken *name = prev(p);
    TRY(expect(p, GTOK_LPAREN, "'(' and the arguments of the terminal"));
    it->target = terminals[k].id;
    it->first_arg = p->v[V_ARGS].count;
    for (uint32_t a = 0; a < terminals[k].arity; ++a) {
        if (a > 0 && peek(p)->kind != GTOK_COMMA) break;
        if (a > 0) advance(p);
        uint32_t e = PGT_NONE;
        if (a == terminals[k].smooth_arg) {
            for (uint32_t s = 0; s < 3; ++s)
                if (tok_is(p, peek(p), pgt_grammar_smoothness_name(s)))
                    TRY(const_expr(p, (float)s, peek(p), &e));
            if (e == PGT_NONE) return expected(p, "the smoothness discontinuous, C0 or C1");
            advance(p);
        } else {
            TRY(parse_expr(p, &e));
        }
        uint32_t *slot = push(p, V_ARGS);
        if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
        *slot = e;
        it->arg_count++;
    }
    if (it->arg_count != terminals[k].arity || peek(p)->kind == GTOK_COMMA)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name,
                       "%s takes %u arguments, found %s than that", terminals[k].name,
                       terminals[k].arity, it->arg_count < terminals[k].arity ? "fewer" : "more");
    return expect(p, GTOK_RPAREN, "')' after the arguments of the terminal");
}

/* Marching(length, angle, condition) {TopSucc, ExtrudedSucc} and Branch(N) {SEQ, ...}. */
static pgt_result parse_marching_or_branch(parser *p, const gtoken *t, pgt_grammar_item *it) {
    const int marching = tok_is(p, t, "Marching");
    it->kind = marching ? PGT_GRAMMAR_ITEM_MARCHING : PGT_GRAMMAR_ITEM_BRANCH;
    if (peek(p)->kind != GTOK_LPAREN)
        return expected(p, marching ? "'(' and length, angle, condition of Marching"
                                    : "'(' and the count of Branch");
    TRY(parse_args(p, &it->first_arg, &it->arg_count));
    if (marching && it->arg_count != 3)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "Marching takes 3 arguments (length, angle, condition), found %u",
                       it->arg_count);
    if (marching) return parse_successors(p, t, 2, &it->first_sub, &it->sub_count);
    if (it->arg_count != 1)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "Branch takes 1 argument (the number of sequences), found %u",
                       it->arg_count);
    const uint32_t e = AT(p, V_ARGS, uint32_t, it->first_arg);
    const pgt_grammar_expr *ex = &AT(p, V_EXPRS, pgt_grammar_expr, e);
    if (!(ex->flags & PGT_GRAMMAR_EXPR_CONSTANT))
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "the count of Branch reads rand, a context or a rule parameter, "
                       "expected a constant (numbers and params)");
    float n = 0.0f;
    TRY(eval_now(p, e, "the count of Branch", &n));
    if (!(n >= 1.0f && n <= (float)PGT_GRAMMAR_MAX_SEQUENCES && n == floorf(n)))
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "the count of Branch is %g, expected a whole number from 1 to %u", (double)n,
                       PGT_GRAMMAR_MAX_SEQUENCES);
    TRY(parse_successors(p, t, 0, &it->first_sub, &it->sub_count));
    if (it->sub_count != (uint32_t)n)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "Branch(%u) has %u successor sequence%s, expected %u", (uint32_t)n,
                       it->sub_count, it->sub_count == 1 ? "" : "s", (uint32_t)n);
    return PGT_OK;
}

static pgt_result parse_item(parser *p) {
    const gtoken *t = peek(p);
    if (p->v[V_ITEMS].count + p->v[V_SCRATCH_ITEMS].count >= PGT_GRAMMAR_MAX_ITEMS)
        return limit_error(p, t, "PGT_GRAMMAR_MAX_ITEMS items", PGT_GRAMMAR_MAX_ITEMS);
    pgt_grammar_item it = {PGT_GRAMMAR_ITEM_CALL, PGT_NONE, 0, 0, 0, 0, t->line, t->col};
    const uint32_t term = find_terminal(p, t);
    advance(p);
    if (tok_is(p, t, "Marching") || tok_is(p, t, "Branch")) {
        TRY(parse_marching_or_branch(p, t, &it));
    } else if (tok_is(p, t, "split")) {
        it.kind = PGT_GRAMMAR_ITEM_SPLIT;
        TRY(parse_split(p, &it));
    } else if (term != PGT_NONE) {
        it.kind = PGT_GRAMMAR_ITEM_TERMINAL;
        TRY(parse_terminal(p, term, &it));
    } else if (is_reserved(p, t)) {
        char found[64];
        pgt_grammar_describe(p->text, t, found, sizeof found);
        return fail_at(p, PGT_ERROR_PARSE, t,
                       "expected a rule call, Marching, Branch, split, a terminal or NIL, found "
                       "the built-in %s",
                       found);
    } else {
        /* a rule call: target holds the name's token until resolve_calls */
        it.target = (uint32_t)(t - p->toks);
        TRY(parse_args(p, &it.first_arg, &it.arg_count));
    }
    pgt_grammar_item *slot = push(p, V_SCRATCH_ITEMS);
    if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
    *slot = it;
    return PGT_OK;
}

/* Words that end a sequence besides punctuation: the next case, else, param, attr. */
static int ends_sequence(const parser *p, const gtoken *t) {
    return t->kind != GTOK_IDENT || rule_starts_at(p, (uint32_t)(t - p->toks)) ||
           tok_is(p, t, "case") || tok_is(p, t, "else") || tok_is(p, t, "param") ||
           tok_is(p, t, "attr");
}

static pgt_result parse_seq(parser *p, uint32_t *out) {
    const gtoken *start = peek(p);
    if (++p->nesting > PGT_GRAMMAR_MAX_NESTING)
        return limit_error(p, start, "PGT_GRAMMAR_MAX_NESTING nested sequences",
                           PGT_GRAMMAR_MAX_NESTING);
    const uint32_t mark = p->v[V_SCRATCH_ITEMS].count;
    const gtoken *nil = NULL;
    while (!ends_sequence(p, peek(p))) {
        const gtoken *t = peek(p);
        if (nil || (tok_is(p, t, "NIL") && p->v[V_SCRATCH_ITEMS].count > mark))
            return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                           "found %s, expected NIL alone (NIL is the empty sequence)",
                           nil ? "an item after NIL" : "NIL after an item");
        if (tok_is(p, t, "NIL")) {
            nil = t;
            advance(p);
            continue;
        }
        TRY(parse_item(p));
    }
    if (p->v[V_SEQUENCES].count >= PGT_GRAMMAR_MAX_SEQUENCES)
        return limit_error(p, start, "PGT_GRAMMAR_MAX_SEQUENCES sequences",
                           PGT_GRAMMAR_MAX_SEQUENCES);
    pgt_grammar_sequence s = {0, p->v[V_SCRATCH_ITEMS].count - mark};
    TRY(flush(p, V_SCRATCH_ITEMS, mark, V_ITEMS, &s.first_item));
    pgt_grammar_sequence *slot = push(p, V_SEQUENCES);
    if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
    *slot = s;
    *out = p->v[V_SEQUENCES].count - 1;
    p->nesting--;
    return PGT_OK;
}

/* ---- rules and params ---- */

static pgt_result add_case(parser *p, uint32_t condition) {
    pgt_grammar_case c = {condition, 0};
    TRY(parse_seq(p, &c.sequence));
    pgt_grammar_case *slot = push(p, V_CASES);
    if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
    *slot = c;
    AT(p, V_RULES, pgt_grammar_rule, p->rule).case_count++;
    return PGT_OK;
}

/* case EXPR : SEQ ... else : SEQ */
static pgt_result parse_cases(parser *p) {
    while (tok_is(p, peek(p), "case")) {
        advance(p);
        uint32_t cond = PGT_NONE;
        TRY(parse_expr(p, &cond));
        TRY(expect(p, GTOK_COLON, "':' after the condition of a case"));
        TRY(add_case(p, cond));
    }
    if (!tok_is(p, peek(p), "else"))
        return expected(p, "'case' or 'else' (a conditional rule ends with else : SEQ)");
    advance(p);
    TRY(expect(p, GTOK_COLON, "':' after else"));
    return add_case(p, PGT_NONE);
}

/* Name ['(' p1, p2, ... ')'] --> BODY [';'] */
static pgt_result parse_rule(parser *p) {
    const gtoken *name = peek(p);
    TRY(check_new_name(p, name, "rule"));
    const uint32_t dup = find_rule(p, name);
    if (dup != PGT_NONE) {
        const pgt_grammar_rule *d = &AT(p, V_RULES, pgt_grammar_rule, dup);
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name,
                       "found a second rule '%.*s', expected one rule per name (the first is at "
                       "%u:%u; use case/else for alternatives)",
                       (int)name->length, tok_text(p, name), d->line, d->col);
    }
    if (p->v[V_RULES].count >= PGT_GRAMMAR_MAX_RULES)
        return limit_error(p, name, "PGT_GRAMMAR_MAX_RULES rules", PGT_GRAMMAR_MAX_RULES);
    pgt_grammar_rule *r = push(p, V_RULES);
    if (!r) return PGT_ERROR_OUT_OF_MEMORY;
    p->rule = p->v[V_RULES].count - 1;
    uint32_t offset;
    TRY(add_name(p, tok_text(p, name), name->length, &offset));
    r = &AT(p, V_RULES, pgt_grammar_rule, p->rule);
    *r = (pgt_grammar_rule){offset, p->v[V_RULE_PARAMS].count, 0, 0, 0, name->line, name->col};
    advance(p);
    if (peek(p)->kind == GTOK_LPAREN && peek(p)[1].kind != GTOK_RPAREN) {
        do {
            advance(p);
            const gtoken *t = peek(p);
            TRY(check_new_name(p, t, "parameter"));
            if (find_rule_param(p, t) != PGT_NONE || find_param(p, t) != PGT_NONE)
                return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                               "found the parameter name '%.*s' twice, expected names distinct "
                               "from each other and from the params",
                               (int)t->length, tok_text(p, t));
            if (AT(p, V_RULES, pgt_grammar_rule, p->rule).param_count ==
                PGT_GRAMMAR_MAX_RULE_PARAMS)
                return limit_error(p, t, "PGT_GRAMMAR_MAX_RULE_PARAMS parameters",
                                   PGT_GRAMMAR_MAX_RULE_PARAMS);
            TRY(add_name(p, tok_text(p, t), t->length, &offset));
            uint32_t *slot = push(p, V_RULE_PARAMS);
            if (!slot) return PGT_ERROR_OUT_OF_MEMORY;
            *slot = offset;
            AT(p, V_RULES, pgt_grammar_rule, p->rule).param_count++;
            advance(p);
        } while (peek(p)->kind == GTOK_COMMA);
        TRY(expect(p, GTOK_RPAREN, "',' or ')' in the parameter list of the rule"));
    } else if (peek(p)->kind == GTOK_LPAREN) {
        advance(p);
        advance(p);
    }
    if (peek(p)->kind != GTOK_ARROW) {
        char buf[PGT_GRAMMAR_MAX_NAME_CHARS + 64];
        snprintf(buf, sizeof buf, "'-->' after the rule name '%.*s'", (int)name->length,
                 tok_text(p, name));
        return expected(p, buf);
    }
    advance(p);
    AT(p, V_RULES, pgt_grammar_rule, p->rule).first_case = p->v[V_CASES].count;
    if (tok_is(p, peek(p), "case"))
        TRY(parse_cases(p));
    else
        TRY(add_case(p, PGT_NONE));
    if (peek(p)->kind == GTOK_SEMI) advance(p);
    p->rule = PGT_NONE;
    return PGT_OK;
}

/* (param | attr) NAME '=' EXPR [';'] */
static pgt_result parse_param(parser *p) {
    advance(p);
    const gtoken *name = peek(p);
    TRY(check_new_name(p, name, "param"));
    if (find_param(p, name) != PGT_NONE)
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name,
                       "found a second param '%.*s', expected one definition per param",
                       (int)name->length, tok_text(p, name));
    /* a rule above may have a parameter of this name (the rule's own check saw only the params
     * above it; a dump lists every param first, and would not compile) */
    for (uint32_t k = 0; k < p->v[V_RULE_PARAMS].count; ++k)
        if (name_is(p, AT(p, V_RULE_PARAMS, uint32_t, k), name))
            return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, name,
                           "found the param '%.*s', the name of a rule's parameter above, "
                           "expected names distinct from the rules' parameters",
                           (int)name->length, tok_text(p, name));
    if (p->v[V_PARAMS].count >= PGT_GRAMMAR_MAX_PARAMS)
        return limit_error(p, name, "PGT_GRAMMAR_MAX_PARAMS params", PGT_GRAMMAR_MAX_PARAMS);
    advance(p);
    TRY(expect(p, GTOK_ASSIGN, "'=' after the param name"));
    uint32_t expr = PGT_NONE, offset = 0;
    TRY(parse_expr(p, &expr));
    char what[PGT_GRAMMAR_MAX_NAME_CHARS + 16];
    snprintf(what, sizeof what, "param '%.*s'", (int)name->length, tok_text(p, name));
    float value = 0.0f;
    TRY(eval_now(p, expr, what, &value));
    TRY(add_name(p, tok_text(p, name), name->length, &offset));
    pgt_grammar_param *slot = push(p, V_PARAMS);
    float *v = push(p, V_PARAM_VALUES);
    if (!slot || !v) return PGT_ERROR_OUT_OF_MEMORY;
    *slot = (pgt_grammar_param){offset, expr, 0, name->line, name->col};
    *v = value;
    if (peek(p)->kind == GTOK_SEMI) advance(p);
    return PGT_OK;
}

/* Rule calls name rules by token until every rule is known; the earliest bad call in the file
 * is reported. */
static pgt_result resolve_calls(parser *p) {
    uint32_t bad = PGT_NONE;
    for (uint32_t i = 0; i < p->v[V_ITEMS].count; ++i) {
        pgt_grammar_item *it = &AT(p, V_ITEMS, pgt_grammar_item, i);
        if (it->kind != PGT_GRAMMAR_ITEM_CALL) continue;
        const uint32_t r = find_rule(p, &p->toks[it->target]);
        const int ok =
            r != PGT_NONE && AT(p, V_RULES, pgt_grammar_rule, r).param_count == it->arg_count;
        if (!ok &&
            (bad == PGT_NONE || p->toks[it->target].offset <
                                    p->toks[AT(p, V_ITEMS, pgt_grammar_item, bad).target].offset))
            bad = i;
    }
    if (bad != PGT_NONE) {
        const pgt_grammar_item *it = &AT(p, V_ITEMS, pgt_grammar_item, bad);
        const gtoken *t = &p->toks[it->target];
        const uint32_t r = find_rule(p, t);
        if (r != PGT_NONE)
            return fail_at(
                p, PGT_ERROR_INVALID_ARGUMENT, t, "rule '%.*s' takes %u argument%s, found %u",
                (int)t->length, tok_text(p, t), AT(p, V_RULES, pgt_grammar_rule, r).param_count,
                AT(p, V_RULES, pgt_grammar_rule, r).param_count == 1 ? "" : "s", it->arg_count);
        const char *best = NULL;
        uint32_t best_d = 3;
        for (uint32_t k = 0; k < p->v[V_RULES].count; ++k)
            closest(p, t,
                    (const char *)p->v[V_NAMES].data + AT(p, V_RULES, pgt_grammar_rule, k).name,
                    &best, &best_d);
        char hint[PGT_GRAMMAR_MAX_NAME_CHARS + 32];
        did_you_mean(best, hint, sizeof hint);
        return fail_at(p, PGT_ERROR_INVALID_ARGUMENT, t,
                       "unknown rule '%.*s'%s, expected a rule defined in this file",
                       (int)t->length, tok_text(p, t), hint);
    }
    for (uint32_t i = 0; i < p->v[V_ITEMS].count; ++i) {
        pgt_grammar_item *it = &AT(p, V_ITEMS, pgt_grammar_item, i);
        if (it->kind == PGT_GRAMMAR_ITEM_CALL) it->target = find_rule(p, &p->toks[it->target]);
    }
    return PGT_OK;
}

static pgt_result parse_file(parser *p) {
    while (peek(p)->kind != GTOK_EOF) {
        const gtoken *t = peek(p);
        if (t->kind == GTOK_SEMI)
            advance(p);
        else if (tok_is(p, t, "param") || tok_is(p, t, "attr"))
            TRY(parse_param(p));
        else if (t->kind == GTOK_IDENT)
            TRY(parse_rule(p));
        else
            return expected(p, "a rule (Name --> ...) or a param");
    }
    if (p->v[V_RULES].count == 0)
        return expected(p, "at least one rule (the first rule is the axiom)");
    TRY(resolve_calls(p));
    const pgt_grammar_rule *axiom = &AT(p, V_RULES, pgt_grammar_rule, 0);
    if (axiom->param_count > 0)
        return fail_rule(p, axiom,
                         "the axiom '%s' (the first rule) has parameters, expected none: the "
                         "expander starts it without arguments (add a rule like "
                         "Start --> %s(...) above it)",
                         (const char *)p->v[V_NAMES].data + axiom->name,
                         (const char *)p->v[V_NAMES].data + axiom->name);
    return PGT_OK;
}

/* Line and column of byte offset `at` of text's size bytes (for the file-size limit). */
static void position_of(const char *text, size_t size, size_t at, uint32_t *line, uint32_t *col) {
    *line = *col = 1;
    for (size_t i = 0; i < at; ++i) {
        if (pgt_grammar_line_end(text, size, i))
            ++*line, *col = 1;
        else if (((unsigned char)text[i] & 0xC0u) != 0x80u)
            ++*col;
    }
}

pgt_result pgt_grammar_compile(pgt_grammar *out, const char *text, size_t size,
                               const char *file_name, pgt_error *err) {
    memset(out, 0, sizeof *out);
    const char *file = file_name ? file_name : "<grammar>";
    if (size > PGT_GRAMMAR_MAX_FILE_BYTES) {
        uint32_t line, col;
        position_of(text, size, PGT_GRAMMAR_MAX_FILE_BYTES, &line, &col);
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s:%u:%u: the file goes on past PGT_GRAMMAR_MAX_FILE_BYTES (%u "
                             "bytes) here, expected a smaller grammar",
                             file, line, col, PGT_GRAMMAR_MAX_FILE_BYTES);
    }
    parser p;
    memset(&p, 0, sizeof p);
    p.text = text;
    p.file = file;
    p.g = out;
    p.err = err;
    p.rule = PGT_NONE;
    uint32_t ntok = 0;
    pgt_result r = pgt_grammar_lex(text, size, file, &p.toks, &ntok, err);
    if (r == PGT_OK) r = parse_file(&p);
    uint32_t name = 0;
    if (r == PGT_OK) r = add_name(&p, file, strlen(file), &name);
    free(p.toks);
    for (int k = V_SCRATCH_ITEMS; k < V_COUNT; ++k) free(p.v[k].data);
    if (r != PGT_OK) {
        for (int k = 0; k < V_SCRATCH_ITEMS; ++k) free(p.v[k].data);
        memset(out, 0, sizeof *out);
        return r;
    }
    sync(&p);
    out->file_name = name;
    return PGT_OK;
}

pgt_result pgt_grammar_load(pgt_grammar *out, const char *path, pgt_error *err) {
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* one byte past the limit is enough for compile to report it */
    char *text = malloc(PGT_GRAMMAR_MAX_FILE_BYTES + 1);
    if (!text) {
        fclose(f);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    const size_t n = fread(text, 1, PGT_GRAMMAR_MAX_FILE_BYTES + 1, f);
    const int bad = ferror(f), bad_errno = errno; /* a folder: EISDIR */
    fclose(f);
    pgt_result r =
        bad ? pgt_error_set(err, PGT_ERROR_IO, "%s: cannot read: %s", path, strerror(bad_errno))
            : pgt_grammar_compile(out, text, n, path, err);
    free(text);
    return r;
}

void pgt_grammar_destroy(pgt_grammar *g) {
    if (!g) return;
    free(g->rules);
    free(g->cases);
    free(g->sequences);
    free(g->items);
    free(g->parts);
    free(g->args);
    free(g->subs);
    free(g->exprs);
    free(g->code);
    free(g->code_pos);
    free(g->consts);
    free(g->params);
    free(g->param_values);
    free(g->rule_params);
    free(g->names);
    memset(g, 0, sizeof *g);
}

uint32_t pgt_grammar_find_rule(const pgt_grammar *g, const char *name) {
    for (uint32_t r = 0; g && name && r < g->rule_count; ++r)
        if (!strcmp(g->names + g->rules[r].name, name)) return r;
    return PGT_NONE;
}
