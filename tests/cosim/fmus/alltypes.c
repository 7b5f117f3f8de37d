/* Alltypes: an output and an input of every FMI 3.0 type, unclocked and clocked.
 *
 * Four groups of the fourteen value types (Float32, Float64, Int8, UInt8, Int16, UInt16, Int32,
 * UInt32, Int64, UInt64, Boolean, String, Binary, Enumeration):
 *   y_*   outputs,          y  = derive(u, n) after every step and every Set (n: steps taken)
 *   u_*   inputs
 *   c_*   outputs clocked by the output clock `out`, which ticks with the periodic input clock
 *         `tick` (interval 0.3): c = derive(y, k) at the k-th tick
 *   ci_*  inputs clocked by the triggered input clock `tin`
 * With the parameter `echo`, a tick of `tin` asks for another instant in which `out` ticks
 * again with c = derive(ci, k): connected to itself (out -> tin), that never settles.
 *
 * derive(src, m) moves each value by m in its own way (wrapping integers, a Boolean that flips
 * with odd m, a String that grows by ',"m"', a Binary that grows by the byte m), so every type
 * shows whether it travelled. */
#include <stdbool.h>
#include <stdint.h>
#include "framework_values.h"
typedef struct {
    float f32;
    double f64;
    int8_t i8;
    uint8_t u8;
    int16_t i16;
    uint16_t u16;
    int32_t i32;
    uint32_t u32;
    int64_t i64;
    uint64_t u64;
    bool b;
    Text s;
    Bytes bin;
    int64_t e; /* Enumeration, items 1..3 */
} Values;
typedef struct {
    bool tick, out, tin, echo, pending;
    int64_t n, k;
    Values y, u, c, ci;
} Model;
#include "framework_types.h"
#define OFF(f) offsetof(Model, f)
#define GROUP(g, base, causality, clock)                                   \
    {base + 0, T_F32, OFF(g.f32), causality, clock, 0, 0},               \
    {base + 1, T_F64, OFF(g.f64), causality, clock, 0, 0},               \
    {base + 2, T_I8, OFF(g.i8), causality, clock, 0, 0},                 \
    {base + 3, T_U8, OFF(g.u8), causality, clock, 0, 0},                 \
    {base + 4, T_I16, OFF(g.i16), causality, clock, 0, 0},               \
    {base + 5, T_U16, OFF(g.u16), causality, clock, 0, 0},               \
    {base + 6, T_I32, OFF(g.i32), causality, clock, 0, 0},               \
    {base + 7, T_U32, OFF(g.u32), causality, clock, 0, 0},               \
    {base + 8, T_I64, OFF(g.i64), causality, clock, 0, 0},               \
    {base + 9, T_U64, OFF(g.u64), causality, clock, 0, 0},               \
    {base + 10, T_BOOL, OFF(g.b), causality, clock, 0, 0},               \
    {base + 11, T_STRING, OFF(g.s), causality, clock, 0, 0},             \
    {base + 12, T_BINARY, OFF(g.bin), causality, clock, 0, 0},           \
    {base + 13, T_I64, OFF(g.e), causality, clock, 0, 0}
static const VarInfo VARS[] = {
    {1, T_CLOCK, OFF(tick), C_INPUT, -1, 0.3, 0},
    {2, T_CLOCK, OFF(out), C_OUTPUT, -1, 0, 0},
    {3, T_CLOCK, OFF(tin), C_INPUT, -1, 0, 0},
    {4, T_BOOL, OFF(echo), C_PARAM, -1, 0, 0},
    GROUP(y, 10, C_OUTPUT, -1),
    GROUP(u, 30, C_INPUT, -1),
    GROUP(c, 50, C_OUTPUT, 2),
    GROUP(ci, 70, C_INPUT, 3),
};

static void derive(Values *dst, const Values *src, int64_t m) {
    Values v = *src;
    char grown[TEXT_SIZE + 32];
    v.f32 = src->f32 + 0.5f * (float)m;
    v.f64 = src->f64 + 0.25 * (double)m + 0.1;
    v.i8 = (int8_t)(src->i8 - m);
    v.u8 = (uint8_t)(src->u8 + 37 * m);
    v.i16 = (int16_t)(src->i16 - 300 * m);
    v.u16 = (uint16_t)(src->u16 + 1000 * m);
    v.i32 = (int32_t)(src->i32 - 100000 * m);
    v.u32 = (uint32_t)(src->u32 + 3000000000u * (uint32_t)m);
    v.i64 = src->i64 - m * 1000000007;
    v.u64 = src->u64 + (uint64_t)m * 0x8000000000000001u;
    v.b = src->b != (m % 2 == 1);
    snprintf(grown, sizeof grown, "%s,\"%d\"", src->s, (int)m);
    grown[TEXT_SIZE - 1] = '\0';
    memcpy(v.s, grown, TEXT_SIZE);
    if (m > 0 && v.bin.size < BYTES_SIZE) v.bin.data[v.bin.size++] = (uint8_t)m;
    v.e = (src->e - 1 + m) % 3 + 1;
    *dst = v;
}

static void model_defaults(Model *m) {
    memset(m, 0, sizeof *m);
    m->u.f64 = 1.5;
    m->u.i8 = -3;
    m->u.e = 2;
    m->u.u64 = 7;
    snprintf(m->u.s, TEXT_SIZE, "a b");
    m->ci.e = 1;
}
static void model_exit_init(Instance *c) { derive(&c->m.y, &c->m.u, c->m.n); }
static void model_changed(Instance *c) { derive(&c->m.y, &c->m.u, c->m.n); }
static void model_clock_set(Instance *c, unsigned vr) {
    if (vr == 1) {
        c->m.out = true;
        c->m.k++;
        derive(&c->m.c, &c->m.y, c->m.k);
    } else if (vr == 3 && c->m.echo) {
        c->m.pending = true;
    }
}
static void model_new_instant(Instance *c) {
    if (c->m.pending) {
        c->m.pending = false;
        c->m.out = true;
        c->m.k++;
        derive(&c->m.c, &c->m.ci, c->m.k);
    }
}
static double model_step(Instance *c, double t, double h, bool *event, bool *terminate) {
    (void)event; (void)terminate;
    c->m.n++;
    derive(&c->m.y, &c->m.u, c->m.n);
    return t + h;
}
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next) {
    (void)terminate; (void)nextDefined; (void)next;
    *needUpdate = c->m.pending;
    return fmi3OK;
}
#include "framework.h"
