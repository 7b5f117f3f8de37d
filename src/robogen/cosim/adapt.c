/* Interface adapters: an FMI 3.0 Co-Simulation instance in front of an FMU that offers another
 * interface (adapt.h says which). This file: the adapter, loading the FMU's functions, its life
 * cycle and modes, and Scheduled Execution; adapt_values.c: the values (FMI 2.0's types mapped to
 * FMI 3.0's) and FMU states; adapt_me.c: the integrator of a Model Exchange FMU. Compiled as one
 * unit in that order (robogen.cosim.interfaces builds it with the FMI 2.0 and 3.0 headers of the
 * installed fmpy).
 *
 * The exported functions are the FMI 3.0 Co-Simulation functions the master calls, with the
 * standard's signatures (the compiler checks them against fmi3Functions.h); their fmi3Instance is
 * an adapter. What each does per kind:
 *   FMI 2.0 CS  the fmi2 call of the same meaning; no Event Mode, no clocks; fmi2DoStep's
 *               fmi2Pending waited for (fmi2GetStatus), fmi2Discard with fmi2Terminated a request
 *               to terminate at fmi2LastSuccessfulTime, fmi2Discard without it returned as such
 *   ME          fmi3DoStep integrates (adapt_me.c) and returns early at a state, step or time
 *               event, asking for Event Mode; Event Mode and fmi3UpdateDiscreteStates are the
 *               FMU's own, fmi3EnterStepMode its Continuous-Time Mode
 *   SE          fmi3SetClock of an input clock notes its partition, run by fmi3ActivateModelPartition
 *               before the FMU is next read or updated, all noted partitions in priority order;
 *               fmi3DoStep lets time pass
 */
#define _POSIX_C_SOURCE 199309L
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fmi2FunctionTypes.h"
#include "fmi3Functions.h"
#include "adapt.h"

#define RGA_EXPORT __attribute__((visibility("default")))

RGA_EXPORT void *rga_instantiate(const rga_config *config, const char *name, const char *token, const char *resources,
                                 bool visible, bool logging, void *environment, void *log, char *error, size_t error_size);
RGA_EXPORT void rga_statistics(void *adapter, long *steps, long *rhs, long *roots);

/* The FMU's functions (those its kind has; the others stay NULL). */
typedef struct {
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2TerminateTYPE *terminate;
    fmi2GetRealTYPE *get_real;
    fmi2GetIntegerTYPE *get_integer;
    fmi2GetBooleanTYPE *get_boolean;
    fmi2GetStringTYPE *get_string;
    fmi2SetRealTYPE *set_real;
    fmi2SetIntegerTYPE *set_integer;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2SetStringTYPE *set_string;
    fmi2GetFMUstateTYPE *get_state;
    fmi2SetFMUstateTYPE *set_state;
    fmi2FreeFMUstateTYPE *free_state;
    fmi2DoStepTYPE *do_step;
    fmi2GetStatusTYPE *get_status;
    fmi2GetRealStatusTYPE *get_real_status;
    fmi2GetBooleanStatusTYPE *get_boolean_status;
    fmi2EnterEventModeTYPE *enter_event;
    fmi2NewDiscreteStatesTYPE *new_discrete_states;
    fmi2EnterContinuousTimeModeTYPE *enter_continuous;
    fmi2CompletedIntegratorStepTYPE *completed;
    fmi2SetTimeTYPE *set_time;
    fmi2SetContinuousStatesTYPE *set_x;
    fmi2GetDerivativesTYPE *get_dx;
    fmi2GetEventIndicatorsTYPE *get_z;
    fmi2GetContinuousStatesTYPE *get_x;
    fmi2GetNominalsOfContinuousStatesTYPE *get_nominals;
} rga_fmi2;

/* An FMI 3.0 Get or Set function of any type but Binary and Clock (their arguments differ only in
 * the element type of the values, which the adapter passes on untouched). */
typedef fmi3Status rga_get3(fmi3Instance, const fmi3ValueReference[], size_t, void *, size_t);
typedef fmi3Status rga_set3(fmi3Instance, const fmi3ValueReference[], size_t, const void *, size_t);

