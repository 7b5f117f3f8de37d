/* FMI 3.0 call-order misuse, one program for the two implementations of the rules: robogen's C
 * runtime (robogen_runtime_modes.c and friends, in generated FMUs) and the Python-FMU slave
 * (robogen/pyfmu/slave.py behind shim.c). test_misuse_python.py runs it against one FMU of each
 * and requires the same verdict, case by case.
 *
 *     misuse_python <library.so> <token> <resources> <roles...>
 *
 * The roles are value references of variables both FMUs have, in this order: a periodic input
 * clock, a triggered input clock, an Int64 input clocked by it, an output clock, a variable
 * clocked by that (then its type, "Int64" or "Float64"), an unclocked Int64 output, a fixed and a
 * tunable Float64 parameter; then the periodic clock's interval. Every case starts from a fresh
 * instance driven legally to the state it needs; a misuse must return fmi3Error or fmi3Discard
 * and log a message containing the given text (or, without a live instance, just fail). Output
 * as misuse_harness.h describes. */
#define HARNESS_FUNCTIONS(X)                                                                       \
    X(InstantiateCoSimulation) X(InstantiateModelExchange) X(FreeInstance)                          \
    X(EnterInitializationMode) X(ExitInitializationMode) X(EnterEventMode) X(EnterStepMode)         \
    X(Terminate) X(Reset) X(DoStep) X(UpdateDiscreteStates) X(GetFloat64) X(SetFloat64)             \
    X(GetInt64) X(SetInt64) X(GetClock) X(SetClock) X(GetIntervalDecimal) X(GetShiftDecimal)

#include "misuse_harness.h"

static fmu_api fmu;
static const char *token, *resources;
static fmi3ValueReference periodic, triggered, clocked_input, output_clock, clocked_output, output, fixed, tunable;
static int clocked_output_is_float;
static double interval;

#define STOP_TIME 10.0

/* ---- driving an instance ------------------------------------------------------------------ */

/* The states a case starts from. EVENT is the first instant after initialization, not yet
 * closed; CLOSED is Event Mode after that instant's fmi3UpdateDiscreteStates; STEP is Step Mode
 * at t = 0; LATER is Event Mode at t = interval / 2, between two ticks of the periodic clock. */
typedef enum { INSTANTIATED, INITIALIZATION, EVENT, CLOSED, STEP, LATER, TERMINATED } start;
static const char *const start_names[] = {"Instantiated", "Initialization Mode", "Event Mode", "Event Mode",
                                          "Step Mode", "Event Mode", "Terminated"};

static fmi3Instance instantiate(void)
{
    fmi3Instance inst = fmu.InstantiateCoSimulation("misuse", token, resources, fmi3False, fmi3True, fmi3True,
                                                    fmi3True, NULL, 0, NULL, capture_log, NULL);
    if (inst == NULL) {
        printf("Bail out! cannot instantiate (last log: %s)\n", last_log);
        exit(2);
    }
    return inst;
}

static fmi3Status set_clock(fmi3Instance inst, fmi3ValueReference vr, fmi3Clock value)
{
    return fmu.SetClock(inst, &vr, 1, &value);
}

static fmi3Status get_clock(fmi3Instance inst, fmi3ValueReference vr)
{
    fmi3Clock value;
    return fmu.GetClock(inst, &vr, 1, &value);
}

static fmi3Status update(fmi3Instance inst)
{
    fmi3Boolean need, terminate, nominals, values, defined;
    fmi3Float64 next;
    return fmu.UpdateDiscreteStates(inst, &need, &terminate, &nominals, &values, &defined, &next);
}

static fmi3Status step(fmi3Instance inst, double t, double h)
{
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return fmu.DoStep(inst, t, h, fmi3True, &event, &terminate, &early, &last);
}

static fmi3Status get_int64(fmi3Instance inst, fmi3ValueReference vr)
{
    fmi3Int64 value;
    return fmu.GetInt64(inst, &vr, 1, &value, 1);
}

static fmi3Status set_int64(fmi3Instance inst, fmi3ValueReference vr, fmi3Int64 value)
{
    return fmu.SetInt64(inst, &vr, 1, &value, 1);
}

static fmi3Status set_float64(fmi3Instance inst, fmi3ValueReference vr, fmi3Float64 value)
{
    return fmu.SetFloat64(inst, &vr, 1, &value, 1);
}

static fmi3Status get_clocked_output(fmi3Instance inst)
{
    fmi3Float64 real;
    fmi3Int64 integer;
    return clocked_output_is_float ? fmu.GetFloat64(inst, &clocked_output, 1, &real, 1)
                                   : fmu.GetInt64(inst, &clocked_output, 1, &integer, 1);
}

