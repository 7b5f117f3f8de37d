/* Robertson's chemical kinetics, the classic stiff system (rates 0.04, 1e4, 3e7):
 * y0' = -0.04 y0 + 1e4 y1 y2, y1' = 0.04 y0 - 1e4 y1 y2 - 3e7 y1^2, y2' = 3e7 y1^2. No events. */
#include "mex_core.h"
#define NX 3
#define NZ 0
#define CS_STEP 1e-6
typedef struct {
    double x[NX];
} Model;
static const VarInfo VARS[] = {{1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, x[1]), 0}, {3, T_F64, offsetof(Model, x[2]), 0}};
static void model_defaults(Model *m)
{
    m->x[0] = 1.0;
    m->x[1] = m->x[2] = 0.0;
}
static void model_derivatives(Model *m, double t, double *dx)
{
    (void)t;
    dx[0] = -0.04 * m->x[0] + 1e4 * m->x[1] * m->x[2];
    dx[1] = 0.04 * m->x[0] - 1e4 * m->x[1] * m->x[2] - 3e7 * m->x[1] * m->x[1];
    dx[2] = 3e7 * m->x[1] * m->x[1];
}
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