enum { T_F32 = 0, T_F64, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_I64, T_U64, T_BOOL, T_STRING, N_TYPES };

typedef struct {
    fmi3InstantiateModelExchangeTYPE *instantiate_me;
    fmi3InstantiateScheduledExecutionTYPE *instantiate_se;
    fmi3FreeInstanceTYPE *free_instance;
    fmi3EnterInitializationModeTYPE *enter_init;
    fmi3ExitInitializationModeTYPE *exit_init;
    fmi3EnterEventModeTYPE *enter_event;
    fmi3TerminateTYPE *terminate;
    rga_get3 *get[N_TYPES];
    rga_set3 *set[N_TYPES];
    fmi3GetBinaryTYPE *get_binary;
    fmi3SetBinaryTYPE *set_binary;
    fmi3GetClockTYPE *get_clock;
    fmi3SetClockTYPE *set_clock;
    fmi3GetIntervalDecimalTYPE *get_interval;
    fmi3GetShiftDecimalTYPE *get_shift;
    fmi3SetIntervalDecimalTYPE *set_interval;
    fmi3SetShiftDecimalTYPE *set_shift;
    fmi3GetFMUStateTYPE *get_state;
    fmi3SetFMUStateTYPE *set_state;
    fmi3FreeFMUStateTYPE *free_state;
    fmi3UpdateDiscreteStatesTYPE *update;
    fmi3EnterContinuousTimeModeTYPE *enter_continuous;
    fmi3CompletedIntegratorStepTYPE *completed;
    fmi3SetTimeTYPE *set_time;
    fmi3SetContinuousStatesTYPE *set_x;
    fmi3GetContinuousStateDerivativesTYPE *get_dx;
    fmi3GetEventIndicatorsTYPE *get_z;
    fmi3GetContinuousStatesTYPE *get_x;
    fmi3GetNominalsOfContinuousStatesTYPE *get_nominals;
    fmi3GetNumberOfContinuousStatesTYPE *number_of_states;
    fmi3GetNumberOfEventIndicatorsTYPE *number_of_indicators;
    fmi3ActivateModelPartitionTYPE *activate;
} rga_fmi3;

typedef struct rga_me rga_me; /* adapt_me.c */

typedef struct {
    rga_config cfg;              /* its arrays copied */
    void *library;               /* dlopen's handle of the FMU's shared object */
    void *inner;                 /* the FMU's fmi2Component or fmi3Instance */
    rga_fmi2 f2;
    rga_fmi3 f3;
    fmi2CallbackFunctions callbacks;
    void *environment;
    fmi3LogMessageCallback log;
    char *name;
    double time;                 /* where the FMU is: the start, then the end of each step */
    bool tolerance_defined, stop_defined;
    double tolerance, stop;
    rga_me *me;                  /* Model Exchange: the integrator */
    bool *pending;               /* Scheduled Execution: per partition, activated and not run yet */
    bool clock_update;           /* the FMU called clockUpdate since it was last read */
    void *scratch;               /* FMI 2.0's values converted (grown as needed) */
    size_t scratch_size;
} rga;

static bool is_fmi2(const rga *a) { return a->cfg.kind == RGA_FMI2_CS || a->cfg.kind == RGA_FMI2_ME; }
static bool is_me(const rga *a) { return a->cfg.kind == RGA_FMI2_ME || a->cfg.kind == RGA_FMI3_ME; }

/* A message to the master's logger (as an FMU would log it). */
static void say(const rga *a, fmi3Status status, const char *format, ...)
{
    char text[512];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    if (a->log != NULL) a->log(a->environment, status, status >= fmi3Error ? "logStatusError" : "logEvents", text);
}

/* FMI 2.0's logger: the message formatted, to the master's FMI 3.0 logger. */
static void log_fmi2(fmi2ComponentEnvironment environment, fmi2String name, fmi2Status status, fmi2String category,
                 fmi2String message, ...)
{
    const rga *a = (const rga *)environment;
    char text[1024];
    va_list args;
    (void)name;
    va_start(args, message);
    vsnprintf(text, sizeof text, message != NULL ? message : "", args);
    va_end(args);
    if (a->log != NULL) a->log(a->environment, status > fmi2Fatal ? fmi3Warning : (fmi3Status)status,
                               category != NULL ? category : "", text);
}

