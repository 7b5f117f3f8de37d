/* mex3.h continued: events, Model Exchange, Co-Simulation, Scheduled Execution, the rest. */

static bool crossed(const double *before, const double *after)
{
    int k;
    for (k = 0; k < NZ; k++)
        if ((before[k] < 0 && after[k] >= 0) || (before[k] > 0 && after[k] <= 0)) return true;
    return false;
}

FMI3_Export fmi3Status fmi3UpdateDiscreteStates(fmi3Instance i, fmi3Boolean *needs, fmi3Boolean *terminate,
                                                fmi3Boolean *nominals, fmi3Boolean *values, fmi3Boolean *next_defined,
                                                fmi3Float64 *next)
{
    Instance *c = (Instance *)i;
    Events e;
    size_t k;
    memset(&e, 0, sizeof e);
    model_event(&c->m, c->time, &e);
    for (k = 0; k < NVARS; k++) /* the clocks of this instant are over */
        if (VARS[k].type == T_CLOCK) *(bool *)((char *)&c->m + VARS[k].offset) = false;
    *needs = e.needs_update;
    *terminate = e.terminate;
    *nominals = false;
    *values = e.values_changed;
    *next_defined = c->next_defined = e.next_defined;
    *next = c->next = e.next;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance i) { return fail((Instance *)i, "not provided"); }

/* -- Model Exchange ------------------------------------------------------------------------- */

