/* robogen state-machine support: what every generated model.c uses, the same for every model.
 *
 *   - the results of a machine's run and the run-time errors (faults) it can report;
 *   - the transition prologue (RG_BEGIN_TRANSITION) and node entry (RG_ENTER);
 *   - the event tables through which events reach a machine (rg_event_slot, rg_deliver);
 *   - arithmetic as robogen defines it: wrapping integers, checked division, checked conversion
 *     of reals to integers, 1-based checked indices. Each helper does what robogen.ir.interp
 *     does for the same operation, so the C and the reference interpreter cannot disagree.
 *
 * model.c includes it after config.h and robogen_runtime.h (see the unity file). From config.h it
 * reads RG_STEPWISE (1 in stepwise semantics), RG_MAX_TRANSITIONS and the rg_model_data members
 * fault (int32_t) and dropped_events (uint64_t); nothing else of the model.
 */
#ifndef ROBOGEN_MACHINE_H
#define ROBOGEN_MACHINE_H

#include <math.h>
#include <string.h>

/* ---- runs and faults ------------------------------------------------------------------------ */

/* The result of a machine's run function rg_run_<i>. */
enum {
    RG_RUN_SUSPENDED = 0, /* the cycle's work is done; the machine resumes at m->pc next time */
    RG_RUN_MICRO = 1,     /* stepwise: a micro-step ended in front of the run's second transition */
    RG_RUN_FAULT = -1,    /* a run-time error, already logged */
    RG_RUN_JUMP = 2       /* a part of a large machine's blocks: control goes on in another part */
};

/* rg_model_data.fault: the run-time error of the current instant. */
enum {
    RG_FAULT_NONE = 0,
    RG_FAULT_DIVISION = 1,
    RG_FAULT_INDEX = 2,
    RG_FAULT_RUNAWAY = 3,
    RG_FAULT_STUCK = 4,
    RG_FAULT_CONVERSION = 5,
    RG_FAULT_COLLECTION = 6, /* a set or sequence: its message is model.c's rg_sites[fault_site] */
    RG_FAULT_EMPTY_RANGE = 7
};

/* Blocks one run may execute before it is reported as a runaway: the bound for any loop. */
#define RG_MAX_STEPS (64UL * RG_MAX_TRANSITIONS)

static const char *rg_fault_text(int32_t fault) RG_MAYBE_UNUSED;
static const char *rg_fault_text(int32_t fault)
{
    switch (fault) {
    case RG_FAULT_DIVISION: return "division by zero";
    case RG_FAULT_INDEX: return "index out of range";
    case RG_FAULT_RUNAWAY: return "runaway cycle";
    case RG_FAULT_CONVERSION: return "real number out of range for an integer";
    case RG_FAULT_EMPTY_RANGE: return "a choice from an empty range";
    default: return "run-time error";
    }
}

/* A statement of machine `machine` set the fault code in block `block`; `node` is the node the
 * machine entered last. Logs it and ends the run. */
static int rg_report_fault_text(rg_instance *inst, const char *machine, const char *text, const char *block,
                                const char *node) RG_MAYBE_UNUSED;
static int rg_report_fault_text(rg_instance *inst, const char *machine, const char *text, const char *block,
                                const char *node)
{
    rg_log(inst, RG_LOG_ERROR, fmi3Error, "state machine %s: %s in %s (last node entered: %s)", machine, text, block, node);
    return RG_RUN_FAULT;
}

static int rg_report_fault(rg_instance *inst, const char *machine, const char *block, const char *node) RG_MAYBE_UNUSED;
static int rg_report_fault(rg_instance *inst, const char *machine, const char *block, const char *node)
{
    return rg_report_fault_text(inst, machine, rg_fault_text(inst->s.data.fault), block, node);
}

/* More than RG_MAX_TRANSITIONS transitions (or RG_MAX_STEPS blocks) in one run. */
static int rg_report_runaway(rg_instance *inst, const char *machine, const char *block, const char *node) RG_MAYBE_UNUSED;
static int rg_report_runaway(rg_instance *inst, const char *machine, const char *block, const char *node)
{
    inst->s.data.fault = RG_FAULT_RUNAWAY;
    rg_log(inst, RG_LOG_ERROR, fmi3Error, "state machine %s: more than %lu transitions in one cycle without exec "
           "(a runaway cycle), at %s (last node entered: %s)", machine, RG_MAX_TRANSITIONS, block, node);
    return RG_RUN_FAULT;
}