static void step_finished(fmi2ComponentEnvironment environment, fmi2Status status)
{
    (void)environment;
    (void)status; /* the adapter asks fmi2GetStatus whether the step is still pending */
}

/* An FMI 3.0 FMU's messages, to the host's callback with the host's environment: the inner FMU
 * is given the adapter as its instance environment (clockUpdate below needs it). */
static void log_fmi3(fmi3InstanceEnvironment environment, fmi3Status status, fmi3String category, fmi3String message)
{
    const rga *a = (const rga *)environment;
    if (a->log != NULL) a->log(a->environment, status, category, message);
}

/* FMI 3.0's clockUpdate (Scheduled Execution): an output clock ticked, or a countdown clock's
 * interval is known. Its environment is the adapter (never the host's). */
static void clock_update(fmi3InstanceEnvironment environment) { ((rga *)environment)->clock_update = true; }
static void no_lock(void) {}

/* ---------------------------------------------------------------------------------------------
 * Loading */

typedef struct {
    const char *name;
    size_t offset;   /* in rga */
    unsigned kinds;  /* the kinds that need it: bit (1 << kind); 0: optional */
} rga_symbol;

#define F2(field, name, kinds) {name, offsetof(rga, f2) + offsetof(rga_fmi2, field), kinds}
#define F3(field, name, kinds) {name, offsetof(rga, f3) + offsetof(rga_fmi3, field), kinds}
#define CS2 (1u << RGA_FMI2_CS)
#define ME2 (1u << RGA_FMI2_ME)
#define ME3 (1u << RGA_FMI3_ME)
#define SE3 (1u << RGA_FMI3_SE)

