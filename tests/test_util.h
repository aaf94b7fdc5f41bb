/*
 * test_util.h — what every cmocka test includes: cmocka's required headers in
 * its required order, a relative-tolerance check that prints both numbers, and
 * reproducible random test data, and where a test may write its files.
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
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <sys/stat.h>

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

/* The path tests/out/NAME in buf (tests run from the repository's root),
 * creating tests/out when missing, so a test binary run by hand writes where
 * tests/run_all.sh's do. Fails the test when the directory cannot be made. */
static inline const char *test_out_path(char *buf, size_t size, const char *name)
{
    if (mkdir("tests/out", 0777) != 0 && errno != EEXIST)
        fail_msg("cannot create tests/out (run from the repository's root)");
    snprintf(buf, size, "tests/out/%s", name);
    return buf;
}

#endif
