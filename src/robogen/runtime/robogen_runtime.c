/* robogen FMI 3.0 Co-Simulation runtime: the 75 exported fmi3* functions.
 *
 * Compiled as the last part of an FMU's unity translation unit (see robogen_runtime.h), after
 * config.h and model.c. Hand-written, model-independent; the model plugs in through the rg_model_*
 * hooks and the rg_variables / rg_clocks tables.
 *
 * This file holds the design note and the machinery every function shares (allowed states,
 * logging, the instance registry, table lookups, lazy evaluation); at its end it includes the API
 * by concern: robogen_runtime_modes.c, _values.c, _clocks.c, _fmu_state.c and _unsupported.c.
 * An FMU's sources/ folder therefore carries all robogen_* files (binary.runtime_sources()).
 *
 * DESIGN NOTE
 *
 * State machine. An instance is in exactly one rg_mode: Instantiated, Initialization Mode, Event
 * Mode, Step Mode or Terminated. Every fmi3* function names the set of modes it is allowed in
 * (RG_ALLOWED_* below) and checks it on entry (rg_enter). A call outside its set, or with illegal
 * arguments, logs why and returns fmi3Error. Following the FMI 3.0 state machine ("if any function
 * called in super state FMU State Setable returns fmi3Error, the FMU enters state Terminated"),
 * every fmi3Error moves the instance to Terminated (rg_fail): only Get of non-clocked variables,
 * the FMU-state functions, fmi3Reset and fmi3FreeInstance go on from there, so a master can roll
 * back with fmi3SetFMUState or start over with fmi3Reset. fmi3Discard (from the model's DoStep)
 * leaves the instance exactly as it was before the call: the runtime restores a copy it took.
 *   Instantiated --EnterInitializationMode--> Initialization Mode --ExitInitializationMode-->
 *   Event Mode (eventModeUsed) or Step Mode; Event Mode --EnterStepMode--> Step Mode (only after
 *   an UpdateDiscreteStates that asked for no further iteration, with no clock active);
 *   Step Mode --EnterEventMode--> Event Mode (only if eventModeUsed); Event/Step --Terminate-->
 *   Terminated; any --Reset--> Instantiated (start values).
 *
 * Lazy evaluation of an Event Mode instant. fmi3SetClock only records activations. The first
 * fmi3Get* or fmi3GetClock of an instant hands every active, not yet latched input clock to the
 * model (rg_model_latch) and then calls rg_model_evaluate once; later Gets of the same instant
 * read the computed values. fmi3UpdateDiscreteStates evaluates if no Get came, latches input
 * activations that arrived after the evaluation (the model sees them in its next cycle), calls
 * rg_model_update, deactivates every clock (input and output), clears the latch and evaluation
 * flags and advances the super-dense index. Output clocks therefore read active, repeatedly,
 * within their instant and inactive after the UpdateDiscreteStates that closes it.
 * A periodic (constant) input clock ticks at t_k = t_start + shift + k * interval (k an integer,
 * see rg_tick_time); fmi3SetClock accepts only the next tick k, at a time equal to t_k under
 * RG_TIME_RELATIVE_TOLERANCE, and before the instant was evaluated; k then advances, so a tick
 * is activated at most once (and at most once per Event Mode). fmi3DoStep refuses to step past
 * a tick that was not activated, so a lost tick is reported instead of silently skipped - unless
 * the importer has never activated that clock since fmi3ExitInitializationMode: such an importer
 * has no clocks (fmpy's simulate_fmu), and its ticks pass with fmi3Warning and a log message.
 *
 * FMU state. A snapshot is the rg_snapshot_part of the instance: mode, start and stop time, time,
 * super-dense index,
 * clock activation / latch / next-tick arrays, the evaluation and iteration flags, and the whole
 * rg_model_data (plain data by contract). Snapshots belong to the instance that made them (a
 * linked list; fmi3FreeInstance frees those still held). The serialized form is a 32-byte header
 * (magic "RGSTATE1", FNV-1a hash of the instantiation token, payload size, FNV-1a checksum of the
 * payload) followed by the snapshot bytes; foreign, truncated or corrupted data is rejected.
 *
 * Instance handles and double free. An FMU cannot tell a freed pointer from a live one by reading
 * through it: that read is itself the use-after-free. The runtime therefore never dereferences an
 * fmi3Instance it did not find in its registry of live instances (a mutex-protected linked list,
 * per FMU binary). fmi3FreeInstance unlinks the instance and returns all its memory to malloc;
 * a second fmi3FreeInstance, or any call with a freed, foreign or NULL instance, is detected by
 * pointer comparison only, does nothing and returns fmi3Error (FreeInstance returns nothing).
 * Such calls cannot be logged through logMessage (its lifetime ended with the instance, or there
 * never was one), so the runtime writes one line to stderr instead. The only case it cannot
 * detect is a stale handle whose address malloc has since given to a new live instance of the
 * same FMU; no memory-safe scheme can, short of never reusing addresses.
 *
 * Logging. Messages with status fmi3Error/fmi3Fatal go to logMessage whenever the callback is not
 * NULL (FMI 3.0.3 recommends logging errors regardless of the logging settings); all other
 * messages only when logging is on and their category is enabled (fmi3SetDebugLogging with zero
 * categories enables all four). Messages start with the instance name and the function name.
 */

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
#include <windows.h>
#else
#include <pthread.h>
#endif