static const rga_symbol SYMBOLS[] = {
    F2(instantiate, "fmi2Instantiate", CS2 | ME2), F2(free_instance, "fmi2FreeInstance", CS2 | ME2),
    F2(setup, "fmi2SetupExperiment", CS2 | ME2), F2(enter_init, "fmi2EnterInitializationMode", CS2 | ME2),
    F2(exit_init, "fmi2ExitInitializationMode", CS2 | ME2), F2(terminate, "fmi2Terminate", CS2 | ME2),
    F2(get_real, "fmi2GetReal", CS2 | ME2), F2(get_integer, "fmi2GetInteger", CS2 | ME2),
    F2(get_boolean, "fmi2GetBoolean", CS2 | ME2), F2(get_string, "fmi2GetString", CS2 | ME2),
    F2(set_real, "fmi2SetReal", CS2 | ME2), F2(set_integer, "fmi2SetInteger", CS2 | ME2),
    F2(set_boolean, "fmi2SetBoolean", CS2 | ME2), F2(set_string, "fmi2SetString", CS2 | ME2),
    F2(get_state, "fmi2GetFMUstate", 0), F2(set_state, "fmi2SetFMUstate", 0), F2(free_state, "fmi2FreeFMUstate", 0),
    F2(do_step, "fmi2DoStep", CS2), F2(get_status, "fmi2GetStatus", 0), F2(get_real_status, "fmi2GetRealStatus", 0),
    F2(get_boolean_status, "fmi2GetBooleanStatus", 0),
    F2(enter_event, "fmi2EnterEventMode", ME2), F2(new_discrete_states, "fmi2NewDiscreteStates", ME2),
    F2(enter_continuous, "fmi2EnterContinuousTimeMode", ME2), F2(completed, "fmi2CompletedIntegratorStep", ME2),
    F2(set_time, "fmi2SetTime", ME2), F2(set_x, "fmi2SetContinuousStates", ME2), F2(get_dx, "fmi2GetDerivatives", ME2),
    F2(get_z, "fmi2GetEventIndicators", ME2), F2(get_x, "fmi2GetContinuousStates", ME2),
    F2(get_nominals, "fmi2GetNominalsOfContinuousStates", ME2),
    F3(instantiate_me, "fmi3InstantiateModelExchange", ME3), F3(instantiate_se, "fmi3InstantiateScheduledExecution", SE3),
    F3(free_instance, "fmi3FreeInstance", ME3 | SE3), F3(enter_init, "fmi3EnterInitializationMode", ME3 | SE3),
    F3(exit_init, "fmi3ExitInitializationMode", ME3 | SE3), F3(enter_event, "fmi3EnterEventMode", ME3),
    F3(terminate, "fmi3Terminate", ME3 | SE3),
    F3(get[T_F32], "fmi3GetFloat32", 0), F3(get[T_F64], "fmi3GetFloat64", ME3 | SE3), F3(get[T_I8], "fmi3GetInt8", 0),
    F3(get[T_U8], "fmi3GetUInt8", 0), F3(get[T_I16], "fmi3GetInt16", 0), F3(get[T_U16], "fmi3GetUInt16", 0),
    F3(get[T_I32], "fmi3GetInt32", 0), F3(get[T_U32], "fmi3GetUInt32", 0), F3(get[T_I64], "fmi3GetInt64", 0),
    F3(get[T_U64], "fmi3GetUInt64", 0), F3(get[T_BOOL], "fmi3GetBoolean", 0), F3(get[T_STRING], "fmi3GetString", 0),
    F3(set[T_F32], "fmi3SetFloat32", 0), F3(set[T_F64], "fmi3SetFloat64", ME3 | SE3), F3(set[T_I8], "fmi3SetInt8", 0),
    F3(set[T_U8], "fmi3SetUInt8", 0), F3(set[T_I16], "fmi3SetInt16", 0), F3(set[T_U16], "fmi3SetUInt16", 0),
    F3(set[T_I32], "fmi3SetInt32", 0), F3(set[T_U32], "fmi3SetUInt32", 0), F3(set[T_I64], "fmi3SetInt64", 0),
    F3(set[T_U64], "fmi3SetUInt64", 0), F3(set[T_BOOL], "fmi3SetBoolean", 0), F3(set[T_STRING], "fmi3SetString", 0),
    F3(get_binary, "fmi3GetBinary", 0), F3(set_binary, "fmi3SetBinary", 0),
    F3(get_clock, "fmi3GetClock", 0), F3(set_clock, "fmi3SetClock", 0),
    F3(get_interval, "fmi3GetIntervalDecimal", 0), F3(get_shift, "fmi3GetShiftDecimal", 0),
    F3(set_interval, "fmi3SetIntervalDecimal", 0), F3(set_shift, "fmi3SetShiftDecimal", 0),
    F3(get_state, "fmi3GetFMUState", 0), F3(set_state, "fmi3SetFMUState", 0), F3(free_state, "fmi3FreeFMUState", 0),
    F3(update, "fmi3UpdateDiscreteStates", ME3), F3(enter_continuous, "fmi3EnterContinuousTimeMode", ME3),
    F3(completed, "fmi3CompletedIntegratorStep", ME3), F3(set_time, "fmi3SetTime", ME3),
    F3(set_x, "fmi3SetContinuousStates", ME3), F3(get_dx, "fmi3GetContinuousStateDerivatives", ME3),
    F3(get_z, "fmi3GetEventIndicators", ME3), F3(get_x, "fmi3GetContinuousStates", ME3),
    F3(get_nominals, "fmi3GetNominalsOfContinuousStates", ME3),
    F3(number_of_states, "fmi3GetNumberOfContinuousStates", ME3),
    F3(number_of_indicators, "fmi3GetNumberOfEventIndicators", ME3),
    F3(activate, "fmi3ActivateModelPartition", SE3),
};

