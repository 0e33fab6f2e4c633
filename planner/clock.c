/* The clock of a plan's solve_time (clock.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner/clock.h"

#include <time.h>

double hpi_plan_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
