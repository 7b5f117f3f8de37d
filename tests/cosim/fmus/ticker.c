/* Ticker: a constant periodic input clock `tick` (interval 0.25 s, shift 0). Each tick raises
 * the triggered output clock `out` in the same instant, with the tick number as clocked
 * payload `count`. `ticks` (not clocked) follows `count` after each instant; `phase` is time. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    bool tick, out;
    int64_t count, ticks;
    double phase;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_CLOCK, OFF(tick), C_INPUT, -1, 0.25, 0},
    {2, T_CLOCK, OFF(out), C_OUTPUT, -1, 0, 0},
    {3, T_I64, OFF(count), C_OUTPUT, 2, 0, 0},
    {4, T_I64, OFF(ticks), C_OUTPUT, -1, 0, 0},
    {5, T_F64, OFF(phase), C_OUTPUT, -1, 0, 0},
};

static void model_defaults(Model *m) { memset(m, 0, sizeof *m); }
static void model_exit_init(Instance *c) { c->m.phase = c->time; }
static void model_changed(Instance *c) { (void)c; }
static void model_new_instant(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) {
    if (vr == 1) { c->m.count++; c->m.out = true; }
}
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)event; (void)terminate;
    c->m.phase = t + h;
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    c->m.ticks = c->m.count;
    return fmi3OK;
}
#include "framework.h"
