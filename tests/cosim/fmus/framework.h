/* The fmi3* functions of the test-FMU runtime; see framework_types.h. */
#include "framework_types.h"

static void logf_(Instance *c, fmi3Status s, const char *msg) {
    if (c && c->log) c->log(c->env, s, "logStatusError", msg);
}

static fmi3Status fail(Instance *c, const char *fn, const char *why) {
    char buf[256];
    snprintf(buf, sizeof buf, "%s: %s", fn, why);
    logf_(c, fmi3Error, buf);
    return fmi3Error;
}

#define CHECK_STATE(fn, mask) \
    do { if (!(c->state & (mask))) return fail(c, fn, "not allowed in the current state"); } while (0)

static const VarInfo *find(unsigned vr) {
    for (size_t i = 0; i < NVARS; i++)
        if (VARS[i].vr == vr) return &VARS[i];
    return NULL;
}

static void *field(Instance *c, const VarInfo *v) { return (char *)&c->m + v->offset; }

static bool clock_active(Instance *c, int vr) {
    const VarInfo *k = find((unsigned)vr);
    return k && *(bool *)field(c, k);
}

/* May variable v be read (write=false) or written (write=true) now? */
static const char *access_problem(Instance *c, const VarInfo *v, bool write) {
    if (v->clock >= 0) {
        if (c->state == S_INIT) return NULL;
        if (c->state == S_EVENT && clock_active(c, v->clock)) return NULL;
        return "clocked variable accessed while its clock is inactive";
    }
    if (!write) return c->state == S_INSTANTIATED ? "get before initialization" : NULL;
    if (v->causality == C_OUTPUT || v->causality == C_LOCAL) return "variable is not settable";
    if (v->causality == C_PARAM && !(c->state & (S_INSTANTIATED | S_INIT))) return "parameter is not tunable";
    return NULL;
}

/* The bytes of one value of a numeric or Boolean type. */
static size_t value_size(int type) {
    switch (type) {
    case T_F64: case T_I64: case T_U64: return 8;
    case T_F32: case T_I32: case T_U32: return 4;
    case T_I16: case T_U16: return 2;
    case T_I8: case T_U8: return 1;
    default: return sizeof(bool);
    }
}

static const char *checked(Instance *c, const VarInfo *v, int type, bool write) {
    if (!v || v->type != type) return "unknown value reference or wrong type";
    return access_problem(c, v, write);
}

static fmi3Status get_values(Instance *c, const char *fn, int type, const fmi3ValueReference vr[], size_t n, void *out) {
    for (size_t i = 0; i < n; i++) {
        const VarInfo *v = find(vr[i]);
        const char *why = checked(c, v, type, false);
        if (why) return fail(c, fn, why);
        if (type == T_STRING) ((const char **)out)[i] = (const char *)field(c, v);
        else memcpy((char *)out + i * value_size(type), field(c, v), value_size(type));
    }
    return fmi3OK;
}

static fmi3Status set_values(Instance *c, const char *fn, int type, const fmi3ValueReference vr[], size_t n, const void *in) {
    for (size_t i = 0; i < n; i++) {
        const VarInfo *v = find(vr[i]);
        const char *why = checked(c, v, type, true);
        if (why) return fail(c, fn, why);
        if (type == T_STRING) {
            const char *text = ((const char *const *)in)[i];
            snprintf((char *)field(c, v), TEXT_SIZE, "%s", text ? text : "");
        } else {
            const char *value = (const char *)in + i * value_size(type);
            if ((type == T_F64 && !isfinite(*(const double *)value)) || (type == T_F32 && !isfinite(*(const float *)value)))
                return fail(c, fn, "the value is not a finite number");
            memcpy(field(c, v), value, value_size(type));
        }
    }
    model_changed(c);
    return fmi3OK;
}

/* ---- common functions ---------------------------------------------------------------- */

FMI3_Export const char *fmi3GetVersion(void) { return fmi3Version; }

