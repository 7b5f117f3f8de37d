/* Stair: `counter` steps up by one at every multiple of `period`, a time event announced
 * through nextEventTime. A step that would pass the event returns early at it (when allowed);
 * a step that reaches it asks for Event Mode. With `last` > 0, the stair asks to terminate the
 * simulation (terminateSimulation from fmi3UpdateDiscreteStates) when `counter` reaches it. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    int64_t counter;
    double period;
    int64_t last;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_I64, OFF(counter), C_OUTPUT, -1, 0, 0},
    {2, T_F64, OFF(period), C_PARAM, -1, 0, 0},
    {3, T_I64, OFF(last), C_PARAM, -1, 0, 0},
};
#define EPS(t) (1e-9 * (1.0 + fabs(t)))

static void model_defaults(Model *m) { m->counter = 0; m->period = 1.0; m->last = 0; }
static void model_exit_init(Instance *c) { (void)c; }
static void model_changed(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }
static double next_event(const Model *m) { return (double)(m->counter + 1) * m->period; }

static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    double next = next_event(&c->m), end = t + h;
    (void)terminate;
    if (end < next - EPS(next)) return end;
    *event = true;
    if (end > next + EPS(next) && c->earlyReturnAllowed) return next;
    return end;
}

static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)needUpdate;
    while (c->time >= next_event(&c->m) - EPS(c->time)) c->m.counter++;
    if (c->m.last > 0 && c->m.counter >= c->m.last) *terminate = true;
    *nextDefined = true;
    *next = next_event(&c->m);
    return fmi3OK;
}
#include "framework.h"