FMI3_Export fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance i)
{
    Instance *c = (Instance *)i;
    c->mode = M_CONTINUOUS;
    model_indicators(&c->m, c->time, c->z);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3CompletedIntegratorStep(fmi3Instance i, fmi3Boolean no_set, fmi3Boolean *enter,
                                                   fmi3Boolean *terminate)
{
    Instance *c = (Instance *)i;
    (void)no_set;
    *enter = model_step_event(&c->m, c->time);
    *terminate = false;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3SetTime(fmi3Instance i, fmi3Float64 t)
{
    ((Instance *)i)->time = t;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3SetContinuousStates(fmi3Instance i, const fmi3Float64 x[], size_t n)
{
    Instance *c = (Instance *)i;
    if (n != NX) return fail(c, "fmi3SetContinuousStates: wrong number of states");
    memcpy(c->m.x, x, sizeof(double) * NX);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance i, fmi3Float64 dx[], size_t n)
{
    Instance *c = (Instance *)i;
    if (n != NX) return fail(c, "fmi3GetContinuousStateDerivatives: wrong number of states");
    model_derivatives(&c->m, c->time, dx);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetEventIndicators(fmi3Instance i, fmi3Float64 z[], size_t n)
{
    Instance *c = (Instance *)i;
    if (n != NZ) return fail(c, "fmi3GetEventIndicators: wrong number of indicators");
    model_indicators(&c->m, c->time, z);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetContinuousStates(fmi3Instance i, fmi3Float64 x[], size_t n)
{
    Instance *c = (Instance *)i;
    if (n != NX) return fail(c, "fmi3GetContinuousStates: wrong number of states");
    memcpy(x, c->m.x, sizeof(double) * NX);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance i, fmi3Float64 nominals[], size_t n)
{
    size_t k;
    (void)i;
    for (k = 0; k < n; k++) nominals[k] = 1.0;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance i, size_t *n)
{
    (void)i;
    *n = NZ;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance i, size_t *n)
{
    (void)i;
    *n = NX;
    return fmi3OK;
}

/* -- Co-Simulation: RK4 at CS_STEP; at an event (a sign change at an internal step's end, a time
 * event, a step event) an early return where allowed, else the event handled inside the step. -- */

MEX_RK4(Model, model_derivatives)

/* One internal step from c->time towards end; true at an event. */
static bool internal_step(Instance *c, double end)
{
    double before[NZ + 1], t = c->time, h = end - t < CS_STEP * (1 + 1e-9) ? end - t : CS_STEP;
    bool time_event;
    if (c->next_defined && c->next > t && c->next < t + h) h = c->next - t;
    memcpy(before, c->z, sizeof before);
    rk4(&c->m, t, h);
    c->time = t + h;
    time_event = c->next_defined && c->time >= c->next;
    model_indicators(&c->m, c->time, c->z);
    return crossed(before, c->z) || time_event || model_step_event(&c->m, c->time);
}

FMI3_Export fmi3Status fmi3DoStep(fmi3Instance i, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_set, fmi3Boolean *event,
                                  fmi3Boolean *terminate, fmi3Boolean *early, fmi3Float64 *last)
{
    Instance *c = (Instance *)i;
    double end = t + h;
    (void)no_set;
    *event = *terminate = *early = false;
    c->time = t;
    while (c->time < end - 1e-12 * (fabs(end) > 1 ? fabs(end) : 1)) {
        if (!internal_step(c, end)) continue;
        if (c->event_mode_used) {
            *event = true;
            if (c->early_return_allowed) break;
        } else {
            Events e;
            memset(&e, 0, sizeof e);
            do model_event(&c->m, c->time, &e); while (e.needs_update);
            c->next_defined = e.next_defined;
            c->next = e.next;
            model_indicators(&c->m, c->time, c->z);
            if (e.terminate) {
                *terminate = true;
                break;
            }
        }
    }
    *early = c->time < end - 1e-12 * (fabs(end) > 1 ? fabs(end) : 1);
    *last = *early ? c->time : end;
    if (!*early) c->time = end;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3EnterStepMode(fmi3Instance i)
{
    Instance *c = (Instance *)i;
    c->mode = M_CONTINUOUS;
    model_indicators(&c->m, c->time, c->z);
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3GetOutputDerivatives(fmi3Instance i, const fmi3ValueReference v[], size_t n,
                                                const fmi3Int32 o[], fmi3Float64 d[], size_t m)
{
    (void)v; (void)n; (void)o; (void)d; (void)m;
    return fail((Instance *)i, "not provided");
}

/* -- Scheduled Execution -------------------------------------------------------------------- */

FMI3_Export fmi3Status fmi3ActivateModelPartition(fmi3Instance i, fmi3ValueReference clock, fmi3Float64 t)
{
    Instance *c = (Instance *)i;
    c->time = t;
    if (model_partition(&c->m, clock, t) && c->clock_update != NULL) c->clock_update(c->env);
    return fmi3OK;
}

/* -- FMU state ------------------------------------------------------------------------------ */

FMI3_Export fmi3Status fmi3GetFMUState(fmi3Instance i, fmi3FMUState *state)
{
    Instance *copy = (Instance *)malloc(sizeof(Instance));
    if (copy == NULL) return fail((Instance *)i, "no memory");
    memcpy(copy, i, sizeof(Instance));
    if (*state != NULL) free(*state);
    *state = copy;
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3SetFMUState(fmi3Instance i, fmi3FMUState state)
{
    memcpy(i, state, sizeof(Instance));
    return fmi3OK;
}

FMI3_Export fmi3Status fmi3FreeFMUState(fmi3Instance i, fmi3FMUState *state)
{
    (void)i;
    free(*state);
    *state = NULL;
    return fmi3OK;
}

/* -- not provided --------------------------------------------------------------------------- */

FMI3_Export fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance i, fmi3ValueReference v, size_t *n)
{
    (void)v; (void)n;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3GetVariableDependencies(fmi3Instance i, fmi3ValueReference d, size_t e[], fmi3ValueReference v[],
                                                   size_t f[], fmi3DependencyKind k[], size_t n)
{
    (void)d; (void)e; (void)v; (void)f; (void)k; (void)n;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SerializedFMUStateSize(fmi3Instance i, fmi3FMUState s, size_t *n)
{
    (void)s; (void)n;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SerializeFMUState(fmi3Instance i, fmi3FMUState s, fmi3Byte b[], size_t n)
{
    (void)s; (void)b; (void)n;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3DeserializeFMUState(fmi3Instance i, const fmi3Byte b[], size_t n, fmi3FMUState *s)
{
    (void)b; (void)n; (void)s;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3GetDirectionalDerivative(fmi3Instance i, const fmi3ValueReference u[], size_t nu,
                                                    const fmi3ValueReference k[], size_t nk, const fmi3Float64 s[],
                                                    size_t ns, fmi3Float64 d[], size_t nd)
{
    (void)u; (void)nu; (void)k; (void)nk; (void)s; (void)ns; (void)d; (void)nd;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3GetAdjointDerivative(fmi3Instance i, const fmi3ValueReference u[], size_t nu,
                                                const fmi3ValueReference k[], size_t nk, const fmi3Float64 s[], size_t ns,
                                                fmi3Float64 d[], size_t nd)
{
    (void)u; (void)nu; (void)k; (void)nk; (void)s; (void)ns; (void)d; (void)nd;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3EnterConfigurationMode(fmi3Instance i) { return fail((Instance *)i, "not provided"); }
FMI3_Export fmi3Status fmi3ExitConfigurationMode(fmi3Instance i) { return fail((Instance *)i, "not provided"); }
FMI3_Export fmi3Status fmi3GetIntervalDecimal(fmi3Instance i, const fmi3ValueReference v[], size_t n, fmi3Float64 x[],
                                              fmi3IntervalQualifier q[])
{
#ifdef MODEL_INTERVALS
    Instance *c = (Instance *)i;
    size_t k;
    for (k = 0; k < n; k++) {
        int known = model_interval(&c->m, v[k], &x[k]);
        if (known < 0) return fail(c, "fmi3GetIntervalDecimal: not a countdown clock");
        q[k] = known ? fmi3IntervalChanged : fmi3IntervalNotYetKnown;
    }
    return fmi3OK;
#else
    (void)v; (void)n; (void)x; (void)q;
    return fail((Instance *)i, "no clock with an interval to ask for");
#endif
}
FMI3_Export fmi3Status fmi3GetIntervalFraction(fmi3Instance i, const fmi3ValueReference v[], size_t n, fmi3UInt64 c[],
                                               fmi3UInt64 r[], fmi3IntervalQualifier q[])
{
    (void)v; (void)n; (void)c; (void)r; (void)q;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3GetShiftDecimal(fmi3Instance i, const fmi3ValueReference v[], size_t n, fmi3Float64 x[])
{
    (void)v; (void)n; (void)x;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3GetShiftFraction(fmi3Instance i, const fmi3ValueReference v[], size_t n, fmi3UInt64 c[],
                                            fmi3UInt64 r[])
{
    (void)v; (void)n; (void)c; (void)r;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SetIntervalDecimal(fmi3Instance i, const fmi3ValueReference v[], size_t n, const fmi3Float64 x[])
{
    (void)v; (void)n; (void)x;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SetIntervalFraction(fmi3Instance i, const fmi3ValueReference v[], size_t n, const fmi3UInt64 c[],
                                               const fmi3UInt64 r[])
{
    (void)v; (void)n; (void)c; (void)r;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SetShiftDecimal(fmi3Instance i, const fmi3ValueReference v[], size_t n, const fmi3Float64 x[])
{
    (void)v; (void)n; (void)x;
    return fail((Instance *)i, "not provided");
}
FMI3_Export fmi3Status fmi3SetShiftFraction(fmi3Instance i, const fmi3ValueReference v[], size_t n, const fmi3UInt64 c[],
                                            const fmi3UInt64 r[])
{
    (void)v; (void)n; (void)c; (void)r;
    return fail((Instance *)i, "not provided");
}
