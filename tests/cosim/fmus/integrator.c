/* A plant for Model Exchange (FMI 2.0 or 3.0): x' = u, u a discrete input (held between its sets),
 * x(0) = x0. No events. */
#include "mex_core.h"
#define NX 1
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    double u;
} Model;
static const VarInfo VARS[] = {{1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, u), 0}};
static void model_defaults(Model *m) { memset(m, 0, sizeof *m); }
static void model_derivatives(Model *m, double t, double *dx) { (void)t; dx[0] = m->u; }
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
