/* pgt: the grammar language and its rule compiler (paper 000 sections 5, 7 and 8; issue 5 item 1;
 * split parts for issue 6 item 1).
 *
 * This work is based on:
 *   Paper 000, "Dynamic On-Mesh Procedural Generation": sec. 5 (the marching rule
 *   Pred -> Marching(length, angle, condition) {TopSucc, ExtrudedSucc}), sec. 7 (the CPU "rule
 *   compiler" turning the grammar into GPU-ready rule and parameter maps), sec. 8 (the ivy
 *   grammar, shipped as grammars/ivy.grammar).
 *   CGA shape grammars (Mueller et al. 2006) and CityEngine's CGA reference for conditional rules
 *   (case/else), attr, NIL and the split syntax (absolute, relative ', floating ~, repeat *).
 *
 * The language is specified in grammars/README.md. pgt_grammar_compile turns one grammar text
 * into a pgt_grammar: flat arrays of packed structs of uint32 (and float) with indices between
 * them and no pointers inside, so every array can be uploaded to a GPU as is; a GPU port reads
 * the layout below and never re-defines it.
 *
 * Layout (every index is a uint32; PGT_NONE = 0xFFFFFFFF means "none"):
 *   rules[r]      name, rule parameters rule_params[first_param .. +param_count) (name offsets),
 *                 cases[first_case .. +case_count). rules[0] is the axiom; it has no parameters.
 *                 A rule without case/else has exactly one case whose condition is PGT_NONE.
 *   cases[c]      condition (expression, PGT_NONE = always: the unconditional body or the else),
 *                 sequence. The first case whose condition is not 0 is taken, in order.
 *   sequences[s]  items[first_item .. +item_count), applied in order (an empty sequence is NIL).
 *   items[i]      kind (pgt_grammar_item_kind) and, by kind:
 *                   CALL      target = rule, args = one expression per rule parameter;
 *                   MARCHING  args = (length, angle, condition), subs = (TopSucc, ExtrudedSucc);
 *                   BRANCH    args = (count), subs = count sequences, count = sub_count;
 *                   TERMINAL  target = pgt_grammar_terminal, args = its arguments;
 *                   SPLIT     target = axis (0 x, 1 y, 2 z), parts[first_sub .. +sub_count).
 *                 args are args[first_arg .. +arg_count) (expression indices), subs are
 *                 subs[first_sub .. +sub_count) (sequence indices) except for SPLIT.
 *   parts[p]      one split part: kind (pgt_grammar_part_kind), size expression, successor
 *                 sequence; a REPEAT part has no size and no sequence but its own parts
 *                 parts[first_part .. +part_count) (repeat groups do not nest).
 *   exprs[e]      code[first_code .. +code_count), a postfix program for the stack machine of
 *                 pgt_grammar_eval; max_stack is its deepest stack (at most
 *                 PGT_GRAMMAR_VM_STACK); flags say what it reads (PGT_GRAMMAR_EXPR_*).
 *   code[k]       one instruction: opcode in the low PGT_GRAMMAR_OP_BITS bits, operand above
 *                 (const index, param index, rule parameter index or context id).
 *   code_pos[k]   the source token of code[k] (the operator, function, number or name): where an
 *                 error of that instruction points. For messages only; the machine never reads
 *                 it (a GPU port need not upload it).
 *   consts[k]     float32 literal pool (PI included); param_values[k] the params' current values.
 *   params[k]     name, the expression it was defined by, whether pgt_grammar_set_param
 *                 overrode it.
 *   names         a char pool of NUL-terminated names (rules, rule parameters, params, the
 *                 file name); name fields are byte offsets into it.
 * Items, parts and expressions carry their source line and column (1-based, columns count UTF-8
 * code points) for runtime errors. */
#ifndef PGT_GRAMMAR_H
#define PGT_GRAMMAR_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits. Exceeding one is PGT_ERROR_LIMIT naming the limit and FILE:LINE:COL. */

/* A grammar is a hand-written text of a few KB; 1 MiB bounds the token array (about 32 bytes a
 * token) and the time spent on a wrong file passed by mistake. */
