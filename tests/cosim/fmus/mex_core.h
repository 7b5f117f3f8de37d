/* The core of the test FMUs of other interfaces than FMI 3.0 Co-Simulation (mex3.h: FMI 3.0 Model
 * Exchange, Co-Simulation and Scheduled Execution in one binary; mex2.h: FMI 2.0 Model Exchange and
 * Co-Simulation). A model file defines, before including mex3.h or mex2.h:
 *
 *   NX, NZ                       its continuous states (Model.x) and event indicators
 *   Model                        its state and variables (x[NX] first), VARS its variables
 *   model_defaults(m)            the start values
 *   model_derivatives(m, t, dx)  dx/dt at (t, m->x)
 *   model_indicators(m, t, z)    the event indicators at (t, m->x)
 *   model_event(m, t, e)         Event Mode: one update (e: what it asks for, see Events)
 *   model_step_event(m, t)       after an integrator step: whether to enter Event Mode
 *   model_partition(m, vr, t)    Scheduled Execution: the partition of input clock vr at t
 *   model_outputs(m, t)          (optional, #define MODEL_OUTPUTS) the outputs, before they are read
 *   model_interval(m, vr, &x)    (optional, #define MODEL_INTERVALS) FMI 3.0: a countdown clock's
 *                                interval, once announced (1: x set, the interval changed; 0: not
 *                                known; -1: vr is not a countdown clock)
 *   model_async_polls(m)         (optional, #define MODEL_ASYNC) FMI 2.0 Co-Simulation: fmi2DoStep
 *                                returns fmi2Pending, fmi2GetStatus says so this many times more
 *   CS_STEP                      Co-Simulation: the internal step (classic Runge-Kutta; an event
 *                                indicator's sign change ends a step early, at the internal step)
 *
 * Variables are Float64 (T_F64), Int32 (T_I32, an FMI 2.0 Integer), Int64 (T_I64), Boolean (T_BOOL,
 * an int in FMI 2.0, a bool in FMI 3.0) and Clock (T_CLOCK: a bool, active or not); a VarInfo's
 * count is an array's number of elements (0: a scalar). */
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { T_F64, T_I32, T_I64, T_BOOL, T_CLOCK };

typedef struct {
    unsigned vr;
    int type;
    size_t offset;
    size_t count;
} VarInfo;

#ifndef MODEL_OUTPUTS
#define model_outputs(m, t) ((void)(m), (void)(t))
#endif
#ifndef MODEL_ASYNC
#define model_async_polls(m) ((void)(m), 0)
#endif

typedef struct {
    bool needs_update, terminate, next_defined, values_changed;
    double next;
} Events;

static size_t type_size(int type)
{
    switch (type) {
    case T_F64: case T_I64: return 8;
    case T_I32: return 4;
    default: return sizeof(bool);
    }
}

static const VarInfo *find_var(const VarInfo *vars, size_t n, unsigned vr)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (vars[i].vr == vr) return &vars[i];
    return NULL;
}

/* The model's step of the classic Runge-Kutta method from t by h. */
#define MEX_RK4(MODEL, DERIVATIVES)                                                                    \
    static void rk4(MODEL *m, double t, double h)                                                      \
    {                                                                                                  \
        double x0[NX + 1], k1[NX + 1], k2[NX + 1], k3[NX + 1], k4[NX + 1];                             \
        int i;                                                                                         \
        memcpy(x0, m->x, sizeof(double) * NX);                                                         \
        DERIVATIVES(m, t, k1);                                                                         \
        for (i = 0; i < NX; i++) m->x[i] = x0[i] + 0.5 * h * k1[i];                                    \
        DERIVATIVES(m, t + 0.5 * h, k2);                                                               \
        for (i = 0; i < NX; i++) m->x[i] = x0[i] + 0.5 * h * k2[i];                                    \
        DERIVATIVES(m, t + 0.5 * h, k3);                                                               \
        for (i = 0; i < NX; i++) m->x[i] = x0[i] + h * k3[i];                                          \
        DERIVATIVES(m, t + h, k4);                                                                     \
        for (i = 0; i < NX; i++) m->x[i] = x0[i] + h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);  \
    }
