/* Name tables (common/names.h). */
#include "common/names.h"

#include <stdio.h>
#include <string.h>

int hpi_names_count(const char *const *words)
{
    int n = 0;
    while (words[n]) ++n;
    return n;
}

const char *hpi_names_word(const char *const *words, int v)
{
    return v >= 0 && v < hpi_names_count(words) ? words[v] : "unknown";
}

hp_error hpi_names_parse(const char *const *words, const char *s, int *out)
{
    if (!s || !out) return HP_ERR_NULL;
    for (int i = 0; words[i]; ++i)
        if (strcmp(s, words[i]) == 0) {
            *out = i;
            return HP_OK;
        }
    return HP_ERR_INVALID;
}

const char *hpi_names_join(const char *const *words, const char *last, char *buf, size_t len)
{
    if (!buf || !len) return buf;
    buf[0] = '\0';
    const int n = hpi_names_count(words);
    size_t at = 0;
    for (int i = 0; i < n && at < len; ++i) {
        const char *sep = i == 0 ? "" : (i == n - 1 && last) ? last : ", ";
        int w = snprintf(buf + at, len - at, "%s%s", sep, words[i]);
        if (w < 0) break;
        at += (size_t)w;
    }
    return buf;
}

hp_error hpi_names_parse_to(const char *const *words, const char *s, int *out, int null_out)
{
    return null_out ? HP_ERR_NULL : hpi_names_parse(words, s, out);
}
