/* Internal: what every Ipopt user in the library (the per-row backend backend_ipopt.c, the
 * load level's HOLD load_ipopt.c) shares: the one process-wide solver mutex and the fixed
 * option set (ipopt_shared.c). */
#ifndef HP_PLANNER_IPOPT_SHARED_H
#define HP_PLANNER_IPOPT_SHARED_H

#include "headplan/hp_common.h"

#include <IpStdCInterface.h>

/* Debian's Ipopt/MUMPS is not thread-safe even with one problem per thread: every Ipopt
 * call (create, options, solve, free) anywhere in the library runs between these two. */
void hpi_ipopt_lock(void);
void hpi_ipopt_unlock(void);

/* An Ipopt string (number) option that fails loudly (HP_ERR_SOLVER naming it, in d) instead of
 * printing. Caller holds the lock. */
hp_error hpi_ipopt_opt_str(IpoptProblem a, const char *k, const char *v, hp_diag *d);
hp_error hpi_ipopt_opt_num(IpoptProblem a, const char *k, double v, hp_diag *d);

/* The options every solve of the library sets (caller holds the lock): silent (`sb`,
 * print_level 0), no option file, tolerances tol (also on the constraint violation), bounds
 * never relaxed, no "acceptable" early stop, the iteration and CPU-time budgets, tiny
 * warm-start pushes. HP_ERR_SOLVER naming the option Ipopt rejected. */
hp_error hpi_ipopt_base_options(IpoptProblem app, double tol, int max_iter, double max_time,
                                hp_diag *d);

#endif
