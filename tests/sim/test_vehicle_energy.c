/*
 * test_vehicle_energy.c — the vehicle model (vehicle_model.h) conserves total
 * mechanical energy when every dissipation and the drive are off: a check that
 * the generalised forces are the gradient of the potential the model states
 * (track elements, span elements, torsion bars, foundation, anchor, gravity)
 * and that the mass matrix and velocity terms belong together.
 */
#include "test_util.h"
#define PLUCK      0.01 /* m, span mode amplitude */
#define PITCH_RATE 0.5  /* rad/s, initial hull pitch rate (moves the chord frames) */

#include <stdlib.h>
#include <string.h>

#include "api/config_json.h"
#include "sim/tanksim.h"
#include "sim/vehicle_model.h"

typedef struct ud {
    const vm *v;
    vm_work *w;
} ud;

static int rhs(double t, const double *y, double *ydot, void *p)
{
    ud *u = p;
    return vm_rhs(u->v, u->w, t, y, ydot, NULL);
}

static ts_config conservative(const char *fidelity)
{
    ts_config c;
    ts_err err;
    /* EA and the anchor are softened tenfold so the stiffest modes (road-wheel
     * and roller spins between track elements) sit near 130 Hz instead of 410 Hz
     * and a fixed-step RK4 at 0.2 ms resolves them; conservation does not
     * depend on the values. */
    json_t *doc =
        json_pack("{s:{s:s},s:{s:s,s:f},s:{s:s,s:f},s:{s:f,s:f}}", "run", "kind", "vehicle",
                  "track", "fidelity", fidelity, "ea", 3e6, "drive", "kind", "constant", "torque",
                  0.0, "vehicle", "damping_scale", 0.0, "anchor_stiffness", 1e7);
    assert_int_equal(tsa_config_load(doc, &c, NULL, NULL, &err), TS_OK);
    json_decref(doc);
    return c;
}

/* Energy drift over 10 s after dropping the hull 3 cm, setting it pitching at
 * PITCH_RATE and plucking a span. */
static void check_energy(const char *fidelity, double tol)
{
    ts_config c = conservative(fidelity);
    ts_err err;
    vm *v = vm_make(&c, &err);
    assert_non_null(v);
    int ny = vm_ny(v), nq = vm_nq(v);
    double *y = malloc(sizeof(double) * (size_t)ny);
    memcpy(y, vm_equilibrium(v), sizeof(double) * (size_t)ny);
    ud u = {v, vm_work_make(v)};
    double e_eq = vm_energy(v, u.w, y);
    /* hull lifted 3 cm with the road wheels left where they are (each arm turned
     * down to keep its hub), then let go: it drops onto its torsion bars */
    double arm = c.vehicle.road_arm_length;
    y[1] += 0.03;
    for (int i = 0; i < 7; i++)
        y[3 + i] = asin(sin(y[3 + i]) + 0.03 / arm);
    if (nq > 21) y[nq - 1] += PLUCK; /* last modal coordinate of the last span plucked 1 cm */
    y[nq + 2] = PITCH_RATE;
    double e0 = vm_energy(v, u.w, y);
    double disturbance = e0 - e_eq;
    assert_true(disturbance > 10000.0);
    /* Classic fourth-order Runge-Kutta at a fixed 0.2-ms step (omega dt < 0.2
     * for the stiffest mode), independent of the production integrator. */
    double dt = 2e-4, t = 0, worst = 0;
    double *k1 = malloc(sizeof(double) * (size_t)ny * 5), *k2 = k1 + ny, *k3 = k2 + ny,
           *k4 = k3 + ny, *tmp = k4 + ny;
    int nstep = (int)lround(10.0 / dt);
    for (int s = 1; s <= nstep; s++) {
        assert_int_equal(rhs(t, y, k1, &u), 0);
        for (int i = 0; i < ny; i++)
            tmp[i] = y[i] + 0.5 * dt * k1[i];
        assert_int_equal(rhs(t + 0.5 * dt, tmp, k2, &u), 0);
        for (int i = 0; i < ny; i++)
            tmp[i] = y[i] + 0.5 * dt * k2[i];
        assert_int_equal(rhs(t + 0.5 * dt, tmp, k3, &u), 0);
        for (int i = 0; i < ny; i++)
            tmp[i] = y[i] + dt * k3[i];
        assert_int_equal(rhs(t + dt, tmp, k4, &u), 0);
        for (int i = 0; i < ny; i++)
            y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        t += dt;
        if (s % 500 == 0) worst = fmax(worst, fabs(vm_energy(v, u.w, y) - e0));
    }
    free(k1);
    printf("# %s: disturbance %.1f J, worst energy error over 10 s %.2f J (%.3f %%)\n", fidelity,
           disturbance, worst, 100 * worst / disturbance);
    assert_true(worst <= tol * disturbance);
    vm_work_free(u.w);
    vm_free(v);
    free(y);
}

/* EVIDENCE: conservation of mechanical energy (closed form: dE/dt = 0 for a
 * conservative Lagrangian system). Static fidelity (massless chain, 21 DOF),
 * all dampers, foundation/anchor/track damping and the drive off; the hull is
 * dropped 3 cm onto its suspension, pitching at 0.5 rad/s. Tolerance: 0.5 % of
 * the disturbance energy (~19 kJ) over 10 s (fixed-step RK4; measured
 * 0.05-0.17 % over the six fidelities when written). Nothing calibrated. */
static void static_model_conserves_energy(void **state)
{
    (void)state;
    check_energy("static", 0.005);
}

/* EVIDENCE: as above for the coupled fidelity (31 DOF: span longitudinal and
 * transverse modes, inertia coupling to the supports); a span mode plucked
 * 1 cm as well; this also checks the span blocks' velocity terms (dM/dq of
 * the moving chord frame, vehicle_model.c): without their road-arm part the
 * drift is 1.0 % (coupled) and 2.6 % (longitudinal), so 0.5 % fails it. Their
 * pitch part (span_pitch_terms) is below this test's resolution: without it
 * 0.18 % instead of 0.12 % (coupled). Tolerance 0.5 % over 10 s. Nothing
 * calibrated. */
static void coupled_model_conserves_energy(void **state)
{
    (void)state;
    check_energy("coupled", 0.005);
}

/* EVIDENCE: as above for the lumped, quasi-static, longitudinal and
 * transverse fidelities. Tolerance 0.5 % over 10 s. */
static void other_fidelities_conserve_energy(void **state)
{
    (void)state;
    check_energy("lumped", 0.005);
    check_energy("quasi_static", 0.005);
    check_energy("longitudinal", 0.005);
    check_energy("transverse", 0.005);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(static_model_conserves_energy),
        cmocka_unit_test(coupled_model_conserves_energy),
        cmocka_unit_test(other_fidelities_conserve_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
