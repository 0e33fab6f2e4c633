/* Strict typed reading of scene values (see scene_read.h). */
#include "scene/scene_read.h"
#include "scene/strict_number.h"
#include "common/names.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

hp_error sr_fail(const sr_ctx *c, const yt_node *at, const char *path, hp_error code,
                 const char *fmt, ...)
{
    char msg[HP_DIAG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return hp_diag_set(c->diag, code, "%s:%lu:%lu: %s: %s", c->file, at ? at->line : 1UL,
                       at ? at->col : 1UL, path && path[0] ? path : "scene", msg);
}

void sr_join(char *buf, size_t size, const char *path, const char *key)
{
    if (path && path[0]) snprintf(buf, size, "%s.%s", path, key);
    else snprintf(buf, size, "%s", key);
}

void sr_index(char *buf, size_t size, const char *path, size_t i)
{
    snprintf(buf, size, "%s[%zu]", path, i);
}

const char *sr_type_name(const yt_node *node)
{
    switch (node->type) {
    case YT_SEQUENCE: return "a list";
    case YT_MAPPING: return "a mapping";
    default: break;
    }
    if (node->plain && node->len == 0) return "nothing";
    if (node->plain && hpi_decimal_syntax(node->value, node->len)) return "a single number";
    return "text";
}

hp_error sr_map(const sr_ctx *c, const yt_node *node, const char *path, const char *const *allowed,
                const char *what)
{
    if (node->type != YT_MAPPING)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected a mapping of keys, found %s",
                       sr_type_name(node));
    for (size_t i = 0; i < yt_map_size(node); ++i) {
        const yt_node *k = yt_map_key(node, i);
        int known = 0;
        for (const char *const *a = allowed; *a; ++a)
            if (strcmp(k->value, *a) == 0) known = 1;
        if (known) continue;
        char list[320];
        size_t used = 0;
        list[0] = '\0';
        for (const char *const *a = allowed; *a && used < sizeof list; ++a) {
            int w = snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "", *a);
            if (w > 0) used += (size_t)w;
        }
        char kpath[SR_PATH_MAX];
        sr_join(kpath, sizeof kpath, path, k->value);
        return sr_fail(c, k, kpath, HP_ERR_PARSE, "unknown key%s%s (allowed: %s)", what ? " " : "",
                       what ? what : "", list);
    }
    return HP_OK;
}

hp_error sr_require(const sr_ctx *c, const yt_node *map, const char *path, const char *key,
                    const yt_node **out)
{
    *out = yt_map_get(map, key);
    if (*out) return HP_OK;
    char kpath[SR_PATH_MAX];
    sr_join(kpath, sizeof kpath, path, key);
    return sr_fail(c, map, kpath, HP_ERR_PARSE, "missing required key");
}

static hp_error not_number(const sr_ctx *c, const yt_node *node, const char *path)
{
    if (node->type != YT_SCALAR)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected a number, found %s",
                       sr_type_name(node));
    if (!node->plain)
        return sr_fail(c, node, path, HP_ERR_PARSE,
                       "expected a number, found quoted text \"%.40s\" (write numbers "
                       "without quotes)",
                       node->value);
    if (node->len == 0)
        return sr_fail(c, node, path, HP_ERR_PARSE, "missing value (expected a number)");
    const char *v = node->value;
    const char *u = (*v == '+' || *v == '-') ? v + 1 : v;
    if (strcmp(u, ".nan") == 0 || strcmp(u, ".NaN") == 0 || strcmp(u, ".NAN") == 0 ||
        strcmp(u, "nan") == 0 || strcmp(u, "NaN") == 0)
        return sr_fail(c, node, path, HP_ERR_INVALID, "'%s' is not a finite number", v);
    if (strcmp(u, ".inf") == 0 || strcmp(u, ".Inf") == 0 || strcmp(u, ".INF") == 0 ||
        strcmp(u, "inf") == 0 || strcmp(u, "infinity") == 0)
        return sr_fail(c, node, path, HP_ERR_INVALID,
                       "'%s' is not a finite number (omit the key where a limit is optional)", v);
    if (u[0] == '0' && (u[1] == 'x' || u[1] == 'X' || u[1] == 'o' || u[1] == 'b'))
        return sr_fail(c, node, path, HP_ERR_PARSE, "'%.40s': only decimal numbers are accepted",
                       v);
    if (strcmp(v, "~") == 0 || strcmp(v, "null") == 0 || strcmp(v, "Null") == 0 ||
        strcmp(v, "NULL") == 0)
        return sr_fail(c, node, path, HP_ERR_PARSE, "missing value (expected a number)");
    return sr_fail(c, node, path, HP_ERR_PARSE, "'%.40s' is not a number", v);
}

