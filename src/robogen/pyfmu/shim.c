/* The exported FMI 3.0 API of a Python-implemented FMU (robogen package-py).
 *
 * Every fmi3* function of fmi3Functions.h is defined here, so the official prototypes check
 * the signatures. The calls a Python model implements are forwarded to the pyfmu_py_*
 * functions of the cffi module (see bridge.h); the rest log and return fmi3Error
 * (the Instantiate variants other than Co-Simulation return NULL).
 *
 * Compiled with -std=c99 -Wall -Wextra -Wpedantic -Werror -fvisibility=hidden; only the
 * fmi3* names (FMI3_Export) and the cffi module's init symbol leave the shared object.
 *
 * PYFMU_LIBPYTHON (defined by the build) is the soname of the libpython the module links; the
 * tests build without it once to show what the constructor below fixes.
 */
#define _GNU_SOURCE 1 /* RTLD_NOLOAD */

#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "bridge.h"

/* ---- loading ----------------------------------------------------------------------------- */

/* A host that dlopen()s this library with RTLD_LOCAL (most C importers) loads libpython, our
 * DT_NEEDED dependency, into a local scope too. Extension modules imported later (cffi's
 * _cffi_backend, numpy, pybullet) are separate shared objects that expect the Py* symbols in
 * the global scope and fail with "undefined symbol". Re-opening the already loaded libpython
 * with RTLD_NOLOAD | RTLD_GLOBAL promotes it to the global scope. In a Python host it is
 * already global and this changes nothing. The handle is kept on purpose (never dlclose'd). */
