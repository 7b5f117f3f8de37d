/* API misuse against FMUs that robogen generated, as a plain C importer.
 *
 *     misuse_generated <ur5e.so> <arith.so>
 *
 * Compiled with -include of a header that test_misuse_generated.py writes from the two FMUs'
 * modelDescription.xml (tokens and value references: UR5E_*, ARITH_*). The UR5e d-model is called
 * wrongly in every way the runtime must refuse; arith.rst's run-time errors (division by zero,
 * a runaway cycle, a deadlock, a real out of range) must each end in fmi3Error with a message.
 * Every misuse must return fmi3Error or fmi3Discard and log why (or, with no live instance to
 * log through, report on stderr); nothing may crash. Built with -fsanitize=address,undefined so
 * that any memory error, undefined behaviour or leak in the runtime or the generated code stops
 * the run; 1,000 instantiate/drive/free cycles end it.
 *
 * Output: "ok <n> - <kind>: <name>" or "not ok <n> - <kind>: <name>: <why>" per case, kind
 * "misuse" or "check", then "# cases <n> misuse <k> failures <m>"; exit 0 only without failures.
 */
#include <math.h>
#include <stdint.h>

#define HARNESS_FUNCTIONS(X)                                                                       \
    X(InstantiateCoSimulation) X(InstantiateModelExchange) X(InstantiateScheduledExecution)         \
    X(FreeInstance) X(EnterInitializationMode) X(ExitInitializationMode) X(EnterEventMode)          \
    X(EnterStepMode) X(Terminate) X(Reset) X(DoStep) X(UpdateDiscreteStates) X(GetFloat64)          \
    X(GetInt64) X(SetInt64) X(GetUInt64) X(SetUInt64) X(SetFloat64) X(GetString) X(GetClock) X(SetClock)          \
    X(GetIntervalDecimal) X(SetIntervalDecimal) X(GetFMUState) X(SetFMUState) X(FreeFMUState)       \
    X(SerializedFMUStateSize) X(SerializeFMUState) X(DeserializeFMUState) X(SetTime)                 \
    X(GetDirectionalDerivative) X(EvaluateDiscreteStates) X(GetNumberOfVariableDependencies)

#include "misuse_harness.h"

/* ---- driving an instance ------------------------------------------------------------------ */

static fmu_api ur5e, arith;

typedef enum { INSTANTIATED, INITIALIZATION, EVENT, STEP } target;

static fmi3Instance create(const fmu_api *f, const char *token, const char *name)
{
    fmi3Instance inst = f->InstantiateCoSimulation(name, token, NULL, fmi3False, fmi3True, fmi3True, fmi3False,
                                                   NULL, 0, NULL, capture_log, NULL);
    if (inst == NULL) {
        printf("Bail out! cannot instantiate %s (last log: %s)\n", name, last_log);
        exit(2);
    }
    return inst;
}

static fmi3Status update(const fmu_api *f, fmi3Instance inst, fmi3Boolean *need)
{
    fmi3Boolean n, term, nominals, values, defined;
    fmi3Float64 next;
    fmi3Status status = f->UpdateDiscreteStates(inst, &n, &term, &nominals, &values, &defined, &next);
    if (need != NULL) *need = n;
    return status;
}

static fmi3Status step(const fmu_api *f, fmi3Instance inst, double t, double h)
{
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return f->DoStep(inst, t, h, fmi3True, &event, &terminate, &early, &last);
}

static fmi3Status tick(const fmu_api *f, fmi3Instance inst, fmi3ValueReference clock)
{
    const fmi3Clock on = fmi3ClockActive;
    return f->SetClock(inst, &clock, 1, &on);
}

/* Close the instant and every following one (stepwise FMUs need several). */
static fmi3Status settle(const fmu_api *f, fmi3Instance inst)
{
    fmi3Boolean need = fmi3True;
    fmi3Status status = fmi3OK;
    int guard = 0;
    while (need && status <= fmi3Warning && guard++ < 10000) status = update(f, inst, &need);
    return status;
}

