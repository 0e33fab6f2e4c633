/* Internal: the one clock of a plan (clock.c): its solve_time, and the time budget
 * (max_time) of the backends that read it themselves (Ipopt, the NLopt restarts). */
#ifndef HP_PLANNER_CLOCK_H
#define HP_PLANNER_CLOCK_H

/* CLOCK_MONOTONIC in seconds: wall time, so that a plan's budget counts this plan only
 * (a process CPU clock, such as clock(), also counts every other thread: under
 * `headplan batch --jobs N` it ran up to N times faster than the plan's own time). */
double hpi_plan_now(void);

/* The same on the POSIX clock clk (a clockid_t: the realtime backend's budget clock, which
 * may be the coarse one), and the test clock too when a test set one. */
double hpi_plan_now_on(int clk);

/* TEST-ONLY (inert unless a test sets it; production code never calls it): with step > 0
 * the clock is a counter that starts at 0 and moves step s at every reading, process-wide,
 * so that a test can count the readings a budget takes without timing anything; 0 gives
 * back CLOCK_MONOTONIC. */
void hpi_test_plan_clock(double step);

#endif