#ifdef PYFMU_LIBPYTHON
__attribute__((constructor)) static void pyfmu_promote_libpython(void)
{
    (void)dlopen(PYFMU_LIBPYTHON, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
}
#endif

/* ---- instances and logging --------------------------------------------------------------- */

enum { CATEGORY_EVENTS = 1u, CATEGORY_WARNING = 2u, CATEGORY_ERROR = 4u, CATEGORY_ALL = 7u };

static const struct {
    const char *name;
    unsigned bit;
} categories[] = {
    {"logEvents", CATEGORY_EVENTS},
    {"logStatusWarning", CATEGORY_WARNING},
    {"logStatusError", CATEGORY_ERROR},
};

typedef struct {
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
    bool logging_on;
    unsigned categories; /* enabled log categories (bits above) */
    int handle;          /* the Python-side instance; 0 before instantiation succeeded */
} pyfmu_instance;

static unsigned category_bit(const char *name)
{
    size_t i;
    for (i = 0; i < sizeof categories / sizeof categories[0]; i++) {
        if (strcmp(categories[i].name, name) == 0) {
            return categories[i].bit;
        }
    }
    return 0;
}

/* Errors are always reported (FMI 3.0: whatever loggingOn and the categories say); other
 * messages only while logging is on for their category. */
static bool log_enabled(const pyfmu_instance *inst, fmi3Status status, const char *category)
{
    if (inst == NULL || inst->log_message == NULL) {
        return false;
    }
    return status >= fmi3Error || (inst->logging_on && (inst->categories & category_bit(category)));
}

static void log_text(const pyfmu_instance *inst, fmi3Status status, const char *category, const char *message)
{
    if (log_enabled(inst, status, category)) {
        inst->log_message(inst->environment, status, category, message);
    }
}

static void log_format(const pyfmu_instance *inst, fmi3Status status, const char *format, ...)
{
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    log_text(inst, status, status >= fmi3Error ? "logStatusError" : "logStatusWarning", message);
}

/* Called from Python (bridge.h). */
void pyfmu_log(void *c_instance, int status, const char *category, const char *message)
{
    log_text((const pyfmu_instance *)c_instance, (fmi3Status)status, category, message);
}

/* Called from Python (bridge.h): whether a message would reach the host, so that the Python side
 * formats none that would not. */
int pyfmu_log_enabled(void *c_instance, int status, const char *category)
{
    return log_enabled((const pyfmu_instance *)c_instance, (fmi3Status)status, category) ? 1 : 0;
}

#define INSTANCE(function)                                                      \
    pyfmu_instance *inst = (pyfmu_instance *)instance;                          \
    if (inst == NULL) {                                                         \
        return fmi3Error;                                                       \
    }                                                                           \
    if (inst->handle == 0) {                                                    \
        log_format(inst, fmi3Error, "%s: the instance is not usable", function); \
        return fmi3Error;                                                       \
    }

static fmi3Status unsupported(fmi3Instance instance, const char *function)
{
    log_format((const pyfmu_instance *)instance, fmi3Error, "%s is not supported by this FMU", function);
    return fmi3Error;
}

/* ---- inquire version, logging ------------------------------------------------------------ */

const char *fmi3GetVersion(void)
{
    return fmi3Version;
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categoryNames[])
{
    pyfmu_instance *inst = (pyfmu_instance *)instance;
    unsigned selected = 0;
    size_t i;
    if (inst == NULL) {
        return fmi3Error;
    }
    for (i = 0; i < nCategories; i++) {
        unsigned bit = categoryNames[i] != NULL ? category_bit(categoryNames[i]) : 0;
        if (bit == 0) {
            log_format(inst, fmi3Error, "fmi3SetDebugLogging: unknown log category '%s'",
                       categoryNames[i] != NULL ? categoryNames[i] : "(null)");
            return fmi3Error;
        }
        selected |= bit;
    }
    inst->logging_on = loggingOn;
    inst->categories = nCategories == 0 ? CATEGORY_ALL : selected;
    return fmi3OK;
}

/* ---- creation and destruction ------------------------------------------------------------ */

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instanceName, (void)instantiationToken, (void)resourcePath, (void)visible;
    if (logMessage != NULL && loggingOn) {
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "this FMU supports Co-Simulation only, not Model Exchange");
    }
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName, (void)instantiationToken, (void)resourcePath, (void)visible;
    (void)clockUpdate, (void)lockPreemption, (void)unlockPreemption;
    if (logMessage != NULL && loggingOn) {
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "this FMU supports Co-Simulation only, not Scheduled Execution");
    }
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
    char message[1024];
    pyfmu_instance *inst = (pyfmu_instance *)calloc(1, sizeof *inst);
    (void)requiredIntermediateVariables, (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate; /* providesIntermediateUpdate="false" */
    if (inst == NULL) {
        if (logMessage != NULL && loggingOn) {
            logMessage(instanceEnvironment, fmi3Error, "logStatusError", "out of memory");
        }
        return NULL;
    }
    inst->environment = instanceEnvironment;
    inst->log_message = logMessage;
    inst->logging_on = loggingOn;
    inst->categories = CATEGORY_ALL;
    /* Python is started here, in C, so a failure is reported instead of every later call
     * silently returning 0 (= fmi3OK) from an unbound extern "Python" function. */
    if (pyfmu_start_python(message, sizeof message) != 0) {
        log_text(inst, fmi3Error, "logStatusError", message);
        free(inst);
        return NULL;
    }
    inst->handle = pyfmu_py_instantiate(inst, instanceName, instantiationToken, resourcePath, visible, loggingOn,
                                        eventModeUsed, earlyReturnAllowed);
    if (inst->handle <= 0) { /* the Python side logged why */
        free(inst);
        return NULL;
    }
    return inst;
}

void fmi3FreeInstance(fmi3Instance instance)
{
    pyfmu_instance *inst = (pyfmu_instance *)instance;
    if (inst == NULL) {
        return;
    }
    if (inst->handle != 0) {
        pyfmu_py_free_instance(inst->handle);
    }
    free(inst);
}