/* ============================================================================================
 * Allowed states per function
 * ============================================================================================ */

#define RG_ANY_STATE (RG_INSTANTIATED | RG_INITIALIZATION_MODE | RG_EVENT_MODE | RG_STEP_MODE | RG_TERMINATED)

#define RG_ALLOWED_SET_DEBUG_LOGGING RG_ANY_STATE
#define RG_ALLOWED_ENTER_INITIALIZATION_MODE RG_INSTANTIATED
#define RG_ALLOWED_EXIT_INITIALIZATION_MODE RG_INITIALIZATION_MODE
#define RG_ALLOWED_ENTER_EVENT_MODE RG_STEP_MODE
#define RG_ALLOWED_ENTER_STEP_MODE RG_EVENT_MODE
#define RG_ALLOWED_TERMINATE (RG_EVENT_MODE | RG_STEP_MODE)
#define RG_ALLOWED_RESET RG_ANY_STATE
#define RG_ALLOWED_GET (RG_INITIALIZATION_MODE | RG_EVENT_MODE | RG_STEP_MODE | RG_TERMINATED)
#define RG_ALLOWED_SET (RG_INSTANTIATED | RG_INITIALIZATION_MODE | RG_EVENT_MODE | RG_STEP_MODE)
#define RG_ALLOWED_GET_CLOCK (RG_INITIALIZATION_MODE | RG_EVENT_MODE)
#define RG_ALLOWED_SET_CLOCK RG_EVENT_MODE
#define RG_ALLOWED_GET_INTERVAL (RG_INITIALIZATION_MODE | RG_EVENT_MODE)
#define RG_ALLOWED_GET_SHIFT RG_INITIALIZATION_MODE
#define RG_ALLOWED_SET_INTERVAL (RG_INITIALIZATION_MODE | RG_EVENT_MODE)
#define RG_ALLOWED_SET_SHIFT RG_INITIALIZATION_MODE
#define RG_ALLOWED_UPDATE_DISCRETE_STATES RG_EVENT_MODE
#define RG_ALLOWED_DO_STEP RG_STEP_MODE
#define RG_ALLOWED_FMU_STATE RG_ANY_STATE
#define RG_ALLOWED_FREE_INSTANCE RG_ANY_STATE

/* Longest log message; longer ones are truncated, never overflow. */
#define RG_LOG_MESSAGE_SIZE 1024

struct rg_fmu_state {
    rg_fmu_state *next;
    rg_snapshot_part s;
};

static const char *const rg_category_names[RG_LOG_NUM_CATEGORIES] = {
    "logEvents",
    "logTransitions",
    "logStatusWarning",
    "logStatusError",
};

