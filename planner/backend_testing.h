/* INTERNAL, TEST-ONLY: fault injection into the Ipopt backend's evaluation callbacks, so the
 * reliability tests can show that a failing or NaN-producing evaluation becomes an honest
 * status (never a NaN or out-of-limit result). Not installed; not for production code. */
#ifndef HP_PLANNER_BACKEND_TESTING_H
#define HP_PLANNER_BACKEND_TESTING_H

enum hp_test_fault {
    HP_TEST_FAULT_NONE = 0,     /* normal evaluations */
    HP_TEST_FAULT_NAN_OBJECTIVE, /* eval_f returns true with f = NaN */
    HP_TEST_FAULT_FAIL_CONSTRAINTS /* eval_g and eval_jac_g return false */
};

/* Sets the fault every Ipopt backend in the process injects from now on (an atomic store;
 * HP_TEST_FAULT_NONE switches it off). */
void hp_backend_ipopt_test_hook(int fault);

#endif
