/* The backend table: the one place the core learns which backends exist. Adding a backend
 * is its own file (filling an hp_backend_ops), its enum value and name in hp_planner.h, and
 * one line here (CONTRIBUTING.md). */
#include "planner/planner_internal.h"

static const hp_backend_ops *const table[HP_BACKEND_COUNT_] = {
    [HP_BACKEND_REALTIME] = &hpi_backend_realtime_ops,
    [HP_BACKEND_IPOPT] = &hpi_backend_ipopt_ops,
    [HP_BACKEND_NLOPT_SLSQP] = &hpi_backend_nlopt_slsqp_ops,
    [HP_BACKEND_NLOPT_COBYLA] = &hpi_backend_nlopt_cobyla_ops,
};

const hp_backend_ops *hpi_backend_table(hp_backend b)
{
    if ((int)b < 0 || b >= HP_BACKEND_COUNT_) return NULL;
    return table[b];
}
