/* A gantry for Model Exchange (FMI 2.0 or 3.0), a plant the UR5e d-model can command: the grid
 * cell X, Y, Z (Integer inputs, vr 4-6, held between commands) is the point (cell X, cell Y,
 * cell Z) (cell: vr 7, 0.05 m), which the carriage x, y, z (vr 1-3) approaches as a first-order lag
 * of time constant tau (vr 8, 0.5 s). No events. */
#include "mex_core.h"
#define NX 3
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    int32_t target[3];
    double cell, tau;
} Model;
static const VarInfo VARS[] = {
    {1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, x[1]), 0}, {3, T_F64, offsetof(Model, x[2]), 0},
    {4, T_I32, offsetof(Model, target[0]), 0}, {5, T_I32, offsetof(Model, target[1]), 0},
    {6, T_I32, offsetof(Model, target[2]), 0}, {7, T_F64, offsetof(Model, cell), 0}, {8, T_F64, offsetof(Model, tau), 0},
};
static void model_defaults(Model *m)
{
    memset(m, 0, sizeof *m);
    m->cell = 0.05;
    m->tau = 0.5;
}
static void model_derivatives(Model *m, double t, double *dx)
{
    int i;
    (void)t;
    for (i = 0; i < 3; i++) dx[i] = (m->cell * m->target[i] - m->x[i]) / m->tau;
}
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