hp_error sr_number_text(const sr_ctx *c, const yt_node *node, const char *path, double *out,
                        char *text, size_t size)
{
    if (node->type != YT_SCALAR || !node->plain || !hpi_decimal_syntax(node->value, node->len))
        return not_number(c, node, path);
    char *end = NULL;
    double v = hpi_c_strtod(node->value, &end);
    if (end != node->value + node->len)
        return sr_fail(c, node, path, HP_ERR_PARSE, "'%.40s' is not a number", node->value);
    if (errno == ERANGE && fabs(v) > 1.0)
        return sr_fail(c, node, path, HP_ERR_INVALID, "'%.40s' overflows a double", node->value);
    if (errno == ERANGE || (v != 0.0 && fabs(v) < DBL_MIN))
        return sr_fail(c, node, path, HP_ERR_INVALID,
                       "'%.40s' is too small for a double (underflow)", node->value);
    if (!isfinite(v))
        return sr_fail(c, node, path, HP_ERR_INVALID, "'%.40s' is not finite", node->value);
    if (text) {
        if (node->len >= size)
            return sr_fail(c, node, path, HP_ERR_PARSE, "'%.40s' is longer than %zu characters",
                           node->value, size - 1);
        memcpy(text, node->value, node->len + 1);
    }
    *out = v;
    return HP_OK;
}

hp_error sr_number(const sr_ctx *c, const yt_node *node, const char *path, double *out)
{
    return sr_number_text(c, node, path, out, NULL, 0);
}

hp_error sr_vector(const sr_ctx *c, const yt_node *node, const char *path, int n, double *out)
{
    if (node->type != YT_SEQUENCE)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected a list of %d numbers, found %s", n,
                       sr_type_name(node));
    if (node->n != (size_t)n)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected a list of %d numbers, found %zu", n,
                       node->n);
    for (int i = 0; i < n; ++i) {
        char ipath[SR_PATH_MAX];
        sr_index(ipath, sizeof ipath, path, (size_t)i);
        hp_error e = sr_number(c, node->items[i], ipath, &out[i]);
        if (e != HP_OK) return e;
    }
    return HP_OK;
}

hp_error sr_integer(const sr_ctx *c, const yt_node *node, const char *path, long lo, long hi,
                    long *out)
{
    if (node->type != YT_SCALAR || !node->plain || node->len == 0)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected a whole number, found %s",
                       node->type == YT_SCALAR && !node->plain ? "quoted text"
                                                               : sr_type_name(node));
    const char *v = node->value;
    const char *digits = (*v == '-' || *v == '+') ? v + 1 : v;
    if (*digits == '\0' || strspn(digits, "0123456789") != strlen(digits))
        return sr_fail(c, node, path, HP_ERR_PARSE, "'%.40s' is not a whole number", v);
    errno = 0;
    long x = strtol(v, NULL, 10);
    if (errno == ERANGE || x < lo || x > hi)
        return sr_fail(c, node, path, HP_ERR_INVALID, "%.40s is out of range [%ld, %ld]", v, lo,
                       hi);
    *out = x;
    return HP_OK;
}

hp_error sr_text(const sr_ctx *c, const yt_node *node, const char *path, char *buf, size_t size)
{
    if (node->type != YT_SCALAR)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected text, found %s", sr_type_name(node));
    if (node->len == 0)
        return sr_fail(c, node, path, HP_ERR_PARSE, "missing value (expected text)");
    if (node->len >= size)
        return sr_fail(c, node, path, HP_ERR_PARSE, "text longer than %zu characters", size - 1);
    size_t blank = 0;
    for (size_t i = 0; i < node->len; ++i) {
        if ((unsigned char)node->value[i] < 0x20 || node->value[i] == 0x7f)
            return sr_fail(c, node, path, HP_ERR_PARSE, "text holds a control character");
        blank += node->value[i] == ' ';
    }
    /* A name, title or file of spaces only names nothing (and prints as nothing). */
    if (blank == node->len) return sr_fail(c, node, path, HP_ERR_PARSE, "blank text (only spaces)");
    memcpy(buf, node->value, node->len + 1);
    return HP_OK;
}

hp_error sr_word(const sr_ctx *c, const yt_node *node, const char *path, const char *what,
                 const char *const *known, char *buf, size_t size)
{
    if (node->type != YT_SCALAR)
        return sr_fail(c, node, path, HP_ERR_PARSE, "expected text, found %s", sr_type_name(node));
    if (sr_text(c, node, path, buf, size) == HP_OK)
        for (int i = 0; known[i]; ++i)
            if (strcmp(buf, known[i]) == 0) return HP_OK;
    char list[256];
    hpi_names_join(known, NULL, list, sizeof list);
    return sr_fail(c, node, path, HP_ERR_PARSE, "unknown %s '%.40s' (known: %s)", what, node->value,
                   list);
}
