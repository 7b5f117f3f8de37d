/* API-misuse suite for the robogen runtime, as a plain C importer.
 *
 *     misuse <counter.so> <plain.so>
 *
 * Loads the two test FMUs (tests/runtime/models) with dlopen, like a real importer, and calls
 * them wrongly in every way the runtime must catch. Every misuse case must return fmi3Error or
 * fmi3Discard and, when the FMU has a logMessage callback, log why; none may crash. Built once
 * plainly and once with -fsanitize=address,undefined (test_misuse.py), so that any memory error
 * or leak inside the runtime stops the run (ASAN_OPTIONS=detect_leaks=1:halt_on_error=1).
 *
 * Output, one line per case: "ok <n> - <kind>: <name>" or "not ok <n> - <kind>: <name>: <why>",
 * where kind is "misuse" (a wrong call that must be refused) or "check" (a control: the legal
 * call next to a misuse works, or a misuse left the instance as the standard says); finally
 * "# cases <n> misuse <k> failures <m>". Exit status 0 only if every case passed. Calls with a NULL or dead
 * instance cannot reach a logger; the runtime reports them on stderr, which test_misuse.py checks.
 */
#include <math.h>
#include <stdint.h>

#define HARNESS_FUNCTIONS(X)                                                                       \
    X(InstantiateCoSimulation) X(InstantiateModelExchange) X(InstantiateScheduledExecution)         \
    X(FreeInstance) X(SetDebugLogging) X(EnterInitializationMode) X(ExitInitializationMode)         \
    X(EnterEventMode) X(EnterStepMode) X(Terminate) X(Reset) X(DoStep) X(UpdateDiscreteStates)      \
    X(GetFloat64) X(SetFloat64) X(GetInt64) X(SetInt64) X(GetUInt64) X(SetInt32) X(GetBoolean)      \
    X(GetString) X(SetBinary) X(GetClock) X(SetClock) X(GetIntervalDecimal) X(GetIntervalFraction)  \
    X(GetShiftDecimal) X(SetIntervalDecimal) X(GetFMUState) X(SetFMUState) X(FreeFMUState)          \
    X(SerializedFMUStateSize) X(SerializeFMUState) X(DeserializeFMUState)                           \
    X(GetNumberOfVariableDependencies) X(GetDirectionalDerivative) X(EnterConfigurationMode)        \
    X(SetTime) X(GetOutputDerivatives) X(EvaluateDiscreteStates) X(ActivateModelPartition)

#include "misuse_harness.h"

/* Must equal RG_INSTANTIATION_TOKEN in models/<name>/config.h (a mismatch fails every case). */
#define COUNTER_TOKEN "{robogen-test-counter-7d1c0e52}"
#define PLAIN_TOKEN "{robogen-test-plain-4be2a907}"

/* counter's value references (models/counter/modelDescription.xml) */
enum {
    VR_CYCLE = 1, VR_COMMAND = 2, VR_COMMAND_VALUE = 3, VR_TICK = 4, VR_TICK_VALUE = 5, VR_COUNT = 6,
    VR_FLAG = 7, VR_GAINS = 8, VR_OFFSET = 9, VR_LEVEL = 10, VR_EARLY_AT = 11, VR_LAST_COMMAND = 12
};
/* plain's value references */
enum { VR_U = 1, VR_Y = 2, VR_EVENT_AT = 3, VR_MISBEHAVE = 4 };

#define INSTANTIATION_FAILS(name, expected, instance)                                          \
    do {                                                                                       \
        size_t before_ = log_count;                                                            \
        fmi3Instance made_ = (instance);                                                       \
        report_misuse(name, made_ == NULL && log_count > before_ && strstr(last_log, expected) != NULL, \
               made_ != NULL ? "an instance was returned" : last_log);                         \
    } while (0)

/* ---- building instances in a given state -------------------------------------------------- */

typedef enum { AT_INSTANTIATED, AT_INITIALIZATION, AT_EVENT, AT_STEP } target_state;

static fmu_api counter, plain;

static fmi3Instance new_instance(const fmu_api *f, const char *token, const char *name, int event_mode, int early)
{
    fmi3Instance instance = f->InstantiateCoSimulation(name, token, "/tmp/", fmi3False, fmi3True,
                                                       event_mode ? fmi3True : fmi3False, early ? fmi3True : fmi3False,
                                                       NULL, 0, NULL, capture_log, NULL);
    if (instance == NULL) {
        printf("Bail out! cannot instantiate %s (last log: %s)\n", name, last_log);
        exit(2);
    }
    return instance;
}

