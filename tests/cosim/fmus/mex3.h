/* FMI 3.0 for the models of mex_core.h: Model Exchange, Co-Simulation (with Event Mode and early
 * return at events when the importer allows them) and Scheduled Execution, every function of the
 * standard exported (importers such as fmpy look them all up; the ones a test FMU does not need
 * return fmi3Error). Include it after the model. */
#include "fmi3Functions.h"

enum { I_ME, I_CS, I_SE };
enum { M_INSTANTIATED, M_INIT, M_EVENT, M_CONTINUOUS, M_TERMINATED };

typedef struct {
    Model m;
    double time;
    int mode, interface;
    bool event_mode_used, early_return_allowed;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    fmi3ClockUpdateCallback clock_update;
    bool next_defined;
    double next;
    double z[NZ + 1];
} Instance;

#define NVARS (sizeof VARS / sizeof VARS[0])

static fmi3Status fail(Instance *c, const char *what)
{
    if (c != NULL && c->log != NULL) c->log(c->env, fmi3Error, "logStatusError", what);
    return fmi3Error;
}

static Instance *make(fmi3String token, int interface, fmi3InstanceEnvironment env, fmi3LogMessageCallback log)
{
    Instance *c;
    if (token == NULL || strcmp(token, MODEL_TOKEN) != 0) return NULL;
    c = (Instance *)calloc(1, sizeof(Instance));
    if (c == NULL) return NULL;
    model_defaults(&c->m);
    c->interface = interface;
    c->env = env;
    c->log = log;
    return c;
}

FMI3_Export const char *fmi3GetVersion(void) { return fmi3Version; }
FMI3_Export fmi3Status fmi3SetDebugLogging(fmi3Instance i, fmi3Boolean on, size_t n, const fmi3String c[])
{
    (void)i; (void)on; (void)n; (void)c;
    return fmi3OK;
}

FMI3_Export fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
                                                      fmi3Boolean visible, fmi3Boolean logging,
                                                      fmi3InstanceEnvironment env, fmi3LogMessageCallback log)
{
    (void)name; (void)resources; (void)visible; (void)logging;
    return make(token, I_ME, env, log);
}

FMI3_Export fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
                                                     fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean event_mode_used,
                                                     fmi3Boolean early_return_allowed, const fmi3ValueReference required[],
                                                     size_t n_required, fmi3InstanceEnvironment env,
                                                     fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update)
{
    Instance *c = make(token, I_CS, env, log);
    (void)name; (void)resources; (void)visible; (void)logging; (void)required; (void)n_required; (void)update;
    if (c != NULL) {
        c->event_mode_used = event_mode_used;
        c->early_return_allowed = early_return_allowed;
    }
    return c;
}

FMI3_Export fmi3Instance fmi3InstantiateScheduledExecution(fmi3String name, fmi3String token, fmi3String resources,
                                                           fmi3Boolean visible, fmi3Boolean logging,
                                                           fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
                                                           fmi3ClockUpdateCallback clock_update,
                                                           fmi3LockPreemptionCallback lock,
                                                           fmi3UnlockPreemptionCallback unlock)
{
    Instance *c = make(token, I_SE, env, log);
    (void)name; (void)resources; (void)visible; (void)logging; (void)lock; (void)unlock;
    if (c != NULL) c->clock_update = clock_update;
    return c;
}

FMI3_Export void fmi3FreeInstance(fmi3Instance i) { free(i); }

FMI3_Export fmi3Status fmi3EnterInitializationMode(fmi3Instance i, fmi3Boolean td, fmi3Float64 tol, fmi3Float64 start,
                                                   fmi3Boolean sd, fmi3Float64 stop)
{
    Instance *c = (Instance *)i;
    (void)td; (void)tol; (void)sd; (void)stop;
    c->time = start;
    c->mode = M_INIT;
    return fmi3OK;
}

/* Initialization's event: the model's first update (Model Exchange and CS with Event Mode: the
 * importer's event iteration does it). */
