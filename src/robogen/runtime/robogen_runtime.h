/* robogen FMI 3.0 Co-Simulation runtime: the contract between the hand-written runtime
 * (robogen_runtime.c and the robogen_runtime_*.c parts it includes: every fmi3* entry point) and
 * one model (generated config.h + model.c).
 *
 * An FMU's sources are compiled as one unity translation unit <modelIdentifier>.c:
 *
 *     #include "config.h"            generated: sizes, tokens, capabilities, rg_model_data
 *     #include "robogen_runtime.h"   this file: types and the hooks a model implements
 *     #include "model.c"             generated: variable/clock tables and the hooks (it includes
 *                                    robogen_machine.h, the state-machine support)
 *     #include "robogen_runtime.c"   hand-written: the 75 exported fmi3* functions
 *
 * Everything except the fmi3* API is static, so several FMUs can be linked into one program.
 * Names starting with fmi3 are reserved for the API; the runtime's own names start with rg_.
 * The unit needs only the include path of its own folder (or of this folder) and fmpy's folder
 * with fmi3Functions.h; it links against libc (and libm if the model uses it), nothing else.
 *
 * config.h must define (and include <stdbool.h>/<stdint.h> itself if rg_model_data needs them):
 *   RG_MODEL_IDENTIFIER      string literal, the modelIdentifier
 *   RG_INSTANTIATION_TOKEN   string literal, equal to the modelDescription's token
 *   RG_NUM_VARIABLES         entries in rg_variables (clocks included, "time" excluded), >= 1
 *   RG_NUM_CLOCKS            entries in rg_clocks (0 allowed)
 *   RG_MIGHT_RETURN_EARLY    0 or 1, as mightReturnEarlyFromDoStep in the XML
 *   typedef struct {...} rg_model_data;   all model memory: plain data, no pointers, so that
 *                                         an FMU state is a byte copy of it
 *
 * Capabilities, as the Reference FMUs' config.h has them: config.h defines (with no value) the
 * macro of each optional hook model.c implements; for every hook it does not list, the runtime
 * supplies the default (robogen_runtime.c), so a model has no stub functions:
 *   RG_HAS_EXIT_INITIALIZATION  rg_model_exit_initialization  default: accepts any start values
 *   RG_HAS_LATCH                rg_model_latch                default: input clocks carry nothing
 *   RG_HAS_EVALUATE             rg_model_evaluate             default: an instant computes nothing
 *   RG_HAS_UPDATE               rg_model_update               default: no further instant needed
 *   RG_HAS_DO_STEP              rg_model_do_step              default: a step lets time pass (and
 *                                                             the runtime keeps no copy to undo it)
 * RG_MIGHT_RETURN_EARLY 1 needs RG_HAS_DO_STEP. rg_model_reset is always the model's.
 *
 * The runtime checks the tables once per fmi3InstantiateCoSimulation (sorted unique value
 * references, offsets inside rg_model_data, clock indices and kinds) and refuses to instantiate,
 * with a log message, if the generator produced inconsistent tables.
 */
#ifndef ROBOGEN_RUNTIME_H
#define ROBOGEN_RUNTIME_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fmi3Functions.h"

#if defined(__GNUC__)
#define RG_MAYBE_UNUSED __attribute__((unused))
#define RG_PRINTF_FORMAT(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define RG_MAYBE_UNUSED
#define RG_PRINTF_FORMAT(fmt_index, first_arg)
#endif

/* ---- time ------------------------------------------------------------------------------- */

/* The one rule by which the runtime (and robogen's master, robogen.fmu.fmi.tolerance) decides that
 * two time instants are the same: |a - b| within RG_TIME_RELATIVE_TOLERANCE of the larger (1e-9 s
 * absolute below 1 s), but never a quarter of the FMU's time resolution or more (the greatest
 * common divisor of its constant clocks' intervals and shifts, read as the decimals they were
 * written as: rg_time_resolution), so that on a long horizon two ticks are never taken for one,
 * and never less than RG_TIME_ULPS units in the last place. A periodic tick
 * t_k = t_start + shift + k * interval is "due" at time t when rg_time_equal(t, t_k); tick indices
 * are integers. The master uses the same values and the same formula. */