#define PGT_GRAMMAR_MAX_FILE_BYTES (1u << 20)
/* Rules per grammar: the paper's ivy has 3 and a CGA building a few hundred. */
#define PGT_GRAMMAR_MAX_RULES 4096u
/* Top-level params (attr) per grammar. */
#define PGT_GRAMMAR_MAX_PARAMS 4096u
/* Parameters of one rule, and so arguments of one call or terminal: the expander keeps a rule's
 * arguments in a fixed-size frame per stack level (16 floats = 64 bytes). */
#define PGT_GRAMMAR_MAX_RULE_PARAMS 16u
/* Items (calls, Marching, Branch, terminals, splits) per grammar. */
#define PGT_GRAMMAR_MAX_ITEMS 65536u
/* Sequences per grammar (Branch(N) and split parts make one each; empty ones count). */
#define PGT_GRAMMAR_MAX_SEQUENCES 65536u
/* Expressions per grammar (every argument, condition, size and param is one). */
#define PGT_GRAMMAR_MAX_EXPRS 65536u
/* Instruction words per grammar. */
#define PGT_GRAMMAR_MAX_CODE (1u << 18)
/* Float literals per grammar (not de-duplicated). */
#define PGT_GRAMMAR_MAX_CONSTS 65536u
/* Nesting of successor sequences ({ } of Marching, Branch, split and repeat groups): the parser
 * recurses once per level, so this bounds its C stack; real grammars nest a handful. */
#define PGT_GRAMMAR_MAX_NESTING 64u
/* Nesting of one expression (parentheses, unary operators, right operands, function
 * arguments): the parser recurses once per level. A right-nested `a + (b + (...))` takes two
 * levels per stack entry, so 128 lets PGT_GRAMMAR_VM_STACK be the bound such expressions meet. */
#define PGT_GRAMMAR_MAX_EXPR_DEPTH 128u
/* The evaluator's stack in floats: small enough to live in GPU registers or private memory;
 * every expression's max_stack is computed at compile time and checked against it. */
#define PGT_GRAMMAR_VM_STACK 32u
/* Characters of one identifier, and of one number literal. */
#define PGT_GRAMMAR_MAX_NAME_CHARS 128u

/* Instructions: opcode | operand << PGT_GRAMMAR_OP_BITS. */
#define PGT_GRAMMAR_OP_BITS 8u
#define PGT_GRAMMAR_OP_MASK 0xFFu
typedef enum pgt_grammar_op {
    PGT_GRAMMAR_OP_CONST = 0,    /* push consts[operand] */
    PGT_GRAMMAR_OP_PARAM = 1,    /* push param_values[operand] */
    PGT_GRAMMAR_OP_ARG = 2,      /* push the enclosing rule's argument number operand */
    PGT_GRAMMAR_OP_NEG = 3,      /* unary -, then binary operators: pop b, pop a, push a op b */
    PGT_GRAMMAR_OP_NOT = 4,      /* !a = (a == 0) */
    PGT_GRAMMAR_OP_ADD = 5,      /* + */
    PGT_GRAMMAR_OP_SUB = 6,      /* - */
    PGT_GRAMMAR_OP_MUL = 7,      /* * */
    PGT_GRAMMAR_OP_DIV = 8,      /* / */
    PGT_GRAMMAR_OP_MOD = 9,      /* % as C's fmodf (the sign of a) */
    PGT_GRAMMAR_OP_LT = 10,      /* comparisons and logic give 1 or 0 */
    PGT_GRAMMAR_OP_LE = 11,      /* <= */
    PGT_GRAMMAR_OP_GT = 12,      /* > */
    PGT_GRAMMAR_OP_GE = 13,      /* >= */
    PGT_GRAMMAR_OP_EQ = 14,      /* == */
    PGT_GRAMMAR_OP_NE = 15,      /* != */
    PGT_GRAMMAR_OP_AND = 16,     /* && (both sides evaluated: no short circuit, see README) */
    PGT_GRAMMAR_OP_OR = 17,      /* || (both sides evaluated) */
    PGT_GRAMMAR_OP_RAND = 18,    /* pop b, pop a, push rand(a, b) */
    PGT_GRAMMAR_OP_CONTEXT = 19, /* push context(operand = pgt_grammar_context, texCoord) */
    PGT_GRAMMAR_OP_SIN = 20,     /* the functions, in the order of the language reference */
    PGT_GRAMMAR_OP_COS = 21,
    PGT_GRAMMAR_OP_TAN = 22,
    PGT_GRAMMAR_OP_ASIN = 23,
    PGT_GRAMMAR_OP_ACOS = 24,
    PGT_GRAMMAR_OP_ATAN = 25,
    PGT_GRAMMAR_OP_ATAN2 = 26, /* atan2(y, x) */
    PGT_GRAMMAR_OP_SQRT = 27,
    PGT_GRAMMAR_OP_ABS = 28,
    PGT_GRAMMAR_OP_FLOOR = 29,
    PGT_GRAMMAR_OP_CEIL = 30,
    PGT_GRAMMAR_OP_MIN = 31,
    PGT_GRAMMAR_OP_MAX = 32,
    PGT_GRAMMAR_OP_POW = 33,
    PGT_GRAMMAR_OP_EXP = 34,
    PGT_GRAMMAR_OP_LOG = 35,   /* natural logarithm */
    PGT_GRAMMAR_OP_CLAMP = 36, /* clamp(x, lo, hi) = min(max(x, lo), hi) */
    PGT_GRAMMAR_OP_COUNT = 37
} pgt_grammar_op;