FMI3_Export fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean on, size_t n, const fmi3String cats[]) {
    (void)instance; (void)on; (void)n; (void)cats;
    return fmi3OK;
}

FMI3_Export fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
    const fmi3ValueReference required[], size_t nRequired, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update) {
    (void)resources; (void)visible; (void)loggingOn; (void)required; (void)nRequired; (void)update;
    if (!token || strcmp(token, MODEL_TOKEN) != 0) {
        if (log) log(env, fmi3Error, "logStatusError", "wrong instantiation token");
        return NULL;
    }
    Instance *c = calloc(1, sizeof(Instance));
    if (!c) return NULL;
    snprintf(c->name, sizeof c->name, "%s", name ? name : "");
    c->env = env;
    c->log = log;
    c->state = S_INSTANTIATED;
    c->eventModeUsed = eventModeUsed;
    c->earlyReturnAllowed = earlyReturnAllowed;
    model_defaults(&c->m);
    return c;
}

FMI3_Export fmi3Instance fmi3InstantiateModelExchange(fmi3String a, fmi3String b, fmi3String d, fmi3Boolean e,
    fmi3Boolean f, fmi3InstanceEnvironment g, fmi3LogMessageCallback h) {
    (void)a; (void)b; (void)d; (void)e; (void)f; (void)g; (void)h;
    return NULL;
}

FMI3_Export fmi3Instance fmi3InstantiateScheduledExecution(fmi3String a, fmi3String b, fmi3String d, fmi3Boolean e,
    fmi3Boolean f, fmi3InstanceEnvironment g, fmi3LogMessageCallback h, fmi3ClockUpdateCallback i,
    fmi3LockPreemptionCallback j, fmi3UnlockPreemptionCallback k) {
    (void)a; (void)b; (void)d; (void)e; (void)f; (void)g; (void)h; (void)i; (void)j; (void)k;
    return NULL;
}

FMI3_Export void fmi3FreeInstance(fmi3Instance instance) { free(instance); }

