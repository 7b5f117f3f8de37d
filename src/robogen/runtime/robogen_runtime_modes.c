/* robogen runtime, part of robogen_runtime.c: creation and destruction of instances, logging
 * control, the mode changes (initialization, Event Mode, Step Mode, Terminated, Reset),
 * fmi3UpdateDiscreteStates and fmi3DoStep.
 *
 * Included at the end of robogen_runtime.c, never compiled on its own: it uses the helpers defined
 * there (rg_enter, rg_fail, rg_log, the tables, rg_prepare_instant). See the design note there.
 */
#ifndef ROBOGEN_RUNTIME_PARTS
#error "robogen_runtime_modes.c is part of robogen_runtime.c; compile robogen_runtime.c (through the FMU's unity file)"
#endif

/* ============================================================================================
 * Inquire version, set debug logging
 * ============================================================================================ */

const char *fmi3GetVersion(void)
{
    return fmi3Version;
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    static const char *const fn = "fmi3SetDebugLogging";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_SET_DEBUG_LOGGING);
    bool selected[RG_LOG_NUM_CATEGORIES] = {false};
    bool on = rg_read_flag(&loggingOn);
    size_t i;
    int c;
    if (inst == NULL) return fmi3Error;
    if (nCategories > 0 && categories == NULL) return rg_fail(inst, fn, "categories is NULL but nCategories is %zu", nCategories);
    for (i = 0; i < nCategories; ++i) {
        bool known = false;
        if (categories[i] == NULL) return rg_fail(inst, fn, "categories[%zu] is NULL", i);
        for (c = 0; c < RG_LOG_NUM_CATEGORIES; ++c) {
            if (strcmp(categories[i], rg_category_names[c]) == 0) {
                selected[c] = true;
                known = true;
            }
        }
        if (!known) {
            return rg_fail(inst, fn, "unknown log category '%s' (known: logEvents, logTransitions, "
                           "logStatusWarning, logStatusError)", categories[i]);
        }
    }
    if (on) {
        /* zero categories: all of them; otherwise exactly the listed ones */
        inst->logging_on = true;
        for (c = 0; c < RG_LOG_NUM_CATEGORIES; ++c) inst->log_category_on[c] = nCategories == 0 || selected[c];
    } else if (nCategories == 0) {
        inst->logging_on = false;
    } else {
        for (c = 0; c < RG_LOG_NUM_CATEGORIES; ++c) {
            if (selected[c]) inst->log_category_on[c] = false;
        }
    }
    return fmi3OK;
}