/* The UR5e FMU at t=0 in the target state; STEP has run the first cycle. */
static fmi3Instance ur5e_at(target where, double stop_time)
{
    fmi3Instance inst = create(&ur5e, UR5E_TOKEN, "ur5e");
    if (where == INSTANTIATED) return inst;
    require("EnterInitializationMode", ur5e.EnterInitializationMode(inst, fmi3False, 0.0, 0.0, stop_time > 0.0, stop_time));
    if (where == INITIALIZATION) return inst;
    require("ExitInitializationMode", ur5e.ExitInitializationMode(inst));
    if (where == EVENT) return inst;
    require("SetClock(cycle)", tick(&ur5e, inst, UR5E_VR_CYCLE));
    require("UpdateDiscreteStates", settle(&ur5e, inst));
    require("EnterStepMode", ur5e.EnterStepMode(inst));
    return inst;
}

#define FRESH(where, name, expected, call)          \
    do {                                            \
        fmi3Instance fresh = ur5e_at(where, 0.0);   \
        MISUSE(name, expected, call);               \
        ur5e.FreeInstance(fresh);                   \
    } while (0)

/* The UR5e story (move, feasible, completed, stopped), as test_ur5e_traces.py tells it; returns
 * the number of movediscrete calls seen with the command's arguments and checks every step. */
static int ur5e_story(fmi3Instance inst, int *stops)
{
    int moves = 0, t;
    *stops = 0;
    for (t = 0; t <= 6; ++t) {
        fmi3ValueReference clocks[2] = {UR5E_VR_MOVE, UR5E_VR_STOP};
        fmi3Clock active[2];
        fmi3Boolean need = fmi3True;
        if (t > 0) {
            require("EnterStepMode", ur5e.EnterStepMode(inst));
            require("DoStep", step(&ur5e, inst, t - 1.0, 1.0));
            require("EnterEventMode", ur5e.EnterEventMode(inst));
        }
        require("SetClock(cycle)", tick(&ur5e, inst, UR5E_VR_CYCLE));
        if (t == 1) {
            const fmi3ValueReference args[3] = {UR5E_VR_COMMAND_X, UR5E_VR_COMMAND_X + 1, UR5E_VR_COMMAND_X + 2};
            const fmi3Int64 values[3] = {0, 23, 1};
            require("SetClock(command)", tick(&ur5e, inst, UR5E_VR_COMMAND));
            require("SetInt64(command)", ur5e.SetInt64(inst, args, 3, values, 3));
        }
        if (t == 2) require("SetClock(feasible)", tick(&ur5e, inst, UR5E_VR_FEASIBLE));
        if (t == 4) require("SetClock(completed)", tick(&ur5e, inst, UR5E_VR_COMPLETED));
        if (t == 5) require("SetClock(stopped)", tick(&ur5e, inst, UR5E_VR_STOPPED));
        while (need) {
            require("GetClock", ur5e.GetClock(inst, clocks, 2, active));
            if (active[0]) {
                const fmi3ValueReference args[3] = {UR5E_VR_MOVE_X, UR5E_VR_MOVE_X + 1, UR5E_VR_MOVE_X + 2};
                fmi3Int64 values[3];
                require("GetInt64(movediscrete)", ur5e.GetInt64(inst, args, 3, values, 3));
                if (values[0] == 0 && values[1] == 23 && values[2] == 1) moves += 1;
            }
            if (active[1]) *stops += 1;
            require("UpdateDiscreteStates", update(&ur5e, inst, &need));
        }
    }
    return moves;
}

/* ---- the cases ---------------------------------------------------------------------------- */