/* The FMU's functions from its shared object; false with the reason in error. */
static bool load(rga *a, char *error, size_t error_size)
{
    size_t i;
    a->library = dlopen(a->cfg.binary, RTLD_NOW | RTLD_LOCAL);
    if (a->library == NULL) {
        snprintf(error, error_size, "cannot load the FMU binary %s: %s", a->cfg.binary, dlerror());
        return false;
    }
    for (i = 0; i < sizeof SYMBOLS / sizeof SYMBOLS[0]; i++) {
        void *symbol = dlsym(a->library, SYMBOLS[i].name);
        if (symbol == NULL && (SYMBOLS[i].kinds & (1u << a->cfg.kind))) {
            snprintf(error, error_size, "the FMU binary %s does not export %s", a->cfg.binary, SYMBOLS[i].name);
            return false;
        }
        memcpy((char *)a + SYMBOLS[i].offset, &symbol, sizeof symbol);
    }
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * Life cycle */

static int me_new(rga *a, char *error, size_t error_size);     /* adapt_me.c */
static void me_free(rga *a);
static void me_restart_later(rga *a);
static void me_next_event(rga *a, bool defined, double t);
static fmi3Status me_restart(rga *a);
static fmi3Status me_step(rga *a, double t, double h, bool *event, bool *terminate, bool *early, double *last);
static void me_statistics(const rga *a, long *steps, long *rhs, long *roots);

static char *copy_text(const char *text)
{
    char *copy = (char *)malloc(strlen(text) + 1);
    if (copy != NULL) strcpy(copy, text);
    return copy;
}

static void release(rga *a)
{
    if (a == NULL) return;
    me_free(a);
    if (a->library != NULL) dlclose(a->library);
    free((void *)a->cfg.binary); free((void *)a->cfg.sundials_core); free((void *)a->cfg.sundials_cvode);
    free((void *)a->cfg.partition_vr); free((void *)a->cfg.partition_priority);
    free(a->pending); free(a->name); free(a->scratch); free(a);
}

/* The configuration copied (the caller's arrays need not outlive this call). */
static bool copy_config(rga *a, const rga_config *c)
{
    size_t n = (size_t)(c->n_partitions > 0 ? c->n_partitions : 1);
    uint32_t *vrs = (uint32_t *)calloc(n, sizeof(uint32_t)), *priorities = (uint32_t *)calloc(n, sizeof(uint32_t));
    a->cfg = *c;
    a->cfg.binary = copy_text(c->binary);
    a->cfg.sundials_core = copy_text(c->sundials_core != NULL ? c->sundials_core : "");
    a->cfg.sundials_cvode = copy_text(c->sundials_cvode != NULL ? c->sundials_cvode : "");
    a->cfg.partition_vr = vrs;
    a->cfg.partition_priority = priorities;
    a->pending = (bool *)calloc(n, sizeof(bool));
    if (vrs == NULL || priorities == NULL || a->pending == NULL || a->cfg.binary == NULL) return false;
    if (c->n_partitions > 0) {
        memcpy(vrs, c->partition_vr, (size_t)c->n_partitions * sizeof(uint32_t));
        memcpy(priorities, c->partition_priority, (size_t)c->n_partitions * sizeof(uint32_t));
    }
    return true;
}

/* FMI 2.0's resource location: a file URI of the folder. */
static char *resource_uri(const char *resources)
{
    char *uri;
    if (resources == NULL) return NULL;
    uri = (char *)malloc(strlen(resources) + 8);
    if (uri != NULL) sprintf(uri, "file://%s", resources);
    return uri;
}

static void *instantiate_inner(rga *a, const char *token, const char *resources, bool visible, bool logging)
{
    void *inner = NULL;
    char *uri;
    switch (a->cfg.kind) {
    case RGA_FMI2_CS:
    case RGA_FMI2_ME:
        a->callbacks.logger = log_fmi2;
        a->callbacks.allocateMemory = calloc;
        a->callbacks.freeMemory = free;
        a->callbacks.stepFinished = step_finished;
        a->callbacks.componentEnvironment = a;
        uri = resource_uri(resources);
        inner = a->f2.instantiate(a->name, a->cfg.kind == RGA_FMI2_CS ? fmi2CoSimulation : fmi2ModelExchange, token,
                                  uri, &a->callbacks, visible, logging);
        free(uri);
        return inner;
    case RGA_FMI3_ME:
        return a->f3.instantiate_me(a->name, token, resources, visible, logging, a, log_fmi3);
    default:
        return a->f3.instantiate_se(a->name, token, resources, visible, logging, a, log_fmi3,
                                    clock_update, no_lock, no_lock);
    }
}

RGA_EXPORT void *rga_instantiate(const rga_config *config, const char *name, const char *token, const char *resources,
                                 bool visible, bool logging, void *environment, void *log, char *error, size_t error_size)
{
    rga *a = (rga *)calloc(1, sizeof(rga));
    if (a == NULL || !copy_config(a, config) || (a->name = copy_text(name)) == NULL) {
        snprintf(error, error_size, "no memory left for an adapter");
        release(a);
        return NULL;
    }
    a->environment = environment;
    memcpy(&a->log, &log, sizeof log);
    if (!load(a, error, error_size)) {
        release(a);
        return NULL;
    }
    a->inner = instantiate_inner(a, token, resources, visible, logging);
    if (a->inner == NULL) {
        snprintf(error, error_size, "the FMU's %s returned NULL", a->cfg.kind == RGA_FMI2_CS || a->cfg.kind == RGA_FMI2_ME
                 ? "fmi2Instantiate" : a->cfg.kind == RGA_FMI3_ME ? "fmi3InstantiateModelExchange"
                 : "fmi3InstantiateScheduledExecution");
        release(a);
        return NULL;
    }
    if (is_me(a) && me_new(a, error, error_size) != 0) {
        if (is_fmi2(a)) a->f2.free_instance(a->inner);
        else a->f3.free_instance(a->inner);
        a->inner = NULL;
        release(a);
        return NULL;
    }
    return a;
}

RGA_EXPORT void rga_statistics(void *adapter, long *steps, long *rhs, long *roots)
{
    me_statistics((const rga *)adapter, steps, rhs, roots);
}

FMI3_Export const char *fmi3GetVersion(void) { return fmi3Version; }

FMI3_Export fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean on, size_t n, const fmi3String categories[])
{
    (void)instance; (void)on; (void)n; (void)categories;
    return fmi3OK;
}

