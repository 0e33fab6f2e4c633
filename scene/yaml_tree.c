/* A YAML stream into a tree with line:column marks (see yaml_tree.h). libyaml's event API
 * is used rather than its document API because the events show anchors and aliases, which
 * are refused here: a scene has no use for them and they are the billion-laughs vector. */
#include "scene/yaml_tree.h"
#include "scene/text_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

/* A mapping with more keys than this is not a scene (the largest has about twenty); the
 * cap keeps the duplicate-key check cheap on hostile input. */
#define YT_MAX_KEYS 256

typedef struct builder {
    const char *file;
    hp_diag *diag;
    yt_node *stack[YT_MAX_DEPTH + 1];
    int depth; /* number of open containers */
    yt_node *root;
} builder;

static yt_node *node_new(yt_type type, const yaml_mark_t *m)
{
    yt_node *n = calloc(1, sizeof *n);
    if (!n) return NULL;
    n->type = type;
    n->line = (unsigned long)m->line + 1;
    n->col = (unsigned long)m->column + 1;
    return n;
}

void yt_free(yt_node *node)
{
    if (!node) return;
    for (size_t i = 0; i < node->n; ++i) yt_free(node->items[i]);
    free(node->items);
    free(node->value);
    free(node);
}

static int node_push(yt_node *parent, yt_node *child)
{
    if (parent->n == parent->cap) {
        size_t cap = parent->cap ? 2 * parent->cap : 8;
        yt_node **items = realloc(parent->items, cap * sizeof *items);
        if (!items) return 0;
        parent->items = items;
        parent->cap = cap;
    }
    parent->items[parent->n++] = child;
    return 1;
}

/* The key path of the node about to be attached, e.g. "bladders[2].material". An outer
 * container already holds its open child (sequence: index n-1; mapping: the key before it);
 * the innermost one is about to receive the node (index n; a value's key is the last item). */
static void open_path(const builder *b, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < b->depth && used < size; ++i) {
        const yt_node *c = b->stack[i];
        int inner = i == b->depth - 1, w = 0;
        if (c->type == YT_MAPPING) {
            size_t key = inner ? c->n - 1 : c->n - 2; /* valid when n is odd / n >= 2 */
            if (inner ? c->n % 2 == 1 : c->n >= 2)
                w = snprintf(buf + used, size - used, "%s%s", used ? "." : "",
                             c->items[key]->value);
        } else {
            w = snprintf(buf + used, size - used, "[%zu]", inner ? c->n : c->n - 1);
        }
        if (w > 0) used += (size_t)w;
    }
}

static hp_error fail_at(builder *b, const yaml_mark_t *m, const char *what)
{
    char path[192];
    open_path(b, path, sizeof path);
    return hp_diag_set(b->diag, HP_ERR_PARSE, "%s:%lu:%lu: %s: %s", b->file,
                       (unsigned long)m->line + 1, (unsigned long)m->column + 1,
                       path[0] ? path : "yaml", what);
}

/* Adds a finished node to the open container (or makes it the root). */
static hp_error attach(builder *b, yt_node *n, const yaml_mark_t *m)
{
    if (b->depth == 0) {
        b->root = n;
        return HP_OK;
    }
    yt_node *parent = b->stack[b->depth - 1];
    if (parent->type == YT_MAPPING && parent->n % 2 == 0) { /* n is a key */
        if (n->type != YT_SCALAR) {
            yt_free(n);
            return fail_at(b, m, "a mapping key must be a plain word, not a list or mapping");
        }
        if (parent->n / 2 >= YT_MAX_KEYS) {
            yt_free(n);
            return fail_at(b, m, "more than 256 keys in one mapping");
        }
        for (size_t i = 0; i < parent->n; i += 2) {
            const yt_node *k = parent->items[i];
            if (k->len == n->len && memcmp(k->value, n->value, n->len) == 0) {
                char path[192], msg[256];
                open_path(b, path, sizeof path);
                snprintf(msg, sizeof msg, "duplicate key '%s' (first at line %lu)", n->value,
                         k->line);
                yt_free(n);
                return hp_diag_set(b->diag, HP_ERR_PARSE, "%s:%lu:%lu: %s%s%s: %s", b->file,
                                   (unsigned long)m->line + 1, (unsigned long)m->column + 1, path,
                                   path[0] ? "." : "", k->value, msg);
            }
        }
    }
    if (!node_push(parent, n)) {
        yt_free(n);
        return hp_diag_set(b->diag, HP_ERR_NOMEM, "%s: out of memory", b->file);
    }
    return HP_OK;
}

static hp_error open_container(builder *b, yt_type type, const yaml_mark_t *m,
                               const yaml_char_t *anchor, const yaml_char_t *tag, int implicit)
{
    if (anchor) return fail_at(b, m, "anchors (&name) are not allowed in a scene");
    if (tag && !implicit) return fail_at(b, m, "tags (!name) are not allowed in a scene");
    if (b->depth >= YT_MAX_DEPTH) return fail_at(b, m, "nested more than 32 levels deep");
    yt_node *n = node_new(type, m);
    if (!n) return hp_diag_set(b->diag, HP_ERR_NOMEM, "%s: out of memory", b->file);
    hp_error e = attach(b, n, m);
    if (e != HP_OK) return e;
    b->stack[b->depth++] = n;
    return HP_OK;
}

