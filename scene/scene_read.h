/* Internal: typed, strict reading of yaml_tree nodes with "FILE:LINE:COL: PATH: message"
 * errors. Every reader returns HP_OK or an error already written into the context's diag. */
#ifndef HP_SCENE_READ_H
#define HP_SCENE_READ_H

#include <stddef.h>

#include "headplan/hp_common.h"
#include "scene/yaml_tree.h"

/* Longest key path kept in messages ("bladders[12].material.C10_pa"). */
#define SR_PATH_MAX 96

typedef struct sr_ctx {
    const char *file;
    hp_diag *diag;
} sr_ctx;

/* Writes "FILE:LINE:COL: PATH: message" (at node `at`) and returns code. */
hp_error sr_fail(const sr_ctx *c, const yt_node *at, const char *path, hp_error code,
                 const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* path + "." + key (or key alone when path is empty) into buf. */
void sr_join(char *buf, size_t size, const char *path, const char *key);
/* path + "[i]" into buf. */
void sr_index(char *buf, size_t size, const char *path, size_t i);

/* Checks that node is a mapping whose keys are all in allowed (NULL-terminated). `what`
 * qualifies the unknown-key message ("in a sphere head"); may be NULL. */
hp_error sr_map(const sr_ctx *c, const yt_node *node, const char *path, const char *const *allowed,
                const char *what);

/* The value under key in map, or an error "PATH.KEY: missing required key" pointing at the
 * enclosing mapping. */
hp_error sr_require(const sr_ctx *c, const yt_node *map, const char *path, const char *key,
                    const yt_node **out);

/* A finite number written as a plain YAML scalar: decimal only, no quotes, no .nan/.inf,
 * no hex, no overflow or underflow. */
hp_error sr_number(const sr_ctx *c, const yt_node *node, const char *path, double *out);

/* The same, with the literal text copied into text (size bytes; longer is refused). */
hp_error sr_number_text(const sr_ctx *c, const yt_node *node, const char *path, double *out,
                        char *text, size_t size);

/* A flow or block sequence of exactly n numbers. */
hp_error sr_vector(const sr_ctx *c, const yt_node *node, const char *path, int n, double *out);

/* A plain decimal integer in [lo, hi]. */
hp_error sr_integer(const sr_ctx *c, const yt_node *node, const char *path, long lo, long hi,
                    long *out);

/* Text (plain or quoted scalar), 1..size-1 bytes, no control characters. */
hp_error sr_text(const sr_ctx *c, const yt_node *node, const char *path, char *buf, size_t size);

/* A word from a fixed set (`known`, NULL-terminated), copied into buf: "expected text, found
 * ..." for a node that is no scalar, and "unknown WHAT 'x' (known: a, b, ...)" for any other
 * text that is not in the set (including empty or over-long text). */
hp_error sr_word(const sr_ctx *c, const yt_node *node, const char *path, const char *what,
                 const char *const *known, char *buf, size_t size);

/* Name of a node's type for messages: "a number", "a list", "a mapping", "text". */
const char *sr_type_name(const yt_node *node);

#endif