/* ============================================================================================
 * Small helpers: names, sizes, status
 * ============================================================================================ */

static const char *rg_mode_name(rg_mode mode)
{
    switch (mode) {
    case RG_INSTANTIATED: return "Instantiated";
    case RG_INITIALIZATION_MODE: return "Initialization Mode";
    case RG_EVENT_MODE: return "Event Mode";
    case RG_STEP_MODE: return "Step Mode";
    case RG_TERMINATED: return "Terminated";
    }
    return "an unknown state";
}

static const char *rg_type_name(rg_type type)
{
    switch (type) {
    case RG_FLOAT64: return "Float64";
    case RG_INT32: return "Int32";
    case RG_INT64: return "Int64";
    case RG_UINT64: return "UInt64";
    case RG_BOOLEAN: return "Boolean";
    case RG_CLOCK: return "Clock";
    case RG_FLOAT32: return "Float32";
    case RG_INT8: return "Int8";
    case RG_UINT8: return "UInt8";
    case RG_INT16: return "Int16";
    case RG_UINT16: return "UInt16";
    case RG_UINT32: return "UInt32";
    case RG_STRING: return "String";
    }
    return "unknown";
}

/* Bytes per element in rg_model_data and in the fmi3Get/Set value arrays (0: not stored there). */
static size_t rg_type_size(rg_type type)
{
    switch (type) {
    case RG_FLOAT64: return sizeof(fmi3Float64);
    case RG_INT32: return sizeof(fmi3Int32);
    case RG_INT64: return sizeof(fmi3Int64);
    case RG_UINT64: return sizeof(fmi3UInt64);
    case RG_BOOLEAN: return sizeof(fmi3Boolean);
    case RG_CLOCK: return 0;
    case RG_FLOAT32: return sizeof(fmi3Float32);
    case RG_INT8: return sizeof(fmi3Int8);
    case RG_UINT8: return sizeof(fmi3UInt8);
    case RG_INT16: return sizeof(fmi3Int16);
    case RG_UINT16: return sizeof(fmi3UInt16);
    case RG_UINT32: return sizeof(fmi3UInt32);
    case RG_STRING: return sizeof(int64_t); /* its number, not the text */
    }
    return 0;
}

static const char *rg_clock_kind_name(rg_clock_kind kind)
{
    switch (kind) {
    case RG_CLOCK_INPUT_CONSTANT: return "constant input";
    case RG_CLOCK_INPUT_TRIGGERED: return "triggered input";
    case RG_CLOCK_OUTPUT_TRIGGERED: return "triggered output";
    }
    return "unknown";
}

static bool rg_clock_is_input(int clock_index)
{
    return rg_clocks[clock_index].kind != RG_CLOCK_OUTPUT_TRIGGERED;
}

static fmi3Status rg_worse(fmi3Status a, fmi3Status b)
{
    return a > b ? a : b;
}

/* An fmi3Boolean / fmi3Clock coming from the importer, read as a byte: a C bool holding anything
 * but 0 or 1 would be undefined behaviour to load, and ctypes or C callers may pass such bytes. */
static bool rg_read_flag(const void *address)
{
    unsigned char byte;
    memcpy(&byte, address, 1);
    return byte != 0;
}

static char *rg_strdup(const char *text)
{
    size_t length = strlen(text) + 1;
    char *copy = (char *)malloc(length);
    if (copy != NULL) memcpy(copy, text, length);
    return copy;
}

static bool rg_is_blank(const char *text)
{
    for (; *text != '\0'; ++text) {
        if (*text != ' ' && *text != '\t' && *text != '\n' && *text != '\r' && *text != '\v' && *text != '\f') {
            return false;
        }
    }
    return true;
}

/* FNV-1a, 64 bit: token hash and payload checksum of serialized FMU states. */
static uint64_t rg_fnv1a(const void *bytes, size_t size)
{
    const unsigned char *p = (const unsigned char *)bytes;
    uint64_t hash = UINT64_C(14695981039346656037);
    size_t i;
    for (i = 0; i < size; ++i) {
        hash ^= p[i];
        hash *= UINT64_C(1099511628211);
    }
    return hash;
}

