/* Setcount: counts the Set calls it receives. `sets` is the number of fmi3Set<Type> calls since
 * instantiation (each call, however many values it carries), `y` follows the Int64 input `u`. A
 * master that sets an input only when its value changed makes `sets` the number of changes. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    int64_t u, y, sets;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_I64, OFF(u), C_INPUT, -1, 0, 0},
    {2, T_I64, OFF(y), C_OUTPUT, -1, 0, 0},
    {3, T_I64, OFF(sets), C_OUTPUT, -1, 0, 0},
};
static void model_defaults(Model *m) { m->u = 0; m->y = 0; m->sets = 0; }
static void model_exit_init(Instance *c) { c->m.y = c->m.u; }
static void model_changed(Instance *c) { c->m.sets++; c->m.y = c->m.u; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)c; (void)event; (void)terminate;
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)c; (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    return fmi3OK;
}
#include "framework.h"
