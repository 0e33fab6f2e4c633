/* Whether two plan results carry the same bits in every field a caller reads (solve_time,
 * a measurement, aside; memcmp of the whole struct would compare padding). */
#ifndef HP_TEST_SAME_RESULT_H
#define HP_TEST_SAME_RESULT_H

#include <headplan/headplan.h>

#include <string.h>

static inline int hp_test_same_result(const hp_result *a, const hp_result *b)
{
#define SAME(f) (memcmp(&a->f, &b->f, sizeof a->f) == 0)
    if (!(SAME(status) && SAME(raw_code) && SAME(backend) && SAME(level) && SAME(desired) &&
          SAME(achieved) && SAME(commanded) && SAME(uncommanded) && SAME(pose_error) && SAME(n) &&
          SAME(iterations)))
        return 0;
    for (int k = 0; k < a->n; ++k)
        if (!(SAME(bladders[k].ri) && SAME(bladders[k].ro) && SAME(bladders[k].pressure) &&
              SAME(bladders[k].stretch) && SAME(bladders[k].binding)))
            return 0;
#undef SAME
    return 1;
}

#endif