/* ============================================================================================
 * Creation and destruction of instances
 * ============================================================================================ */

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                               "fmi3InstantiateModelExchange: FMU '%s' supports Co-Simulation only", RG_MODEL_IDENTIFIER);
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                               "fmi3InstantiateScheduledExecution: FMU '%s' supports Co-Simulation only", RG_MODEL_IDENTIFIER);
    return NULL;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    static const char *const fn = "fmi3InstantiateCoSimulation";
    char problem[256];
    const char *table_problem;
    rg_instance *inst;
    int c;
    (void)visible;              /* robogen FMUs have no user interface */
    (void)intermediateUpdate;   /* providesIntermediateUpdate="false": never called */
    (void)requiredIntermediateVariables;

    if (instanceName == NULL || rg_is_blank(instanceName)) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                                   "%s: instanceName must be a non-empty string", fn);
        return NULL;
    }
    if (instantiationToken == NULL || strcmp(instantiationToken, RG_INSTANTIATION_TOKEN) != 0) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                                   "%s: instantiationToken '%s' does not match this binary's '%s' "
                                   "(modelDescription.xml and binary differ)", fn,
                                   instantiationToken != NULL ? instantiationToken : "(NULL)", RG_INSTANTIATION_TOKEN);
        return NULL;
    }
    if (RG_NUM_CLOCKS > 0 && !rg_read_flag(&eventModeUsed)) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                                   "%s: this FMU has clocks, so eventModeUsed must be true", fn);
        return NULL;
    }
    if (nRequiredIntermediateVariables > 0) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                                   "%s: %zu requiredIntermediateVariables given, but this FMU provides no "
                                   "intermediate update (no variable has intermediateUpdate=\"true\")",
                                   fn, nRequiredIntermediateVariables);
        return NULL;
    }
    table_problem = rg_check_tables(problem, sizeof problem);
    if (table_problem != NULL) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName,
                                   "%s: internal error in the generated model tables: %s", fn, table_problem);
        return NULL;
    }

    inst = (rg_instance *)calloc(1, sizeof *inst);
    if (inst == NULL) {
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName, "%s: out of memory", fn);
        return NULL;
    }
    inst->instance_name = rg_strdup(instanceName);
    inst->resource_path = resourcePath != NULL ? rg_strdup(resourcePath) : NULL;
    if (inst->instance_name == NULL || (resourcePath != NULL && inst->resource_path == NULL)) {
        free(inst->instance_name);
        free(inst->resource_path);
        free(inst);
        rg_log_instantiation_error(logMessage, instanceEnvironment, instanceName, "%s: out of memory", fn);
        return NULL;
    }
    inst->environment = instanceEnvironment;
    inst->log_message = logMessage;
    inst->logging_on = rg_read_flag(&loggingOn);
    for (c = 0; c < RG_LOG_NUM_CATEGORIES; ++c) inst->log_category_on[c] = true;
    inst->event_mode_used = rg_read_flag(&eventModeUsed);
    inst->early_return_allowed = rg_read_flag(&earlyReturnAllowed) && RG_MIGHT_RETURN_EARLY;
    inst->states = NULL;
    rg_reset_instance(inst);
    rg_register(inst);
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: instantiated (eventModeUsed=%d, earlyReturnAllowed=%d)", fn,
           (int)inst->event_mode_used, (int)inst->early_return_allowed);
    return inst;
}

void fmi3FreeInstance(fmi3Instance instance)
{
    rg_instance *inst;
    rg_fmu_state *state;
    if (instance == NULL) return; /* the standard: a NULL instance is ignored */
    inst = rg_unregister(instance);
    if (inst == NULL) {
        rg_report_bad_handle("fmi3FreeInstance", instance);
        return;
    }
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "fmi3FreeInstance: freed");
    state = inst->states;
    while (state != NULL) {
        rg_fmu_state *next = state->next;
        free(state);
        state = next;
    }
    free(inst->instance_name);
    free(inst->resource_path);
    free(inst);
}

/* ============================================================================================
 * Enter and exit initialization mode, terminate and reset
 * ============================================================================================ */

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    static const char *const fn = "fmi3EnterInitializationMode";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_ENTER_INITIALIZATION_MODE);
    bool stop_defined = rg_read_flag(&stopTimeDefined);
    (void)toleranceDefined; (void)tolerance; /* the generated machines have no numerical solver */
    if (inst == NULL) return fmi3Error;
    if (!isfinite(startTime)) return rg_fail(inst, fn, "startTime must be finite");
    if (stop_defined && !(isfinite(stopTime) && stopTime >= startTime)) {
        return rg_fail(inst, fn, "stopTime %.17g must be finite and not before startTime %.17g", stopTime, startTime);
    }
    inst->s.start_time = startTime;
    inst->s.stop_time_defined = stop_defined;
    inst->s.stop_time = stop_defined ? stopTime : 0.0;
    inst->s.time = startTime;
    inst->s.superdense = 0;
    inst->s.mode = RG_INITIALIZATION_MODE;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: start time %.17g", fn, startTime);
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    static const char *const fn = "fmi3ExitInitializationMode";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_EXIT_INITIALIZATION_MODE);
    fmi3Status status;
    int c;
    if (inst == NULL) return fmi3Error;
    status = rg_model_exit_initialization(inst);
    if (status > fmi3Warning) return rg_fail(inst, fn, "the model rejected its parameters or start values");
    for (c = 0; c < RG_CLOCK_ARRAY_SIZE; ++c) {
        inst->s.clock_active[c] = false;
        inst->s.clock_latched[c] = false;
        inst->s.clock_next_tick[c] = 0;
        inst->s.clock_ever_activated[c] = false;
    }
    inst->s.superdense = 0;
    inst->s.evaluated = false;
    inst->s.event_pending = false;
    inst->s.inputs_set_in_step_mode = false;
    /* With event mode the instant (t_start, 0) is handled in Event Mode right away: a periodic
     * clock with shift 0 ticks there, exactly once. */
    inst->s.mode = inst->event_mode_used ? RG_EVENT_MODE : RG_STEP_MODE;
    inst->s.update_pending = inst->event_mode_used;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: now in %s at t=%.17g", fn, rg_mode_name(inst->s.mode), inst->s.time);
    return status;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    static const char *const fn = "fmi3EnterEventMode";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_ENTER_EVENT_MODE);
    int c;
    if (inst == NULL) return fmi3Error;
    if (!inst->event_mode_used) return rg_fail(inst, fn, "the instance was created with eventModeUsed=false");
    inst->s.mode = RG_EVENT_MODE;
    inst->s.update_pending = true;
    inst->s.evaluated = false;
    inst->s.event_pending = false;
    inst->s.inputs_set_in_step_mode = false;
    for (c = 0; c < RG_CLOCK_ARRAY_SIZE; ++c) inst->s.clock_latched[c] = false;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: at t=%.17g (instant %" PRIu64 ")", fn, inst->s.time, inst->s.superdense);
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    static const char *const fn = "fmi3Terminate";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_TERMINATE);
    if (inst == NULL) return fmi3Error;
    inst->s.mode = RG_TERMINATED;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: terminated at t=%.17g", fn, inst->s.time);
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    static const char *const fn = "fmi3Reset";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_RESET);
    if (inst == NULL) return fmi3Error;
    rg_reset_instance(inst);
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: back to Instantiated with start values", fn);
    return fmi3OK;
}

