/* FMI 2.0 for the models of mex_core.h: Model Exchange and Co-Simulation in one binary, every
 * function of the standard exported. Co-Simulation: RK4 at CS_STEP, events handled inside the
 * step; a request to terminate ends the step early with fmi2Discard (fmi2Terminated true,
 * fmi2LastSuccessfulTime the event's time), as the standard has a slave say so. */
#include "fmi2Functions.h"

enum { M_INSTANTIATED, M_INIT, M_EVENT, M_CONTINUOUS, M_TERMINATED };

typedef struct {
    Model m;
    double time, next, last_successful;
    int mode;
    bool cs, next_defined, terminated;
    int polls_left;          /* an asynchronous step: fmi2GetStatus says fmi2Pending this often more */
    fmi2Status step_status;  /* then this */
    const fmi2CallbackFunctions *callbacks;
    double z[NZ + 1];
} Instance;

#define NVARS (sizeof VARS / sizeof VARS[0])
#define UNUSED(x) (void)(x)

static fmi2Status fail(Instance *c, const char *what)
{
    if (c != NULL && c->callbacks != NULL && c->callbacks->logger != NULL)
        c->callbacks->logger(c->callbacks->componentEnvironment, "test", fmi2Error, "logStatusError", "%s", what);
    return fmi2Error;
}

FMI2_Export const char *fmi2GetTypesPlatform(void)
{
    (void)model_partition; /* FMI 2.0 has no Scheduled Execution */
    return fmi2TypesPlatform;
}
FMI2_Export const char *fmi2GetVersion(void) { return fmi2Version; }
FMI2_Export fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String k[])
{
    UNUSED(c); UNUSED(on); UNUSED(n); UNUSED(k);
    return fmi2OK;
}

FMI2_Export fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                                          const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean logging)
{
    Instance *c;
    UNUSED(name); UNUSED(resources); UNUSED(visible); UNUSED(logging);
    if (guid == NULL || strcmp(guid, MODEL_TOKEN) != 0) return NULL;
    c = (Instance *)calloc(1, sizeof(Instance));
    if (c == NULL) return NULL;
    model_defaults(&c->m);
    c->cs = type == fmi2CoSimulation;
    c->callbacks = callbacks;
    return c;
}

FMI2_Export void fmi2FreeInstance(fmi2Component c) { free(c); }

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean td, fmi2Real tol, fmi2Real start, fmi2Boolean sd,
                                           fmi2Real stop)
{
    UNUSED(td); UNUSED(tol); UNUSED(sd); UNUSED(stop);
    ((Instance *)c)->time = start;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    ((Instance *)c)->mode = M_INIT;
    return fmi2OK;
}

static void handle_events(Instance *c)
{
    Events e;
    memset(&e, 0, sizeof e);
    do model_event(&c->m, c->time, &e); while (e.needs_update);
    c->next_defined = e.next_defined;
    c->next = e.next;
    c->terminated = e.terminate;
    model_indicators(&c->m, c->time, c->z);
}

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Instance *x = (Instance *)c;
    x->mode = x->cs ? M_CONTINUOUS : M_EVENT;
    if (x->cs) handle_events(x);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c)
{
    ((Instance *)c)->mode = M_TERMINATED;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2Reset(fmi2Component c)
{
    model_defaults(&((Instance *)c)->m);
    return fmi2OK;
}

static fmi2Status access_values(Instance *c, int type, const fmi2ValueReference vrs[], size_t n, void *values, bool set)
{
    size_t k;
    for (k = 0; k < n; k++) {
        const VarInfo *v = find_var(VARS, NVARS, vrs[k]);
        char *field;
        if (v == NULL || (v->type != type && !(type == T_I32 && v->type == T_I64)))
            return fail(c, "unknown value reference or wrong type");
        field = (char *)&c->m + v->offset;
        if (v->type == T_I64 && type == T_I32 && set) *(int64_t *)field = ((const fmi2Integer *)values)[k];
        else if (v->type == T_I64 && type == T_I32) ((fmi2Integer *)values)[k] = (fmi2Integer)*(int64_t *)field;
        else if (type == T_BOOL && set) *(bool *)field = ((const fmi2Boolean *)values)[k] != fmi2False;
        else if (type == T_BOOL) ((fmi2Boolean *)values)[k] = *(bool *)field ? fmi2True : fmi2False;
        else if (set) memcpy(field, (char *)values + k * type_size(type), type_size(type));
        else memcpy((char *)values + k * type_size(type), field, type_size(type));
    }
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2Real x[])
{
    return access_values((Instance *)c, T_F64, v, n, x, false);
}
FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2Integer x[])
{
    return access_values((Instance *)c, T_I32, v, n, x, false);
}
FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2Boolean x[])
{
    return access_values((Instance *)c, T_BOOL, v, n, x, false);
}
FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2String x[])
{
    UNUSED(v); UNUSED(n); UNUSED(x);
    return fail((Instance *)c, "no String variable");
}
FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2Real x[])
{
    return access_values((Instance *)c, T_F64, v, n, (void *)x, true);
}
FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2Integer x[])
{
    return access_values((Instance *)c, T_I32, v, n, (void *)x, true);
}
FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2Boolean x[])
{
    return access_values((Instance *)c, T_BOOL, v, n, (void *)x, true);
}
FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2String x[])
{
    UNUSED(v); UNUSED(n); UNUSED(x);
    return fail((Instance *)c, "no String variable");
}

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    Instance *copy = (Instance *)malloc(sizeof(Instance));
    if (copy == NULL) return fail((Instance *)c, "no memory");
    memcpy(copy, c, sizeof(Instance));
    if (*s != NULL) free(*s);
    *s = copy;
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    memcpy(c, s, sizeof(Instance));
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    UNUSED(c);
    free(*s);
    *s = NULL;
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n)
{
    UNUSED(s); UNUSED(n);
    return fail((Instance *)c, "not provided");
}
FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n)
{
    UNUSED(s); UNUSED(b); UNUSED(n);
    return fail((Instance *)c, "not provided");
}
FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s)
{
    UNUSED(s); UNUSED(b); UNUSED(n);
    return fail((Instance *)c, "not provided");
}
FMI2_Export fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                                    const fmi2ValueReference k[], size_t nk, const fmi2Real dk[],
                                                    fmi2Real du[])
{
    UNUSED(u); UNUSED(nu); UNUSED(k); UNUSED(nk); UNUSED(dk); UNUSED(du);
    return fail((Instance *)c, "not provided");
}

#include "mex2_rest.h"
