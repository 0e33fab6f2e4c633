/* Allocation-free message building for the planner's two text channels (hp_planner_error,
 * hp_planner_note): hp_plan must not allocate, and printf's float formatting may. */
#include "planner/planner_internal.h"

#include <math.h>
#include <string.h>

void hp_text_set(char *buf, const char *s)
{
    size_t n = strlen(s);
    if (n >= HP_DIAG_MAX) n = HP_DIAG_MAX - 1;
    memcpy(buf, s, n);
    buf[n] = '\0';
}

void hp_text_add(char *buf, const char *s)
{
    size_t have = strlen(buf), n = strlen(s);
    if (have + n >= HP_DIAG_MAX) n = HP_DIAG_MAX - 1 - have;
    memcpy(buf + have, s, n);
    buf[have + n] = '\0';
}

void hp_text_add_int(char *buf, long long v)
{
    char tmp[32], *q = tmp + sizeof tmp - 1;
    unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    *q = '\0';
    do {
        *--q = (char)('0' + u % 10u);
        u /= 10u;
    } while (u);
    if (v < 0) *--q = '-';
    hp_text_add(buf, q);
}

void hp_text_add_num(char *buf, double v, int dec)
{
    /* The fraction's digits go into a 16-byte buffer below; no double has more than 15
     * significant decimals to print there anyway. */
    if (dec > 15) dec = 15;
    double scale = 1.0;
    for (int i = 0; i < dec; ++i) scale *= 10.0;
    if (!(fabs(v) * scale < 1e15)) {
        hp_text_add(buf, v != v ? "nan" : "huge");
        return;
    }
    long long q = llround(fabs(v) * scale);
    if (v < 0 && q != 0) hp_text_add(buf, "-");
    long long ip = q;
    for (int i = 0; i < dec; ++i) ip /= 10;
    hp_text_add_int(buf, ip);
    if (dec > 0) {
        char frac[16];
        long long f = q;
        for (int i = dec - 1; i >= 0; --i) {
            frac[i] = (char)('0' + f % 10);
            f /= 10;
        }
        /* dec <= 15 (clamped above), which cppcheck does not follow. */
        // cppcheck-suppress arrayIndexOutOfBoundsCond
        frac[dec] = '\0';
        hp_text_add(buf, ".");
        hp_text_add(buf, frac);
    }
}

/* "(x, y, z) mm (pitch, roll, yaw) deg, W mm/deg away" of a round trip's end, with 9 decimals
 * (a reader can evaluate the distances there to ~1e-8 mm). */
static void add_trip_end(char *buf, const hp_plan_trip *t)
{
    double x[6];
    hp_plan_to_scaled(t->end, x);
    hp_text_add(buf, "(");
    for (int i = 0; i < 6; ++i) {
        hp_text_add_num(buf, x[i], 9);
        hp_text_add(buf, i == 2 ? ") mm (" : i == 5 ? ") deg, " : ", ");
    }
    hp_text_add_num(buf, t->worst, 6);
    hp_text_add(buf, " mm/deg away");
}

void hp_plan_trip_text(char *buf, const hp_plan_trip *t)
{
    hp_text_add(buf, "forward contact kinematics from the nominal pose ");
    if (!isfinite(t->worst)) {
        hp_text_add(buf, "did not converge, so it cannot confirm these pressures' pose");
        return;
    }
    if (t->gap_mm <= HP_IDENT_NAME_MM) {
        hp_text_add(buf, "finds another pose, ");
        add_trip_end(buf, t);
        hp_text_add(buf, ", whose contact distances match these pressures' to within 1 nm");
        return;
    }
    hp_text_add(buf, "stalled at ");
    add_trip_end(buf, t);
    if (isfinite(t->gap_mm)) {
        hp_text_add(buf, ", where its contact distances miss these pressures' by ");
        hp_text_add_num(buf, t->gap_mm, 6);
        hp_text_add(buf, " mm");
    } else {
        hp_text_add(buf, ", where its contact distances cannot be evaluated");
    }
    hp_text_add(buf, ", so it cannot confirm their pose");
}
