/*
 * test_util.h — what every cmocka test includes: cmocka's required headers in
 * its required order, a relative-tolerance check that prints both numbers, and
 * reproducible random test data.
 *
 * Physics tests begin with an EVIDENCE comment: source (Eq./Table/Fig. or
 * closed-form reference), quantity, tolerance, and whether the input was
 * calibrated to it.
 */
#ifndef TS_TEST_UTIL_H
#define TS_TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>

/* Fail unless |got - want| <= rel * |want| (+ abs_tol). */
#define assert_close(got, want, rel, abs_tol)                                                      \
    do {                                                                                           \
        double g_ = (got), w_ = (want);                                                            \
        double tol_ = (rel) * fabs(w_) + (abs_tol);                                                \
        if (!(fabs(g_ - w_) <= tol_))                                                              \
            fail_msg("%s = %.9g, want %.9g (tolerance %.3g)", #got, g_, w_, tol_);                 \
    } while (0)

/* Deterministic pseudo-random test data in [-1, 1) from state *s (a fixed
 * LCG: reproducible, not for statistics). */
static inline double test_urand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / (double)(1u << 23) - 1.0;
}

#endif
