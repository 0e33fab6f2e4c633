/* INTERNAL, TEST-ONLY: fault injection into the backends, so the reliability tests
 * (tests/reliability/test_faults.c, tests/planner/test_backends.c) can show that every way a
 * backend fails becomes an honest status with a safe output (never a NaN or out-of-limit
 * result, never an unlabelled failure).
 *
 * NOT PART OF THE PUBLIC API: not installed, declared in no public header, may change or
 * vanish without notice. The hooks are compiled in always (so the tested library is the
 * shipped one) but are inert until a test sets them: each is one process-wide atomic int
 * read once per evaluation or solve, default "off". Production code must never call them. */
#ifndef HP_PLANNER_BACKEND_TESTING_H
#define HP_PLANNER_BACKEND_TESTING_H

enum hp_test_fault {
    HP_TEST_FAULT_NONE = 0,         /* normal evaluations */
    HP_TEST_FAULT_NAN_OBJECTIVE,    /* Ipopt/NLopt: the objective returns NaN (call "succeeds") */
    HP_TEST_FAULT_FAIL_CONSTRAINTS, /* Ipopt: eval_g/eval_jac_g return false;
                                       NLopt: the constraint evaluation reports failure */
    HP_TEST_FAULT_STOP,             /* Ipopt: the intermediate callback asks to stop */
    HP_TEST_FAULT_NAN_CONTACT,      /* realtime: every contact evaluation in the backend
                                       returns NaN distances */
    HP_TEST_FAULT_NAN_CONTACT_LATE  /* realtime: the first QP is clean, every later contact
                                       evaluation in the backend returns NaN */
};

/* Sentinel for "no forced code" in the force hooks below. */
#define HP_TEST_NO_FORCE (-1000000)

/* Sets the fault every Ipopt backend in the process injects from now on (an atomic store;
 * HP_TEST_FAULT_NONE switches it off). hpi_backend_ipopt_test_hook is the older name. */
void hpi_test_ipopt_fault(int fault);
void hpi_backend_ipopt_test_hook(int fault);

/* After the next IpoptSolve calls, report this ApplicationReturnStatus instead of the real
 * one (the solve still runs; its point is kept). HP_TEST_NO_FORCE switches it off. For codes
 * a test cannot provoke honestly (restoration failure, internal error, ...). */
void hpi_test_ipopt_force_status(int code);

/* The same two hooks for the NLopt backends (SLSQP and COBYLA): the fault in the
 * evaluations, and an nlopt_result to report instead of nlopt_optimize's own. */
void hpi_test_nlopt_fault(int fault);
void hpi_test_nlopt_force_result(int code);

/* Fault in the realtime backend's contact evaluations (HP_TEST_FAULT_NAN_CONTACT*). */
void hpi_test_realtime_fault(int fault);

/* The path a realtime solve stopped by its budget at a point outside a curved limit takes,
 * so a test can hold the rare ones to the same checks: HP_TEST_LATE_AS_BUILT; _BISECT: no
 * interpolated step fraction, the bisection toward the anchor at once; _ANCHOR: neither, the
 * anchor itself (a bisection the clock stopped before any step). */
enum { HP_TEST_LATE_AS_BUILT = 0, HP_TEST_LATE_BISECT, HP_TEST_LATE_ANCHOR };
void hpi_test_realtime_late_path(int path);

/* 1 when a realtime backend created with this max_time reads its time budget on the coarse
 * monotonic clock (max_time at least 100 of its ticks), 0 when on the precise one. */
int hpi_test_realtime_coarse_clock(double max_time);

/* Counts of the realtime backend's less travelled paths, summed over every solve in the
 * process while counting is on (so a test can assert that its targets walk them through the
 * planner): solves, QPs solved, SQP steps whose QP's warm start was accepted, second-order-correction
 * re-solves and those of them whose warm start was accepted, line-search trials that kept
 * the previous point's Hessians, answers whose radii were extrapolated over the last step,
 * and answers after a short last step whose extrapolation the step bound refused (their
 * radii evaluated instead), and the contact evaluations and QPs a solve began after its
 * time budget had run out (late: what a deadline overshoots by), and the Goldfarb–Idnani
 * add and drop steps of every QP solve call (qp_steps: hp_qp.gi_steps summed), and the
 * restorations' bisections that ended inside the segment (bisect_kept: part of the step
 * kept) and at its anchor (bisect_anchor). Off by default: a solve then reads one atomic int
 * and adds nothing. */
typedef struct hp_test_rt_counts {
    long solves, qps, qp_warm, soc, soc_warm, h_kept, rho_step, rho_refused, late, qp_steps;
    long bisect_kept, bisect_anchor;
} hp_test_rt_counts;
/* on = 1: zero the counts and count from now on; on = 0: stop counting (counts kept). */
void hpi_test_realtime_count(int on);
void hpi_test_realtime_counts(hp_test_rt_counts *out);

/* Takes (hold = 1) or releases (hold = 0) the process-wide Ipopt mutex from the calling
 * thread, so a test can prove that the realtime and NLopt backends never wait on it. */
void hpi_test_ipopt_lock(int hold);

#endif
