/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The functions of FMI 3.0 that a co-simulation FMU of a mechanism does not offer (model
 * exchange, scheduled execution, clocks, event mode, derivatives, other types than Float64 and
 * String): each answers fmi3Error with a message, NULL for the instantiations. They exist so
 * that an importer which looks every function up finds them. One macro per family of
 * signatures, as the Reference FMUs write them; the parameters are there for the prototypes of
 * fmi3Functions.h alone, hence unused. */
#include "fmi3_glue.h"

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic ignored "-Wunused-parameter"
#endif
/* NOLINTBEGIN(misc-unused-parameters): the prototypes' parameters, unused by design */

/* name(instance, ...) answering fmi3Error with its own name */
#define UNSUPPORTED(name, ...)                                                                     \
  fmi3Status name(fmi3Instance instance, __VA_ARGS__) { return fmi3_unsupported(instance, #name); }
#define UNSUPPORTED_0(name)                                                                        \
  fmi3Status name(fmi3Instance instance) { return fmi3_unsupported(instance, #name); }
/* fmi3GetT and fmi3SetT of a type T */
#define VR const fmi3ValueReference valueReferences[], size_t nValueReferences
#define GET_SET(T)                                                                                 \
  UNSUPPORTED(fmi3Get##T, VR, fmi3##T values[], size_t nValues)                                    \
  UNSUPPORTED(fmi3Set##T, VR, const fmi3##T values[], size_t nValues)
/* the instantiations other than co-simulation: no instance */
#define INSTANTIATE                                                                                \
  fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,                 \
      fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,     \
      fmi3LogMessageCallback logMessage

fmi3Instance fmi3InstantiateModelExchange(INSTANTIATE) { return NULL; }
fmi3Instance fmi3InstantiateScheduledExecution(INSTANTIATE, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
  return NULL;
}

GET_SET(Float32)
GET_SET(Int8)
GET_SET(UInt8)
GET_SET(Int16)
GET_SET(UInt16)
GET_SET(Int32)
GET_SET(UInt32)
GET_SET(Int64)
GET_SET(UInt64)
GET_SET(Boolean)
UNSUPPORTED(fmi3GetBinary, VR, size_t valueSizes[], fmi3Binary values[], size_t nValues)
UNSUPPORTED(fmi3SetBinary, VR, const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
UNSUPPORTED(fmi3GetClock, VR, fmi3Clock values[])
UNSUPPORTED(fmi3SetClock, VR, const fmi3Clock values[])

UNSUPPORTED(fmi3GetNumberOfVariableDependencies, fmi3ValueReference valueReference,
            size_t *nDependencies)
UNSUPPORTED(fmi3GetVariableDependencies, fmi3ValueReference dependent,
            size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
            size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
            size_t nDependencies)
#define DERIVATIVE                                                                                 \
  const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[],        \
      size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],           \
      size_t nSensitivity
UNSUPPORTED(fmi3GetDirectionalDerivative, DERIVATIVE)
UNSUPPORTED(fmi3GetAdjointDerivative, DERIVATIVE)
UNSUPPORTED(fmi3GetOutputDerivatives, VR, const fmi3Int32 orders[], fmi3Float64 values[],
            size_t nValues)

UNSUPPORTED_0(fmi3EnterConfigurationMode)
UNSUPPORTED_0(fmi3ExitConfigurationMode)
UNSUPPORTED(fmi3GetIntervalDecimal, VR, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
UNSUPPORTED(fmi3GetIntervalFraction, VR, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
            fmi3IntervalQualifier qualifiers[])
UNSUPPORTED(fmi3GetShiftDecimal, VR, fmi3Float64 shifts[])
UNSUPPORTED(fmi3GetShiftFraction, VR, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
UNSUPPORTED(fmi3SetIntervalDecimal, VR, const fmi3Float64 intervals[])
UNSUPPORTED(fmi3SetIntervalFraction, VR, const fmi3UInt64 counters[],
            const fmi3UInt64 resolutions[])
UNSUPPORTED(fmi3SetShiftDecimal, VR, const fmi3Float64 shifts[])
UNSUPPORTED(fmi3SetShiftFraction, VR, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
UNSUPPORTED(fmi3ActivateModelPartition, fmi3ValueReference clockReference,
            fmi3Float64 activationTime)

UNSUPPORTED_0(fmi3EnterEventMode)
UNSUPPORTED_0(fmi3EvaluateDiscreteStates)
UNSUPPORTED(fmi3UpdateDiscreteStates, fmi3Boolean *discreteStatesNeedUpdate,
            fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
            fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
            fmi3Float64 *nextEventTime)
UNSUPPORTED_0(fmi3EnterContinuousTimeMode)
UNSUPPORTED(fmi3CompletedIntegratorStep, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
            fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
UNSUPPORTED(fmi3SetTime, fmi3Float64 time)
UNSUPPORTED(fmi3SetContinuousStates, const fmi3Float64 continuousStates[], size_t nContinuousStates)
UNSUPPORTED(fmi3GetContinuousStateDerivatives, fmi3Float64 derivatives[], size_t nContinuousStates)
UNSUPPORTED(fmi3GetEventIndicators, fmi3Float64 eventIndicators[], size_t nEventIndicators)
UNSUPPORTED(fmi3GetContinuousStates, fmi3Float64 continuousStates[], size_t nContinuousStates)
UNSUPPORTED(fmi3GetNominalsOfContinuousStates, fmi3Float64 nominals[], size_t nContinuousStates)
UNSUPPORTED(fmi3GetNumberOfEventIndicators, size_t *nEventIndicators)
UNSUPPORTED(fmi3GetNumberOfContinuousStates, size_t *nContinuousStates)
/* NOLINTEND(misc-unused-parameters) */
