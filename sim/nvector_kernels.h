/*
 * nvector_kernels.h — the serial N_Vector's arithmetic, compiled with this
 * project's flags, installed on a vector CVODE works with.
 *
 * Why: Debian 12's SUNDIALS 6.4.1 packages are built without optimisation
 * (their N_VWSqrSumLocal_Serial, for one, keeps every local in a stack slot;
 * `objdump -d` on libsundials_cvode.so.6 shows it), and CVODE calls these
 * kernels several times per step: they were 15 % of the coupled bump run's
 * time. SUNDIALS lets a program supply its own vector operations through the
 * vector's ops table, and clones copy that table, so installing them on the
 * vector passed to CVodeInit covers every vector CVODE makes from it.
 *
 * The kernels do each operation's arithmetic in the same order and with the
 * same special cases (a == 1, a == -1, a == b, z == x, ...) as SUNDIALS'
 * serial vector, so results are the same to the last bit; the project builds
 * with -std=c11, under which GCC does not contract a * b + c into an FMA.
 * Only the operations CVODE calls every step are replaced (the list is in
 * ts_nvector_use_kernels); the others keep SUNDIALS' own.
 */
#ifndef TS_NVECTOR_KERNELS_H
#define TS_NVECTOR_KERNELS_H

#include <sundials/sundials_nvector.h>

#include "errors.h"

/* Replace the per-step compute operations of v, a serial N_Vector
 * (N_VNew_Serial); fused operations only where v has them (they stay off
 * unless enabled on v first). Returns 0, or -1 if v is not a serial vector. */
TS_MUST_CHECK int ts_nvector_use_kernels(N_Vector v);

#endif
