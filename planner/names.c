/* The planner's name tables and the name/parse calls made from them. */
#include "headplan/hp_planner.h"
#include "common/names.h"
#include "planner/names.h"

const char *const hpi_backend_words[] = {"realtime", "ipopt", "nlopt-slsqp", "nlopt-cobyla", NULL};
_Static_assert(sizeof hpi_backend_words / sizeof *hpi_backend_words == HP_BACKEND_COUNT_ + 1,
               "one word per backend");

const char *const hpi_status_words[] = {"reached",      "closest",          "iteration-limit",
                                        "time-limit",   "infeasible-start", "invalid-input",
                                        "solver-error", "uncommanded",      NULL};
_Static_assert(sizeof hpi_status_words / sizeof *hpi_status_words == HP_STATUS_COUNT_ + 1,
               "one word per status");

const char *const hpi_binding_words[] = {
    "pressure_min", "pressure_max", "stretch_min", "stretch_max", "rate_down", "rate_up",
    "limit_point",  "stress_max",   "indent_max",  "cannot_pull", "stability", NULL};
_Static_assert(sizeof hpi_binding_words / sizeof *hpi_binding_words == HP_BIND_COUNT + 1,
               "one word per binding reason");

const char *const hpi_load_tiebreak_words[] = {"least-squeeze", "previous", "stiffness", NULL};
_Static_assert(sizeof hpi_load_tiebreak_words / sizeof *hpi_load_tiebreak_words ==
                   HP_TIE_COUNT_ + 1,
               "one word per load tie-breaker");

const char *hp_binding_name(unsigned flag)
{
    for (int i = 0; i < HP_BIND_COUNT; ++i)
        if (flag == (1u << i)) return hpi_binding_words[i];
    return "unknown";
}

HP_NAMES_CALLS(hp_backend, hpi_backend_words, hp_backend_name, hp_backend_parse)

HP_NAMES_CALLS(hp_load_tiebreak, hpi_load_tiebreak_words, hp_load_tiebreak_name,
               hp_load_tiebreak_parse)

HP_NAMES_NAME_CALL(hp_status, hpi_status_words, hp_status_name)