FMI3_Export fmi3Status fmi3ExitInitializationMode(fmi3Instance i)
{
    Instance *c = (Instance *)i;
    c->mode = (c->interface == I_ME || (c->interface == I_CS && c->event_mode_used)) ? M_EVENT : M_CONTINUOUS;
    if (c->mode == M_CONTINUOUS && c->interface == I_CS) { /* the start's event, handled at once */
        Events e;
        memset(&e, 0, sizeof e);
        do model_event(&c->m, c->time, &e); while (e.needs_update);
        c->next_defined = e.next_defined;
        c->next = e.next;
    }
    model_indicators(&c->m, c->time, c->z);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3EnterEventMode(fmi3Instance i)
{
    ((Instance *)i)->mode = M_EVENT;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3Terminate(fmi3Instance i)
{
    ((Instance *)i)->mode = M_TERMINATED;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3Reset(fmi3Instance i)
{
    Instance *c = (Instance *)i;
    model_defaults(&c->m);
    c->mode = M_INSTANTIATED;
    return fmi3OK;
}

static fmi3Status access_values(Instance *c, int type, const fmi3ValueReference vrs[], size_t n, void *values, bool set,
                                size_t n_values)
{
    size_t k, j = 0;
    if (!set) model_outputs(&c->m, c->time);
    for (k = 0; k < n; k++) {
        const VarInfo *v = find_var(VARS, NVARS, vrs[k]);
        size_t count = v != NULL && v->count > 0 ? v->count : 1;
        char *field;
        if (v == NULL || v->type != type) return fail(c, "unknown value reference or wrong type");
        if (j + count > n_values) {
            char why[96];
            snprintf(why, sizeof why, "Expected nValues >= %lu but was %lu", (unsigned long)(j + count), (unsigned long)n_values);
            return fail(c, why);
        }
        field = (char *)&c->m + v->offset;
        if (set) memcpy(field, (char *)values + j * type_size(type), count * type_size(type));
        else memcpy((char *)values + j * type_size(type), field, count * type_size(type));
        j += count;
    }
    if (set && c->mode == M_CONTINUOUS) model_indicators(&c->m, c->time, c->z);
    return fmi3OK;
}

#define ACCESS(T, CTYPE, type)                                                                                       \
    FMI3_Export fmi3Status fmi3Get##T(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, CTYPE values[], size_t m) \
    {                                                                                                                \
        (void)m;                                                                                                     \
        return access_values((Instance *)i, type, vrs, n, (void *)values, false, m);                                           \
    }                                                                                                                \
    FMI3_Export fmi3Status fmi3Set##T(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, const CTYPE values[], \
                                      size_t m)                                                                      \
    {                                                                                                                \
        (void)m;                                                                                                     \
        return access_values((Instance *)i, type, vrs, n, (void *)values, true, m);                                            \
    }
#define NONE(T, CTYPE)                                                                                               \
    FMI3_Export fmi3Status fmi3Get##T(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, CTYPE values[], size_t m) \
    {                                                                                                                \
        (void)vrs; (void)n; (void)values; (void)m;                                                                   \
        return fail((Instance *)i, "fmi3Get" #T ": no variable of this type");                                       \
    }                                                                                                                \
    FMI3_Export fmi3Status fmi3Set##T(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, const CTYPE values[], \
                                      size_t m)                                                                      \
    {                                                                                                                \
        (void)vrs; (void)n; (void)values; (void)m;                                                                   \
        return fail((Instance *)i, "fmi3Set" #T ": no variable of this type");                                       \
    }

ACCESS(Float64, fmi3Float64, T_F64)
ACCESS(Int32, fmi3Int32, T_I32)
ACCESS(Int64, fmi3Int64, T_I64)
ACCESS(Boolean, fmi3Boolean, T_BOOL)
NONE(Float32, fmi3Float32)
NONE(Int8, fmi3Int8)
NONE(UInt8, fmi3UInt8)
NONE(Int16, fmi3Int16)
NONE(UInt16, fmi3UInt16)
NONE(UInt32, fmi3UInt32)
NONE(UInt64, fmi3UInt64)
NONE(String, fmi3String)

FMI3_Export fmi3Status fmi3GetBinary(fmi3Instance i, const fmi3ValueReference v[], size_t n, size_t s[], fmi3Binary b[], size_t m)
{
    (void)v; (void)n; (void)s; (void)b; (void)m;
    return fail((Instance *)i, "no Binary variable");
}
FMI3_Export fmi3Status fmi3SetBinary(fmi3Instance i, const fmi3ValueReference v[], size_t n, const size_t s[],
                                     const fmi3Binary b[], size_t m)
{
    (void)v; (void)n; (void)s; (void)b; (void)m;
    return fail((Instance *)i, "no Binary variable");
}

/* Clocks: a Clock variable's bool (input clocks set by the importer, output clocks by the model;
 * reset by fmi3UpdateDiscreteStates, Scheduled Execution: when read). */
FMI3_Export fmi3Status fmi3GetClock(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, fmi3Clock values[])
{
    Instance *c = (Instance *)i;
    fmi3Status status = access_values(c, T_CLOCK, vrs, n, values, false, n);
    size_t k;
    for (k = 0; status == fmi3OK && c->interface == I_SE && k < n; k++)
        *(bool *)((char *)&c->m + find_var(VARS, NVARS, vrs[k])->offset) = false;
    return status;
}
FMI3_Export fmi3Status fmi3SetClock(fmi3Instance i, const fmi3ValueReference vrs[], size_t n, const fmi3Clock values[])
{
    return access_values((Instance *)i, T_CLOCK, vrs, n, (void *)values, true, n);
}

#include "mex3_rest.h"