/* ---- life cycle -------------------------------------------------------------------------- */

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    INSTANCE("fmi3EnterInitializationMode")
    return (fmi3Status)pyfmu_py_enter_initialization_mode(inst->handle, toleranceDefined, tolerance, startTime,
                                                          stopTimeDefined, stopTime);
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    INSTANCE("fmi3ExitInitializationMode")
    return (fmi3Status)pyfmu_py_exit_initialization_mode(inst->handle);
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    INSTANCE("fmi3EnterEventMode")
    return (fmi3Status)pyfmu_py_enter_event_mode(inst->handle);
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    INSTANCE("fmi3Terminate")
    return (fmi3Status)pyfmu_py_terminate(inst->handle);
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    INSTANCE("fmi3Reset")
    return (fmi3Status)pyfmu_py_reset(inst->handle);
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    INSTANCE("fmi3EnterStepMode")
    return (fmi3Status)pyfmu_py_enter_step_mode(inst->handle);
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    int flags[3] = {0, 0, 0};
    double next = 0.0;
    fmi3Status status;
    INSTANCE("fmi3UpdateDiscreteStates")
    status = (fmi3Status)pyfmu_py_update_discrete_states(inst->handle, flags, &next);
    if (status <= fmi3Warning) {
        if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = flags[0] != 0;
        if (terminateSimulation) *terminateSimulation = flags[1] != 0;
        if (nominalsOfContinuousStatesChanged) *nominalsOfContinuousStatesChanged = false;
        if (valuesOfContinuousStatesChanged) *valuesOfContinuousStatesChanged = false;
        if (nextEventTimeDefined) *nextEventTimeDefined = flags[2] != 0;
        if (nextEventTime) *nextEventTime = next;
    }
    return status;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime)
{
    int flags[3] = {0, 0, 0};
    double last = currentCommunicationPoint;
    fmi3Status status;
    INSTANCE("fmi3DoStep")
    (void)noSetFMUStatePriorToCurrentPoint;
    status = (fmi3Status)pyfmu_py_do_step(inst->handle, currentCommunicationPoint, communicationStepSize, flags,
                                          &last);
    if (status <= fmi3Warning) {
        if (eventHandlingNeeded) *eventHandlingNeeded = flags[0] != 0;
        if (terminateSimulation) *terminateSimulation = flags[1] != 0;
        if (earlyReturn) *earlyReturn = flags[2] != 0;
        if (lastSuccessfulTime) *lastSuccessfulTime = last;
    }
    return status;
}

/* ---- values of the types a Python model declares ----------------------------------------- */

