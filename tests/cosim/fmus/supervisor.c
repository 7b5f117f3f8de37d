/* The supervisor of the supervisory-control example (FMI 3.0 Co-Simulation with Event Mode): it
 * watches x (vr 1, an input that is not clocked); in fmi3DoStep, the first internal step that finds
 * x above the threshold (vr 4, 0.5) is a state event: the step asks for Event Mode, where the output
 * clock s (vr 2, triggered) ticks once, carrying the new reference as (vr 3, clocked by s: 0). */
#include "mex_core.h"
#define NX 0
#define NZ 0
#define CS_STEP 1e-3
typedef struct {
    double x[1];
    double in;
    bool s, raised;
    double as, threshold;
} Model;
static const VarInfo VARS[] = {
    {1, T_F64, offsetof(Model, in), 0}, {2, T_CLOCK, offsetof(Model, s), 0}, {3, T_F64, offsetof(Model, as), 0},
    {4, T_F64, offsetof(Model, threshold), 0},
};
static void model_defaults(Model *m) { memset(m, 0, sizeof *m); m->threshold = 0.5; }
static void model_derivatives(Model *m, double t, double *dx) { (void)m; (void)t; (void)dx; }
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t)
{
    (void)t;
    if (m->raised || m->in <= m->threshold) return false;
    m->raised = m->s = true; /* s ticks in the Event Mode this asks for */
    m->as = 0.0;
    return true;
}
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t) { (void)m; (void)vr; (void)t; return 0; }
#include "mex.h"
