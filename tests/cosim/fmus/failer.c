/* Failer: `y` follows time; every fmi3DoStep that starts at or after `fail_time` returns
 * fmi3Error. The step that reaches `crash_time` (if >= 0) kills the process that runs the FMU
 * with SIGSEGV inside fmi3DoStep, as a generated FMU with a bug would (the signal is raised: a
 * write through a null pointer is undefined behaviour, which the optimiser may leave out). */
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    double y, fail_time, crash_time;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_F64, OFF(y), C_OUTPUT, -1, 0, 0},
    {2, T_F64, OFF(fail_time), C_PARAM, -1, 0, 0},
    {3, T_F64, OFF(crash_time), C_PARAM, -1, 0, 0},
};
static void model_defaults(Model *m) { m->y = 0; m->fail_time = 0.5; m->crash_time = -1; }
static void model_exit_init(Instance *c) { c->m.y = c->time; }
static void model_changed(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)event; (void)terminate;
    if (c->m.crash_time >= 0 && t + h >= c->m.crash_time - 1e-9) raise(SIGSEGV);
    if (t >= c->m.fail_time - 1e-9) return -1;
    c->m.y = t + h;
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)c; (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    return fmi3OK;
}
#include "framework.h"