/* A deadlock, or a resume point that does not exist: logged, the run ends with a fault. */
static int rg_machine_fail(rg_instance *inst, const char *message) RG_MAYBE_UNUSED;
static int rg_machine_fail(rg_instance *inst, const char *message)
{
    inst->s.data.fault = RG_FAULT_STUCK;
    rg_log(inst, RG_LOG_ERROR, fmi3Error, "%s", message);
    return RG_RUN_FAULT;
}

/* A RoboChart deadline was missed: counted and logged, never enforced. */
static void rg_deadline_miss(rg_instance *inst, const char *message) RG_MAYBE_UNUSED;
static void rg_deadline_miss(rg_instance *inst, const char *message)
{
    inst->s.data.deadline_misses++;
    rg_log(inst, RG_LOG_WARNING, fmi3Warning, "%s (t=%.17g)", message, inst->s.time);
}

/* The end of a run: true if it faulted (already logged); otherwise records in *in_cycle whether
 * a stepwise run stopped between two micro-steps of its cycle. */
static bool rg_run_failed(int result, bool *in_cycle) RG_MAYBE_UNUSED;
static bool rg_run_failed(int result, bool *in_cycle)
{
    if (result == RG_RUN_FAULT) return true;
    *in_cycle = result == RG_RUN_MICRO;
    return false;
}

/* ---- transitions (used inside rg_run_<i>, where m is the machine's memory) --------------------- */

/* A transition was taken: logged in the category logTransitions. */
#define RG_TRACE(inst, text) \
    do { if ((inst)->logging_on && (inst)->log_category_on[RG_LOG_TRANSITIONS]) \
        rg_log((inst), RG_LOG_TRANSITIONS, fmi3OK, "%s", (text)); } while (0)

/* The start of a transition segment (an IR block marked step). It counts toward the runaway
 * bound (returning `runaway` beyond it) and, in stepwise semantics, ends the micro-step in front
 * of the run's second transition (the local `taken` says whether the run began one already). */
#if RG_STEPWISE
#define RG_BEGIN_TRANSITION(runaway) \
    do { \
        if (taken) return RG_RUN_MICRO; \
        taken = true; \
        if (++m->transitions > RG_MAX_TRANSITIONS) return (runaway); \
    } while (0)
#else
#define RG_BEGIN_TRANSITION(runaway) \
    do { if (++m->transitions > RG_MAX_TRANSITIONS) return (runaway); } while (0)
#endif

/* The machine enters node `id` (its FMI state output) now: sinceEntry(id) counts from here. */
#define RG_ENTER(id) do { m->node = (id); m->entered[id] = m->ticks; } while (0)

/* ---- events: where each input event of a machine is kept ---------------------------------------- */

/* One row of a machine's event table rg_events_<i>, indexed by its event enum: where the event
 * is latched when it arrives (its register) and where the machine reads it (its sample in
 * RoboSim, its buffer in RoboChart), as offsets into rg_model_data. */
typedef struct {
    size_t reg_present; /* bool: the event is in the register */
    size_t smp_present; /* bool: the event is in the sample or buffer */
    size_t reg_value;   /* typed events: the value in the register (else 0) */
    size_t smp_value;   /* typed events: the value in the sample or buffer (else 0) */
    size_t size;        /* typed events: bytes of the value; 0 for an event without one */
    size_t new_input;   /* bool: the machine's new_input flag */
} rg_event_slot;

/* The row of event `event` (its enum constant) of the machine whose memory is rg_model_data
 * member `machine`; a typed event's value lives in the members reg_e_<value> and smp_e_<value>. */
#define RG_EVENT(machine, event) \
    { offsetof(rg_model_data, machine.reg_present) + (size_t)(event) * sizeof(bool), \
      offsetof(rg_model_data, machine.smp_present) + (size_t)(event) * sizeof(bool), 0, 0, 0, \
      offsetof(rg_model_data, machine.new_input) }