#define FORWARD_GET(fmi_name, c_type, py_name)                                                          \
    fmi3Status fmi_name(fmi3Instance instance, const fmi3ValueReference valueReferences[],              \
                        size_t nValueReferences, c_type values[], size_t nValues)                       \
    {                                                                                                   \
        INSTANCE(#fmi_name)                                                                             \
        return (fmi3Status)py_name(inst->handle, valueReferences, nValueReferences, values, nValues);   \
    }

#define FORWARD_SET(fmi_name, c_type, py_name)                                                          \
    fmi3Status fmi_name(fmi3Instance instance, const fmi3ValueReference valueReferences[],              \
                        size_t nValueReferences, const c_type values[], size_t nValues)                 \
    {                                                                                                   \
        INSTANCE(#fmi_name)                                                                             \
        return (fmi3Status)py_name(inst->handle, valueReferences, nValueReferences, values, nValues);   \
    }

FORWARD_GET(fmi3GetFloat64, fmi3Float64, pyfmu_py_get_float64)
FORWARD_SET(fmi3SetFloat64, fmi3Float64, pyfmu_py_set_float64)
FORWARD_GET(fmi3GetInt32, fmi3Int32, pyfmu_py_get_int32)
FORWARD_SET(fmi3SetInt32, fmi3Int32, pyfmu_py_set_int32)
FORWARD_GET(fmi3GetInt64, fmi3Int64, pyfmu_py_get_int64)
FORWARD_SET(fmi3SetInt64, fmi3Int64, pyfmu_py_set_int64)
FORWARD_GET(fmi3GetBoolean, fmi3Boolean, pyfmu_py_get_boolean)
FORWARD_SET(fmi3SetBoolean, fmi3Boolean, pyfmu_py_set_boolean)
FORWARD_GET(fmi3GetString, fmi3String, pyfmu_py_get_string)
FORWARD_SET(fmi3SetString, fmi3String, pyfmu_py_set_string)

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        fmi3Clock values[])
{
    INSTANCE("fmi3GetClock")
    return (fmi3Status)pyfmu_py_get_clock(inst->handle, valueReferences, nValueReferences, values);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        const fmi3Clock values[])
{
    INSTANCE("fmi3SetClock")
    return (fmi3Status)pyfmu_py_set_clock(inst->handle, valueReferences, nValueReferences, values);
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    int q[64];
    size_t i;
    fmi3Status status;
    INSTANCE("fmi3GetIntervalDecimal")
    if (nValueReferences > sizeof q / sizeof q[0]) {
        log_format(inst, fmi3Error, "fmi3GetIntervalDecimal: at most %u clocks per call",
                   (unsigned)(sizeof q / sizeof q[0]));
        return fmi3Error;
    }
    status = (fmi3Status)pyfmu_py_get_interval_decimal(inst->handle, valueReferences, nValueReferences, intervals, q);
    if (status <= fmi3Warning) {
        for (i = 0; i < nValueReferences; i++) {
            qualifiers[i] = (fmi3IntervalQualifier)q[i];
        }
    }
    return status;
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[])
{
    INSTANCE("fmi3GetShiftDecimal")
    return (fmi3Status)pyfmu_py_get_shift_decimal(inst->handle, valueReferences, nValueReferences, shifts);
}

/* ---- everything else: log and return fmi3Error ------------------------------------------- */

/* The stubs keep the official parameter names for readability; none of them is used. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"

#define UNSUPPORTED_GET(fmi_name, c_type)                                                              \
    fmi3Status fmi_name(fmi3Instance instance, const fmi3ValueReference valueReferences[],             \
                        size_t nValueReferences, c_type values[], size_t nValues)                      \
    {                                                                                                  \
        return unsupported(instance, #fmi_name);                                                       \
    }

#define UNSUPPORTED_SET(fmi_name, c_type)                                                              \
    fmi3Status fmi_name(fmi3Instance instance, const fmi3ValueReference valueReferences[],             \
                        size_t nValueReferences, const c_type values[], size_t nValues)                \
    {                                                                                                  \
        return unsupported(instance, #fmi_name);                                                       \
    }

UNSUPPORTED_GET(fmi3GetFloat32, fmi3Float32)
UNSUPPORTED_GET(fmi3GetInt8, fmi3Int8)
UNSUPPORTED_GET(fmi3GetUInt8, fmi3UInt8)
UNSUPPORTED_GET(fmi3GetInt16, fmi3Int16)
UNSUPPORTED_GET(fmi3GetUInt16, fmi3UInt16)
UNSUPPORTED_GET(fmi3GetUInt32, fmi3UInt32)
UNSUPPORTED_GET(fmi3GetUInt64, fmi3UInt64)
UNSUPPORTED_SET(fmi3SetFloat32, fmi3Float32)
UNSUPPORTED_SET(fmi3SetInt8, fmi3Int8)
UNSUPPORTED_SET(fmi3SetUInt8, fmi3UInt8)
UNSUPPORTED_SET(fmi3SetInt16, fmi3Int16)
UNSUPPORTED_SET(fmi3SetUInt16, fmi3UInt16)
UNSUPPORTED_SET(fmi3SetUInt32, fmi3UInt32)
UNSUPPORTED_SET(fmi3SetUInt64, fmi3UInt64)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    return unsupported(instance, "fmi3GetBinary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    return unsupported(instance, "fmi3SetBinary");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    return unsupported(instance, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return unsupported(instance, "fmi3GetFMUState");
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    return unsupported(instance, "fmi3SetFMUState");
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return unsupported(instance, "fmi3FreeFMUState");
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    return unsupported(instance, "fmi3SerializedFMUStateSize");
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size)
{
    return unsupported(instance, "fmi3SerializeFMUState");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    return unsupported(instance, "fmi3DeserializeFMUState");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    return unsupported(instance, "fmi3GetDirectionalDerivative");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    return unsupported(instance, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    return unsupported(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    return unsupported(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[])
{
    return unsupported(instance, "fmi3SetIntervalDecimal (the FMU's clocks are constant or triggered)");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{
    return unsupported(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[])
{
    return unsupported(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    return unsupported(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EvaluateDiscreteStates");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterContinuousTimeMode (Model Exchange)");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    return unsupported(instance, "fmi3CompletedIntegratorStep (Model Exchange)");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    return unsupported(instance, "fmi3SetTime (Model Exchange)");
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    return unsupported(instance, "fmi3SetContinuousStates (Model Exchange)");
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    return unsupported(instance, "fmi3GetContinuousStateDerivatives (Model Exchange)");
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    return unsupported(instance, "fmi3GetEventIndicators (Model Exchange)");
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    return unsupported(instance, "fmi3GetContinuousStates (Model Exchange)");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates)
{
    return unsupported(instance, "fmi3GetNominalsOfContinuousStates (Model Exchange)");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    return unsupported(instance, "fmi3GetNumberOfEventIndicators (Model Exchange)");
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    return unsupported(instance, "fmi3GetNumberOfContinuousStates (Model Exchange)");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues)
{
    return unsupported(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    return unsupported(instance, "fmi3ActivateModelPartition (Scheduled Execution)");
}

#pragma GCC diagnostic pop
