/* The library's test counters (hpi_test_* readers): how often a path ran, for tests and the
 * benchmark lab to assert and report. */
#ifndef HP_COMMON_TEST_COUNT_H
#define HP_COMMON_TEST_COUNT_H

#include <stdatomic.h>

/* Adds v to counter c with a relaxed load and a relaxed store, not a read-modify-write: an
 * atomic add is a locked instruction on x86 (about 20 cycles, and a barrier the processor
 * cannot overlap work across), and a rate-limited plan counted dozens of them on its hot
 * path. Exact while one thread plans, which is how the tests and the benchmark read them;
 * plans on several threads at once may lose increments, never tear a count. */
static inline void hpi_count(atomic_ulong *c, unsigned long v)
{
    atomic_store_explicit(c, atomic_load_explicit(c, memory_order_relaxed) + v,
                          memory_order_relaxed);
}

#endif