FMI3_Export fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tolDef, fmi3Float64 tol,
    fmi3Float64 start, fmi3Boolean stopDef, fmi3Float64 stop) {
    Instance *c = instance;
    (void)tolDef; (void)tol; (void)stopDef; (void)stop;
    CHECK_STATE("fmi3EnterInitializationMode", S_INSTANTIATED);
    c->time = start;
    c->state = S_INIT;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    Instance *c = instance;
    CHECK_STATE("fmi3ExitInitializationMode", S_INIT);
    model_exit_init(c);
    c->state = c->eventModeUsed ? S_EVENT : S_STEP;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    Instance *c = instance;
    if (!c->eventModeUsed) return fail(c, "fmi3EnterEventMode", "instantiated without eventModeUsed");
    CHECK_STATE("fmi3EnterEventMode", S_STEP | S_EVENT);
    c->state = S_EVENT;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3Terminate(fmi3Instance instance) {
    Instance *c = instance;
    c->state = S_TERMINATED;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3Reset(fmi3Instance instance) {
    Instance *c = instance;
    c->state = S_INSTANTIATED;
    c->time = 0;
    model_defaults(&c->m);
    return fmi3OK;
}

/* ---- getters and setters ------------------------------------------------------------- */

#define GETSET(T, CT, TYPE)                                                                                    \
    FMI3_Export fmi3Status fmi3Get##T(fmi3Instance i, const fmi3ValueReference vr[], size_t n, CT v[], size_t nv) { \
        (void)nv;                                                                                              \
        return get_values(i, "fmi3Get" #T, TYPE, vr, n, v);                                                    \
    }                                                                                                          \
    FMI3_Export fmi3Status fmi3Set##T(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const CT v[], size_t nv) { \
        (void)nv;                                                                                              \
        return set_values(i, "fmi3Set" #T, TYPE, vr, n, v);                                                    \
    }
GETSET(Float32, fmi3Float32, T_F32)
GETSET(Float64, fmi3Float64, T_F64)
GETSET(Int8, fmi3Int8, T_I8)
GETSET(UInt8, fmi3UInt8, T_U8)
GETSET(Int16, fmi3Int16, T_I16)
GETSET(UInt16, fmi3UInt16, T_U16)
GETSET(Int32, fmi3Int32, T_I32)
GETSET(UInt32, fmi3UInt32, T_U32)
GETSET(Int64, fmi3Int64, T_I64)
GETSET(UInt64, fmi3UInt64, T_U64)
GETSET(Boolean, fmi3Boolean, T_BOOL)
GETSET(String, fmi3String, T_STRING)

FMI3_Export fmi3Status fmi3GetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t n, size_t sizes[], fmi3Binary v[], size_t nv) {
    Instance *c = i;
    (void)nv;
    for (size_t k = 0; k < n; k++) {
        const VarInfo *var = find(vr[k]);
        const char *why = checked(c, var, T_BINARY, false);
        if (why) return fail(c, "fmi3GetBinary", why);
        const Bytes *b = field(c, var);
        sizes[k] = b->size;
        v[k] = b->data;
    }
    return fmi3OK;
}
FMI3_Export fmi3Status fmi3SetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const size_t sizes[], const fmi3Binary v[], size_t nv) {
    Instance *c = i;
    (void)nv;
    for (size_t k = 0; k < n; k++) {
        const VarInfo *var = find(vr[k]);
        const char *why = checked(c, var, T_BINARY, true);
        if (why) return fail(c, "fmi3SetBinary", why);
        if (sizes[k] > BYTES_SIZE) return fail(c, "fmi3SetBinary", "value longer than the variable holds");
        Bytes *b = field(c, var);
        b->size = sizes[k];
        if (sizes[k]) memcpy(b->data, v[k], sizes[k]);
    }
    model_changed(c);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Clock v[]) {
    Instance *c = instance;
    CHECK_STATE("fmi3GetClock", S_INIT | S_EVENT);
    for (size_t i = 0; i < n; i++) {
        const VarInfo *k = find(vr[i]);
        if (!k || k->type != T_CLOCK) return fail(c, "fmi3GetClock", "not a clock");
        v[i] = c->state == S_EVENT && *(bool *)field(c, k);
    }
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Clock v[]) {
    Instance *c = instance;
    CHECK_STATE("fmi3SetClock", S_EVENT);
    for (size_t i = 0; i < n; i++) {
        const VarInfo *k = find(vr[i]);
        if (!k || k->type != T_CLOCK || k->causality != C_INPUT) return fail(c, "fmi3SetClock", "not an input clock");
        if (!v[i]) return fail(c, "fmi3SetClock", "clock cannot be deactivated");
        *(bool *)field(c, k) = true;
        model_clock_set(c, vr[i]);
    }
    model_changed(c);
    return fmi3OK;
}

/* ---- FMU state (a copy of the model struct) ------------------------------------------ */

FMI3_Export fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state) {
    Instance *c = instance;
    SavedState *s = *state ? *state : malloc(sizeof(SavedState));
    if (!s) return fail(c, "fmi3GetFMUState", "out of memory");
    s->m = c->m;
    s->time = c->time;
    s->state = c->state;
    *state = s;
    return fmi3OK;
}
FMI3_Export fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
    Instance *c = instance;
    const SavedState *s = state;
    if (!s) return fail(c, "fmi3SetFMUState", "NULL state");
    c->m = s->m;
    c->time = s->time;
    c->state = s->state;
    return fmi3OK;
}
FMI3_Export fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state) {
    (void)instance;
    if (state) { free(*state); *state = NULL; }
    return fmi3OK;
}

/* ---- clocks: intervals and shifts from the table --------------------------------------- */