static hp_error scalar(builder *b, const yaml_event_t *ev)
{
    const yaml_mark_t *m = &ev->start_mark;
    if (ev->data.scalar.anchor) return fail_at(b, m, "anchors (&name) are not allowed in a scene");
    if (ev->data.scalar.tag && !ev->data.scalar.plain_implicit && !ev->data.scalar.quoted_implicit)
        return fail_at(b, m, "tags (!name) are not allowed in a scene");
    yt_node *n = node_new(YT_SCALAR, m);
    if (!n) return hp_diag_set(b->diag, HP_ERR_NOMEM, "%s: out of memory", b->file);
    n->len = ev->data.scalar.length;
    n->value = malloc(n->len + 1);
    if (!n->value) {
        yt_free(n);
        return hp_diag_set(b->diag, HP_ERR_NOMEM, "%s: out of memory", b->file);
    }
    memcpy(n->value, ev->data.scalar.value, n->len);
    n->value[n->len] = '\0';
    n->plain = ev->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
    if (strlen(n->value) != n->len) {
        yt_free(n);
        return fail_at(b, m, "text holds a NUL character");
    }
    return attach(b, n, m);
}

static hp_error parser_error(builder *b, const yaml_parser_t *p)
{
    if (p->error == YAML_MEMORY_ERROR)
        return hp_diag_set(b->diag, HP_ERR_NOMEM, "%s: out of memory", b->file);
    const yaml_mark_t *m = &p->problem_mark;
    const char *problem = p->problem ? p->problem : "malformed YAML";
    if (p->context)
        return hp_diag_set(b->diag, HP_ERR_PARSE, "%s:%lu:%lu: yaml: %s %s (line %lu)", b->file,
                           (unsigned long)m->line + 1, (unsigned long)m->column + 1, problem,
                           p->context, (unsigned long)p->context_mark.line + 1);
    return hp_diag_set(b->diag, HP_ERR_PARSE, "%s:%lu:%lu: yaml: %s", b->file,
                       (unsigned long)m->line + 1, (unsigned long)m->column + 1, problem);
}

/* A NUL byte or broken UTF-8 anywhere, reported at its own line and column (libyaml would
 * report 1:1, or read the text as another encoding). Columns count characters. */
static hp_error check_bytes(const char *text, size_t len, const char *filename, hp_diag *diag)
{
    int nul = 0;
    long at = hpi_text_bad_byte(text, len, &nul);
    if (at < 0) return HP_OK;
    unsigned long line = 1, col = 1;
    for (long i = 0; i < at; ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else if (((unsigned char)text[i] & 0xC0) != 0x80) {
            ++col;
        }
    }
    return hp_diag_set(diag, HP_ERR_PARSE, "%s:%lu:%lu: %s", filename, line, col,
                       nul ? "NUL byte" : "invalid UTF-8");
}

hp_error yt_parse(const char *text, size_t len, const char *filename, yt_node **root, hp_diag *diag)
{
    *root = NULL;
    /* A UTF-8 byte-order mark is skipped (editors on Windows write one). */
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) {
        text += 3;
        len -= 3;
    }
    hp_error bytes = check_bytes(text, len, filename, diag);
    if (bytes != HP_OK) return bytes;
    builder b = {.file = filename, .diag = diag};
    yaml_parser_t p;
    if (!yaml_parser_initialize(&p))
        return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", filename);
    yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
    yaml_parser_set_encoding(&p, YAML_UTF8_ENCODING);

    hp_error e = HP_OK;
    int documents = 0, done = 0;
    while (!done && e == HP_OK) {
        yaml_event_t ev;
        if (!yaml_parser_parse(&p, &ev)) {
            e = parser_error(&b, &p);
            break;
        }
        switch (ev.type) {
        case YAML_STREAM_END_EVENT: done = 1; break;
        case YAML_DOCUMENT_START_EVENT:
            if (++documents > 1)
                e = fail_at(&b, &ev.start_mark, "only one YAML document is allowed");
            break;
        case YAML_ALIAS_EVENT:
            e = fail_at(&b, &ev.start_mark, "aliases (*name) are not allowed in a scene");
            break;
        case YAML_SCALAR_EVENT: e = scalar(&b, &ev); break;
        case YAML_SEQUENCE_START_EVENT:
            e = open_container(&b, YT_SEQUENCE, &ev.start_mark, ev.data.sequence_start.anchor,
                               ev.data.sequence_start.tag, ev.data.sequence_start.implicit);
            break;
        case YAML_MAPPING_START_EVENT:
            e = open_container(&b, YT_MAPPING, &ev.start_mark, ev.data.mapping_start.anchor,
                               ev.data.mapping_start.tag, ev.data.mapping_start.implicit);
            break;
        case YAML_SEQUENCE_END_EVENT:
        case YAML_MAPPING_END_EVENT:
            if (b.depth > 0) --b.depth;
            break;
        default: break;
        }
        yaml_event_delete(&ev);
    }
    yaml_parser_delete(&p);
    if (e == HP_OK && !b.root)
        e = hp_diag_set(diag, HP_ERR_PARSE,
                        "%s:1:1: headplan_scene: empty file (a scene starts with "
                        "'headplan_scene: 1')",
                        filename);
    if (e != HP_OK) {
        yt_free(b.root);
        return e;
    }
    *root = b.root;
    return HP_OK;
}

size_t yt_map_size(const yt_node *map) { return map->n / 2; }
const yt_node *yt_map_key(const yt_node *map, size_t i) { return map->items[2 * i]; }
const yt_node *yt_map_value(const yt_node *map, size_t i) { return map->items[2 * i + 1]; }

const yt_node *yt_map_get(const yt_node *map, const char *name)
{
    for (size_t i = 0; i < map->n / 2; ++i)
        if (strcmp(map->items[2 * i]->value, name) == 0) return map->items[2 * i + 1];
    return NULL;
}