FMI3_Export void fmi3FreeInstance(fmi3Instance instance)
{
    rga *a = (rga *)instance;
    if (a == NULL) return;
    if (a->inner != NULL) {
        if (is_fmi2(a)) a->f2.free_instance(a->inner);
        else a->f3.free_instance(a->inner);
    }
    release(a);
}

FMI3_Export fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                                   fmi3Float64 tolerance, fmi3Float64 startTime,
                                                   fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    rga *a = (rga *)instance;
    fmi2Status status;
    a->time = startTime;
    a->tolerance_defined = toleranceDefined;
    a->tolerance = tolerance;
    a->stop_defined = stopTimeDefined;
    a->stop = stopTime;
    if (!is_fmi2(a)) return a->f3.enter_init(a->inner, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime);
    status = a->f2.setup(a->inner, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime);
    if (status > fmi2Warning) return (fmi3Status)status;
    return (fmi3Status)a->f2.enter_init(a->inner);
}

/* After Initialization Mode a Model Exchange FMU is in Event Mode: the master's event iteration at
 * the start, then fmi3EnterStepMode. */
FMI3_Export fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    rga *a = (rga *)instance;
    return is_fmi2(a) ? (fmi3Status)a->f2.exit_init(a->inner) : a->f3.exit_init(a->inner);
}

FMI3_Export fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    rga *a = (rga *)instance;
    switch (a->cfg.kind) {
    case RGA_FMI2_ME: return (fmi3Status)a->f2.enter_event(a->inner);
    case RGA_FMI3_ME: return a->f3.enter_event(a->inner);
    case RGA_FMI3_SE: return fmi3OK;
    default:
        say(a, fmi3Error, "an FMI 2.0 Co-Simulation FMU has no Event Mode");
        return fmi3Error;
    }
}

FMI3_Export fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    rga *a = (rga *)instance;
    fmi3Status status;
    if (!is_me(a)) return a->cfg.kind == RGA_FMI3_SE ? fmi3OK : fmi3Error;
    status = a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.enter_continuous(a->inner) : a->f3.enter_continuous(a->inner);
    if (status > fmi3Warning) return status;
    return me_restart(a);
}

FMI3_Export fmi3Status fmi3Terminate(fmi3Instance instance)
{
    rga *a = (rga *)instance;
    return is_fmi2(a) ? (fmi3Status)a->f2.terminate(a->inner) : a->f3.terminate(a->inner);
}

FMI3_Export fmi3Status fmi3Reset(fmi3Instance instance)
{
    say((rga *)instance, fmi3Error, "fmi3Reset is not offered by an adapter: the master never resets an instance");
    return fmi3Error;
}

