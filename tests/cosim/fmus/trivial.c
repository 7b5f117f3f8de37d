/* Trivial: y = u + t after every step. The benchmark's FMU. With `stop_at` > 0, the step that
 * reaches stop_at asks to terminate the simulation (terminateSimulation from fmi3DoStep). */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    double u, y, stop_at;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_F64, OFF(u), C_INPUT, -1, 0, 0},
    {2, T_F64, OFF(y), C_OUTPUT, -1, 0, 0},
    {3, T_F64, OFF(stop_at), C_PARAM, -1, 0, 0},
};
static void model_defaults(Model *m) { m->u = 0; m->y = 0; m->stop_at = 0; }
static void model_exit_init(Instance *c) { c->m.y = c->m.u + c->time; }
static void model_changed(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)event;
    c->m.y = c->m.u + t + h;
    if (c->m.stop_at > 0 && t + h >= c->m.stop_at - 1e-9) *terminate = true;
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)c; (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    return fmi3OK;
}
#include "framework.h"
