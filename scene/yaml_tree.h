/* Internal: a YAML stream read into a small tree of scalars, sequences and mappings, each
 * node keeping its 1-based line and column. Anchors, aliases, tags, several documents and
 * nesting deeper than YT_MAX_DEPTH are refused, so a tree's size is bounded by its text. */
#ifndef HP_SCENE_YAML_TREE_H
#define HP_SCENE_YAML_TREE_H

#include <stddef.h>

#include "headplan/hp_common.h"

#define YT_MAX_DEPTH 32

typedef enum yt_type { YT_SCALAR = 0, YT_SEQUENCE, YT_MAPPING } yt_type;

typedef struct yt_node {
    yt_type type;
    unsigned long line, col; /* 1-based start of the node */
    char *value;             /* scalars: NUL-terminated text */
    size_t len;              /* scalars: length of value (may hold NULs: refused later) */
    int plain;               /* scalars: 1 when unquoted (plain style) */
    struct yt_node **items;  /* sequences: n items; mappings: n/2 key,value pairs */
    size_t n, cap;
} yt_node;

/* Parses text (len bytes) into *root. filename is only used in messages. On failure
 * returns HP_ERR_PARSE (or HP_ERR_NOMEM) with "FILE:LINE:COL: yaml: why" in diag and
 * *root == NULL. An empty stream is refused with "FILE:1:1: ...: empty file". */
hp_error yt_parse(const char *text, size_t len, const char *filename, yt_node **root,
                  hp_diag *diag);

/* Frees a tree from yt_parse (NULL is fine). */
void yt_free(yt_node *node);

/* Mapping helpers: the number of pairs, and key / value of pair i. */
size_t yt_map_size(const yt_node *map);
const yt_node *yt_map_key(const yt_node *map, size_t i);
const yt_node *yt_map_value(const yt_node *map, size_t i);
/* The value under key name, or NULL. */
const yt_node *yt_map_get(const yt_node *map, const char *name);

#endif
