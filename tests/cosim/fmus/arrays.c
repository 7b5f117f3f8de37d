/* An array output whose dimension is a structural parameter (as the Reference FMUs' StateSpace
 * model has them): n (vr 2, structural parameter, 3) elements of y (vr 3), y[i] = i x, where x
 * (vr 1) follows x' = 1 from 0 (so x = t). Co-Simulation and Model Exchange. */
#define MODEL_OUTPUTS
#include "mex_core.h"
#define NX 1
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    uint64_t n;
    double y[3];
} Model;
static const VarInfo VARS[] = {{1, T_F64, offsetof(Model, x[0]), 0}, {3, T_F64, offsetof(Model, y), 3}};
static void model_defaults(Model *m) { memset(m, 0, sizeof *m); m->n = 3; }
static void model_outputs(Model *m, double t)
{
    int i;
    (void)t;
    for (i = 0; i < 3; i++) m->y[i] = (i + 1) * m->x[0];
}
static void model_derivatives(Model *m, double t, double *dx) { (void)m; (void)t; dx[0] = 1.0; }
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
