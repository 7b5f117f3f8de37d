/* Scheduled Execution: four model partitions, at the ticks of the input clocks fast (vr 1, every
 * 0.1 s, priority 2), slow (vr 2, every 0.3 s, priority 1: it runs first when both tick), kick
 * (vr 10, triggered, priority 0: first of all; kick_seq, vr 11, its last activation) and later
 * (vr 12, countdown, priority 3): where the parameter delay (vr 13) is positive, each activation
 * of slow at t sets later to tick at t + delay (announced through clockUpdate and
 * fmi3GetIntervalDecimal); later_seq (vr 14) and later_at (vr 15) are its last activation's
 * number and time. Each activation numbers itself (seq); fast_seq and slow_seq keep the number of
 * each partition's last activation, fast_n and slow_n count them; y_fast (clocked by fast) is 10 t
 * at its tick, y_slow (clocked by slow) the fast count when slow last ran. */
#include "mex_core.h"
#define NX 0
#define NZ 0
#define CS_STEP 1e-3
#define MODEL_INTERVALS
typedef struct {
    double x[1];
    bool fast, slow, kick, later, later_announced;
    int64_t seq, fast_seq, slow_seq, fast_n, slow_n, kick_seq, later_seq;
    double y_fast, delay, later_at;
    int64_t y_slow;
} Model;
static const VarInfo VARS[] = {
    {1, T_CLOCK, offsetof(Model, fast), 0}, {2, T_CLOCK, offsetof(Model, slow), 0}, {3, T_I64, offsetof(Model, seq), 0},
    {4, T_I64, offsetof(Model, fast_seq), 0}, {5, T_I64, offsetof(Model, slow_seq), 0}, {6, T_I64, offsetof(Model, fast_n), 0},
    {7, T_I64, offsetof(Model, slow_n), 0}, {8, T_F64, offsetof(Model, y_fast), 0}, {9, T_I64, offsetof(Model, y_slow), 0},
    {10, T_CLOCK, offsetof(Model, kick), 0}, {11, T_I64, offsetof(Model, kick_seq), 0},
    {12, T_CLOCK, offsetof(Model, later), 0}, {13, T_F64, offsetof(Model, delay), 0},
    {14, T_I64, offsetof(Model, later_seq), 0}, {15, T_F64, offsetof(Model, later_at), 0},
};
static void model_defaults(Model *m) { memset(m, 0, sizeof *m); }
static void model_derivatives(Model *m, double t, double *dx) { (void)m; (void)t; (void)dx; }
static void model_indicators(Model *m, double t, double *z) { (void)m; (void)t; (void)z; }
static bool model_step_event(Model *m, double t) { (void)m; (void)t; return false; }
static void model_event(Model *m, double t, Events *e) { (void)m; (void)t; (void)e; }
static int model_partition(Model *m, unsigned vr, double t)
{
    m->seq++;
    if (vr == 10) {
        m->kick_seq = m->seq;
    } else if (vr == 12) {
        m->later_seq = m->seq;
        m->later_at = t;
    } else if (vr == 1) {
        m->fast_seq = m->seq;
        m->fast_n++;
        m->y_fast = 10.0 * t;
    } else {
        m->slow_seq = m->seq;
        m->slow_n++;
        m->y_slow = m->fast_n;
        if (m->delay > 0) {
            m->later_announced = true;
            return 1; /* clockUpdate: later's interval is known */
        }
    }
    return 0;
}
static int model_interval(Model *m, unsigned vr, double *interval)
{
    if (vr != 12) return -1;
    if (!m->later_announced) return 0;
    m->later_announced = false;
    *interval = m->delay;
    return 1;
}
#include "mex.h"