/* ============================================================================================
 * Logging
 * ============================================================================================ */

static void rg_vlog_through(fmi3LogMessageCallback callback, fmi3InstanceEnvironment environment,
                            const char *instance_name, rg_log_category category, fmi3Status status,
                            const char *fmt, va_list args)
{
    char message[RG_LOG_MESSAGE_SIZE];
    int prefix = snprintf(message, sizeof message, "%s: ", instance_name);
    if (prefix < 0 || (size_t)prefix >= sizeof message) prefix = 0;
    vsnprintf(message + prefix, sizeof message - (size_t)prefix, fmt, args);
    callback(environment, status, rg_category_names[category], message);
}

static void rg_log(rg_instance *inst, rg_log_category category, fmi3Status status, const char *fmt, ...)
{
    va_list args;
    if (inst == NULL || inst->log_message == NULL) return;
    if ((unsigned)category >= (unsigned)RG_LOG_NUM_CATEGORIES) category = RG_LOG_ERROR;
    if (status < fmi3Error && !(inst->logging_on && inst->log_category_on[category])) return;
    va_start(args, fmt);
    rg_vlog_through(inst->log_message, inst->environment, inst->instance_name, category, status, fmt, args);
    va_end(args);
}

/* Before an instance exists (fmi3Instantiate*): errors only, to the given callback. */
static void rg_log_instantiation_error(fmi3LogMessageCallback callback, fmi3InstanceEnvironment environment,
                                       fmi3String instance_name, const char *fmt, ...) RG_PRINTF_FORMAT(4, 5);

static void rg_log_instantiation_error(fmi3LogMessageCallback callback, fmi3InstanceEnvironment environment,
                                       fmi3String instance_name, const char *fmt, ...)
{
    va_list args;
    if (callback == NULL) return;
    va_start(args, fmt);
    rg_vlog_through(callback, environment, instance_name != NULL ? instance_name : "(unnamed)",
                    RG_LOG_ERROR, fmi3Error, fmt, args);
    va_end(args);
}

/* Log an error, move the instance to Terminated (FMI 3.0: fmi3Error leads to Terminated) and
 * return fmi3Error. Every error the runtime detects goes through here. */
static fmi3Status rg_fail(rg_instance *inst, const char *function, const char *fmt, ...) RG_PRINTF_FORMAT(3, 4);

static fmi3Status rg_fail(rg_instance *inst, const char *function, const char *fmt, ...)
{
    char detail[RG_LOG_MESSAGE_SIZE];
    va_list args;
    va_start(args, fmt);
    vsnprintf(detail, sizeof detail, fmt, args);
    va_end(args);
    if (inst->s.mode != RG_TERMINATED) {
        rg_log(inst, RG_LOG_ERROR, fmi3Error, "%s: %s (the instance is now Terminated; "
               "fmi3SetFMUState or fmi3Reset can recover it)", function, detail);
        inst->s.mode = RG_TERMINATED;
    } else {
        rg_log(inst, RG_LOG_ERROR, fmi3Error, "%s: %s", function, detail);
    }
    return fmi3Error;
}

/* ============================================================================================
 * Registry of live instances (see "Instance handles and double free" in the design note)
 * ============================================================================================ */

static rg_instance *rg_live_instances = NULL;

#if defined(_WIN32)
static SRWLOCK rg_registry_lock = SRWLOCK_INIT;
static void rg_registry_acquire(void) { AcquireSRWLockExclusive(&rg_registry_lock); }
static void rg_registry_release(void) { ReleaseSRWLockExclusive(&rg_registry_lock); }
#else
static pthread_mutex_t rg_registry_lock = PTHREAD_MUTEX_INITIALIZER;
static void rg_registry_acquire(void) { pthread_mutex_lock(&rg_registry_lock); }
static void rg_registry_release(void) { pthread_mutex_unlock(&rg_registry_lock); }
#endif

