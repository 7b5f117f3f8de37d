/* The controller of the supervisory-control example (FMI 3.0 Co-Simulation with Event Mode): a
 * periodic input clock r (vr 1, every 0.1 s) and a triggered input clock s (vr 2). At r's ticks it
 * reads xr (vr 3, clocked by r) and outputs ur = k (ref - xr) (vr 4, clocked by r; k = 2, vr 7); at
 * s's ticks it takes the new reference as (vr 5, clocked by s) into ref (vr 6, from 1). */
#define MODEL_OUTPUTS
#include "mex_core.h"
#define NX 0
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[1];
    bool r, s;
    double xr, ur, as, ref, k;
} Model;
static const VarInfo VARS[] = {
    {1, T_CLOCK, offsetof(Model, r), 0}, {2, T_CLOCK, offsetof(Model, s), 0}, {3, T_F64, offsetof(Model, xr), 0},
    {4, T_F64, offsetof(Model, ur), 0}, {5, T_F64, offsetof(Model, as), 0}, {6, T_F64, offsetof(Model, ref), 0},
    {7, T_F64, offsetof(Model, k), 0},
};
static void model_defaults(Model *m) { memset(m, 0, sizeof *m); m->ref = 1.0; m->k = 2.0; }
static void model_outputs(Model *m, double t) { (void)t; m->ur = m->k * (m->ref - m->xr); }
static void model_derivatives(Model *m, double t, double *dx) { (void)m; (void)t; (void)dx; }
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e)
{
    (void)t; (void)e;
    if (m->s) m->ref = m->as;
}
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