#define RG_TYPED_EVENT(machine, event, value) \
    { offsetof(rg_model_data, machine.reg_present) + (size_t)(event) * sizeof(bool), \
      offsetof(rg_model_data, machine.smp_present) + (size_t)(event) * sizeof(bool), \
      offsetof(rg_model_data, machine.reg_e_##value), offsetof(rg_model_data, machine.smp_e_##value), \
      sizeof(((rg_model_data *)0)->machine.reg_e_##value), offsetof(rg_model_data, machine.new_input) }

static bool *rg_flag_at(rg_model_data *d, size_t offset) RG_MAYBE_UNUSED;
static bool *rg_flag_at(rg_model_data *d, size_t offset)
{
    return (bool *)((unsigned char *)d + offset);
}

/* An event reaches a machine (from an input clock, or sent by another machine): it is latched
 * in the machine's register until its next cycle (RoboChart: run); one still latched there is
 * overwritten and counted in dropped_events. `value` points to the event's value (NULL if none). */
static void rg_deliver(rg_model_data *d, const rg_event_slot *event, const void *value) RG_MAYBE_UNUSED;
static void rg_deliver(rg_model_data *d, const rg_event_slot *event, const void *value)
{
    bool *present = rg_flag_at(d, event->reg_present);
    if (*present) d->dropped_events++;
    *present = true;
    if (event->size > 0) memcpy((unsigned char *)d + event->reg_value, value, event->size);
    *rg_flag_at(d, event->new_input) = true;
}

/* RoboChart, between two runs: an event latched in the register joins the machine's buffer,
 * where it stays until a transition consumes it (one still in the buffer counts as dropped).
 * Returns whether the event arrived. */
static bool rg_join_buffer(rg_model_data *d, const rg_event_slot *event) RG_MAYBE_UNUSED;
static bool rg_join_buffer(rg_model_data *d, const rg_event_slot *event)
{
    bool *latched = rg_flag_at(d, event->reg_present);
    bool *buffered = rg_flag_at(d, event->smp_present);
    if (!*latched) return false;
    if (*buffered) d->dropped_events++;
    *buffered = true;
    if (event->size > 0) memcpy((unsigned char *)d + event->smp_value, (unsigned char *)d + event->reg_value, event->size);
    *latched = false;
    return true;
}

/* RoboSim: a cycle starts; the events latched since the previous cycle become its sample (the
 * caller copies the values of typed events). */
static void rg_start_cycle(bool *present_reg, bool *present_smp, size_t n_events, uint64_t *ticks, bool *new_input,
                           uint64_t *transitions) RG_MAYBE_UNUSED;
static void rg_start_cycle(bool *present_reg, bool *present_smp, size_t n_events, uint64_t *ticks, bool *new_input,
                           uint64_t *transitions)
{
    memcpy(present_smp, present_reg, n_events * sizeof(bool));
    memset(present_reg, 0, n_events * sizeof(bool));
    *new_input = false;
    (*ticks)++;
    *transitions = 0;
}

/* ---- arithmetic as robogen defines it: wrapping integers, checked division ---------------------- */

static inline int64_t rg_i_add(int64_t a, int64_t b) { return (int64_t)((uint64_t)a + (uint64_t)b); }
static inline int64_t rg_i_sub(int64_t a, int64_t b) { return (int64_t)((uint64_t)a - (uint64_t)b); }
static inline int64_t rg_i_mul(int64_t a, int64_t b) { return (int64_t)((uint64_t)a * (uint64_t)b); }
static inline int64_t rg_i_neg(int64_t a) { return (int64_t)(UINT64_C(0) - (uint64_t)a); }
static inline int64_t rg_i_abs(int64_t a) { return a < 0 ? rg_i_neg(a) : a; }
static inline int64_t rg_i_min(int64_t a, int64_t b) { return a <= b ? a : b; }
static inline int64_t rg_i_max(int64_t a, int64_t b) { return a >= b ? a : b; }
static inline int64_t rg_i_div(rg_model_data *d, int64_t a, int64_t b)
{
    if (b == 0) { d->fault = RG_FAULT_DIVISION; return 0; }
    if (b == -1) return rg_i_neg(a);
    return a / b;
}
static inline int64_t rg_i_mod(rg_model_data *d, int64_t a, int64_t b)
{
    if (b == 0) { d->fault = RG_FAULT_DIVISION; return 0; }
    if (b == -1) return 0;
    return a % b;
}
static inline uint64_t rg_u_add(uint64_t a, uint64_t b) { return a + b; }
static inline uint64_t rg_u_sub(uint64_t a, uint64_t b) { return a - b; }
static inline uint64_t rg_u_mul(uint64_t a, uint64_t b) { return a * b; }
static inline uint64_t rg_u_neg(uint64_t a) { return UINT64_C(0) - a; }
static inline uint64_t rg_u_abs(uint64_t a) { return a; }
static inline uint64_t rg_u_min(uint64_t a, uint64_t b) { return a <= b ? a : b; }
static inline uint64_t rg_u_max(uint64_t a, uint64_t b) { return a >= b ? a : b; }
static inline uint64_t rg_u_div(rg_model_data *d, uint64_t a, uint64_t b)
{
    if (b == 0) { d->fault = RG_FAULT_DIVISION; return 0; }
    return a / b;
}
static inline uint64_t rg_u_mod(rg_model_data *d, uint64_t a, uint64_t b)
{
    if (b == 0) { d->fault = RG_FAULT_DIVISION; return 0; }
    return a % b;
}
static inline double rg_r_div(rg_model_data *d, double a, double b)
{
    if (b == 0.0) { d->fault = RG_FAULT_DIVISION; return 0.0; }
    return a / b;
}
/* RoboChart's % on reals: the remainder with the sign of the dividend, as on integers (fmod). */
static inline double rg_r_mod(rg_model_data *d, double a, double b)
{
    if (b == 0.0) { d->fault = RG_FAULT_DIVISION; return 0.0; }
    return fmod(a, b);
}
static inline double rg_r_abs(double a) { return a < 0.0 ? -a : a; }
static inline double rg_r_min(double a, double b) { return a <= b ? a : b; }
static inline double rg_r_max(double a, double b) { return a >= b ? a : b; }

/* Conversions: a real becomes an integer by truncation toward zero; outside the integer's range
 * (or NaN) it sets the fault code instead of being undefined behaviour. */
static inline int64_t rg_r_to_i(rg_model_data *d, double x)
{
    if (!(x >= -9223372036854775808.0 && x < 9223372036854775808.0)) { d->fault = RG_FAULT_CONVERSION; return 0; }
    return (int64_t)x;
}
static inline uint64_t rg_r_to_u(rg_model_data *d, double x)
{
    if (!(x > -1.0 && x < 18446744073709551616.0)) { d->fault = RG_FAULT_CONVERSION; return 0; }
    return (uint64_t)x;
}
/* nat to int wraps around, like the interpreter (no implementation-defined conversion). */
static inline int64_t rg_u_to_i(uint64_t x)
{
    return x <= (uint64_t)INT64_MAX ? (int64_t)x : -(int64_t)(UINT64_MAX - x) - 1;
}

/* A 1-based index into n elements, as a 0-based offset; out of range sets the fault code. */
static inline int64_t rg_index(rg_model_data *d, int64_t i, int64_t n)
{
    if (i < 1 || i > n) { d->fault = RG_FAULT_INDEX; return 0; }
    return i - 1;
}

/* ---- the seeded generator (SplitMix64) of nondeterministic waits and probabilistic junctions ---- */

static inline uint64_t rg_random_next(uint64_t *state)
{
    uint64_t z = (*state += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}
/* An integer from low to high (both included): low + x mod (high - low + 1); the whole range of
 * int64_t takes x as it is. An empty range sets the fault code. */
static inline int64_t rg_random_int(rg_model_data *d, uint64_t *state, int64_t low, int64_t high)
{
    uint64_t span, x;
    if (high < low) { d->fault = RG_FAULT_EMPTY_RANGE; return low; }
    span = (uint64_t)high - (uint64_t)low + 1u;
    x = rg_random_next(state);
    return rg_u_to_i((uint64_t)low + (span == 0 ? x : x % span));
}
/* A real in [0, 1): the 53 high bits of the next output, scaled. */
static inline double rg_random_real(uint64_t *state)
{
    return (double)(rg_random_next(state) >> 11) * (1.0 / 9007199254740992.0);
}

/* ---- RoboChart time for free (robogen compile --time skip; robogen.ir.lookahead) ------------ */
#ifdef RG_TIME_FREE
/* config.h defines RG_TIME_FREE and RG_TOCK_SECONDS (one time unit in seconds); the FMU has no
 * tock clock: tock k is due at start + k * RG_TOCK_SECONDS, and rg_model_data.cycles counts those
 * processed. After each event iteration the FMU announces as nextEventTime the first tock at which
 * a machine may do something (rg_wake_<i>); the tocks before it pass idle: counted, no machine run. */

#define RG_NEVER UINT64_MAX                        /* no tock: nothing happens until an event comes */
#define RG_LOOKAHEAD_HORIZON (UINT64_C(1) << 40)   /* the most tocks looked ahead (robogen.ir.lookahead.HORIZON) */

static double rg_tock_time(const rg_instance *inst, uint64_t k) RG_MAYBE_UNUSED;
static double rg_tock_time(const rg_instance *inst, uint64_t k)
{
    return inst->s.start_time + (double)k * RG_TOCK_SECONDS; /* rg_tick_time's grid, shift 0 */
}

/* The number of tocks due by time t: those at or before it (under the time tolerance), >= 1. */
static uint64_t rg_tocks_by(const rg_instance *inst, double t) RG_MAYBE_UNUSED;
static uint64_t rg_tocks_by(const rg_instance *inst, double t)
{
    double n = floor((t - inst->s.start_time) / RG_TOCK_SECONDS);
    uint64_t k = n < 0.0 ? 0 : (n > 4.0e18 ? UINT64_C(4000000000000000000) : (uint64_t)n);
    while (k > 0 && !(rg_tock_time(inst, k) <= t || rg_time_equal(rg_tock_time(inst, k), t))) --k;
    while (rg_tock_time(inst, k + 1) <= t || rg_time_equal(rg_tock_time(inst, k + 1), t)) ++k;
    return k + 1;
}

/* A machine's tick count and wait counter as k tocks from now would show them, and back. */
typedef struct {
    uint64_t ticks;
    int64_t wait_left;
} rg_tock_shift;

static rg_tock_shift rg_shift_tocks(uint64_t *ticks, int64_t *wait_left, uint64_t k) RG_MAYBE_UNUSED;
static rg_tock_shift rg_shift_tocks(uint64_t *ticks, int64_t *wait_left, uint64_t k)
{
    rg_tock_shift saved;
    saved.ticks = *ticks;
    saved.wait_left = *wait_left;
    *ticks += k;
    if (*wait_left > 0) *wait_left = (uint64_t)*wait_left > k ? *wait_left - (int64_t)k : 0;
    return saved;
}

static void rg_unshift_tocks(uint64_t *ticks, int64_t *wait_left, rg_tock_shift saved) RG_MAYBE_UNUSED;
static void rg_unshift_tocks(uint64_t *ticks, int64_t *wait_left, rg_tock_shift saved)
{
    *ticks = saved.ticks;
    *wait_left = saved.wait_left;
}

/* The result of a look-ahead that evaluated model expressions: a run-time error in them means the
 * machine must run at the next tock (where the ticking FMU meets the same error). */
static bool rg_lookahead_fault(rg_model_data *d) RG_MAYBE_UNUSED;
static bool rg_lookahead_fault(rg_model_data *d)
{
    if (d->fault == RG_FAULT_NONE) return false;
    d->fault = RG_FAULT_NONE;
    return true;
}

/* min(wake, the least k >= 2 at which sign(inst, k) differs from sign(inst, 1)), sign being
 * monotone in k; RG_LOOKAHEAD_HORIZON if it does not change up to there. Doubling, then bisection:
 * robogen.ir.lookahead.first_change, step for step. */
static uint64_t rg_first_change(rg_instance *inst, int (*sign)(rg_instance *, uint64_t), uint64_t wake) RG_MAYBE_UNUSED;
static uint64_t rg_first_change(rg_instance *inst, int (*sign)(rg_instance *, uint64_t), uint64_t wake)
{
    int first = sign(inst, 1);
    uint64_t low = 1, high = 2, found;
    while (high <= RG_LOOKAHEAD_HORIZON && sign(inst, high) == first) {
        low = high;
        high *= 2;
    }
    if (high > RG_LOOKAHEAD_HORIZON) {
        found = RG_LOOKAHEAD_HORIZON;
    } else {
        while (high - low > 1) {
            uint64_t mid = low + (high - low) / 2;
            if (sign(inst, mid) == first) low = mid;
            else high = mid;
        }
        found = high;
    }
    return found < wake ? found : wake;
}
#endif /* RG_TIME_FREE */

#endif /* ROBOGEN_MACHINE_H */
