/* The Van der Pol oscillator for Model Exchange: x0' = x1, x1' = mu (1 - x0^2) x1 - x0. No events. */
#include "mex_core.h"
#define NX 2
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    double mu;
} Model;
static const VarInfo VARS[] = {{1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, x[1]), 0}, {3, T_F64, offsetof(Model, mu), 0}};
static void model_defaults(Model *m)
{
    m->x[0] = 2.0;
    m->x[1] = 0.0;
    m->mu = 1.0;
}
static void model_derivatives(Model *m, double t, double *dx)
{
    (void)t;
    dx[0] = m->x[1];
    dx[1] = m->mu * (1.0 - m->x[0] * m->x[0]) * m->x[1] - m->x[0];
}
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