static void rg_register(rg_instance *inst)
{
    rg_registry_acquire();
    inst->next_live = rg_live_instances;
    rg_live_instances = inst;
    rg_registry_release();
}

/* The live instance whose address equals handle, or NULL. Compares addresses only: a stale
 * handle is never dereferenced. */
static rg_instance *rg_find_live(fmi3Instance handle)
{
    rg_instance *node;
    rg_registry_acquire();
    for (node = rg_live_instances; node != NULL; node = node->next_live) {
        if ((void *)node == handle) break;
    }
    rg_registry_release();
    return node;
}

/* Unlink and return the live instance at handle, or NULL if there is none. */
static rg_instance *rg_unregister(fmi3Instance handle)
{
    rg_instance **link;
    rg_instance *found = NULL;
    rg_registry_acquire();
    for (link = &rg_live_instances; *link != NULL; link = &(*link)->next_live) {
        if ((void *)*link == handle) {
            found = *link;
            *link = found->next_live;
            found->next_live = NULL;
            break;
        }
    }
    rg_registry_release();
    return found;
}

/* A call with a handle that is not a live instance: there is no logMessage to use. */
static void rg_report_bad_handle(const char *function, fmi3Instance handle)
{
    if (handle == NULL) {
        fprintf(stderr, "robogen FMU %s: %s called with a NULL instance; ignored\n", RG_MODEL_IDENTIFIER, function);
    } else {
        fprintf(stderr, "robogen FMU %s: %s called with an instance that is not live "
                "(already freed, or not created by this FMU); ignored\n", RG_MODEL_IDENTIFIER, function);
    }
}

/* Describe the states in an allowed mask, e.g. "Event Mode or Step Mode". */
static void rg_describe_states(unsigned allowed, char *text, size_t size)
{
    static const rg_mode modes[] = {RG_INSTANTIATED, RG_INITIALIZATION_MODE, RG_EVENT_MODE, RG_STEP_MODE, RG_TERMINATED};
    size_t used = 0;
    size_t i;
    text[0] = '\0';
    for (i = 0; i < sizeof modes / sizeof modes[0]; ++i) {
        if (allowed & (unsigned)modes[i]) {
            int n = snprintf(text + used, size - used, "%s%s", used ? ", " : "", rg_mode_name(modes[i]));
            if (n < 0 || (size_t)n >= size - used) return;
            used += (size_t)n;
        }
    }
}

/* Entry check of every function that takes an instance: the handle must be live and the
 * instance in one of the allowed states. Returns the instance, or NULL after reporting. */
static rg_instance *rg_enter(fmi3Instance handle, const char *function, unsigned allowed)
{
    rg_instance *inst = rg_find_live(handle);
    if (inst == NULL) {
        rg_report_bad_handle(function, handle);
        return NULL;
    }
    if (((unsigned)inst->s.mode & allowed) == 0) {
        char states[128];
        rg_describe_states(allowed, states, sizeof states);
        rg_fail(inst, function, "not allowed in %s (allowed in: %s)", rg_mode_name(inst->s.mode), states);
        return NULL;
    }
    return inst;
}

/* ============================================================================================
 * The model's tables
 * ============================================================================================ */

/* Binary search in rg_variables (sorted by vr, checked at instantiation). */
static const rg_variable *rg_find_variable(fmi3ValueReference vr)
{
    size_t low = 0, high = RG_NUM_VARIABLES;
    while (low < high) {
        size_t middle = low + (high - low) / 2;
        if (rg_variables[middle].vr == vr) return &rg_variables[middle];
        if (rg_variables[middle].vr < vr) low = middle + 1;
        else high = middle;
    }
    return NULL;
}

/* Index into rg_clocks of the clock with this value reference, or -1. */
static int rg_find_clock(fmi3ValueReference vr)
{
    int i;
    for (i = 0; i < RG_NUM_CLOCKS; ++i) {
        if (rg_clocks[i].vr == vr) return i;
    }
    return -1;
}

