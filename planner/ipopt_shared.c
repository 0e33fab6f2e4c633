/* What every Ipopt user in the library shares (ipopt_shared.h): the process-wide solver
 * mutex and the fixed option set. */
#include "planner/ipopt_shared.h"
#include "common/unconst.h"
#include "planner/backend_testing.h"

#include <math.h>
#include <pthread.h>

static pthread_mutex_t ipopt_lock = PTHREAD_MUTEX_INITIALIZER;

void hpi_ipopt_lock(void) { pthread_mutex_lock(&ipopt_lock); }
void hpi_ipopt_unlock(void) { pthread_mutex_unlock(&ipopt_lock); }
/* Test-only (planner/backend_testing.h): holds the solver mutex from outside. */
void hpi_test_ipopt_lock(int hold)
{
    if (hold) pthread_mutex_lock(&ipopt_lock);
    else pthread_mutex_unlock(&ipopt_lock);
}

/* A warm start's pushes off the bounds: tiny, the start is the previous answer. */
#define WARM_PUSH 1e-9

/* Option setters that fail loudly (in the diagnostic) instead of printing. Caller holds the
 * lock. */
hp_error hpi_ipopt_opt_str(IpoptProblem a, const char *k, const char *v, hp_diag *d)
{
    if (!AddIpoptStrOption(a, hpi_unconst(k), hpi_unconst(v)))
        return hp_diag_set(d, HP_ERR_SOLVER, "ipopt: option %s = %s rejected", k, v);
    return HP_OK;
}
hp_error hpi_ipopt_opt_num(IpoptProblem a, const char *k, double v, hp_diag *d)
{
    if (!AddIpoptNumOption(a, hpi_unconst(k), v))
        return hp_diag_set(d, HP_ERR_SOLVER, "ipopt: option %s = %g rejected", k, v);
    return HP_OK;
}
static hp_error opt_int(IpoptProblem a, const char *k, int v, hp_diag *d)
{
    if (!AddIpoptIntOption(a, hpi_unconst(k), v))
        return hp_diag_set(d, HP_ERR_SOLVER, "ipopt: option %s = %d rejected", k, v);
    return HP_OK;
}

/* Complementarity (a bound's slack in mm times its multiplier) at which an
 * active bound's slack is far below HP_BINDING_TOL_MM for any multiplier above 1e-3. */
#define IPOPT_COMPL_TOL 1e-10

hp_error hpi_ipopt_base_options(IpoptProblem app, double tol, int max_iter, double max_time,
                                hp_diag *d)
{
    /* bound_relax_factor 0: by default Ipopt relaxes each bound by 1e-8 relative (3e-7 mm
     * here) and then projects the answer back onto it, which breaks the contact equality by
     * that much at every binding bladder. Ipopt's acceptable-level heuristic would stop with a contact violation up to 1e-2 mm
     * (acceptable_constr_viol_tol): keep it off, and its tolerances tight where it can still
     * be reached (restoration). */
    double acc = fmax(10.0 * tol, 1e-9);
    /* compl_inf_tol: the slack·multiplier products must vanish to IPOPT_COMPL_TOL whatever
     * the tolerance. With only the overall tolerance (1e-4, say) the interior point stops
     * up to ~1e-5 mm inside an active bound, where the planner's one binding threshold
     * (HP_BINDING_TOL_MM, 1e-6 mm) sees no limit and must refuse a CLOSEST claim: a loose
     * tolerance then gave solver-error on 35 of the bench's 40 binding targets. */
    hp_error e;
    if ((e = hpi_ipopt_opt_str(app, "sb", "yes", d)) || (e = opt_int(app, "print_level", 0, d)) ||
        (e = hpi_ipopt_opt_str(app, "option_file_name", "", d)) ||
        (e = hpi_ipopt_opt_num(app, "tol", tol, d)) ||
        (e = hpi_ipopt_opt_num(app, "constr_viol_tol", tol, d)) ||
        (e = hpi_ipopt_opt_num(app, "compl_inf_tol", fmin(tol, IPOPT_COMPL_TOL), d)) ||
        (e = hpi_ipopt_opt_num(app, "bound_relax_factor", 0.0, d)) ||
        (e = opt_int(app, "acceptable_iter", 0, d)) ||
        (e = hpi_ipopt_opt_num(app, "acceptable_tol", acc, d)) ||
        (e = hpi_ipopt_opt_num(app, "acceptable_constr_viol_tol", acc, d)) ||
        (e = opt_int(app, "max_iter", max_iter, d)) ||
        (e = hpi_ipopt_opt_num(app, "max_cpu_time", max_time, d)) ||
        (e = hpi_ipopt_opt_num(app, "warm_start_bound_push", WARM_PUSH, d)) ||
        (e = hpi_ipopt_opt_num(app, "warm_start_bound_frac", WARM_PUSH, d)) ||
        (e = hpi_ipopt_opt_num(app, "warm_start_slack_bound_push", WARM_PUSH, d)) ||
        (e = hpi_ipopt_opt_num(app, "warm_start_slack_bound_frac", WARM_PUSH, d)) ||
        (e = hpi_ipopt_opt_num(app, "warm_start_mult_bound_push", WARM_PUSH, d)))
        return e;
    return HP_OK;
}
