/* Internal: the clock a plan's solve_time is measured with (clock.c). */
#ifndef HP_PLANNER_CLOCK_H
#define HP_PLANNER_CLOCK_H

/* CLOCK_MONOTONIC in seconds. */
double hpi_plan_now(void);

#endif