/* ============================================================================================
 * Event Mode: UpdateDiscreteStates, EnterStepMode
 * ============================================================================================ */

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    static const char *const fn = "fmi3UpdateDiscreteStates";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_UPDATE_DISCRETE_STATES);
    bool need_update = false, terminate = false, next_defined = false;
    double next_time = 0.0;
    fmi3Status status, update_status;
    int c;
    if (inst == NULL) return fmi3Error;
    if (discreteStatesNeedUpdate == NULL || terminateSimulation == NULL || nominalsOfContinuousStatesChanged == NULL ||
        valuesOfContinuousStatesChanged == NULL || nextEventTimeDefined == NULL || nextEventTime == NULL) {
        return rg_fail(inst, fn, "an output argument is NULL");
    }
    status = rg_prepare_instant(inst, fn); /* no Get came: evaluate now */
    if (status > fmi3Warning) return status;
    rg_latch_pending(inst);                /* activations after the evaluation: next cycle */
    update_status = rg_model_update(inst, &need_update, &terminate, &next_defined, &next_time);
    if (update_status > fmi3Warning) return rg_fail(inst, fn, "the model failed to close the instant at t=%.17g", inst->s.time);
    status = rg_worse(status, update_status);
    for (c = 0; c < RG_CLOCK_ARRAY_SIZE; ++c) {
        inst->s.clock_active[c] = false;
        inst->s.clock_latched[c] = false;
    }
    inst->s.evaluated = false;
    inst->s.superdense += 1;
    inst->s.update_pending = need_update;
    *discreteStatesNeedUpdate = need_update;
    *terminateSimulation = terminate;
    *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = false;
    *nextEventTimeDefined = next_defined;
    *nextEventTime = next_defined ? next_time : 0.0;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: instant closed, now (t=%.17g, %" PRIu64 "); discreteStatesNeedUpdate=%d "
           "terminateSimulation=%d", fn, inst->s.time, inst->s.superdense, (int)need_update, (int)terminate);
    return status;
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    static const char *const fn = "fmi3EnterStepMode";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_ENTER_STEP_MODE);
    int c;
    if (inst == NULL) return fmi3Error;
    if (inst->s.update_pending) {
        return rg_fail(inst, fn, "the event iteration is not finished: call fmi3UpdateDiscreteStates until it "
                       "returns discreteStatesNeedUpdate=false");
    }
    for (c = 0; c < RG_NUM_CLOCKS; ++c) {
        if (inst->s.clock_active[c]) {
            return rg_fail(inst, fn, "clock '%s' is active: close its instant with fmi3UpdateDiscreteStates first",
                           rg_clocks[c].name);
        }
    }
    inst->s.mode = RG_STEP_MODE;
    rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: at t=%.17g", fn, inst->s.time);
    return fmi3OK;
}

