/* Bouncing ball: h'' = -g, solved in closed form. The impact is a state event: with early
 * return the step stops at the impact time and asks for Event Mode, where the velocity is
 * reversed (v := -e v). Without early return the impact is handled inside the step. */
#include <stdbool.h>
#include <stdint.h>
typedef struct {
    double h, v, h0, e;
    int64_t bounces;
    bool resting;
} Model;
#include "framework_types.h"
#define G 9.81
#define OFF(f) offsetof(Model, f)
static const VarInfo VARS[] = {
    {1, T_F64, OFF(h), C_OUTPUT, -1, 0, 0},
    {2, T_F64, OFF(v), C_OUTPUT, -1, 0, 0},
    {3, T_I64, OFF(bounces), C_OUTPUT, -1, 0, 0},
    {4, T_F64, OFF(h0), C_PARAM, -1, 0, 0},
    {5, T_F64, OFF(e), C_PARAM, -1, 0, 0},
};

static void model_defaults(Model *m) {
    m->h0 = 1.0; m->e = 0.7; m->h = 1.0; m->v = 0; m->bounces = 0; m->resting = false;
}
static void model_exit_init(Instance *c) { c->m.h = c->m.h0; }
static void model_changed(Instance *c) { if (c->state & (S_INSTANTIATED | S_INIT)) c->m.h = c->m.h0; }
static void model_clock_set(Instance *c, unsigned vr) { (void)c; (void)vr; }
static void model_new_instant(Instance *c) { (void)c; }

static void bounce(Model *m) {
    m->v = -m->e * m->v;
    m->bounces++;
    if (m->v < 0.01) { m->v = 0; m->h = 0; m->resting = true; }
}

/* time until impact from (h, v), or +inf when resting */
static double impact_in(const Model *m) {
    if (m->resting) return INFINITY;
    return (m->v + sqrt(m->v * m->v + 2 * G * m->h)) / G;
}

static void fly(Model *m, double dt) {
    if (m->resting) return;
    m->h += m->v * dt - 0.5 * G * dt * dt;
    m->v -= G * dt;
}

static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    Model *m = &c->m;
    double now = t, end = t + h;
    (void)terminate;
    for (;;) {
        double tau = impact_in(m);
        if (m->h <= 0 && m->v < 0) tau = 0; /* impact pending at the step start */
        if (now + tau > end) { fly(m, end - now); return end; }
        fly(m, tau);
        m->h = 0;
        now += tau;
        if (c->earlyReturnAllowed && c->eventModeUsed) { *event = true; return now; }
        bounce(m); /* handled internally */
    }
}

static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)needUpdate; (void)terminate; (void)nextDefined; (void)next;
    if (c->m.h <= 0 && c->m.v < 0) bounce(&c->m);
    return fmi3OK;
}
#include "framework.h"