#define RG_TIME_RELATIVE_TOLERANCE 1e-9
#define RG_TIME_ULPS 4

static inline double rg_abs(double x) { return x < 0.0 ? -x : x; }

static double rg_time_resolution(void); /* robogen_runtime_clocks.c; 0: no constant clock */

static inline bool rg_time_equal(double a, double b)
{
    double scale = 1.0, close, least, resolution = rg_time_resolution();
    if (rg_abs(a) > scale) scale = rg_abs(a);
    if (rg_abs(b) > scale) scale = rg_abs(b);
    close = RG_TIME_RELATIVE_TOLERANCE * scale;
    if (resolution > 0.0 && close > resolution / 4) close = resolution / 4;
    least = RG_TIME_ULPS * (nextafter(scale, HUGE_VAL) - scale);
    return rg_abs(a - b) <= (close > least ? close : least);
}

/* ---- variables -------------------------------------------------------------------------- */

/* The storage type of a variable; it selects the fmi3Get/Set function that may access it.
 * Enumerations are RG_INT64 (FMI 3.0 accesses them with fmi3Get/SetInt64). A String is stored as
 * an int64_t, its number among the model's strings (robogen_runtime_values.c; rg_model_data holds
 * no pointers). There are no Binary variables: fmi3Get/SetBinary reject every value reference.
 * Values are explicit and never reordered. */
typedef enum {
    RG_FLOAT64 = 0,
    RG_INT32 = 1,
    RG_INT64 = 2,
    RG_UINT64 = 3,
    RG_BOOLEAN = 4, /* stored as C bool */
    RG_CLOCK = 5,   /* stored in rg_snapshot_part.clock_active, not in rg_model_data */
    RG_FLOAT32 = 6,
    RG_INT8 = 7,
    RG_UINT8 = 8,
    RG_INT16 = 9,
    RG_UINT16 = 10,
    RG_UINT32 = 11,
    RG_STRING = 12   /* stored as int64_t: the number of the string (see above) */
} rg_type;

typedef enum {
    RG_PARAMETER = 0, /* fixed or tunable parameter */
    RG_CALCULATED_PARAMETER = 1,
    RG_INPUT = 2,
    RG_OUTPUT = 3,
    RG_LOCAL = 4
} rg_causality;

typedef enum {
    RG_CONSTANT = 0,
    RG_FIXED = 1,
    RG_TUNABLE = 2,
    RG_DISCRETE = 3,
    RG_CONTINUOUS = 4
} rg_variability;

typedef struct {
    fmi3ValueReference vr;    /* rg_variables is sorted by vr, strictly increasing */
    const char *name;         /* as in modelDescription.xml, for log messages */
    rg_type type;
    rg_causality causality;
    rg_variability variability;
    int clock;                /* index into rg_clocks of the variable's clock, or -1 (also for clocks) */
    size_t offset;            /* offsetof(rg_model_data, field); unused for RG_CLOCK */
    size_t count;             /* number of scalar elements: 1, or the array size (>= 1) */
    bool settable_in_init;    /* initial="exact" (parameters, or states with a start value) or an
                                 input: may be set in Instantiated and Initialization Mode.
                                 robogen emits no initial="approx" variables. */
} rg_variable;

/* ---- clocks ----------------------------------------------------------------------------- */

typedef enum {
    RG_CLOCK_INPUT_CONSTANT = 0,  /* time-based periodic input clock, intervalVariability="constant" */
    RG_CLOCK_INPUT_TRIGGERED = 1, /* triggered input clock, activated by the importer */
    RG_CLOCK_OUTPUT_TRIGGERED = 2 /* triggered output clock, activated by the model */
} rg_clock_kind;

