/* Crasher: a model that misbehaves on request, to test that a campaign survives its runs.
 * `y` = gain * time. When a step reaches `crash_time` the FMU writes through a null pointer
 * (SIGSEGV); at `hang_time` it spins forever; `delay` seconds of wall time pass in every
 * fmi3DoStep (runs that last long enough to kill their worker). A negative time disables its
 * misbehaviour (the default). */
#define _POSIX_C_SOURCE 199309L
#include <stdbool.h>
#include <stdint.h>
#include <time.h>
typedef struct {
    double y, gain, crash_time, hang_time, delay;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_F64, OFF(y), C_OUTPUT, -1, 0, 0},
    {2, T_F64, OFF(gain), C_PARAM, -1, 0, 0},
    {3, T_F64, OFF(crash_time), C_PARAM, -1, 0, 0},
    {4, T_F64, OFF(hang_time), C_PARAM, -1, 0, 0},
    {5, T_F64, OFF(delay), C_PARAM, -1, 0, 0},
};
static void model_defaults(Model *m) { m->y = 0; m->gain = 1.0; m->crash_time = -1; m->hang_time = -1; m->delay = 0; }
static void model_exit_init(Instance *c) { c->m.y = c->m.gain * c->time; }
static void model_changed(Instance *c) { (void)c; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }

static bool reached(double when, double t, double h) { return when >= 0 && t + h >= when - 1e-9; }

static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)event; (void)terminate;
    if (c->m.delay > 0) {
        struct timespec pause;
        pause.tv_sec = (time_t)c->m.delay;
        pause.tv_nsec = (long)((c->m.delay - (double)pause.tv_sec) * 1e9);
        nanosleep(&pause, NULL);
    }
    if (reached(c->m.crash_time, t, h)) {
        int *volatile nowhere = NULL;
        *nowhere = 1;
    }
    if (reached(c->m.hang_time, t, h)) {
        volatile unsigned long spins = 0;
        for (;;) spins++;
    }
    c->m.y = c->m.gain * (t + h);
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)c; (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    return fmi3OK;
}
#include "framework.h"