/* ============================================================================================
 * Step Mode: DoStep
 * ============================================================================================ */

/* The index of the first tick of constant clock c at or after time t (equal under the time
 * tolerance), from the integer grid; capped so that no conversion overflows. */
static uint64_t rg_first_tick_at_or_after(const rg_instance *inst, int c, double t)
{
    double origin = inst->s.start_time + rg_clocks[c].shift;
    double n = floor((t - origin) / rg_clocks[c].interval);
    uint64_t k = n < 0.0 ? 0 : (n > 4.0e18 ? UINT64_C(4000000000000000000) : (uint64_t)n);
    while (k > 0 && (rg_tick_time(inst, c, k - 1) > t || rg_time_equal(rg_tick_time(inst, c, k - 1), t))) --k;
    while (rg_tick_time(inst, c, k) < t && !rg_time_equal(rg_tick_time(inst, c, k), t)) ++k;
    return k;
}

/* fmi3DoStep's checks before anything changes: the step starts at the FMU's time, is finite,
 * ends no later than stopTime, and no event from the previous step waits for Event Mode. */
static fmi3Status rg_check_step(rg_instance *inst, const char *fn, double t, double h, double *t_end)
{
    if (inst->s.event_pending) {
        return rg_fail(inst, fn, "the previous step reported eventHandlingNeeded at t=%.17g: call fmi3EnterEventMode "
                       "before stepping on", inst->s.time);
    }
    if (!isfinite(t) || !isfinite(h) || !(h > 0.0)) {
        return rg_fail(inst, fn, "communicationStepSize must be > 0 and both arguments finite (got t=%.17g, h=%.17g)", t, h);
    }
    if (!rg_time_equal(t, inst->s.time)) {
        return rg_fail(inst, fn, "currentCommunicationPoint %.17g differs from the FMU's time %.17g (after an early "
                       "return the next step starts at lastSuccessfulTime)", t, inst->s.time);
    }
    *t_end = t + h;
    if (!isfinite(*t_end)) return rg_fail(inst, fn, "t + h overflows");
    if (inst->s.stop_time_defined && *t_end > inst->s.stop_time && !rg_time_equal(*t_end, inst->s.stop_time)) {
        return rg_fail(inst, fn, "the step would end at %.17g, past stopTime %.17g", *t_end, inst->s.stop_time);
    }
    return fmi3OK;
}

/* A step must not pass a tick of a periodic clock the importer uses without activating it: the
 * tick would be lost silently. */
static fmi3Status rg_check_no_tick_skipped(rg_instance *inst, const char *fn, double t_end)
{
    int c;
    for (c = 0; c < RG_NUM_CLOCKS; ++c) {
        double due;
        if (rg_clocks[c].kind != RG_CLOCK_INPUT_CONSTANT || !inst->s.clock_ever_activated[c]) continue;
        due = rg_tick_time(inst, c, inst->s.clock_next_tick[c]);
        if (t_end > due && !rg_time_equal(t_end, due)) {
            return rg_fail(inst, fn, "the step to %.17g would pass tick k=%" PRIu64 " of '%s' at t=%.17g, which "
                           "was not activated: step to the tick and activate it in Event Mode", t_end,
                           inst->s.clock_next_tick[c], rg_clocks[c].name, due);
        }
    }
    return fmi3OK;
}

/* The model's part of the step from t (the FMU's time) to t_end: *last is where it ended (t_end,
 * or earlier on an early return). A model that discards the step gets the state it had before. */