/* counter at t=0 in the requested state; AT_STEP has run the first tick at t=0. */
static fmi3Instance counter_at(target_state target, double stop_time)
{
    fmi3Instance c = new_instance(&counter, COUNTER_TOKEN, "counter", 1, 1);
    fmi3ValueReference cycle = VR_CYCLE;
    fmi3Clock active = fmi3ClockActive;
    fmi3Boolean need, term, nominals, values, next_defined;
    fmi3Float64 next_time;
    if (target == AT_INSTANTIATED) return c;
    require("EnterInitializationMode", counter.EnterInitializationMode(c, fmi3False, 0.0, 0.0, stop_time > 0.0, stop_time));
    if (target == AT_INITIALIZATION) return c;
    require("ExitInitializationMode", counter.ExitInitializationMode(c));
    if (target == AT_EVENT) return c;
    require("SetClock(cycle)", counter.SetClock(c, &cycle, 1, &active));
    require("UpdateDiscreteStates", counter.UpdateDiscreteStates(c, &need, &term, &nominals, &values, &next_defined, &next_time));
    require("EnterStepMode", counter.EnterStepMode(c));
    return c;
}

/* One misuse on a fresh counter instance in `state` (stop time undefined), freed afterwards;
 * `call` refers to the instance as `fresh`. */
#define MISUSE_FRESH(state, name, expected, call)                \
    do {                                                         \
        fmi3Instance fresh = counter_at(state, 0.0);             \
        MISUSE(name, expected, call);                            \
        counter.FreeInstance(fresh);                             \
    } while (0)

static fmi3Status do_step(const fmu_api *f, fmi3Instance instance, double t, double h)
{
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return f->DoStep(instance, t, h, fmi3True, &event, &terminate, &early, &last);
}

static fmi3Status update(const fmu_api *f, fmi3Instance instance)
{
    fmi3Boolean need, term, nominals, values, next_defined;
    fmi3Float64 next_time;
    return f->UpdateDiscreteStates(instance, &need, &term, &nominals, &values, &next_defined, &next_time);
}

/* ---- the cases ---------------------------------------------------------------------------- */