typedef struct {
    fmi3ValueReference vr;  /* must also appear in rg_variables with type RG_CLOCK */
    const char *name;
    rg_clock_kind kind;
    double interval;  /* constant clocks: intervalDecimal (s), > 0; otherwise 0 */
    double shift;     /* constant clocks: shiftDecimal (s), >= 0; otherwise 0 */
} rg_clock;

/* ---- the instance ----------------------------------------------------------------------- */

/* The Co-Simulation states the runtime distinguishes (bit flags, so that every fmi3* function
 * can state the set of states it is allowed in as one mask). */
typedef enum {
    RG_INSTANTIATED = 1 << 0,
    RG_INITIALIZATION_MODE = 1 << 1,
    RG_EVENT_MODE = 1 << 2,
    RG_STEP_MODE = 1 << 3,
    RG_TERMINATED = 1 << 4
} rg_mode;

/* Log categories, in this order in <LogCategories> (the model description template emits them). */
typedef enum {
    RG_LOG_EVENTS = 0,       /* "logEvents": clock activations, event iterations, mode changes */
    RG_LOG_TRANSITIONS = 1,  /* "logTransitions": transitions taken by the state machine */
    RG_LOG_WARNING = 2,      /* "logStatusWarning" */
    RG_LOG_ERROR = 3,        /* "logStatusError": every fmi3Error/fmi3Discard explains itself here */
    RG_LOG_NUM_CATEGORIES = 4
} rg_log_category;

typedef struct rg_instance rg_instance;

#define RG_CLOCK_ARRAY_SIZE (RG_NUM_CLOCKS > 0 ? RG_NUM_CLOCKS : 1)

/* Mutable runtime state that belongs in an FMU state snapshot next to rg_model_data.
 * The model may read mode, time, superdense and clock_active (e.g. "did cycle tick in this
 * instant"); it writes only data, and activates output clocks through rg_activate_output_clock. */
typedef struct {
    rg_mode mode;
    double start_time;            /* fmi3EnterInitializationMode: origin of the periodic tick grid */
    bool stop_time_defined;
    double stop_time;
    double time;                  /* current communication point / event time */
    uint64_t superdense;          /* k of (time, k); reset to 0 by DoStep, +1 per UpdateDiscreteStates */
    bool clock_active[RG_CLOCK_ARRAY_SIZE];
    bool clock_latched[RG_CLOCK_ARRAY_SIZE];      /* input activation handed to the model */
    uint64_t clock_next_tick[RG_CLOCK_ARRAY_SIZE]; /* constant clocks: k of the next tick not yet
                                                     activated; at most one activation per tick,
                                                     hence at most one per Event Mode */
    bool clock_ever_activated[RG_CLOCK_ARRAY_SIZE]; /* constant clocks: the importer has activated
                                                      it since fmi3ExitInitializationMode (an
                                                      importer that never does has no clocks:
                                                      fmi3DoStep lets its ticks pass, warning) */
    bool evaluated;               /* rg_model_evaluate ran in the current instant */
    bool update_pending;          /* Event Mode: no fmi3UpdateDiscreteStates yet, or the last one
                                     asked for another iteration; fmi3EnterStepMode refuses */
    bool event_pending;           /* DoStep reported eventHandlingNeeded: the next call that
                                     moves on must be fmi3EnterEventMode */
    bool inputs_set_in_step_mode; /* Get-after-Set rule: a Set in Step Mode since the last DoStep */
    rg_model_data data;
} rg_snapshot_part;

typedef struct rg_fmu_state rg_fmu_state; /* defined in robogen_runtime.c */

struct rg_instance {
    /* set at instantiation, never part of an FMU state */
    rg_instance *next_live;              /* the runtime's registry of live instances */
    char *instance_name;
    char *resource_path;                 /* may be NULL */
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;  /* may be NULL */
    bool logging_on;
    bool log_category_on[RG_LOG_NUM_CATEGORIES];
    bool event_mode_used;
    bool early_return_allowed;           /* earlyReturnAllowed && RG_MIGHT_RETURN_EARLY */
    rg_fmu_state *states;                /* FMU states owned by this instance (freed with it) */
    /* the part an FMU state copies */
    rg_snapshot_part s;
};