/* External contexts (paper 000 sec. 7): texture maps in atlas space read at texCoord. */
typedef enum pgt_grammar_context {
    PGT_GRAMMAR_CONTEXT_MASK = 0,    /* context.mask(texCoord) */
    PGT_GRAMMAR_CONTEXT_DENSITY = 1, /* context.density(texCoord) */
    PGT_GRAMMAR_CONTEXT_COUNT = 2
} pgt_grammar_context;

typedef enum pgt_grammar_item_kind {
    PGT_GRAMMAR_ITEM_CALL = 0,
    PGT_GRAMMAR_ITEM_MARCHING = 1,
    PGT_GRAMMAR_ITEM_BRANCH = 2,
    PGT_GRAMMAR_ITEM_TERMINAL = 3,
    PGT_GRAMMAR_ITEM_SPLIT = 4
} pgt_grammar_item_kind;

/* Built-in terminal shapes (a table in grammar_parse.c). */
typedef enum pgt_grammar_terminal {
    PGT_GRAMMAR_TERMINAL_BARK = 0,   /* Bark(radius, smoothness) */
    PGT_GRAMMAR_TERMINAL_LEAVES = 1, /* Leaves(density, size) */
    /* Facade terminals (paper 003 sec. 6.2.1; facade.h gives their geometry). */
    PGT_GRAMMAR_TERMINAL_WALL = 2,    /* Wall() */
    PGT_GRAMMAR_TERMINAL_WINDOW = 3,  /* Window(margin, frame, frameDepth, recess, sillHeight,
                                         sillDepth) */
    PGT_GRAMMAR_TERMINAL_DOOR = 4,    /* Door(margin, frame, frameDepth, recess) */
    PGT_GRAMMAR_TERMINAL_LEDGE = 5,   /* Ledge(depth) */
    PGT_GRAMMAR_TERMINAL_BALCONY = 6, /* Balcony(depth, slab, railing) */
    PGT_GRAMMAR_TERMINAL_MESH = 7,    /* Mesh(id): geometry image id of the facade scene */
    PGT_GRAMMAR_TERMINAL_COUNT = 8
} pgt_grammar_terminal;

/* Bark's smoothness along the trajectory (paper 000 sec. 6), the value of its second argument. */
typedef enum pgt_grammar_smoothness {
    PGT_GRAMMAR_DISCONTINUOUS = 0,
    PGT_GRAMMAR_C0 = 1,
    PGT_GRAMMAR_C1 = 2
} pgt_grammar_smoothness;

