/* Enum <-> string for the planner's public enums. */
#include "headplan/hp_planner.h"

#include <string.h>

static const char *const backend_names[HP_BACKEND_COUNT_] = {
    "realtime", "ipopt", "nlopt-slsqp", "nlopt-cobyla"};

static const char *const status_names[HP_STATUS_COUNT_] = {
    "reached", "closest", "iteration-limit", "time-limit",
    "infeasible-start", "invalid-input", "solver-error", "uncommanded"};

static const char *const binding_names[HP_BIND_COUNT] = {
    "pressure_min", "pressure_max", "stretch_min", "stretch_max",
    "rate_down", "rate_up", "limit_point", "stress_max", "indent_max", "cannot_pull"};

const char *hp_backend_name(hp_backend b)
{
    if ((int)b < 0 || b >= HP_BACKEND_COUNT_) return "unknown";
    return backend_names[b];
}

hp_error hp_backend_parse(const char *s, hp_backend *out)
{
    if (!s || !out) return HP_ERR_NULL;
    for (int i = 0; i < HP_BACKEND_COUNT_; ++i)
        if (strcmp(s, backend_names[i]) == 0) {
            *out = (hp_backend)i;
            return HP_OK;
        }
    return HP_ERR_INVALID;
}

const char *hp_status_name(hp_status s)
{
    if ((int)s < 0 || s >= HP_STATUS_COUNT_) return "unknown";
    return status_names[s];
}

static const char *const tie_names[HP_TIE_COUNT_] = {"least-squeeze", "previous",
                                                      "stiffness"};

const char *hp_load_tiebreak_name(hp_load_tiebreak t)
{
    return (int)t >= 0 && t < HP_TIE_COUNT_ ? tie_names[t] : "unknown";
}

hp_error hp_load_tiebreak_parse(const char *s, hp_load_tiebreak *out)
{
    if (!s || !out) return HP_ERR_NULL;
    for (int i = 0; i < HP_TIE_COUNT_; ++i)
        if (strcmp(s, tie_names[i]) == 0) {
            *out = (hp_load_tiebreak)i;
            return HP_OK;
        }
    return HP_ERR_INVALID;
}

const char *hp_binding_name(unsigned flag)
{
    for (int i = 0; i < HP_BIND_COUNT; ++i)
        if (flag == (1u << i)) return binding_names[i];
    return "unknown";
}