/* A fresh instance in state `where`, reached by legal calls only. */
static fmi3Instance at(start where)
{
    fmi3Instance inst = instantiate();
    if (where == INSTANTIATED) return inst;
    require("EnterInitializationMode", fmu.EnterInitializationMode(inst, fmi3False, 0.0, 0.0, fmi3True, STOP_TIME));
    if (where == INITIALIZATION) return inst;
    require("ExitInitializationMode", fmu.ExitInitializationMode(inst));
    require("SetClock(periodic) at t=0", set_clock(inst, periodic, fmi3ClockActive));
    if (where == EVENT) return inst;
    require("UpdateDiscreteStates", update(inst));
    if (where == CLOSED) return inst;
    require("EnterStepMode", fmu.EnterStepMode(inst));
    if (where == STEP) return inst;
    if (where == LATER) {
        require("DoStep to half an interval", step(inst, 0.0, interval / 2));
        require("EnterEventMode", fmu.EnterEventMode(inst));
        return inst;
    }
    require("Terminate", fmu.Terminate(inst));
    return inst;
}

/* A misuse from a fresh instance in state `where` (`fresh` in `call`). */
#define FROM(where, name, expected, call)           \
    do {                                            \
        fmi3Instance fresh = at(where);             \
        MISUSE(name, expected, call);               \
        fmu.FreeInstance(fresh);                    \
    } while (0)

/* A legal call from a fresh instance in state `where`: the control next to the misuses. */
#define LEGAL(where, name, call)                                                                  \
    do {                                                                                          \
        fmi3Instance fresh = at(where);                                                           \
        fmi3Status status_ = (call);                                                              \
        report(name, status_ == fmi3OK || status_ == fmi3Warning, last_log);                      \
        fmu.FreeInstance(fresh);                                                                  \
    } while (0)

/* ---- the cases ---------------------------------------------------------------------------- */

/* Which function each state allows (FMI 3.0 §4.2, Co-Simulation with Event Mode). */
enum { F_ENTER_INIT, F_EXIT_INIT, F_ENTER_EVENT, F_ENTER_STEP, F_TERMINATE, F_UPDATE, F_DO_STEP, F_SET_CLOCK,
       F_GET_CLOCK, F_GET, F_COUNT };
static const char *const function_names[F_COUNT] = {
    "fmi3EnterInitializationMode", "fmi3ExitInitializationMode", "fmi3EnterEventMode", "fmi3EnterStepMode",
    "fmi3Terminate", "fmi3UpdateDiscreteStates", "fmi3DoStep", "fmi3SetClock", "fmi3GetClock", "fmi3GetInt64"};
/* allowed[f] lists the starts in which function f is legal; the others are misuses */
static const int allowed[F_COUNT][7] = {
    /*                 INSTANTIATED INITIALIZATION EVENT CLOSED STEP LATER TERMINATED */
    [F_ENTER_INIT] = {1, 0, 0, 0, 0, 0, 0},
    [F_EXIT_INIT] = {0, 1, 0, 0, 0, 0, 0},
    [F_ENTER_EVENT] = {0, 0, 0, 0, 1, 0, 0},
    [F_ENTER_STEP] = {0, 0, 1, 1, 0, 1, 0},
    [F_TERMINATE] = {0, 0, 1, 1, 1, 1, 0},
    [F_UPDATE] = {0, 0, 1, 1, 0, 1, 0},
    [F_DO_STEP] = {0, 0, 0, 0, 1, 0, 0},
    [F_SET_CLOCK] = {0, 0, 1, 1, 0, 1, 0},
    [F_GET_CLOCK] = {0, 1, 1, 1, 0, 1, 0},
    [F_GET] = {0, 1, 1, 1, 1, 1, 1},
};

static fmi3Status call(int function, fmi3Instance inst)
{
    switch (function) {
    case F_ENTER_INIT: return fmu.EnterInitializationMode(inst, fmi3False, 0.0, 0.0, fmi3False, 0.0);
    case F_EXIT_INIT: return fmu.ExitInitializationMode(inst);
    case F_ENTER_EVENT: return fmu.EnterEventMode(inst);
    case F_ENTER_STEP: return fmu.EnterStepMode(inst);
    case F_TERMINATE: return fmu.Terminate(inst);
    case F_UPDATE: return update(inst);
    case F_DO_STEP: return step(inst, 0.0, interval / 2);
    case F_SET_CLOCK: return set_clock(inst, triggered, fmi3ClockActive);
    case F_GET_CLOCK: return get_clock(inst, output_clock);
    default: return get_int64(inst, output);
    }
}

