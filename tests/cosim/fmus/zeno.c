/* Zeno: from time `start` on (a time event announced by nextEventTime) it raises its output
 * clock `z` in every instant and always asks for another one: an event iteration that never
 * ends. `k` counts the instants. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    bool z;
    double start;
    int64_t k;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_CLOCK, OFF(z), C_OUTPUT, -1, 0, 0},
    {2, T_F64, OFF(start), C_PARAM, -1, 0, 0},
    {3, T_I64, OFF(k), C_OUTPUT, -1, 0, 0},
};
static void model_defaults(Model *m) { m->z = false; m->start = 0.5; m->k = 0; }
static void model_exit_init(Instance *c) { (void)c; }
static void model_changed(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static bool looping(const Instance *c) { return c->time >= c->m.start - 1e-9; }
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)terminate;
    if (t + h < c->m.start - 1e-9) return t + h;
    *event = true;
    return c->earlyReturnAllowed && t < c->m.start ? c->m.start : t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)terminate;
    if (looping(c)) { c->m.k++; *needUpdate = true; }
    else { *nextDefined = true; *next = c->m.start; }
    return fmi3OK;
}
static void model_new_instant(Instance *c) { if (looping(c)) c->m.z = true; }
#include "framework.h"