static void instantiation(void)
{
    const fmi3ValueReference vr = UR5E_VR_STATE;
    size_t before;
#define REFUSED(name, expected, expr)                                                              \
    before = log_count;                                                                            \
    {                                                                                              \
        fmi3Instance made = (expr);                                                                \
        report_misuse(name, made == NULL && log_count > before && strstr(last_log, expected) != NULL, \
                      made != NULL ? "an instance was returned" : last_log);                       \
    }
    REFUSED("instantiate: wrong token", "does not match this binary",
            ur5e.InstantiateCoSimulation("u", "{0}", NULL, 0, 1, 1, 0, NULL, 0, NULL, capture_log, NULL))
    REFUSED("instantiate: NULL token", "instantiationToken '(NULL)'",
            ur5e.InstantiateCoSimulation("u", NULL, NULL, 0, 1, 1, 0, NULL, 0, NULL, capture_log, NULL))
    REFUSED("instantiate: NULL instance name", "instanceName must be a non-empty string",
            ur5e.InstantiateCoSimulation(NULL, UR5E_TOKEN, NULL, 0, 1, 1, 0, NULL, 0, NULL, capture_log, NULL))
    REFUSED("instantiate: eventModeUsed=false on an FMU with clocks", "eventModeUsed must be true",
            ur5e.InstantiateCoSimulation("u", UR5E_TOKEN, NULL, 0, 1, 0, 0, NULL, 0, NULL, capture_log, NULL))
    REFUSED("instantiate: requiredIntermediateVariables", "provides no intermediate update",
            ur5e.InstantiateCoSimulation("u", UR5E_TOKEN, NULL, 0, 1, 1, 0, &vr, 1, NULL, capture_log, NULL))
    REFUSED("instantiate: Model Exchange", "supports Co-Simulation only",
            ur5e.InstantiateModelExchange("u", UR5E_TOKEN, NULL, 0, 1, NULL, capture_log))
    REFUSED("instantiate: Scheduled Execution", "supports Co-Simulation only",
            ur5e.InstantiateScheduledExecution("u", UR5E_TOKEN, NULL, 0, 1, NULL, capture_log, NULL, NULL, NULL))
#undef REFUSED
    report_misuse("instantiate: wrong token and no logMessage", ur5e.InstantiateCoSimulation(
        "u", "{0}", NULL, 0, 1, 1, 0, NULL, 0, NULL, NULL, NULL) == NULL, "an instance was returned");
}

static void handles(void)
{
    fmi3ValueReference vr = UR5E_VR_STATE;
    fmi3Int64 value;
    fmi3Clock clock;
    uintptr_t stale;
    fmi3Instance inst;
    MISUSE("NULL instance: fmi3DoStep", NULL, step(&ur5e, NULL, 0.0, 1.0));
    MISUSE("NULL instance: fmi3GetInt64", NULL, ur5e.GetInt64(NULL, &vr, 1, &value, 1));
    ur5e.FreeInstance(NULL);
    report("NULL instance: fmi3FreeInstance ignores it", 1, "");
    inst = ur5e_at(STEP, 0.0);
    stale = (uintptr_t)inst; /* kept as an integer: the harness never uses a dangling pointer */
    ur5e.FreeInstance(inst);
    ur5e.FreeInstance((fmi3Instance)stale);
    report_misuse("double fmi3FreeInstance: ignored, no crash", 1, "");
    MISUSE("freed instance: fmi3DoStep", NULL, step(&ur5e, (fmi3Instance)stale, 0.0, 1.0));
    MISUSE("freed instance: fmi3GetClock", NULL, ur5e.GetClock((fmi3Instance)stale, &vr, 1, &clock));
    inst = create(&arith, ARITH_TOKEN, "arith");
    MISUSE("foreign instance: the UR5e FMU's fmi3Reset on an arith instance", NULL, ur5e.Reset(inst));
    arith.FreeInstance(inst);
}