static fmi3Status rg_step_model(rg_instance *inst, const char *fn, double t, double t_end, bool *event, bool *terminate,
                                double *last)
{
#ifdef RG_HAS_DO_STEP
    rg_snapshot_part before = inst->s; /* restored if the model discards the step */
    fmi3Status status;
    inst->s.time = t;
    *last = t_end;
    status = rg_model_do_step(inst, t_end, event, terminate, last);
    if (status == fmi3Discard) {
        inst->s = before;
        rg_log(inst, RG_LOG_ERROR, fmi3Discard, "%s: the model discarded the step from %.17g to %.17g; state unchanged",
               fn, t, t_end);
        return fmi3Discard;
    }
    if (status > fmi3Warning) return rg_fail(inst, fn, "the model failed in the step from %.17g to %.17g", t, t_end);
    if (!(*last >= t || rg_time_equal(*last, t)) || !(*last <= t_end || rg_time_equal(*last, t_end))) {
        return rg_fail(inst, fn, "internal error: the model returned lastSuccessfulTime %.17g outside [%.17g, %.17g]",
                       *last, t, t_end);
    }
    if (rg_time_equal(*last, t_end)) *last = t_end;
    if (*last < t) *last = t;
    if (*last < t_end && !inst->early_return_allowed) {
        return rg_fail(inst, fn, "internal error: the model returned early at %.17g though early return is not allowed",
                       *last);
    }
    return status;
#else
    /* the default: the machines react only in Event Mode, a step lets time pass */
    (void)inst; (void)fn; (void)t; (void)event; (void)terminate;
    *last = t_end;
    return fmi3OK;
#endif
}

/* An importer that has never activated a periodic clock has no clocks at all (fmpy's
 * simulate_fmu, for one): the ticks before `last` pass unused, with a warning, so that the FMU
 * still runs. (An importer that does use the clock was refused by rg_check_no_tick_skipped.) */
static fmi3Status rg_pass_unused_ticks(rg_instance *inst, const char *fn, double last)
{
    fmi3Status status = fmi3OK;
    int c;
    for (c = 0; c < RG_NUM_CLOCKS; ++c) {
        uint64_t first = inst->s.clock_next_tick[c], next;
        if (rg_clocks[c].kind != RG_CLOCK_INPUT_CONSTANT || inst->s.clock_ever_activated[c]) continue;
        next = rg_first_tick_at_or_after(inst, c, last);
        if (next <= first) continue;
        inst->s.clock_next_tick[c] = next;
        status = fmi3Warning;
        rg_log(inst, RG_LOG_WARNING, fmi3Warning, "%s: ticks k=%" PRIu64 "..%" PRIu64 " of '%s' passed without being "
               "activated (this importer has not used the clock): no cycle ran for them", fn, first, next - 1,
               rg_clocks[c].name);
    }
    return status;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime)
{
    static const char *const fn = "fmi3DoStep";
    rg_instance *inst = rg_enter(instance, fn, RG_ALLOWED_DO_STEP);
    double t_end = 0.0, last = 0.0;
    bool event = false, terminate = false, early;
    fmi3Status status;
    (void)noSetFMUStatePriorToCurrentPoint; /* snapshots are independent copies; nothing to flush */
    if (inst == NULL) return fmi3Error;
    if (eventHandlingNeeded == NULL || terminateSimulation == NULL || earlyReturn == NULL || lastSuccessfulTime == NULL) {
        return rg_fail(inst, fn, "an output argument is NULL");
    }
    status = rg_check_step(inst, fn, currentCommunicationPoint, communicationStepSize, &t_end);
    if (status == fmi3OK) status = rg_check_no_tick_skipped(inst, fn, t_end);
    if (status == fmi3OK) status = rg_step_model(inst, fn, currentCommunicationPoint, t_end, &event, &terminate, &last);
    if (status > fmi3Warning) return status; /* fmi3Discard included: the state is as before */
    early = last < t_end;
    if (event && !inst->event_mode_used) {
        rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: event at t=%.17g handled inside the FMU (eventModeUsed=false)", fn, last);
        event = false;
    }
    status = rg_worse(status, rg_pass_unused_ticks(inst, fn, last));
    inst->s.time = last;
    inst->s.superdense = 0;
    inst->s.inputs_set_in_step_mode = false;
    inst->s.event_pending = event;
    *eventHandlingNeeded = event;
    *terminateSimulation = terminate;
    *earlyReturn = early;
    *lastSuccessfulTime = last;
    if (early || event) {
        rg_log(inst, RG_LOG_EVENTS, fmi3OK, "%s: returned at t=%.17g (earlyReturn=%d, eventHandlingNeeded=%d)", fn, last,
               (int)early, (int)event);
    }
    return status;
}
