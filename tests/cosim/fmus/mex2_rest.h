/* mex2.h continued: Model Exchange and Co-Simulation. */

static bool crossed(const double *before, const double *after)
{
    int k;
    for (k = 0; k < NZ; k++)
        if ((before[k] < 0 && after[k] >= 0) || (before[k] > 0 && after[k] <= 0)) return true;
    return false;
}

FMI2_Export fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    ((Instance *)c)->mode = M_EVENT;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    Instance *x = (Instance *)c;
    Events e;
    memset(&e, 0, sizeof e);
    model_event(&x->m, x->time, &e);
    info->newDiscreteStatesNeeded = e.needs_update;
    info->terminateSimulation = e.terminate;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = e.values_changed;
    info->nextEventTimeDefined = e.next_defined;
    info->nextEventTime = e.next;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    ((Instance *)c)->mode = M_CONTINUOUS;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set, fmi2Boolean *enter,
                                                   fmi2Boolean *terminate)
{
    Instance *x = (Instance *)c;
    UNUSED(no_set);
    *enter = model_step_event(&x->m, x->time);
    *terminate = fmi2False;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t)
{
    ((Instance *)c)->time = t;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n)
{
    if (n != NX) return fail((Instance *)c, "wrong number of states");
    memcpy(((Instance *)c)->m.x, x, sizeof(double) * NX);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n)
{
    Instance *x = (Instance *)c;
    if (n != NX) return fail(x, "wrong number of states");
    model_derivatives(&x->m, x->time, dx);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n)
{
    Instance *x = (Instance *)c;
    if (n != NZ) return fail(x, "wrong number of event indicators");
    model_indicators(&x->m, x->time, z);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n)
{
    if (n != NX) return fail((Instance *)c, "wrong number of states");
    memcpy(x, ((Instance *)c)->m.x, sizeof(double) * NX);
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n)
{
    size_t k;
    UNUSED(c);
    for (k = 0; k < n; k++) x[k] = 1.0;
    return fmi2OK;
}

/* -- Co-Simulation ------------------------------------------------------------------------- */

MEX_RK4(Model, model_derivatives)

/* The step itself (fmi2DoStep: at once, or, for a model that asks for it, reported as pending first). */
static fmi2Status do_step(Instance *x, fmi2Real t, fmi2Real h)
{
    double end = t + h, tiny = 1e-12 * (fabs(end) > 1 ? fabs(end) : 1);
    x->time = t;
    while (x->time < end - tiny) {
        double before[NZ + 1], step = end - x->time < CS_STEP * (1 + 1e-9) ? end - x->time : CS_STEP;
        if (x->next_defined && x->next > x->time && x->next < x->time + step) step = x->next - x->time;
        memcpy(before, x->z, sizeof before);
        rk4(&x->m, x->time, step);
        x->time += step;
        model_indicators(&x->m, x->time, x->z);
        if (crossed(before, x->z) || (x->next_defined && x->time >= x->next) || model_step_event(&x->m, x->time))
            handle_events(x);
        if (x->terminated) {
            x->last_successful = x->time;
            return fmi2Discard;
        }
    }
    x->time = x->last_successful = end;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set)
{
    Instance *x = (Instance *)c;
    fmi2Status status = do_step(x, t, h);
    UNUSED(no_set);
    x->polls_left = model_async_polls(&x->m); /* asked for that many times as pending before it is done */
    if (x->polls_left == 0) return status;
    x->step_status = status;
    return fmi2Pending;
}

FMI2_Export fmi2Status fmi2CancelStep(fmi2Component c) { return fail((Instance *)c, "no asynchronous step"); }
FMI2_Export fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference v[], size_t n,
                                                   const fmi2Integer o[], const fmi2Real d[])
{
    UNUSED(v); UNUSED(n); UNUSED(o); UNUSED(d);
    return fail((Instance *)c, "not provided");
}
FMI2_Export fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference v[], size_t n,
                                                    const fmi2Integer o[], fmi2Real d[])
{
    UNUSED(v); UNUSED(n); UNUSED(o); UNUSED(d);
    return fail((Instance *)c, "not provided");
}
FMI2_Export fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *v)
{
    Instance *x = (Instance *)c;
    if (s != fmi2DoStepStatus) return fmi2Discard;
    *v = x->polls_left > 0 ? fmi2Pending : x->step_status;
    if (x->polls_left > 0) x->polls_left--;
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *v)
{
    if (s != fmi2LastSuccessfulTime) return fmi2Discard;
    *v = ((Instance *)c)->last_successful;
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *v)
{
    UNUSED(c); UNUSED(s); UNUSED(v);
    return fmi2Discard;
}
FMI2_Export fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *v)
{
    if (s != fmi2Terminated) return fmi2Discard;
    *v = ((Instance *)c)->terminated;
    return fmi2OK;
}
FMI2_Export fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *v)
{
    UNUSED(c); UNUSED(s); UNUSED(v);
    return fmi2Discard;
}
