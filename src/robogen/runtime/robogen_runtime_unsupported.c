/* robogen runtime, part of robogen_runtime.c: the functions of interfaces and capabilities this FMU does not
 * offer (Model Exchange, Scheduled Execution, dependencies, derivatives, configuration, fractions):
 * each logs why and returns fmi3Error.
 *
 * Included at the end of robogen_runtime.c, never compiled on its own: it uses the helpers defined
 * there (rg_enter, rg_fail, rg_log, the tables, rg_prepare_instant). See the design note there.
 */
#ifndef ROBOGEN_RUNTIME_PARTS
#error "robogen_runtime_unsupported.c is part of robogen_runtime.c; compile robogen_runtime.c (through the FMU's unity file)"
#endif

/* ============================================================================================
 * Functions this FMU does not support: log and return fmi3Error
 * ============================================================================================ */

static fmi3Status rg_unsupported(fmi3Instance instance, const char *fn, const char *reason)
{
    rg_instance *inst = rg_enter(instance, fn, RG_ANY_STATE);
    if (inst == NULL) return fmi3Error;
    return rg_fail(inst, fn, "not supported: %s", reason);
}

#define RG_NO_FRACTION "supportsFraction is false for every clock; use the Decimal variant"
#define RG_MODEL_EXCHANGE_ONLY "a Model Exchange function; this FMU implements Co-Simulation only"

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions; (void)qualifiers;
    return rg_unsupported(instance, "fmi3GetIntervalFraction", RG_NO_FRACTION);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return rg_unsupported(instance, "fmi3GetShiftFraction", RG_NO_FRACTION);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return rg_unsupported(instance, "fmi3SetIntervalFraction", RG_NO_FRACTION);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return rg_unsupported(instance, "fmi3SetShiftFraction", RG_NO_FRACTION);
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference; (void)nDependencies;
    return rg_unsupported(instance, "fmi3GetNumberOfVariableDependencies",
                          "providesPerElementDependencies is false; dependencies are in <ModelStructure>");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return rg_unsupported(instance, "fmi3GetVariableDependencies",
                          "providesPerElementDependencies is false; dependencies are in <ModelStructure>");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed;
    (void)sensitivity; (void)nSensitivity;
    return rg_unsupported(instance, "fmi3GetDirectionalDerivative", "providesDirectionalDerivatives is false");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed;
    (void)sensitivity; (void)nSensitivity;
    return rg_unsupported(instance, "fmi3GetAdjointDerivative", "providesAdjointDerivatives is false");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return rg_unsupported(instance, "fmi3EnterConfigurationMode", "this FMU has no structural parameters");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return rg_unsupported(instance, "fmi3ExitConfigurationMode", "this FMU has no structural parameters");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return rg_unsupported(instance, "fmi3EvaluateDiscreteStates",
                          "providesEvaluateDiscreteStates is false; fmi3UpdateDiscreteStates evaluates");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues)
{
    (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
    return rg_unsupported(instance, "fmi3GetOutputDerivatives", "maxOutputDerivativeOrder is 0");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return rg_unsupported(instance, "fmi3ActivateModelPartition",
                          "a Scheduled Execution function; this FMU implements Co-Simulation only");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return rg_unsupported(instance, "fmi3EnterContinuousTimeMode", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
    return rg_unsupported(instance, "fmi3CompletedIntegratorStep", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    (void)time;
    return rg_unsupported(instance, "fmi3SetTime", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return rg_unsupported(instance, "fmi3SetContinuousStates", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    (void)derivatives; (void)nContinuousStates;
    return rg_unsupported(instance, "fmi3GetContinuousStateDerivatives", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    (void)eventIndicators; (void)nEventIndicators;
    return rg_unsupported(instance, "fmi3GetEventIndicators", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return rg_unsupported(instance, "fmi3GetContinuousStates", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates)
{
    (void)nominals; (void)nContinuousStates;
    return rg_unsupported(instance, "fmi3GetNominalsOfContinuousStates", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    (void)nEventIndicators;
    return rg_unsupported(instance, "fmi3GetNumberOfEventIndicators", RG_MODEL_EXCHANGE_ONLY);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    (void)nContinuousStates;
    return rg_unsupported(instance, "fmi3GetNumberOfContinuousStates", RG_MODEL_EXCHANGE_ONLY);
}