/* Split part sizes (CGA): absolute (EXPR), relative ('EXPR, that fraction of the scope's length),
 * floating (~EXPR, absolute but stretched to fit), and repeat groups ({ ... }*); split.h lays
 * them out. */
typedef enum pgt_grammar_part_kind {
    PGT_GRAMMAR_PART_ABSOLUTE = 0,
    PGT_GRAMMAR_PART_RELATIVE = 1,
    PGT_GRAMMAR_PART_FLOATING = 2,
    PGT_GRAMMAR_PART_REPEAT = 3
} pgt_grammar_part_kind;

/* Expression flags: what an expression reads. An expression without RAND, CONTEXT and ARGS is a
 * constant of the params (PGT_GRAMMAR_EXPR_CONSTANT is then set). */
#define PGT_GRAMMAR_EXPR_RAND 1u
#define PGT_GRAMMAR_EXPR_CONTEXT 2u
#define PGT_GRAMMAR_EXPR_ARGS 4u
#define PGT_GRAMMAR_EXPR_CONSTANT 8u

typedef struct pgt_grammar_rule {
    uint32_t name;        /* offset in names */
    uint32_t first_param; /* in rule_params */
    uint32_t param_count;
    uint32_t first_case; /* in cases */
    uint32_t case_count; /* >= 1 */
    uint32_t line, col;
} pgt_grammar_rule;

typedef struct pgt_grammar_case {
    uint32_t condition; /* expression, or PGT_NONE (unconditional / else) */
    uint32_t sequence;
} pgt_grammar_case;

typedef struct pgt_grammar_sequence {
    uint32_t first_item;
    uint32_t item_count;
} pgt_grammar_sequence;

typedef struct pgt_grammar_item {
    uint32_t kind;   /* pgt_grammar_item_kind */
    uint32_t target; /* CALL: rule; TERMINAL: pgt_grammar_terminal; SPLIT: axis; else PGT_NONE */
    uint32_t first_arg, arg_count; /* in args */
    uint32_t first_sub, sub_count; /* in subs (MARCHING, BRANCH) or parts (SPLIT) */
    uint32_t line, col;
} pgt_grammar_item;

typedef struct pgt_grammar_part {
    uint32_t kind;                   /* pgt_grammar_part_kind */
    uint32_t size;                   /* expression, PGT_NONE for REPEAT */
    uint32_t sequence;               /* successor, PGT_NONE for REPEAT */
    uint32_t first_part, part_count; /* REPEAT: its parts; else 0, 0 */
    uint32_t line, col;
} pgt_grammar_part;

typedef struct pgt_grammar_expr {
    uint32_t first_code, code_count; /* in code */
    uint32_t max_stack;              /* <= PGT_GRAMMAR_VM_STACK */
    uint32_t flags;                  /* PGT_GRAMMAR_EXPR_* */
    uint32_t line, col;
} pgt_grammar_expr;

/* A source position: line and column (1-based, columns count UTF-8 code points). */
typedef struct pgt_grammar_pos {
    uint32_t line, col;
} pgt_grammar_pos;

typedef struct pgt_grammar_param {
    uint32_t name;       /* offset in names */
    uint32_t expr;       /* its defining expression (constants and earlier params only) */
    uint32_t overridden; /* 1 after pgt_grammar_set_param: no longer re-evaluated */
    uint32_t line, col;
} pgt_grammar_param;

typedef struct pgt_grammar {
    uint32_t file_name; /* offset in names: the name given to pgt_grammar_compile */
    uint32_t rule_count, case_count, sequence_count, item_count, part_count;
    uint32_t arg_count, sub_count, expr_count, code_count, const_count, param_count;
    uint32_t rule_param_count, names_size;
    pgt_grammar_rule *rules;
    pgt_grammar_case *cases;
    pgt_grammar_sequence *sequences;
    pgt_grammar_item *items;
    pgt_grammar_part *parts;
    uint32_t *args; /* expression indices */
    uint32_t *subs; /* sequence indices */
    pgt_grammar_expr *exprs;
    uint32_t *code; /* instructions */
    pgt_grammar_pos *code_pos; /* code_count: each instruction's token (messages only) */
    float *consts;
    pgt_grammar_param *params;
    float *param_values;
    uint32_t *rule_params; /* name offsets */
    char *names;
} pgt_grammar;