static void modes(void)
{
    fmi3ValueReference state = UR5E_VR_STATE, cycle = UR5E_VR_CYCLE, move = UR5E_VR_MOVE;
    fmi3Int64 value;
    fmi3Clock clock;
    fmi3Instance inst;
    FRESH(INSTANTIATED, "wrong state: fmi3DoStep in Instantiated", "not allowed in Instantiated", step(&ur5e, fresh, 0.0, 1.0));
    FRESH(INSTANTIATED, "wrong state: fmi3ExitInitializationMode in Instantiated", "not allowed in Instantiated",
          ur5e.ExitInitializationMode(fresh));
    FRESH(INSTANTIATED, "wrong state: fmi3GetInt64 in Instantiated", "not allowed in Instantiated",
          ur5e.GetInt64(fresh, &state, 1, &value, 1));
    FRESH(INITIALIZATION, "wrong state: fmi3SetClock in Initialization Mode", "fmi3SetClock: not allowed",
          tick(&ur5e, fresh, UR5E_VR_CYCLE));
    FRESH(INITIALIZATION, "wrong state: fmi3DoStep in Initialization Mode", "fmi3DoStep: not allowed",
          step(&ur5e, fresh, 0.0, 1.0));
    FRESH(EVENT, "wrong state: fmi3EnterEventMode in Event Mode", "fmi3EnterEventMode: not allowed",
          ur5e.EnterEventMode(fresh));
    FRESH(EVENT, "event iteration: fmi3EnterStepMode before fmi3UpdateDiscreteStates", "event iteration is not finished",
          ur5e.EnterStepMode(fresh));
    FRESH(STEP, "wrong state: fmi3UpdateDiscreteStates in Step Mode", "not allowed in Step Mode", update(&ur5e, fresh, NULL));
    FRESH(STEP, "wrong state: fmi3SetClock in Step Mode", "not allowed in Step Mode", tick(&ur5e, fresh, UR5E_VR_CYCLE));
    FRESH(STEP, "wrong state: fmi3GetClock in Step Mode", "not allowed in Step Mode", ur5e.GetClock(fresh, &move, 1, &clock));
    inst = ur5e_at(STEP, 0.0);
    require("Terminate", ur5e.Terminate(inst));
    MISUSE("wrong state: fmi3DoStep after fmi3Terminate", "not allowed in Terminated", step(&ur5e, inst, 0.0, 1.0));
    MISUSE("wrong state: fmi3Terminate twice", "not allowed in Terminated", ur5e.Terminate(inst));
    report("Terminated: the state output can still be read", ur5e.GetInt64(inst, &state, 1, &value, 1) == fmi3OK && value == UR5E_IDLE,
          last_log);
    report("Terminated: fmi3Reset leads back to Instantiated", ur5e.Reset(inst) == fmi3OK &&
          ur5e.EnterInitializationMode(inst, 0, 0.0, 0.0, 0, 0.0) == fmi3OK, last_log);
    ur5e.FreeInstance(inst);
    (void)cycle;
}

static void arguments(void)
{
    fmi3ValueReference unknown = 9999, state = UR5E_VR_STATE, cycle = UR5E_VR_CYCLE, local = UR5E_VR_LOCAL;
    fmi3ValueReference pair[2] = {UR5E_VR_STATE, UR5E_VR_LOCAL};
    fmi3Int64 values[3] = {0, 0, 0};
    fmi3Float64 real;
    fmi3String text;
    FRESH(STEP, "bad value reference: fmi3GetInt64 of vr 9999", "unknown value reference 9999",
          ur5e.GetInt64(fresh, &unknown, 1, values, 1));
    FRESH(STEP, "NULL argument: valueReferences", "valueReferences is NULL", ur5e.GetInt64(fresh, NULL, 1, values, 1));
    FRESH(STEP, "NULL argument: values", "values is NULL", ur5e.GetInt64(fresh, &state, 1, NULL, 1));
    FRESH(EVENT, "NULL argument: UpdateDiscreteStates outputs", "an output argument is NULL",
          ur5e.UpdateDiscreteStates(fresh, NULL, NULL, NULL, NULL, NULL, NULL));
    FRESH(STEP, "wrong type: fmi3GetFloat64 of the Enumeration state", "not Float64", ur5e.GetFloat64(fresh, &state, 1, &real, 1));
    FRESH(STEP, "wrong type: fmi3GetInt64 of the Clock cycle", "is a Clock", ur5e.GetInt64(fresh, &cycle, 1, values, 1));
    FRESH(STEP, "wrong count: nValues 3 for two scalars", "nValues is 3 but the 2 value reference(s) hold 2",
          ur5e.GetInt64(fresh, pair, 2, values, 3));
    FRESH(STEP, "no String variables: fmi3GetString", "not String", ur5e.GetString(fresh, &state, 1, &text, 1));
    FRESH(EVENT, "causality: fmi3SetInt64 of the output state", "cannot be set", ur5e.SetInt64(fresh, &state, 1, values, 1));
    FRESH(STEP, "causality: fmi3SetInt64 of a local variable of the machine", "cannot be set",
          ur5e.SetInt64(fresh, &local, 1, values, 1));
}

