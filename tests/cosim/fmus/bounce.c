/* A bouncing ball for Model Exchange (and Co-Simulation, from the same binary): h' = v, v' = -g.
 * State event: the event indicator h reaches 0 falling; then v := -e v, h := 0 (resting below
 * 0.01 m/s). Time event: at kick_time (if >= 0) v += kick. Step event: the first completed
 * integrator step at or after step_event_at (if >= 0) asks for Event Mode, which counts it.
 * Terminate: after max_bounces bounces (if > 0). */
#include "mex_core.h"
#define NX 2
#define NZ 1
#define CS_STEP 1e-3
typedef struct {
    double x[NX];
    double g, e, kick_time, kick, step_event_at;
    int64_t bounces, step_events, max_bounces;
    bool resting, kicked, stepped;
} Model;
static const VarInfo VARS[] = {
    {1, T_F64, offsetof(Model, x[0]), 0}, {2, T_F64, offsetof(Model, x[1]), 0}, {3, T_I64, offsetof(Model, bounces), 0},
    {4, T_F64, offsetof(Model, g), 0}, {5, T_F64, offsetof(Model, e), 0}, {6, T_F64, offsetof(Model, kick_time), 0},
    {7, T_F64, offsetof(Model, kick), 0}, {8, T_F64, offsetof(Model, step_event_at), 0},
    {9, T_I64, offsetof(Model, step_events), 0}, {10, T_I64, offsetof(Model, max_bounces), 0},
};
static void model_defaults(Model *m)
{
    memset(m, 0, sizeof *m);
    m->x[0] = 1.0;
    m->g = 9.81;
    m->e = 0.7;
    m->kick_time = m->step_event_at = -1.0;
}
static void model_derivatives(Model *m, double t, double *dx)
{
    (void)t;
    dx[0] = m->resting ? 0.0 : m->x[1];
    dx[1] = m->resting ? 0.0 : -m->g;
}
static void model_indicators(Model *m, double t, double *z)
{
    (void)t;
    z[0] = m->resting ? 1.0 : m->x[0];
}
static bool model_step_event(Model *m, double t) { return m->step_event_at >= 0 && !m->stepped && t >= m->step_event_at; }
static void model_event(Model *m, double t, Events *e)
{
    if (!m->resting && m->x[0] <= 0 && m->x[1] < 0) {
        m->x[0] = 0.0;
        m->x[1] = -m->e * m->x[1];
        m->bounces++;
        if (m->x[1] < 0.01) m->resting = true, m->x[1] = 0.0;
        e->values_changed = true;
    }
    if (m->kick_time >= 0 && !m->kicked && t >= m->kick_time - 1e-12) {
        m->x[1] += m->kick;
        m->kicked = true;
        m->resting = false;
        e->values_changed = true;
    }
    if (model_step_event(m, t)) {
        m->stepped = true;
        m->step_events++;
    }
    e->next_defined = m->kick_time >= 0 && !m->kicked;
    e->next = m->kick_time;
    if (m->max_bounces > 0 && m->bounces >= m->max_bounces) e->terminate = true;
}
static int model_partition(Model *m, unsigned vr, double t)
{
    (void)m; (void)vr; (void)t;
    return 0;
}
#include "mex.h"
