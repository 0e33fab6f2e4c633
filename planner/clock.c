/* The clock of a plan (clock.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner/clock.h"

#include <math.h>
#include <stdatomic.h>
#include <time.h>

/* The test clock (hpi_test_plan_clock): its step and its reading, in nanoseconds; a step
 * of 0 (the default) leaves the real clock, at the cost of one relaxed atomic load. */
static atomic_llong fake_step_ns;
static atomic_llong fake_now_ns;

void hpi_test_plan_clock(double step)
{
    atomic_store(&fake_now_ns, 0);
    atomic_store(&fake_step_ns, step > 0.0 ? llround(step * 1e9) : 0);
}

double hpi_plan_now_on(int clk)
{
    long long step = atomic_load_explicit(&fake_step_ns, memory_order_relaxed);
    if (step) return 1e-9 * (double)(atomic_fetch_add(&fake_now_ns, step) + step);
    struct timespec ts;
    clock_gettime((clockid_t)clk, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double hpi_plan_now(void) { return hpi_plan_now_on(CLOCK_MONOTONIC); }