static void instantiation_cases(void)
{
    const fmi3ValueReference vr = VR_U;
    INSTANTIATION_FAILS("instantiate: wrong instantiation token", "does not match this binary",
        counter.InstantiateCoSimulation("c", "{not-the-token}", NULL, fmi3False, fmi3True, fmi3True, fmi3False, NULL, 0, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: NULL instantiation token", "instantiationToken '(NULL)'",
        counter.InstantiateCoSimulation("c", NULL, NULL, fmi3False, fmi3True, fmi3True, fmi3False, NULL, 0, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: NULL instance name", "instanceName must be a non-empty string",
        counter.InstantiateCoSimulation(NULL, COUNTER_TOKEN, NULL, fmi3False, fmi3True, fmi3True, fmi3False, NULL, 0, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: blank instance name", "instanceName must be a non-empty string",
        counter.InstantiateCoSimulation("  ", COUNTER_TOKEN, NULL, fmi3False, fmi3True, fmi3True, fmi3False, NULL, 0, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: eventModeUsed=false on an FMU with clocks", "eventModeUsed must be true",
        counter.InstantiateCoSimulation("c", COUNTER_TOKEN, NULL, fmi3False, fmi3True, fmi3False, fmi3False, NULL, 0, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: requiredIntermediateVariables without intermediate update", "provides no intermediate update",
        plain.InstantiateCoSimulation("p", PLAIN_TOKEN, NULL, fmi3False, fmi3True, fmi3False, fmi3False, &vr, 1, NULL, capture_log, NULL));
    INSTANTIATION_FAILS("instantiate: Model Exchange", "supports Co-Simulation only",
        counter.InstantiateModelExchange("c", COUNTER_TOKEN, NULL, fmi3False, fmi3True, NULL, capture_log));
    INSTANTIATION_FAILS("instantiate: Scheduled Execution", "supports Co-Simulation only",
        counter.InstantiateScheduledExecution("c", COUNTER_TOKEN, NULL, fmi3False, fmi3True, NULL, capture_log, NULL, NULL, NULL));
    /* no logger at all: must still fail cleanly */
    report_misuse("instantiate: wrong token with a NULL logMessage returns NULL",
           counter.InstantiateCoSimulation("c", "{x}", NULL, fmi3False, fmi3True, fmi3True, fmi3False, NULL, 0, NULL, NULL, NULL) == NULL,
           "an instance was returned");
}

static void handle_cases(void)
{
    fmi3Float64 value;
    fmi3ValueReference vr = VR_LEVEL;
    fmi3Instance c;
    uintptr_t stale;

    MISUSE_UNLOGGABLE("NULL instance: fmi3DoStep", do_step(&counter, NULL, 0.0, 0.1));
    MISUSE_UNLOGGABLE("NULL instance: fmi3GetFloat64", counter.GetFloat64(NULL, &vr, 1, &value, 1));
    counter.FreeInstance(NULL); /* allowed: ignored */
    report("NULL instance: fmi3FreeInstance is ignored", 1, "");

    /* Double free and use after free: the handle is kept as an integer, so the harness itself
     * never uses an indeterminate pointer value (no undefined behaviour on either side). */
    c = counter_at(AT_STEP, 0.0);
    stale = (uintptr_t)c;
    counter.FreeInstance(c);
    counter.FreeInstance((fmi3Instance)stale);
    report_misuse("double fmi3FreeInstance: ignored, reported on stderr, no crash", 1, "");
    MISUSE_UNLOGGABLE("freed instance: fmi3DoStep", do_step(&counter, (fmi3Instance)stale, 0.0, 0.1));
    MISUSE_UNLOGGABLE("freed instance: fmi3GetFloat64", counter.GetFloat64((fmi3Instance)stale, &vr, 1, &value, 1));
    /* an instance of another FMU is not live in this one */
    c = new_instance(&plain, PLAIN_TOKEN, "plain", 0, 0);
    MISUSE_UNLOGGABLE("foreign instance: counter's fmi3Reset on a plain instance", counter.Reset(c));
    plain.FreeInstance(c);
}

static void state_machine_cases(void)
{
    fmi3Float64 value;
    fmi3ValueReference level = VR_LEVEL, cycle = VR_CYCLE, tick = VR_TICK;
    fmi3Clock clock_value = fmi3ClockActive;
    fmi3Instance c;

    MISUSE_FRESH(AT_INSTANTIATED, "wrong state: fmi3DoStep in Instantiated", "fmi3DoStep: not allowed in Instantiated",
                 do_step(&counter, fresh, 0.0, 0.1));
    MISUSE_FRESH(AT_INSTANTIATED, "wrong state: fmi3ExitInitializationMode in Instantiated", "fmi3ExitInitializationMode: not allowed in Instantiated",
                 counter.ExitInitializationMode(fresh));
    MISUSE_FRESH(AT_INSTANTIATED, "wrong state: fmi3GetFloat64 in Instantiated", "fmi3GetFloat64: not allowed in Instantiated",
                 counter.GetFloat64(fresh, &level, 1, &value, 1));
    MISUSE_FRESH(AT_INSTANTIATED, "wrong state: fmi3Terminate in Instantiated", "fmi3Terminate: not allowed in Instantiated",
                 counter.Terminate(fresh));
    MISUSE_FRESH(AT_INITIALIZATION, "wrong state: fmi3EnterInitializationMode twice", "not allowed in Initialization Mode",
                 counter.EnterInitializationMode(fresh, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    MISUSE_FRESH(AT_INITIALIZATION, "wrong state: fmi3EnterStepMode in Initialization Mode", "fmi3EnterStepMode: not allowed in Initialization Mode",
                 counter.EnterStepMode(fresh));
    MISUSE_FRESH(AT_INITIALIZATION, "wrong state: fmi3SetClock in Initialization Mode", "fmi3SetClock: not allowed in Initialization Mode",
                 counter.SetClock(fresh, &cycle, 1, &clock_value));
    MISUSE_FRESH(AT_EVENT, "wrong state: fmi3EnterEventMode in Event Mode", "fmi3EnterEventMode: not allowed in Event Mode",
                 counter.EnterEventMode(fresh));
    MISUSE_FRESH(AT_EVENT, "event iteration: fmi3EnterStepMode before fmi3UpdateDiscreteStates", "event iteration is not finished",
                 counter.EnterStepMode(fresh));
    MISUSE_FRESH(AT_STEP, "wrong state: fmi3UpdateDiscreteStates in Step Mode", "fmi3UpdateDiscreteStates: not allowed in Step Mode",
                 update(&counter, fresh));
    MISUSE_FRESH(AT_STEP, "wrong state: fmi3SetClock in Step Mode", "fmi3SetClock: not allowed in Step Mode",
                 counter.SetClock(fresh, &cycle, 1, &clock_value));
    MISUSE_FRESH(AT_STEP, "wrong state: fmi3GetClock in Step Mode", "fmi3GetClock: not allowed in Step Mode",
                 counter.GetClock(fresh, &tick, 1, &clock_value));

    /* Terminated, reached by fmi3Terminate */
    c = counter_at(AT_STEP, 0.0);
    require("Terminate", counter.Terminate(c));
    MISUSE("wrong state: fmi3DoStep after fmi3Terminate", "fmi3DoStep: not allowed in Terminated", do_step(&counter, c, 0.0, 0.1));
    MISUSE("wrong state: fmi3SetFloat64 in Terminated", "fmi3SetFloat64: not allowed in Terminated", counter.SetFloat64(c, &level, 1, &value, 1));
    MISUSE("wrong state: fmi3Terminate twice", "fmi3Terminate: not allowed in Terminated", counter.Terminate(c));
    /* ... where non-clocked Gets still work, and fmi3Reset leads back to Instantiated */
    report("Terminated: non-clocked fmi3GetFloat64 still works", counter.GetFloat64(c, &level, 1, &value, 1) == fmi3OK,
           "GetFloat64 failed in Terminated");
    report("Terminated: fmi3Reset works", counter.Reset(c) == fmi3OK, "Reset failed");
    report("after fmi3Reset: fmi3EnterInitializationMode works",
           counter.EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK, "EnterInitializationMode failed");
    counter.FreeInstance(c);

    /* an error moves the instance to Terminated (FMI 3.0 state machine) */
    c = counter_at(AT_STEP, 0.0);
    MISUSE("error path: fmi3DoStep with h = 0", "communicationStepSize must be > 0", do_step(&counter, c, 0.0, 0.0));
    MISUSE("error path: a valid fmi3DoStep after an error is refused (Terminated)", "fmi3DoStep: not allowed in Terminated", do_step(&counter, c, 0.0, 0.1));
    counter.FreeInstance(c);
}

static void argument_cases(void)
{
    fmi3Float64 values[3];
    fmi3Int64 integer;
    fmi3ValueReference unknown = 999, level = VR_LEVEL, gains = VR_GAINS, cycle = VR_CYCLE, count = VR_COUNT;
    fmi3ValueReference pair[2] = {VR_LEVEL, VR_GAINS};
    fmi3String text;
    const fmi3Binary binary = NULL;
    size_t binary_size = 0;

    MISUSE_FRESH(AT_STEP, "bad value reference: fmi3GetFloat64 of vr 999", "unknown value reference 999",
                 counter.GetFloat64(fresh, &unknown, 1, values, 1));
    MISUSE_FRESH(AT_STEP, "NULL argument: valueReferences NULL with nValueReferences 1", "valueReferences is NULL",
                 counter.GetFloat64(fresh, NULL, 1, values, 1));
    MISUSE_FRESH(AT_STEP, "NULL argument: values NULL with nValues 1", "values is NULL",
                 counter.GetFloat64(fresh, &level, 1, NULL, 1));
    MISUSE_FRESH(AT_STEP, "wrong type: fmi3GetInt64 of a Float64", "'level' (vr 10) is a Float64 variable, not Int64",
                 counter.GetInt64(fresh, &level, 1, &integer, 1));
    MISUSE_FRESH(AT_STEP, "wrong type: fmi3GetFloat64 of a Clock", "'cycle' (vr 1) is a Clock",
                 counter.GetFloat64(fresh, &cycle, 1, values, 1));
    MISUSE_FRESH(AT_STEP, "wrong type: fmi3GetInt64 of a UInt64", "is a UInt64 variable, not Int64",
                 counter.GetInt64(fresh, &count, 1, &integer, 1));
    MISUSE_FRESH(AT_STEP, "array size: nValues 1 for the 3-element 'gains'", "nValues is 1 but the 1 value reference(s) hold 3",
                 counter.GetFloat64(fresh, &gains, 1, values, 1));
    MISUSE_FRESH(AT_STEP, "array size: nValues 3 for 'level' + 'gains' (needs 4)", "nValues is 3 but the 2 value reference(s) hold 4",
                 counter.GetFloat64(fresh, pair, 2, values, 3));
    MISUSE_FRESH(AT_STEP, "no String variables: fmi3GetString", "not String",
                 counter.GetString(fresh, &level, 1, &text, 1));
    MISUSE_FRESH(AT_STEP, "no Binary variables: fmi3SetBinary", "not Binary",
                 counter.SetBinary(fresh, &level, 1, &binary_size, &binary, 1));
    values[0] = values[1] = values[2] = 1.0;
    MISUSE_FRESH(AT_STEP, "causality: fmi3SetFloat64 of a fixed parameter in Step Mode", "'gains' (vr 8) cannot be set in Step Mode",
                 counter.SetFloat64(fresh, &gains, 1, values, 3));
    integer = 1;
    MISUSE_FRESH(AT_STEP, "causality: fmi3SetInt64 of the output 'last_command'", "'last_command' (vr 12) cannot be set",
                 counter.SetInt64(fresh, (const fmi3ValueReference[]){VR_LAST_COMMAND}, 1, &integer, 1));
    MISUSE_FRESH(AT_STEP, "logging: fmi3SetDebugLogging with an unknown category", "unknown log category 'logEverything'",
                 counter.SetDebugLogging(fresh, fmi3True, 1, (const fmi3String[]){"logEverything"}));
    MISUSE_FRESH(AT_STEP, "logging: fmi3SetDebugLogging with NULL categories", "categories is NULL",
                 counter.SetDebugLogging(fresh, fmi3True, 2, NULL));
}

static void clock_cases(void)
{
    fmi3Float64 value = 0.0, interval;
    fmi3Int64 command_value = 5;
    fmi3UInt64 counter_value, resolution;
    fmi3IntervalQualifier qualifier;
    fmi3ValueReference cycle = VR_CYCLE, command = VR_COMMAND, tick = VR_TICK, tick_value = VR_TICK_VALUE;
    fmi3ValueReference command_vr = VR_COMMAND_VALUE, level = VR_LEVEL;
    fmi3Clock on = fmi3ClockActive, off = fmi3ClockInactive;
    fmi3Instance c;

    MISUSE_FRESH(AT_STEP, "clocked access: fmi3GetFloat64 of 'tick.value' in Step Mode", "'tick.value' is clocked by 'tick': clocked variables can be read only",
                 counter.GetFloat64(fresh, &tick_value, 1, &value, 1));
    MISUSE_FRESH(AT_STEP, "clocked access: fmi3SetInt64 of 'command.value' in Step Mode", "clocked variables cannot be set in Step Mode",
                 counter.SetInt64(fresh, &command_vr, 1, &command_value, 1));
    MISUSE_FRESH(AT_EVENT, "clocked access: 'tick.value' while 'tick' is inactive", "'tick.value' is clocked by 'tick', which is not active",
                 counter.GetFloat64(fresh, &tick_value, 1, &value, 1));
    MISUSE_FRESH(AT_EVENT, "clocked access: 'command.value' while 'command' is inactive", "'command.value' is clocked by 'command', which is not active",
                 counter.SetInt64(fresh, &command_vr, 1, &command_value, 1));
    c = counter_at(AT_EVENT, 0.0);
    require("SetClock(command)", counter.SetClock(c, &command, 1, &on));
    require("GetFloat64(level) evaluates", counter.GetFloat64(c, &level, 1, &value, 1));
    MISUSE("clocked input set after its activation was consumed", "already consumed by this instant's evaluation", counter.SetInt64(c, &command_vr, 1, &command_value, 1));
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_EVENT, "output clock: fmi3SetClock on 'tick'", "'tick' is an output clock",
                 counter.SetClock(fresh, &tick, 1, &on));
    MISUSE_FRESH(AT_EVENT, "not a clock: fmi3SetClock on 'level'", "not a Clock",
                 counter.SetClock(fresh, &level, 1, &on));
    c = counter_at(AT_EVENT, 0.0);
    require("SetClock(command)", counter.SetClock(c, &command, 1, &on));
    MISUSE("deactivation: fmi3SetClock(inactive) on an active clock without canBeDeactivated", "cannot be deactivated", counter.SetClock(c, &command, 1, &off));
    counter.FreeInstance(c);
    c = counter_at(AT_EVENT, 0.0);
    require("SetClock(cycle)", counter.SetClock(c, &cycle, 1, &on));
    require("UpdateDiscreteStates", update(&counter, c));
    MISUSE("periodic clock: a second tick in the same Event Mode", "'cycle' already ticked at t=0", counter.SetClock(c, &cycle, 1, &on));
    counter.FreeInstance(c);
    c = counter_at(AT_STEP, 0.0);
    require("DoStep to 0.05", do_step(&counter, c, 0.0, 0.05));
    require("EnterEventMode", counter.EnterEventMode(c));
    MISUSE("periodic clock: fmi3SetClock when no tick is due (t=0.05)", "'cycle' is not due", counter.SetClock(c, &cycle, 1, &on));
    counter.FreeInstance(c);
    c = counter_at(AT_EVENT, 0.0);
    require("GetFloat64(level) evaluates", counter.GetFloat64(c, &level, 1, &value, 1));
    MISUSE("periodic clock: activated after the instant was evaluated", "this instant was already evaluated", counter.SetClock(c, &cycle, 1, &on));
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_STEP, "periodic clock: fmi3DoStep past the unactivated tick at t=0.1", "would pass tick k=1 of 'cycle'",
                 do_step(&counter, fresh, 0.0, 0.15));
    c = counter_at(AT_EVENT, 0.0);
    require("UpdateDiscreteStates without ticking", update(&counter, c));
    require("EnterStepMode", counter.EnterStepMode(c));
    /* an importer that never activates the periodic clock has no clocks (fmpy's simulate_fmu):
     * its ticks pass with a warning instead of stopping the FMU */
    {
        fmi3Status status = do_step(&counter, c, 0.0, 0.15);
        report("periodic clock never activated: fmi3DoStep lets ticks k=0..1 pass with fmi3Warning",
               status == fmi3Warning && strstr(last_log, "ticks k=0..1 of 'cycle' passed without being activated") != NULL,
               last_log);
    }
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_INITIALIZATION, "interval: fmi3SetIntervalDecimal on a constant clock", "its interval is fixed",
                 counter.SetIntervalDecimal(fresh, &cycle, 1, &value));
    MISUSE_FRESH(AT_INITIALIZATION, "interval: fmi3GetIntervalDecimal on a triggered clock", "only time-based clocks have an interval",
                 counter.GetIntervalDecimal(fresh, &command, 1, &interval, &qualifier));
    MISUSE_FRESH(AT_INITIALIZATION, "interval: fmi3GetIntervalFraction (supportsFraction=false)", "supportsFraction is false",
           counter.GetIntervalFraction(fresh, &cycle, 1, &counter_value, &resolution, &qualifier));
    MISUSE_FRESH(AT_EVENT, "shift: fmi3GetShiftDecimal in Event Mode", "fmi3GetShiftDecimal: not allowed in Event Mode",
                 counter.GetShiftDecimal(fresh, &cycle, 1, &value));
}

static void step_cases(void)
{
    fmi3Float64 value = 1.0;
    fmi3ValueReference level = VR_LEVEL, early_at = VR_EARLY_AT;
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    fmi3Instance c;

    MISUSE_FRESH(AT_STEP, "DoStep: step size 0", "communicationStepSize must be > 0",
                 do_step(&counter, fresh, 0.0, 0.0));
    MISUSE_FRESH(AT_STEP, "DoStep: negative step size", "communicationStepSize must be > 0",
                 do_step(&counter, fresh, 0.0, -0.05));
    MISUSE_FRESH(AT_STEP, "DoStep: NaN step size", "communicationStepSize must be > 0",
                 do_step(&counter, fresh, 0.0, nan("")));
    MISUSE_FRESH(AT_STEP, "DoStep: starts at 0.02 while the FMU is at 0", "currentCommunicationPoint 0.02 differs",
                 do_step(&counter, fresh, 0.02, 0.05));
    c = counter_at(AT_STEP, 0.05);
    MISUSE("DoStep: past stopTime 0.05", "past stopTime", do_step(&counter, c, 0.0, 0.08));
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_STEP, "DoStep: NULL lastSuccessfulTime", "an output argument is NULL",
                 counter.DoStep(fresh, 0.0, 0.05, fmi3True, &event, &terminate, &early, NULL));
    c = counter_at(AT_STEP, 0.0);
    require("SetFloat64(level) in Step Mode", counter.SetFloat64(c, &level, 1, &value, 1));
    MISUSE("Get after Set in Step Mode without DoStep", "without an fmi3DoStep in between", counter.GetFloat64(c, &level, 1, &value, 1));
    counter.FreeInstance(c);

    /* eventHandlingNeeded ignored by the importer */
    c = new_instance(&counter, COUNTER_TOKEN, "counter", 1, 1);
    value = 0.05;
    require("EnterInitializationMode", counter.EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    require("SetFloat64(early_at)", counter.SetFloat64(c, &early_at, 1, &value, 1));
    require("ExitInitializationMode", counter.ExitInitializationMode(c));
    {
        fmi3ValueReference cycle = VR_CYCLE;
        fmi3Clock on = fmi3ClockActive;
        require("SetClock(cycle)", counter.SetClock(c, &cycle, 1, &on));
    }
    require("UpdateDiscreteStates", update(&counter, c));
    require("EnterStepMode", counter.EnterStepMode(c));
    require("DoStep with an internal event", counter.DoStep(c, 0.0, 0.08, fmi3True, &event, &terminate, &early, &last));
    report("DoStep: early return at 0.05 with eventHandlingNeeded", event && early && last == 0.05, "unexpected DoStep outputs");
    MISUSE("DoStep: stepping on after eventHandlingNeeded without fmi3EnterEventMode", "call fmi3EnterEventMode before stepping on", do_step(&counter, c, 0.05, 0.03));
    counter.FreeInstance(c);

    /* eventModeUsed = false */
    c = new_instance(&plain, PLAIN_TOKEN, "plain", 0, 0);
    require("EnterInitializationMode", plain.EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    require("ExitInitializationMode", plain.ExitInitializationMode(c));
    MISUSE("eventModeUsed=false: fmi3EnterEventMode", "eventModeUsed=false", plain.EnterEventMode(c));
    plain.FreeInstance(c);
}

static fmi3Instance plain_in_step_mode(int misbehave, int early_allowed)
{
    fmi3Instance p = new_instance(&plain, PLAIN_TOKEN, "plain", 0, early_allowed);
    fmi3ValueReference vr = VR_MISBEHAVE;
    fmi3Int32 mode = misbehave;
    require("EnterInitializationMode", plain.EnterInitializationMode(p, fmi3False, 0.0, 0.0, fmi3False, 0.0));
    require("SetInt32(misbehave)", plain.SetInt32(p, &vr, 1, &mode, 1));
    require("ExitInitializationMode", plain.ExitInitializationMode(p));
    return p;
}

static void model_contract_cases(void)
{
    fmi3ValueReference gains = VR_GAINS, command_vr = VR_COMMAND_VALUE, y = VR_Y;
    fmi3Float64 negative[3] = {-1.0, 2.0, 3.0}, y_value = 0.0;
    fmi3Int64 poison = -999; /* models/counter/model.c: COUNTER_POISON */
    fmi3Instance c, p;

    p = plain_in_step_mode(1, 0);
    MISUSE("model contract: early return although earlyReturnAllowed=false", "early return is not allowed", do_step(&plain, p, 0.0, 0.5));
    plain.FreeInstance(p);
    p = plain_in_step_mode(2, 1);
    MISUSE("model contract: lastSuccessfulTime beyond t+h", "lastSuccessfulTime 1.5 outside", do_step(&plain, p, 0.0, 0.5));
    plain.FreeInstance(p);
    p = plain_in_step_mode(3, 0);
    MISUSE("model discards the step", "discarded the step", do_step(&plain, p, 0.0, 0.5));
    report("after fmi3Discard: the state is unchanged (y still 0)",
           plain.GetFloat64(p, &y, 1, &y_value, 1) == fmi3OK && y_value == 0.0, "y changed or Get failed");
    plain.FreeInstance(p);

    c = counter_at(AT_INITIALIZATION, 0.0);
    require("SetFloat64(gains)", counter.SetFloat64(c, &gains, 1, negative, 3));
    MISUSE("model rejects its parameters at fmi3ExitInitializationMode", "rejected its parameters", counter.ExitInitializationMode(c));
    counter.FreeInstance(c);

    c = counter_at(AT_EVENT, 0.0);
    require("SetClock(cycle, command)", counter.SetClock(c, (const fmi3ValueReference[]){VR_CYCLE, VR_COMMAND}, 2,
                                                         (const fmi3Clock[]){fmi3ClockActive, fmi3ClockActive}));
    require("SetInt64(command.value)", counter.SetInt64(c, &command_vr, 1, &poison, 1));
    MISUSE("model fails to evaluate the instant", "failed to evaluate the instant", update(&counter, c));
    counter.FreeInstance(c);
}

static void fmu_state_cases(void)
{
    fmi3Instance c = counter_at(AT_STEP, 0.0), other = counter_at(AT_STEP, 0.0), p;
    fmi3FMUState state = NULL, foreign = NULL, copy;
    uintptr_t stale;
    size_t size = 0;
    fmi3Byte *bytes, *plain_bytes;
    size_t plain_size = 0;

    MISUSE("FMU state: fmi3GetFMUState with a NULL FMUState pointer", "fmi3GetFMUState: FMUState is NULL", counter.GetFMUState(c, NULL));
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_STEP, "FMU state: fmi3SetFMUState(NULL)", "fmi3SetFMUState: FMUState is NULL",
                 counter.SetFMUState(fresh, NULL));

    c = counter_at(AT_STEP, 0.0);
    require("GetFMUState (other instance)", counter.GetFMUState(other, &foreign));
    MISUSE("FMU state: a state of another instance", "not a live FMU state of this instance", counter.SetFMUState(c, foreign));
    counter.FreeInstance(c);

    c = counter_at(AT_STEP, 0.0);
    require("GetFMUState", counter.GetFMUState(c, &state));
    copy = state;
    require("GetFMUState into the same state", counter.GetFMUState(c, &state));
    report("FMU state: fmi3GetFMUState with *FMUState set reuses that state", state == copy, "a new state was made");
    stale = (uintptr_t)state;
    require("FreeFMUState", counter.FreeFMUState(c, &state));
    report("FMU state: fmi3FreeFMUState sets the pointer to NULL", state == NULL, "pointer not cleared");
    report("FMU state: fmi3FreeFMUState of NULL is ignored", counter.FreeFMUState(c, &state) == fmi3OK, "not OK");
    copy = (fmi3FMUState)stale;
    MISUSE("FMU state: a freed state in fmi3SetFMUState", "not a live FMU state of this instance", counter.SetFMUState(c, (fmi3FMUState)stale));
    counter.FreeInstance(c);
    MISUSE_FRESH(AT_STEP, "FMU state: double fmi3FreeFMUState through a copied pointer", "*FMUState is not a live FMU state",
                 counter.FreeFMUState(fresh, &copy));

    c = counter_at(AT_STEP, 0.0);
    require("GetFMUState", counter.GetFMUState(c, &state));
    require("SerializedFMUStateSize", counter.SerializedFMUStateSize(c, state, &size));
    bytes = (fmi3Byte *)malloc(size);
    MISUSE("FMU state: fmi3SerializeFMUState into a buffer one byte short", "but a serialized state takes", counter.SerializeFMUState(c, state, bytes, size - 1));
    counter.FreeInstance(c); /* also frees `state` */
    c = counter_at(AT_STEP, 0.0);
    state = NULL;
    require("GetFMUState", counter.GetFMUState(c, &state));
    require("SerializeFMUState", counter.SerializeFMUState(c, state, bytes, size));
    copy = NULL;
    MISUSE("FMU state: deserialize truncated data", "truncated or mismatched state", counter.DeserializeFMUState(c, bytes, size - 8, &copy));
    counter.FreeInstance(c);
    c = counter_at(AT_STEP, 0.0);
    bytes[size - 1] ^= 0x5a;
    copy = NULL;
    MISUSE("FMU state: deserialize corrupted data", "checksum mismatch", counter.DeserializeFMUState(c, bytes, size, &copy));
    counter.FreeInstance(c);

    p = plain_in_step_mode(0, 0);
    state = NULL;
    require("GetFMUState (plain)", plain.GetFMUState(p, &state));
    require("SerializedFMUStateSize (plain)", plain.SerializedFMUStateSize(p, state, &plain_size));
    plain_bytes = (fmi3Byte *)malloc(plain_size);
    require("SerializeFMUState (plain)", plain.SerializeFMUState(p, state, plain_bytes, plain_size));
    c = counter_at(AT_STEP, 0.0);
    copy = NULL;
    MISUSE("FMU state: deserialize a state of another FMU", "serialized by another FMU", counter.DeserializeFMUState(c, plain_bytes, plain_size, &copy));
    counter.FreeInstance(c);
    plain.FreeInstance(p);
    free(plain_bytes);
    free(bytes);
    counter.FreeInstance(other);
}

static void unsupported_cases(void)
{
    size_t n;
    fmi3ValueReference vr = VR_LEVEL;
    fmi3Float64 value;
    fmi3Int32 order = 1;

    MISUSE_FRESH(AT_STEP, "unsupported: fmi3GetNumberOfVariableDependencies", "providesPerElementDependencies is false",
                 counter.GetNumberOfVariableDependencies(fresh, VR_COUNT, &n));
    MISUSE_FRESH(AT_STEP, "unsupported: fmi3GetDirectionalDerivative", "providesDirectionalDerivatives is false",
                 counter.GetDirectionalDerivative(fresh, &vr, 1, &vr, 1, &value, 1, &value, 1));
    MISUSE_FRESH(AT_INSTANTIATED, "unsupported: fmi3EnterConfigurationMode", "no structural parameters",
                 counter.EnterConfigurationMode(fresh));
    MISUSE_FRESH(AT_STEP, "unsupported: fmi3SetTime (Model Exchange)", "fmi3SetTime: not supported: a Model Exchange function",
                 counter.SetTime(fresh, 0.5));
    MISUSE_FRESH(AT_STEP, "unsupported: fmi3GetOutputDerivatives", "maxOutputDerivativeOrder is 0",
                 counter.GetOutputDerivatives(fresh, &vr, 1, &order, &value, 1));
    MISUSE_FRESH(AT_EVENT, "unsupported: fmi3EvaluateDiscreteStates", "providesEvaluateDiscreteStates is false",
                 counter.EvaluateDiscreteStates(fresh));
    MISUSE_FRESH(AT_STEP, "unsupported: fmi3ActivateModelPartition (Scheduled Execution)", "a Scheduled Execution function",
                 counter.ActivateModelPartition(fresh, VR_CYCLE, 0.0));
}

/* 1,000 instantiate/free cycles; some keep FMU states that FreeInstance must release. */
static void lifecycle_cycles(void)
{
    int i;
    for (i = 0; i < 1000; ++i) {
        fmi3Instance c = counter_at(i % 2 ? AT_STEP : AT_INSTANTIATED, 0.0);
        fmi3FMUState state = NULL;
        if (i % 3 == 0) require("GetFMUState", counter.GetFMUState(c, &state));
        counter.FreeInstance(c);
    }
    report("1000 instantiate/free cycles (leaks are LeakSanitizer's to find)", 1, "");
}

int main(int argc, char **argv)
{
    if (argc != 3 || !load(argv[1], &counter) || !load(argv[2], &plain)) {
        fprintf(stderr, "usage: misuse <counter.so> <plain.so>\n");
        return 2;
    }
    instantiation_cases();
    handle_cases();
    state_machine_cases();
    argument_cases();
    clock_cases();
    step_cases();
    model_contract_cases();
    fmu_state_cases();
    unsupported_cases();
    lifecycle_cycles();
    return harness_finish();
}