/* ---------------------------------------------------------------------------------------------
 * Steps and events */

/* FMI 2.0 Co-Simulation: fmi2DoStep; Pending waited for, Discard as the standard says. */
static fmi3Status cs2_step(rga *a, double t, double h, bool no_set, bool *terminate, bool *early, double *last)
{
    fmi2Status status = a->f2.do_step(a->inner, t, h, no_set), state = fmi2Pending;
    fmi2Boolean terminated = fmi2False;
    fmi2Real reached = t + h;
    struct timespec pause = {0, 1000000};
    while (status == fmi2Pending) { /* an asynchronous step: wait until it is no longer pending */
        if (a->f2.get_status == NULL || a->f2.get_status(a->inner, fmi2DoStepStatus, &state) > fmi2Warning) return fmi3Error;
        if (state != fmi2Pending) status = state;
        else nanosleep(&pause, NULL);
    }
    *last = t + h;
    if (status != fmi2Discard) return status > fmi2Warning ? (fmi3Status)status : fmi3OK;
    if (a->f2.get_boolean_status != NULL) a->f2.get_boolean_status(a->inner, fmi2Terminated, &terminated);
    if (a->f2.get_real_status != NULL) a->f2.get_real_status(a->inner, fmi2LastSuccessfulTime, &reached);
    if (!terminated) {
        say(a, fmi3Error, "fmi2DoStep from t=%.17g discarded the step after t=%.17g (fmi2Discard without fmi2Terminated)", t, reached);
        return fmi3Discard;
    }
    *terminate = true; /* the FMU asks to terminate at lastSuccessfulTime */
    *last = reached;
    *early = reached < t + h;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                                  fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                  fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                                  fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    rga *a = (rga *)instance;
    fmi3Status status = fmi3OK;
    *eventHandlingNeeded = *terminateSimulation = *earlyReturn = false;
    *lastSuccessfulTime = currentCommunicationPoint + communicationStepSize;
    if (a->cfg.kind == RGA_FMI2_CS)
        status = cs2_step(a, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint,
                          terminateSimulation, earlyReturn, lastSuccessfulTime);
    else if (is_me(a))
        status = me_step(a, currentCommunicationPoint, communicationStepSize, eventHandlingNeeded, terminateSimulation,
                         earlyReturn, lastSuccessfulTime);
    if (status <= fmi3Warning) a->time = *lastSuccessfulTime;
    return status;
}

/* Scheduled Execution: the noted partitions run, highest priority (lowest number) first, then by
 * value reference. */
static fmi3Status run_partitions(rga *a)
{
    for (;;) {
        int best = -1, i;
        fmi3Status status;
        for (i = 0; i < a->cfg.n_partitions; i++) {
            if (!a->pending[i]) continue;
            if (best < 0 || a->cfg.partition_priority[i] < a->cfg.partition_priority[best]
                || (a->cfg.partition_priority[i] == a->cfg.partition_priority[best]
                    && a->cfg.partition_vr[i] < a->cfg.partition_vr[best]))
                best = i;
        }
        if (best < 0) return fmi3OK;
        a->pending[best] = false;
        status = a->f3.activate(a->inner, a->cfg.partition_vr[best], a->time);
        if (status > fmi3Warning) return status;
    }
}

/* Before the FMU is read: the partitions activated since run (Scheduled Execution). */
static fmi3Status settle(rga *a) { return a->cfg.kind == RGA_FMI3_SE ? run_partitions(a) : fmi3OK; }