static void clocks(void)
{
    fmi3ValueReference move_x = UR5E_VR_MOVE_X, command = UR5E_VR_COMMAND, command_x = UR5E_VR_COMMAND_X;
    fmi3ValueReference cycle = UR5E_VR_CYCLE, state = UR5E_VR_STATE, move = UR5E_VR_MOVE;
    fmi3Int64 value = 4;
    fmi3Float64 interval;
    fmi3IntervalQualifier qualifier;
    const fmi3Clock off = fmi3ClockInactive;
    fmi3Instance inst;
    FRESH(STEP, "clocked access in Step Mode: fmi3GetInt64 of movediscrete.target_X", "clocked variables can be read only",
          ur5e.GetInt64(fresh, &move_x, 1, &value, 1));
    FRESH(STEP, "clocked access in Step Mode: fmi3SetInt64 of moveDiscreteCommand.target_X", "cannot be set in Step Mode",
          ur5e.SetInt64(fresh, &command_x, 1, &value, 1));
    FRESH(EVENT, "clocked output read while its clock is inactive", "which is not active",
          ur5e.GetInt64(fresh, &move_x, 1, &value, 1));
    FRESH(EVENT, "clocked input set while its clock is inactive", "which is not active",
          ur5e.SetInt64(fresh, &command_x, 1, &value, 1));
    FRESH(EVENT, "setting an output clock: fmi3SetClock(movediscrete)", "is an output clock", tick(&ur5e, fresh, UR5E_VR_MOVE));
    FRESH(EVENT, "fmi3SetClock on a variable that is not a clock", "not a Clock", tick(&ur5e, fresh, UR5E_VR_STATE));
    FRESH(EVENT, "deactivating an input clock without canBeDeactivated", "cannot be deactivated",
          (tick(&ur5e, fresh, UR5E_VR_COMMAND), ur5e.SetClock(fresh, &command, 1, &off)));
    FRESH(EVENT, "periodic clock activated after the instant was evaluated", "already evaluated",
          (ur5e.GetInt64(fresh, &state, 1, &value, 1), tick(&ur5e, fresh, UR5E_VR_CYCLE)));
    inst = ur5e_at(EVENT, 0.0);
    require("SetClock(command)", tick(&ur5e, inst, UR5E_VR_COMMAND));
    require("GetInt64(state) evaluates", ur5e.GetInt64(inst, &state, 1, &value, 1));
    MISUSE("clocked input set after its activation was consumed by the evaluation", "already consumed",
           ur5e.SetInt64(inst, &command_x, 1, &value, 1));
    ur5e.FreeInstance(inst);
    inst = ur5e_at(EVENT, 0.0);
    require("SetClock(cycle)", tick(&ur5e, inst, UR5E_VR_CYCLE));
    require("UpdateDiscreteStates", settle(&ur5e, inst));
    MISUSE("periodic clock: a second tick in the same Event Mode", "already ticked", tick(&ur5e, inst, UR5E_VR_CYCLE));
    ur5e.FreeInstance(inst);
    inst = ur5e_at(STEP, 0.0);
    require("DoStep to 0.5", step(&ur5e, inst, 0.0, 0.5));
    require("EnterEventMode", ur5e.EnterEventMode(inst));
    MISUSE("periodic clock: not due at t=0.5", "is not due", tick(&ur5e, inst, UR5E_VR_CYCLE));
    ur5e.FreeInstance(inst);
    FRESH(STEP, "periodic clock used, then a tick missed: fmi3DoStep past t=1", "would pass tick k=1",
          step(&ur5e, fresh, 0.0, 1.5));
    FRESH(INITIALIZATION, "interval: fmi3SetIntervalDecimal on the constant clock", "its interval is fixed",
          ur5e.SetIntervalDecimal(fresh, &cycle, 1, &interval));
    FRESH(INITIALIZATION, "interval: fmi3GetIntervalDecimal of a triggered clock", "only time-based clocks",
          ur5e.GetIntervalDecimal(fresh, &command, 1, &interval, &qualifier));
    inst = ur5e_at(INITIALIZATION, 0.0);
    report("interval: the cycle clock's interval is 1 s", ur5e.GetIntervalDecimal(inst, &cycle, 1, &interval, &qualifier) ==
          fmi3OK && interval == 1.0, last_log);
    ur5e.FreeInstance(inst);
    (void)move;
}

