/* A first-order lag for FMI 2.0 Co-Simulation: x' = (u - x) / tau, its input u, outputs x, an
 * Integer count of the threshold crossings (the event indicator x - 0.5), a Boolean above = x > 0.5,
 * an Enumeration level (1 low, 2 high). Terminate: at the first crossing past stop_after (> 0).
 * Asynchronous steps: with async_polls (vr 8) > 0, fmi2DoStep is pending that many polls. */
#define MODEL_ASYNC
#include "mex_core.h"
#define NX 1
#define NZ 1
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    double u, tau;
    int32_t crossings, level, stop_after, async_polls;
    bool above;
} Model;
static const VarInfo VARS[] = {
    {1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, u), 0}, {3, T_F64, offsetof(Model, tau), 0},
    {4, T_I32, offsetof(Model, crossings), 0}, {5, T_BOOL, offsetof(Model, above), 0}, {6, T_I32, offsetof(Model, level), 0},
    {7, T_I32, offsetof(Model, stop_after), 0}, {8, T_I32, offsetof(Model, async_polls), 0},
};
static int model_async_polls(Model *m) { return m->async_polls; }
static void model_defaults(Model *m)
{
    memset(m, 0, sizeof *m);
    m->u = 1.0;
    m->tau = 0.5;
    m->level = 1;
}
static void model_derivatives(Model *m, double t, double *dx)
{
    (void)t;
    dx[0] = (m->u - m->x[0]) / m->tau;
}
static void model_indicators(Model *m, double t, double *z)
{
    (void)t;
    z[0] = m->x[0] - 0.5;
}
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e)
{
    bool above = m->x[0] > 0.5;
    (void)t;
    if (above != m->above) {
        m->above = above;
        m->level = above ? 2 : 1;
        m->crossings++;
        if (m->stop_after > 0 && m->crossings >= m->stop_after) e->terminate = true;
    }
}
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