/* Consistency of the generated tables; NULL if fine, else what is wrong (in problem). */
static const char *rg_check_tables(char *problem, size_t size)
{
    size_t i;
    int c;
    if (RG_NUM_VARIABLES < 1) return "RG_NUM_VARIABLES must be at least 1";
    for (i = 0; i < (size_t)RG_NUM_VARIABLES; ++i) {
        const rg_variable *v = &rg_variables[i];
        size_t element_size = rg_type_size(v->type);
        if (v->name == NULL) {
            snprintf(problem, size, "rg_variables[%zu] has no name", i);
            return problem;
        }
        if (i > 0 && v->vr <= rg_variables[i - 1].vr) {
            snprintf(problem, size, "rg_variables is not sorted by strictly increasing value reference at '%s'", v->name);
            return problem;
        }
        if (v->count < 1 || (v->type == RG_CLOCK && v->count != 1)) {
            snprintf(problem, size, "variable '%s' has an invalid element count %zu", v->name, v->count);
            return problem;
        }
        if (v->type != RG_CLOCK && element_size == 0) {
            snprintf(problem, size, "variable '%s' has an unknown type", v->name);
            return problem;
        }
        if (v->clock < -1 || v->clock >= RG_NUM_CLOCKS) {
            snprintf(problem, size, "variable '%s' names clock index %d, outside 0..%d", v->name, v->clock, RG_NUM_CLOCKS - 1);
            return problem;
        }
        if (v->type == RG_CLOCK) {
            if (rg_find_clock(v->vr) < 0) {
                snprintf(problem, size, "clock variable '%s' (vr %u) has no entry in rg_clocks", v->name, (unsigned)v->vr);
                return problem;
            }
            if (v->clock != -1) {
                snprintf(problem, size, "clock '%s' is itself clocked, which robogen does not support", v->name);
                return problem;
            }
        } else if (v->offset > sizeof(rg_model_data) || v->count > (sizeof(rg_model_data) - v->offset) / element_size) {
            snprintf(problem, size, "variable '%s' (offset %zu, %zu elements) lies outside rg_model_data", v->name, v->offset, v->count);
            return problem;
        }
    }
    for (c = 0; c < RG_NUM_CLOCKS; ++c) {
        const rg_clock *k = &rg_clocks[c];
        const rg_variable *v = rg_find_variable(k->vr);
        if (k->name == NULL || v == NULL || v->type != RG_CLOCK) {
            snprintf(problem, size, "rg_clocks[%d] (vr %u) is not a Clock variable of rg_variables", c, (unsigned)k->vr);
            return problem;
        }
        if (k->kind != RG_CLOCK_INPUT_CONSTANT && k->kind != RG_CLOCK_INPUT_TRIGGERED &&
            k->kind != RG_CLOCK_OUTPUT_TRIGGERED) {
            snprintf(problem, size, "clock '%s' has an unknown kind", k->name);
            return problem;
        }
        if (k->kind == RG_CLOCK_INPUT_CONSTANT && !(isfinite(k->interval) && k->interval > 0.0 && isfinite(k->shift) && k->shift >= 0.0)) {
            snprintf(problem, size, "constant clock '%s' needs interval > 0 and shift >= 0", k->name);
            return problem;
        }
        if ((k->kind == RG_CLOCK_OUTPUT_TRIGGERED) != (v->causality == RG_OUTPUT)) {
            snprintf(problem, size, "clock '%s': kind %s does not match its causality", k->name, rg_clock_kind_name(k->kind));
            return problem;
        }
    }
    return NULL;
}

static double rg_tick_time(const rg_instance *inst, int clock_index, uint64_t k)
{
    return inst->s.start_time + rg_clocks[clock_index].shift + (double)k * rg_clocks[clock_index].interval;
}

