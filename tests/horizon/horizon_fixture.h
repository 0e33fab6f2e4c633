/* Test fixture for the horizon planners: a scene of scenarios/ and the first rows of one of
 * the horizon traces, read through the public scene and trace readers (deviation rows). */
#ifndef HP_TEST_HORIZON_FIXTURE_H
#define HP_TEST_HORIZON_FIXTURE_H

#include "headplan/headplan.h"

#include <stdlib.h>
#include <string.h>

#define HF_MAX_ROWS 600
#define HF_MAX_TIME_S 60.0 /* the planners' time budget: see hf_load */

typedef struct hf_case {
    hp_scene sc;
    hp_settings s;
    hp_trace_row rows[HF_MAX_ROWS];
    size_t T;
    double p0[HP_MAX_BLADDERS];
} hf_case;

/* Loads scenarios/SCENE (its settings with a time budget of HF_MAX_TIME_S) and the first
 * max_rows rows of scenarios/traces/TRACE; NULL on failure (the caller asserts). Free with
 * free(). */
static inline hf_case *hf_load(const char *scene, const char *trace, size_t max_rows)
{
    hf_case *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    char path[1024];
    hp_diag d = {{0}};
    snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, scene);
    if (hp_scene_load(path, &c->sc, &d) != HP_OK || hp_scene_settings(&c->sc, &c->s, &d) != HP_OK) {
        fprintf(stderr, "%s\n", d.text);
        free(c);
        return NULL;
    }
    /* The scenes' budget (1 s a plan) is read on the wall clock, and the receding horizon's
     * solve of each row stops within four fifths of it: on a machine stalled that long a row
     * ended "time-limit" (seen at a 1 % CPU share). 60 s, so that no verdict depends on the
     * machine's speed; a test of the budget itself sets its own. */
    c->s.max_time = HF_MAX_TIME_S;
    snprintf(path, sizeof path, "%s/scenarios/traces/%s", HP_SOURCE_DIR, trace);
    hp_trace_rows dev = HP_TRACE_DEVIATION;
    hp_trace_reader *r = NULL;
    if (hp_trace_open(path, &dev, &r, &d) != HP_OK) {
        fprintf(stderr, "%s\n", d.text);
        free(c);
        return NULL;
    }
    while (c->T < max_rows && c->T < HF_MAX_ROWS && hp_trace_next(r, &c->rows[c->T], &d) == HP_OK)
        c->T++;
    hp_trace_close(r);
    if (hp_horizon_nominal_pressures(&c->sc.layout, c->p0, &d) != HP_OK) {
        free(c);
        return NULL;
    }
    return c;
}

#endif