FMI3_Export fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
    fmi3Float64 intervals[], fmi3IntervalQualifier q[]) {
    Instance *c = instance;
    for (size_t i = 0; i < n; i++) {
        const VarInfo *k = find(vr[i]);
        if (!k || k->type != T_CLOCK || k->interval <= 0) return fail(c, "fmi3GetIntervalDecimal", "not a periodic clock");
        intervals[i] = k->interval;
        q[i] = fmi3IntervalUnchanged;
    }
    return fmi3OK;
}
FMI3_Export fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 shifts[]) {
    Instance *c = instance;
    for (size_t i = 0; i < n; i++) {
        const VarInfo *k = find(vr[i]);
        if (!k || k->type != T_CLOCK || k->interval <= 0) return fail(c, "fmi3GetShiftDecimal", "not a periodic clock");
        shifts[i] = k->shift;
    }
    return fmi3OK;
}

/* ---- Event Mode and Step Mode ---------------------------------------------------------- */

FMI3_Export fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *needUpdate, fmi3Boolean *terminate,
    fmi3Boolean *nominalsChanged, fmi3Boolean *valuesChanged, fmi3Boolean *nextDefined, fmi3Float64 *next) {
    Instance *c = instance;
    CHECK_STATE("fmi3UpdateDiscreteStates", S_EVENT);
    bool nu = false, term = false, nd = false;
    double nt = 0;
    fmi3Status s = model_update(c, &nu, &term, &nd, &nt);
    if (s > fmi3Warning) return s;
    for (size_t i = 0; i < NVARS; i++)
        if (VARS[i].type == T_CLOCK) *(bool *)field(c, &VARS[i]) = false;
    model_new_instant(c);
    *needUpdate = nu;
    *terminate = term;
    *nominalsChanged = false;
    *valuesChanged = false;
    *nextDefined = nd;
    *next = nt;
    return s;
}

FMI3_Export fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    Instance *c = instance;
    CHECK_STATE("fmi3EnterStepMode", S_EVENT);
    c->state = S_STEP;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSetPrior,
    fmi3Boolean *eventNeeded, fmi3Boolean *terminate, fmi3Boolean *earlyReturn, fmi3Float64 *lastTime) {
    Instance *c = instance;
    (void)noSetPrior;
    CHECK_STATE("fmi3DoStep", S_STEP);
    if (h <= 0) return fail(c, "fmi3DoStep", "communicationStepSize must be positive");
    if (fabs(t - c->time) > 1e-9 * (1.0 + fabs(t))) return fail(c, "fmi3DoStep", "currentCommunicationPoint is not the FMU's time");
    bool ev = false, term = false;
    double reached = model_step(c, t, h, &ev, &term);
    if (reached < 0) return fail(c, "fmi3DoStep", "the model failed");
    c->time = reached;
    *eventNeeded = c->eventModeUsed && ev;
    *terminate = term;
    *earlyReturn = c->earlyReturnAllowed && reached < t + h - 1e-12 * (1.0 + fabs(t + h));
    *lastTime = reached;
    return fmi3OK;
}

/* ---- everything else is unsupported: log, return fmi3Error -------------------------------- */

