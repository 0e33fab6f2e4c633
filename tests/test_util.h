/* Helpers shared by the cmocka tests: closeness checks that print both numbers. */
#ifndef HP_TEST_UTIL_H
#define HP_TEST_UTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

/* Fails unless |got − want| <= abs_tol + rel_tol·|want|, printing both and the excess. */
#define hp_assert_close(got, want, rel_tol, abs_tol)                                       \
    do {                                                                                    \
        double g_ = (got), w_ = (want);                                                     \
        double lim_ = (abs_tol) + (rel_tol) * fabs(w_);                                     \
        if (!(fabs(g_ - w_) <= lim_)) {                                                     \
            print_error("%s = %.17g, want %.17g (|diff| %.3g > %.3g)\n", #got, g_, w_,     \
                        fabs(g_ - w_), lim_);                                               \
            fail();                                                                         \
        }                                                                                   \
    } while (0)

#endif
