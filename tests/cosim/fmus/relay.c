/* Relay: forwards the triggered input clock `u` to the triggered output clock `y`, with the
 * clocked payload x_out = x_in + 1 (so a chain's end shows the hop count). Immediate mode
 * (stepwise=false): `y` ticks in the instant that activates `u`. Stepwise mode: the FMU latches
 * the tick, asks for another instant, and ticks `y` in the next one. `n` counts input ticks. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    bool u, y, stepwise, pending;
    int64_t x_in, x_out, n, latched;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_CLOCK, OFF(u), C_INPUT, -1, 0, 0},
    {2, T_I64, OFF(x_in), C_INPUT, 1, 0, 0},
    {3, T_CLOCK, OFF(y), C_OUTPUT, -1, 0, 0},
    {4, T_I64, OFF(x_out), C_OUTPUT, 3, 0, 0},
    {5, T_BOOL, OFF(stepwise), C_PARAM, -1, 0, 0},
    {6, T_I64, OFF(n), C_OUTPUT, -1, 0, 0},
};

static void model_defaults(Model *m) { memset(m, 0, sizeof *m); }
static void model_exit_init(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_changed(Instance *c) {
    if (c->state == S_EVENT && c->m.u && !c->m.stepwise) { c->m.x_out = c->m.x_in + 1; c->m.y = true; }
}
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)c; (void)event; (void)terminate;
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)terminate; (void)nextDefined; (void)next;
    if (c->m.u) {
        c->m.n++;
        if (c->m.stepwise) { c->m.pending = true; c->m.latched = c->m.x_in + 1; *needUpdate = true; }
    }
    return fmi3OK;
}
static void model_new_instant(Instance *c) {
    if (c->m.pending) { c->m.pending = false; c->m.x_out = c->m.latched; c->m.y = true; }
}
#include "framework.h"