static void steps(void)
{
    fmi3Boolean event, terminate, early;
    fmi3Instance inst;
    FRESH(STEP, "DoStep: step size 0", "communicationStepSize must be > 0", step(&ur5e, fresh, 0.0, 0.0));
    FRESH(STEP, "DoStep: negative step size", "communicationStepSize must be > 0", step(&ur5e, fresh, 0.0, -1.0));
    FRESH(STEP, "DoStep: NaN step size", "communicationStepSize must be > 0", step(&ur5e, fresh, 0.0, nan("")));
    FRESH(STEP, "DoStep: starts where the FMU is not", "differs from the FMU's time", step(&ur5e, fresh, 0.25, 0.5));
    FRESH(STEP, "DoStep: NULL lastSuccessfulTime", "an output argument is NULL",
          ur5e.DoStep(fresh, 0.0, 1.0, fmi3True, &event, &terminate, &early, NULL));
    inst = ur5e_at(STEP, 0.5);
    MISUSE("DoStep: past stopTime", "past stopTime", step(&ur5e, inst, 0.0, 1.0));
    ur5e.FreeInstance(inst);
}

static void states_and_unsupported(void)
{
    fmi3FMUState state = NULL, copy = NULL;
    fmi3ValueReference vr = UR5E_VR_STATE;
    fmi3Float64 value;
    size_t size = 0, n;
    fmi3Byte *bytes;
    fmi3Instance inst;
    FRESH(STEP, "FMU state: fmi3SetFMUState(NULL)", "FMUState is NULL", ur5e.SetFMUState(fresh, NULL));
    FRESH(STEP, "FMU state: fmi3GetFMUState with a NULL pointer", "FMUState is NULL", ur5e.GetFMUState(fresh, NULL));
    inst = ur5e_at(STEP, 0.0);
    require("GetFMUState", ur5e.GetFMUState(inst, &state));
    require("SerializedFMUStateSize", ur5e.SerializedFMUStateSize(inst, state, &size));
    bytes = (fmi3Byte *)malloc(size);
    require("SerializeFMUState", ur5e.SerializeFMUState(inst, state, bytes, size));
    MISUSE("FMU state: deserialize truncated data", "truncated", ur5e.DeserializeFMUState(inst, bytes, size - 8, &copy));
    ur5e.FreeInstance(inst); /* frees its states too */
    inst = ur5e_at(STEP, 0.0);
    bytes[size / 2] ^= 0x5a;
    copy = NULL;
    MISUSE("FMU state: deserialize corrupted data", "checksum mismatch", ur5e.DeserializeFMUState(inst, bytes, size, &copy));
    ur5e.FreeInstance(inst);
    free(bytes);
    FRESH(STEP, "unsupported: fmi3GetDirectionalDerivative", "providesDirectionalDerivatives is false",
          ur5e.GetDirectionalDerivative(fresh, &vr, 1, &vr, 1, &value, 1, &value, 1));
    FRESH(STEP, "unsupported: fmi3SetTime (Model Exchange)", "Model Exchange", ur5e.SetTime(fresh, 1.0));
    FRESH(EVENT, "unsupported: fmi3EvaluateDiscreteStates", "providesEvaluateDiscreteStates is false",
          ur5e.EvaluateDiscreteStates(fresh));
    FRESH(STEP, "unsupported: fmi3GetNumberOfVariableDependencies", "providesPerElementDependencies is false",
          ur5e.GetNumberOfVariableDependencies(fresh, UR5E_VR_STATE, &n));
}

