/*
 * turbo_fixture.h — test helper: the small turbocharger (10-cm wheels) the
 * engine closed-form and parts tests evaluate the compressor and turbine maps
 * of. The turbine's efficiency eta_t (0.75) differs from the compressor's
 * eta_max (0.8) so a law reading the wrong one shows.
 */
#ifndef TS_TEST_TURBO_FIXTURE_H
#define TS_TEST_TURBO_FIXTURE_H

#include "sim/engine_impl.h"

static inline en_turbo test_turbo(void)
{
    return (en_turbo){.d_c = 0.1,
                      .d_t = 0.1,
                      .psi0 = 0.9,
                      .phi_ch = 0.22,
                      .eta_max = 0.8,
                      .phi_opt = 0.13,
                      .phi_w = 0.15,
                      .eta_min = 0.45,
                      .mach_opt = 1.0,
                      .mach_w = 1.5,
                      .a_t = 1e-3,
                      .eta_t = 0.75,
                      .bsr_opt = 0.7,
                      .inertia = 1e-3,
                      .mech_eff = 0.98,
                      .r_air = 287.0};
}

#endif
