/*
 * vm_fd.h — test helper: one column of the vehicle's stiffness K = -dQ/dq by
 * central differences of vm_forces (drive off), shared by the tests that check
 * the natural frequencies (test_vehicle_dynamics) and vm_rates
 * (test_vehicle_static). Test code only.
 */
#ifndef TS_TEST_VM_FD_H
#define TS_TEST_VM_FD_H

#include "sim/vehicle_model.h"

/* K[i][j] for every i into col (n = vm_nq values) at the state y (restored on
 * return), step h; q1, q2: n-value scratch. */
static inline void vm_fd_stiffness_column(const vm *v, vm_work *w, double *y, int j, double h,
                                          double *q1, double *q2, double *col)
{
    double keep = y[j];
    y[j] = keep + h;
    vm_forces(v, w, 0, y, 0, q1);
    y[j] = keep - h;
    vm_forces(v, w, 0, y, 0, q2);
    y[j] = keep;
    for (int i = 0; i < vm_nq(v); i++)
        col[i] = -(q1[i] - q2[i]) / (2 * h);
}

#endif