/* Compiles text[0 .. size) (UTF-8, no NUL needed) into *out (zeroed first; destroy it with
 * pgt_grammar_destroy, also after a failure). file_name prefixes every message:
 * "FILE:LINE:COL: what was found, what was expected". PGT_ERROR_PARSE for syntax,
 * PGT_ERROR_INVALID_ARGUMENT for semantics, PGT_ERROR_LIMIT for limits. Never crashes. */
pgt_result pgt_grammar_compile(pgt_grammar *out, const char *text, size_t size,
                               const char *file_name, pgt_error *err);

/* Reads the file at path and compiles it (path names the file in messages). */
pgt_result pgt_grammar_load(pgt_grammar *out, const char *path, pgt_error *err);

/* Frees the arrays; g may be NULL or zeroed. */
void pgt_grammar_destroy(pgt_grammar *g);

/* The rule called name, or PGT_NONE. */
uint32_t pgt_grammar_find_rule(const pgt_grammar *g, const char *name);

/* The param called name, or PGT_NONE. */
uint32_t pgt_grammar_find_param(const pgt_grammar *g, const char *name);

/* Overrides a param (as `pgt grammar --param NAME=VALUE`) and re-evaluates the params defined
 * after it that were not overridden. Unknown name, non-finite value, a dependent param that no
 * longer evaluates (division by zero, not finite) or a Branch count that no longer matches is
 * PGT_ERROR_INVALID_ARGUMENT and leaves every value as it was. */
pgt_result pgt_grammar_set_param(pgt_grammar *g, const char *name, float value, pgt_error *err);

/* A context lookup: the value of map context_id (pgt_grammar_context) at texCoord (u, v). */
typedef float (*pgt_grammar_context_fn)(void *ctx, uint32_t context_id, float u, float v);

/* What an expression may read besides its arguments. */
typedef struct pgt_grammar_env {
    uint32_t seed;     /* the seed id */
    uint32_t stream;   /* the RNG stream */
    uint64_t *counter; /* draw counter: rand uses (seed, stream, *counter) then increments it;
                          NULL only for expressions without rand */
    float u, v;        /* texCoord: the marching destination in a Marching condition, the
                          current position elsewhere (the expander decides) */
    pgt_grammar_context_fn context; /* NULL only for expressions without context */
    void *context_data;
    const float *params; /* param values to read instead of the grammar's param_values (one
                            vector per building in a facade scene), or NULL */
} pgt_grammar_env;

/* Evaluates expression expr with the enclosing rule's argument values args[0 .. arg_count) on
 * an explicit stack (no recursion). rand(a, b) = a + (b - a) * pgt_rng_float(seed, stream,
 * counter++), kept below b when a < b. PGT_ERROR_NOT_FINITE with FILE:LINE:COL when the value is
 * NaN or infinite, PGT_ERROR_INVALID_ARGUMENT when env lacks the counter or callback it needs. */
pgt_result pgt_grammar_eval(const pgt_grammar *g, uint32_t expr, const float *args,
                            uint32_t arg_count, const pgt_grammar_env *env, float *out,
                            pgt_error *err);

/* Names of built-ins, for listings: "Bark", "x", "mask", "C1", "sin", "rand", "+", ... */
const char *pgt_grammar_terminal_name(uint32_t terminal);
const char *pgt_grammar_context_name(uint32_t context_id);
const char *pgt_grammar_smoothness_name(uint32_t smoothness);
const char *pgt_grammar_op_name(uint32_t op);

/* Writes the compiled grammar as grammar text (it compiles again to the same listing), with the
 * indices and source positions in comments: params (expression and value), then every rule with
 * its cases and items, expressions in infix. */
void pgt_grammar_dump(const pgt_grammar *g, FILE *f);

#ifdef __cplusplus
}
#endif

#endif