/* ---- provided by the runtime to the model ----------------------------------------------- */

/* printf-style logging through logMessage; NULL-safe and filtered by category. Messages with
 * status fmi3Error or fmi3Fatal are passed on whenever a logMessage callback exists (FMI 3.0.3
 * clarification); all others only while logging is on for their category. */
static void rg_log(rg_instance *inst, rg_log_category category, fmi3Status status, const char *fmt, ...)
    RG_PRINTF_FORMAT(4, 5);

/* Activate an output clock (model side, during rg_model_evaluate or rg_model_do_step). A clock
 * activated in rg_model_do_step stays active into the next Event Mode, so the model must also
 * report eventHandlingNeeded. Invalid indices and non-output clocks are logged and ignored. */
static void rg_activate_output_clock(rg_instance *inst, int clock_index) RG_MAYBE_UNUSED;

/* The time of tick k of constant clock clock_index: t_start + shift + k * interval. */
static double rg_tick_time(const rg_instance *inst, int clock_index, uint64_t k) RG_MAYBE_UNUSED;

/* ---- implemented by the model (model.c) ------------------------------------------------- */

/* With no clocks, model.c still defines rg_clocks[1] = {{0}} (C99 has no empty initializer). */
static const rg_variable rg_variables[RG_NUM_VARIABLES > 0 ? RG_NUM_VARIABLES : 1];
static const rg_clock rg_clocks[RG_CLOCK_ARRAY_SIZE];

/* Start values of every variable and the machine's initial memory (fmi3Instantiate, fmi3Reset).
 * The runtime has zeroed inst->s (data included) before the call. */
static void rg_model_reset(rg_instance *inst);

/* fmi3ExitInitializationMode: check parameters, prepare the machine. fmi3Error stops it. */
static fmi3Status rg_model_exit_initialization(rg_instance *inst);

/* An input clock became active in this instant: copy its clocked inputs (payload) into the
 * model's input register. Called once per activation, before the instant's first evaluation,
 * or at fmi3UpdateDiscreteStates for an activation that arrived after it. */
static void rg_model_latch(rg_instance *inst, int clock_index);

/* Compute the current instant: runs at the first fmi3Get* or fmi3GetClock of an Event Mode
 * instant, or in fmi3UpdateDiscreteStates if no Get came. Activates output clocks, writes
 * clocked outputs and outputs. Returns fmi3Error (after logging) on a runaway or deadlocked cycle. */
static fmi3Status rg_model_evaluate(rg_instance *inst);

/* Close the instant (fmi3UpdateDiscreteStates), after evaluation; the runtime deactivates every
 * clock after this returns. Reports whether another instant is needed at this time. The runtime
 * presets every output to false (next_event_time to 0) before the call. */
static fmi3Status rg_model_update(rg_instance *inst, bool *discrete_states_need_update,
                                  bool *terminate_simulation, bool *next_event_time_defined,
                                  double *next_event_time);

#ifdef RG_HAS_DO_STEP
/* fmi3DoStep from inst->s.time to t_end (> inst->s.time): models with internal events may stop
 * early (only if inst->early_return_allowed). The runtime presets *last_successful_time = t_end
 * and the flags to false. A result of fmi3Discard makes the runtime restore the state it had
 * before the call. Generated state machines have none: they react only in Event Mode. */
static fmi3Status rg_model_do_step(rg_instance *inst, double t_end, bool *event_handling_needed,
                                   bool *terminate_simulation, double *last_successful_time);
#elif RG_MIGHT_RETURN_EARLY
#error "RG_MIGHT_RETURN_EARLY needs a model that implements rg_model_do_step (RG_HAS_DO_STEP)"
#endif

#endif /* ROBOGEN_RUNTIME_H */