/* Every function in every state that does not allow it: refused, the log naming the state. */
static void states(void)
{
    static const start starts[] = {INSTANTIATED, INITIALIZATION, CLOSED, STEP, TERMINATED};
    char name[160], expected[80];
    size_t s;
    int f;
    for (f = 0; f < F_COUNT; ++f) {
        for (s = 0; s < sizeof starts / sizeof starts[0]; ++s) {
            if (allowed[f][starts[s]]) continue;
            snprintf(name, sizeof name, "state: %s in %s", function_names[f], start_names[starts[s]]);
            snprintf(expected, sizeof expected, "not allowed in %s", start_names[starts[s]]);
            FROM(starts[s], name, expected, call(f, fresh));
        }
    }
    LEGAL(TERMINATED, "state: fmi3GetInt64 of an output in Terminated", get_int64(fresh, output));
    LEGAL(TERMINATED, "state: fmi3Reset in Terminated", fmu.Reset(fresh));
    LEGAL(STEP, "state: fmi3Reset in Step Mode", fmu.Reset(fresh));
    LEGAL(INITIALIZATION, "state: fmi3GetClock of an output clock in Initialization Mode", get_clock(fresh, output_clock));
}

static void event_iteration(void)
{
    FROM(EVENT, "event iteration: fmi3EnterStepMode before fmi3UpdateDiscreteStates", "fmi3EnterStepMode",
         fmu.EnterStepMode(fresh));
    FROM(CLOSED, "event iteration: fmi3EnterStepMode with an input clock set after the update", "fmi3EnterStepMode",
         (set_clock(fresh, triggered, fmi3ClockActive), fmu.EnterStepMode(fresh)));
    LEGAL(CLOSED, "event iteration: fmi3EnterStepMode after fmi3UpdateDiscreteStates", fmu.EnterStepMode(fresh));
    LEGAL(CLOSED, "event iteration: a triggered clock in a second instant", set_clock(fresh, triggered, fmi3ClockActive));
}

static void clocks(void)
{
    FROM(CLOSED, "clock: fmi3SetClock of an output clock", "fmi3SetClock", set_clock(fresh, output_clock, fmi3ClockActive));
    FROM(EVENT, "clock: fmi3SetClock(inactive) of an active clock without canBeDeactivated", "cannot be deactivated",
         set_clock(fresh, periodic, fmi3ClockInactive));
    FROM(CLOSED, "clock: the periodic clock twice in one Event Mode", "fmi3SetClock",
         set_clock(fresh, periodic, fmi3ClockActive));
    FROM(LATER, "clock: the periodic clock between two ticks", "fmi3SetClock", set_clock(fresh, periodic, fmi3ClockActive));
    FROM(CLOSED, "clock: fmi3GetIntervalDecimal of a triggered clock", "fmi3GetIntervalDecimal",
         fmu.GetIntervalDecimal(fresh, &triggered, 1, (fmi3Float64[1]){0}, (fmi3IntervalQualifier[1]){0}));
    LEGAL(INITIALIZATION, "clock: fmi3GetIntervalDecimal of the periodic clock in Initialization Mode",
          fmu.GetIntervalDecimal(fresh, &periodic, 1, (fmi3Float64[1]){0}, (fmi3IntervalQualifier[1]){0}));
    LEGAL(INITIALIZATION, "clock: fmi3GetShiftDecimal of the periodic clock in Initialization Mode",
          fmu.GetShiftDecimal(fresh, &periodic, 1, (fmi3Float64[1]){0}));
    FROM(CLOSED, "clock: fmi3GetShiftDecimal in Event Mode", "not allowed in Event Mode",
         fmu.GetShiftDecimal(fresh, &periodic, 1, (fmi3Float64[1]){0}));
    LEGAL(LATER, "clock: the triggered clock between two ticks", set_clock(fresh, triggered, fmi3ClockActive));
}

static void values(void)
{
    FROM(CLOSED, "clocked: an output read while its clock is inactive", "not active", get_clocked_output(fresh));
    FROM(CLOSED, "clocked: an input set while its clock is inactive", "not active", set_int64(fresh, clocked_input, 1));
    FROM(STEP, "clocked: an output read in Step Mode", "clocked", get_clocked_output(fresh));
    FROM(STEP, "clocked: an input set in Step Mode", "clocked", set_int64(fresh, clocked_input, 1));
    LEGAL(CLOSED, "clocked: an input set while its clock is active",
          (set_clock(fresh, triggered, fmi3ClockActive), set_int64(fresh, clocked_input, 1)));
    LEGAL(INITIALIZATION, "clocked: an input set in Initialization Mode", set_int64(fresh, clocked_input, 1));
    FROM(CLOSED, "causality: fmi3SetInt64 of an output", "cannot be set", set_int64(fresh, output, 1));
    FROM(CLOSED, "variability: a fixed parameter set in Event Mode", "cannot be set", set_float64(fresh, fixed, 1.0));
    FROM(STEP, "variability: a fixed parameter set in Step Mode", "cannot be set", set_float64(fresh, fixed, 1.0));
    LEGAL(INSTANTIATED, "variability: a fixed parameter set in Instantiated", set_float64(fresh, fixed, 1.0));
    LEGAL(INITIALIZATION, "variability: a fixed parameter set in Initialization Mode", set_float64(fresh, fixed, 1.0));
    LEGAL(STEP, "variability: a tunable parameter set in Step Mode", set_float64(fresh, tunable, 1.0));
    FROM(STEP, "step: fmi3GetInt64 after a set in Step Mode, before fmi3DoStep", "fmi3GetInt64",
         (set_float64(fresh, tunable, 1.0), get_int64(fresh, output)));
}