static void rg_activate_output_clock(rg_instance *inst, int clock_index)
{
    if (clock_index < 0 || clock_index >= RG_NUM_CLOCKS || rg_clock_is_input(clock_index)) {
        rg_log(inst, RG_LOG_WARNING, fmi3Warning, "internal: the model tried to activate clock index %d, "
               "which is not an output clock; ignored", clock_index);
        return;
    }
    if (!inst->s.clock_active[clock_index]) {
        inst->s.clock_active[clock_index] = true;
        rg_log(inst, RG_LOG_EVENTS, fmi3OK, "output clock '%s' activated at t=%.17g (instant %" PRIu64 ")",
               rg_clocks[clock_index].name, inst->s.time, inst->s.superdense);
    }
}

/* ============================================================================================
 * Instant handling: latching, lazy evaluation
 * ============================================================================================ */

/* Hand every active input clock not yet handed over to the model. */
static void rg_latch_pending(rg_instance *inst)
{
    int c;
    for (c = 0; c < RG_NUM_CLOCKS; ++c) {
        if (rg_clock_is_input(c) && inst->s.clock_active[c] && !inst->s.clock_latched[c]) {
            inst->s.clock_latched[c] = true;
            rg_model_latch(inst, c);
        }
    }
}

/* Event Mode: make sure the current instant was evaluated (latch, then evaluate once). */
static fmi3Status rg_prepare_instant(rg_instance *inst, const char *function)
{
    fmi3Status status;
    if (inst->s.evaluated) return fmi3OK;
    rg_latch_pending(inst);
    inst->s.evaluated = true;
    status = rg_model_evaluate(inst);
    if (status > fmi3Warning) {
        if (status == fmi3Fatal) {
            rg_fail(inst, function, "the model failed fatally while evaluating the instant at t=%.17g", inst->s.time);
            return fmi3Fatal;
        }
        return rg_fail(inst, function, "the model failed to evaluate the instant at t=%.17g (instant %" PRIu64 ")",
                       inst->s.time, inst->s.superdense);
    }
    return status;
}

/* Reset everything an FMU state holds to the state right after instantiation. */
static void rg_reset_instance(rg_instance *inst)
{
    memset(&inst->s, 0, sizeof inst->s); /* start time 0, no stop time, no clock active */
    inst->s.mode = RG_INSTANTIATED;
    rg_model_reset(inst);
}

/* ============================================================================================
 * Defaults of the model hooks config.h does not list (see "Capabilities" in robogen_runtime.h);
 * the default of rg_model_do_step is in fmi3DoStep (rg_step_model)
 * ============================================================================================ */

#ifndef RG_HAS_EXIT_INITIALIZATION
static fmi3Status rg_model_exit_initialization(rg_instance *inst)
{
    (void)inst;
    return fmi3OK;
}
#endif

#ifndef RG_HAS_LATCH
static void rg_model_latch(rg_instance *inst, int clock_index)
{
    (void)inst;
    (void)clock_index;
}
#endif

#ifndef RG_HAS_EVALUATE
static fmi3Status rg_model_evaluate(rg_instance *inst)
{
    (void)inst;
    return fmi3OK;
}
#endif

#ifndef RG_HAS_UPDATE
static fmi3Status rg_model_update(rg_instance *inst, bool *discrete_states_need_update,
                                  bool *terminate_simulation, bool *next_event_time_defined,
                                  double *next_event_time)
{
    (void)inst;
    (void)discrete_states_need_update;
    (void)terminate_simulation;
    (void)next_event_time_defined;
    (void)next_event_time;
    return fmi3OK;
}
#endif

/* ============================================================================================
 * The API, by concern
 * ============================================================================================ */

#define ROBOGEN_RUNTIME_PARTS 1
#include "robogen_runtime_modes.c"       /* instantiate, free, mode changes, UpdateDiscreteStates, DoStep */
#include "robogen_runtime_values.c"      /* fmi3Get/Set{Type} */
#include "robogen_runtime_clocks.c"      /* fmi3Get/SetClock, intervals and shifts */
#include "robogen_runtime_fmu_state.c"   /* FMU state get/set/free/serialize */
#include "robogen_runtime_unsupported.c" /* everything this FMU does not offer: log, fmi3Error */
#undef ROBOGEN_RUNTIME_PARTS