#define UNSUPPORTED(name, args, uses)                              \
    FMI3_Export fmi3Status name args {                             \
        uses;                                                      \
        return fail(instance, #name, "not supported by this FMU"); \
    }

UNSUPPORTED(fmi3GetNumberOfVariableDependencies, (fmi3Instance instance, fmi3ValueReference vr, size_t *n), (void)vr; (void)n)
UNSUPPORTED(fmi3GetVariableDependencies, (fmi3Instance instance, fmi3ValueReference d, size_t a[], fmi3ValueReference b[], size_t e[], fmi3DependencyKind k[], size_t n), (void)d; (void)a; (void)b; (void)e; (void)k; (void)n)
UNSUPPORTED(fmi3SerializedFMUStateSize, (fmi3Instance instance, fmi3FMUState s, size_t *n), (void)s; (void)n)
UNSUPPORTED(fmi3SerializeFMUState, (fmi3Instance instance, fmi3FMUState s, fmi3Byte b[], size_t n), (void)s; (void)b; (void)n)
UNSUPPORTED(fmi3DeserializeFMUState, (fmi3Instance instance, const fmi3Byte b[], size_t n, fmi3FMUState *s), (void)s; (void)b; (void)n)
UNSUPPORTED(fmi3GetDirectionalDerivative, (fmi3Instance instance, const fmi3ValueReference a[], size_t b, const fmi3ValueReference d[], size_t e, const fmi3Float64 f[], size_t g, fmi3Float64 h[], size_t k), (void)a; (void)b; (void)d; (void)e; (void)f; (void)g; (void)h; (void)k)
UNSUPPORTED(fmi3GetAdjointDerivative, (fmi3Instance instance, const fmi3ValueReference a[], size_t b, const fmi3ValueReference d[], size_t e, const fmi3Float64 f[], size_t g, fmi3Float64 h[], size_t k), (void)a; (void)b; (void)d; (void)e; (void)f; (void)g; (void)h; (void)k)
UNSUPPORTED(fmi3EnterConfigurationMode, (fmi3Instance instance), (void)0)
UNSUPPORTED(fmi3ExitConfigurationMode, (fmi3Instance instance), (void)0)
UNSUPPORTED(fmi3GetIntervalFraction, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, fmi3UInt64 b[], fmi3UInt64 d[], fmi3IntervalQualifier q[]), (void)a; (void)n; (void)b; (void)d; (void)q)
UNSUPPORTED(fmi3GetShiftFraction, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, fmi3UInt64 b[], fmi3UInt64 d[]), (void)a; (void)n; (void)b; (void)d)
UNSUPPORTED(fmi3SetIntervalDecimal, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, const fmi3Float64 b[]), (void)a; (void)n; (void)b)
UNSUPPORTED(fmi3SetIntervalFraction, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, const fmi3UInt64 b[], const fmi3UInt64 d[]), (void)a; (void)n; (void)b; (void)d)
UNSUPPORTED(fmi3SetShiftDecimal, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, const fmi3Float64 b[]), (void)a; (void)n; (void)b)
UNSUPPORTED(fmi3SetShiftFraction, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, const fmi3UInt64 b[], const fmi3UInt64 d[]), (void)a; (void)n; (void)b; (void)d)
UNSUPPORTED(fmi3EvaluateDiscreteStates, (fmi3Instance instance), (void)0)
UNSUPPORTED(fmi3EnterContinuousTimeMode, (fmi3Instance instance), (void)0)
UNSUPPORTED(fmi3CompletedIntegratorStep, (fmi3Instance instance, fmi3Boolean a, fmi3Boolean *b, fmi3Boolean *d), (void)a; (void)b; (void)d)
UNSUPPORTED(fmi3SetTime, (fmi3Instance instance, fmi3Float64 t), (void)t)
UNSUPPORTED(fmi3SetContinuousStates, (fmi3Instance instance, const fmi3Float64 x[], size_t n), (void)x; (void)n)
UNSUPPORTED(fmi3GetContinuousStateDerivatives, (fmi3Instance instance, fmi3Float64 x[], size_t n), (void)x; (void)n)
UNSUPPORTED(fmi3GetEventIndicators, (fmi3Instance instance, fmi3Float64 x[], size_t n), (void)x; (void)n)
UNSUPPORTED(fmi3GetContinuousStates, (fmi3Instance instance, fmi3Float64 x[], size_t n), (void)x; (void)n)
UNSUPPORTED(fmi3GetNominalsOfContinuousStates, (fmi3Instance instance, fmi3Float64 x[], size_t n), (void)x; (void)n)
UNSUPPORTED(fmi3GetNumberOfEventIndicators, (fmi3Instance instance, size_t *n), (void)n)
UNSUPPORTED(fmi3GetNumberOfContinuousStates, (fmi3Instance instance, size_t *n), (void)n)
UNSUPPORTED(fmi3GetOutputDerivatives, (fmi3Instance instance, const fmi3ValueReference a[], size_t n, const fmi3Int32 o[], fmi3Float64 v[], size_t nv), (void)a; (void)n; (void)o; (void)v; (void)nv)
UNSUPPORTED(fmi3ActivateModelPartition, (fmi3Instance instance, fmi3ValueReference k, fmi3Float64 t), (void)k; (void)t)