static void steps(void)
{
    FROM(STEP, "step: from a time that is not the FMU's", "fmi3DoStep", step(fresh, interval / 4, interval / 4));
    FROM(STEP, "step: a step size of 0", "fmi3DoStep", step(fresh, 0.0, 0.0));
    FROM(STEP, "step: a negative step size", "fmi3DoStep", step(fresh, 0.0, -interval));
    FROM(STEP, "step: past stopTime", "stopTime", step(fresh, 0.0, 2 * STOP_TIME));
    LEGAL(STEP, "step: half an interval", step(fresh, 0.0, interval / 2));
}

static void after_an_error(void)
{
    FROM(STEP, "after an error: fmi3DoStep", "not allowed in Terminated",
         (set_clock(fresh, periodic, fmi3ClockActive), step(fresh, 0.0, interval / 2)));
    FROM(CLOSED, "after an error: fmi3UpdateDiscreteStates", "not allowed in Terminated",
         (set_clock(fresh, output_clock, fmi3ClockActive), update(fresh)));
    LEGAL(STEP, "after an error: fmi3Reset, then fmi3EnterInitializationMode",
          (set_clock(fresh, periodic, fmi3ClockActive), fmu.Reset(fresh),
           fmu.EnterInitializationMode(fresh, fmi3False, 0.0, 0.0, fmi3False, 0.0)));
}

static void instantiation(void)
{
    size_t before = log_count;
    fmi3Instance made = fmu.InstantiateCoSimulation("misuse", "{not-the-token}", resources, fmi3False, fmi3True,
                                                    fmi3True, fmi3True, NULL, 0, NULL, capture_log, NULL);
    report_misuse("instantiate: a wrong instantiationToken", made == NULL && log_count > before, "an instance was returned");
    before = log_count;
    made = fmu.InstantiateCoSimulation("misuse", token, resources, fmi3False, fmi3True, fmi3False, fmi3True, NULL, 0,
                                       NULL, capture_log, NULL);
    report_misuse("instantiate: eventModeUsed=false on an FMU with clocks", made == NULL && log_count > before,
                  "an instance was returned");
    before = log_count;
    made = fmu.InstantiateModelExchange("misuse", token, resources, fmi3False, fmi3True, NULL, capture_log);
    report_misuse("instantiate: Model Exchange", made == NULL && log_count > before, "an instance was returned");
    MISUSE_UNLOGGABLE("NULL instance: fmi3DoStep", step(NULL, 0.0, 1.0));
    MISUSE_UNLOGGABLE("NULL instance: fmi3EnterStepMode", fmu.EnterStepMode(NULL));
}

static unsigned long role(const char *text)
{
    char *end;
    unsigned long value = strtoul(text, &end, 10);
    if (*end != '\0') {
        fprintf(stderr, "not a value reference: %s\n", text);
        exit(2);
    }
    return value;
}

int main(int argc, char **argv)
{
    if (argc != 14 || !load(argv[1], &fmu)) {
        fprintf(stderr, "usage: misuse_python <library.so> <token> <resources> <periodic> <triggered> <clocked input> "
                        "<output clock> <clocked output> <Int64|Float64> <output> <fixed> <tunable> <interval>\n");
        return 2;
    }
    token = argv[2];
    resources = argv[3];
    periodic = (fmi3ValueReference)role(argv[4]);
    triggered = (fmi3ValueReference)role(argv[5]);
    clocked_input = (fmi3ValueReference)role(argv[6]);
    output_clock = (fmi3ValueReference)role(argv[7]);
    clocked_output = (fmi3ValueReference)role(argv[8]);
    clocked_output_is_float = strcmp(argv[9], "Float64") == 0;
    output = (fmi3ValueReference)role(argv[10]);
    fixed = (fmi3ValueReference)role(argv[11]);
    tunable = (fmi3ValueReference)role(argv[12]);
    interval = strtod(argv[13], NULL);
    instantiation();
    states();
    event_iteration();
    clocks();
    values();
    steps();
    after_an_error();
    return harness_finish();
}