/* arith.rst: each run-time error of the generated code is an fmi3Error with its reason. */
static void model_errors(void)
{
    /* t=0: Compute, no operand: Idle at t=1, where the operand arrives (the real x reaches
     * Compute, where it is converted, only with a at t=2) */
    struct {
        const char *name, *expected;
        fmi3ValueReference clock, value;
        char type; /* i: Int64, u: UInt64, r: Float64 */
        double value_of;
        int then_a;
    } errors[] = {
        {"model error: division by zero (b = 0)", "division by zero", ARITH_VR_B, ARITH_VR_B_VALUE, 'i', 0.0, 0},
        {"model error: a real out of range for an int (x = 1e19)", "out of range for an integer", ARITH_VR_X, ARITH_VR_X_VALUE, 'r', 1e19, 1},
        {"model error: a cycle that never reaches exec (n = 7)", "runaway cycle", ARITH_VR_N, ARITH_VR_N_VALUE, 'u', 7.0, 0},
        {"model error: a deadlock (x = 3.0)", "deadlock in state 'Stuck'", ARITH_VR_X, ARITH_VR_X_VALUE, 'r', 3.0, 0},
    };
    size_t i;
    for (i = 0; i < sizeof errors / sizeof errors[0]; ++i) {
        fmi3Instance inst = create(&arith, ARITH_TOKEN, "arith");
        fmi3Status status = fmi3OK;
        int t;
        size_t before;
        require("EnterInitializationMode", arith.EnterInitializationMode(inst, 0, 0.0, 0.0, 0, 0.0));
        require("ExitInitializationMode", arith.ExitInitializationMode(inst));
        before = log_count;
        begin_case();
        for (t = 0; t < 4 && status <= fmi3Warning; ++t) {
            if (t > 0) {
                require("EnterStepMode", arith.EnterStepMode(inst));
                require("DoStep", step(&arith, inst, t - 1.0, 1.0));
                require("EnterEventMode", arith.EnterEventMode(inst));
            }
            require("SetClock(cycle)", tick(&arith, inst, ARITH_VR_CYCLE));
            if (t == 1) {
                const fmi3Float64 real = errors[i].value_of;
                require("SetClock(operand)", tick(&arith, inst, errors[i].clock));
                if (errors[i].type == 'r') {
                    require("SetFloat64", arith.SetFloat64(inst, &errors[i].value, 1, &real, 1));
                } else if (errors[i].type == 'i') {
                    const fmi3Int64 integer = (fmi3Int64)real; /* small values only */
                    require("SetInt64", arith.SetInt64(inst, &errors[i].value, 1, &integer, 1));
                } else {
                    const fmi3UInt64 natural = (fmi3UInt64)real;
                    require("SetUInt64", arith.SetUInt64(inst, &errors[i].value, 1, &natural, 1));
                }
            }
            if (t == 2 && errors[i].then_a) {
                const fmi3ValueReference a = ARITH_VR_A_VALUE;
                const fmi3Int64 one = 1;
                require("SetClock(a)", tick(&arith, inst, ARITH_VR_A));
                require("SetInt64(a)", arith.SetInt64(inst, &a, 1, &one, 1));
            }
            status = settle(&arith, inst);
        }
        expect_failure(errors[i].name, status, before, errors[i].expected);
        arith.FreeInstance(inst);
    }
}

/* 1,000 instantiate/free cycles, half of them driving the whole UR5e story; some keep FMU states
 * that fmi3FreeInstance must release. */
static void lifecycle(void)
{
    int i, wrong = 0;
    for (i = 0; i < 1000; ++i) {
        fmi3Instance inst = ur5e_at(i % 2 ? INITIALIZATION : INSTANTIATED, 0.0);
        fmi3FMUState state = NULL;
        if (i % 2) {
            int stops, moves;
            require("ExitInitializationMode", ur5e.ExitInitializationMode(inst));
            moves = ur5e_story(inst, &stops);
            if (moves != 2 || stops != 1) wrong += 1;
        }
        if (i % 3 == 0) require("GetFMUState", ur5e.GetFMUState(inst, &state));
        ur5e.FreeInstance(inst);
    }
    report("1000 instantiate/free cycles, 500 of them driving the UR5e story (movediscrete(0, 23, 1) twice, stop once)",
          wrong == 0, "a run of the story went wrong");
}

int main(int argc, char **argv)
{
    if (argc != 3 || !load(argv[1], &ur5e) || !load(argv[2], &arith)) {
        fprintf(stderr, "usage: misuse_generated <ur5e.so> <arith.so>\n");
        return 2;
    }
    instantiation();
    handles();
    modes();
    arguments();
    clocks();
    steps();
    states_and_unsupported();
    model_errors();
    lifecycle();
    return harness_finish();
}
