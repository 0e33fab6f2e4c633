/* The load level through hp_planner for the load tests: a planner at HP_LEVEL_LOAD carrying
 * spec, with settings s (NULL = defaults) whose level names the load level's contact
 * geometry (auto: surface), and tie-breaker tie; and a plan with the load level's details
 * (hp_planner_load_info) when info is not NULL. */
#ifndef TESTS_PLANNER_LOAD_FIXTURE_H
#define TESTS_PLANNER_LOAD_FIXTURE_H

#include "headplan/hp_planner.h"

static inline hp_error load_create(const hp_layout *L, const hp_load_spec *spec,
                                   const hp_settings *s, hp_load_tiebreak tie, hp_planner **out,
                                   hp_diag *d)
{
    hp_settings set;
    if (s) set = *s;
    else hp_settings_default(&set);
    set.load_geometry = set.level == HP_LEVEL_AUTO ? HP_LEVEL_SURFACE : set.level;
    set.level = HP_LEVEL_LOAD;
    set.load = *spec;
    set.load_tiebreak = tie;
    return hp_planner_create(L, &set, out, d);
}

static inline hp_error load_plan(hp_planner *p, const double desired[6], hp_result *r,
                                 hp_load_info *info)
{
    hp_error e = hp_plan(p, desired, r);
    if (e == HP_OK && info) e = hp_planner_load_info(p, info);
    return e;
}

#endif