FMI3_Export fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                                fmi3Boolean *terminateSimulation,
                                                fmi3Boolean *nominalsOfContinuousStatesChanged,
                                                fmi3Boolean *valuesOfContinuousStatesChanged,
                                                fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime)
{
    rga *a = (rga *)instance;
    fmi2EventInfo info;
    fmi2Status status;
    *discreteStatesNeedUpdate = *terminateSimulation = *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = *nextEventTimeDefined = false;
    *nextEventTime = 0.0;
    switch (a->cfg.kind) {
    case RGA_FMI3_ME:
        status = (fmi2Status)a->f3.update(a->inner, discreteStatesNeedUpdate, terminateSimulation,
                                          nominalsOfContinuousStatesChanged, valuesOfContinuousStatesChanged,
                                          nextEventTimeDefined, nextEventTime);
        me_next_event(a, *nextEventTimeDefined, *nextEventTime);
        return (fmi3Status)status;
    case RGA_FMI2_ME:
        memset(&info, 0, sizeof info);
        status = a->f2.new_discrete_states(a->inner, &info);
        *discreteStatesNeedUpdate = info.newDiscreteStatesNeeded != fmi2False;
        *terminateSimulation = info.terminateSimulation != fmi2False;
        *nominalsOfContinuousStatesChanged = info.nominalsOfContinuousStatesChanged != fmi2False;
        *valuesOfContinuousStatesChanged = info.valuesOfContinuousStatesChanged != fmi2False;
        *nextEventTimeDefined = info.nextEventTimeDefined != fmi2False;
        *nextEventTime = info.nextEventTime;
        me_next_event(a, *nextEventTimeDefined, *nextEventTime);
        return (fmi3Status)status;
    case RGA_FMI3_SE:
        a->clock_update = false;
        return run_partitions(a);
    default:
        say(a, fmi3Error, "an FMI 2.0 Co-Simulation FMU has no Event Mode");
        return fmi3Error;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Clocks (FMI 3.0 Model Exchange and Scheduled Execution) */

static bool has_clocks(rga *a, const char *function)
{
    if (!is_fmi2(a) && a->f3.get_clock != NULL) return true;
    say(a, fmi3Error, "%s: the FMU has no clocks", function);
    return false;
}

FMI3_Export fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Clock values[])
{
    rga *a = (rga *)instance;
    fmi3Status status;
    if (!has_clocks(a, "fmi3GetClock")) return fmi3Error;
    if ((status = settle(a)) > fmi3Warning) return status;
    return a->f3.get_clock(a->inner, vrs, n, values);
}

/* Scheduled Execution: an input clock's partition noted (run before the FMU is next read or
 * updated); else the FMU's fmi3SetClock. */
FMI3_Export fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const fmi3Clock values[])
{
    rga *a = (rga *)instance;
    size_t i;
    int p;
    if (a->cfg.kind != RGA_FMI3_SE) return has_clocks(a, "fmi3SetClock") ? a->f3.set_clock(a->inner, vrs, n, values) : fmi3Error;
    for (i = 0; i < n; i++) {
        for (p = 0; p < a->cfg.n_partitions && a->cfg.partition_vr[p] != vrs[i]; p++) continue;
        if (p == a->cfg.n_partitions) {
            say(a, fmi3Error, "fmi3SetClock: value reference %u is not an input clock of the FMU", (unsigned)vrs[i]);
            return fmi3Error;
        }
        if (values[i]) a->pending[p] = true;
    }
    return fmi3OK;
}

static bool timed(rga *a, bool exported, const char *name)
{
    if (!is_fmi2(a) && exported) return true;
    say(a, fmi3Error, "%s: the FMU has no clocks", name);
    return false;
}

FMI3_Export fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                              fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    rga *a = (rga *)instance;
    if (!timed(a, a->f3.get_interval != NULL, "fmi3GetIntervalDecimal")) return fmi3Error;
    return a->f3.get_interval(a->inner, vrs, n, intervals, qualifiers);
}

FMI3_Export fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Float64 shifts[])
{
    rga *a = (rga *)instance;
    if (!timed(a, a->f3.get_shift != NULL, "fmi3GetShiftDecimal")) return fmi3Error;
    return a->f3.get_shift(a->inner, vrs, n, shifts);
}

FMI3_Export fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                              const fmi3Float64 intervals[])
{
    rga *a = (rga *)instance;
    if (!timed(a, a->f3.set_interval != NULL, "fmi3SetIntervalDecimal")) return fmi3Error;
    return a->f3.set_interval(a->inner, vrs, n, intervals);
}

FMI3_Export fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n,
                                           const fmi3Float64 shifts[])
{
    rga *a = (rga *)instance;
    if (!timed(a, a->f3.set_shift != NULL, "fmi3SetShiftDecimal")) return fmi3Error;
    return a->f3.set_shift(a->inner, vrs, n, shifts);
}
