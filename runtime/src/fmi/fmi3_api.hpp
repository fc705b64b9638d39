// fmi3_api.hpp — the FMI 3.0 C interface an FMU exports, declared from the
// standard (Functional Mock-up Interface 3.0, section 2.2: platform types,
// status, callbacks and the functions' signatures). Only the FMU's side: the
// functions defined in fmi3.cpp, with C linkage and default visibility (the
// FMU's version script exports these names and nothing else).
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" {

using fmi3Instance = void*;
using fmi3InstanceEnvironment = void*;
using fmi3FMUState = void*;
using fmi3ValueReference = std::uint32_t;
using fmi3Float32 = float;
using fmi3Float64 = double;
using fmi3Int8 = std::int8_t;
using fmi3UInt8 = std::uint8_t;
using fmi3Int16 = std::int16_t;
using fmi3UInt16 = std::uint16_t;
using fmi3Int32 = std::int32_t;
using fmi3UInt32 = std::uint32_t;
using fmi3Int64 = std::int64_t;
using fmi3UInt64 = std::uint64_t;
using fmi3Boolean = bool;
using fmi3Char = char;
using fmi3String = const fmi3Char*;
using fmi3Byte = std::uint8_t;
using fmi3Binary = const fmi3Byte*;
using fmi3Clock = bool;

typedef enum { fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal } fmi3Status;
typedef enum { fmi3Independent, fmi3Constant, fmi3Fixed, fmi3Tunable, fmi3Discrete, fmi3Dependent } fmi3DependencyKind;
typedef enum { fmi3IntervalNotYetKnown, fmi3IntervalUnchanged, fmi3IntervalChanged } fmi3IntervalQualifier;

typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, fmi3String category, fmi3String message);
typedef void (*fmi3IntermediateUpdateCallback)(fmi3InstanceEnvironment, fmi3Float64 intermediateUpdateTime,
                                               fmi3Boolean intermediateVariableSetRequested,
                                               fmi3Boolean intermediateVariableGetAllowed,
                                               fmi3Boolean intermediateStepFinished, fmi3Boolean canReturnEarly,
                                               fmi3Boolean* earlyReturnRequested, fmi3Float64* earlyReturnTime);
typedef void (*fmi3ClockUpdateCallback)(fmi3InstanceEnvironment);
typedef void (*fmi3LockPreemptionCallback)(void);
typedef void (*fmi3UnlockPreemptionCallback)(void);

#define MBGRT_FMI_EXPORT __attribute__((visibility("default")))
#define MBGRT_FMI3_GET_SET(Name, Type)                                                                         \
  MBGRT_FMI_EXPORT fmi3Status fmi3Get##Name(fmi3Instance, const fmi3ValueReference[], size_t, Type[], size_t); \
  MBGRT_FMI_EXPORT fmi3Status fmi3Set##Name(fmi3Instance, const fmi3ValueReference[], size_t, const Type[], size_t);

MBGRT_FMI_EXPORT const char* fmi3GetVersion(void);
MBGRT_FMI_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance, fmi3Boolean loggingOn, size_t nCategories,
                                                const fmi3String categories[]);
MBGRT_FMI_EXPORT fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                                          fmi3String resourcePath, fmi3Boolean visible,
                                                          fmi3Boolean loggingOn, fmi3InstanceEnvironment,
                                                          fmi3LogMessageCallback);
MBGRT_FMI_EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible,
    fmi3Boolean loggingOn, fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
    const fmi3ValueReference requiredIntermediateVariables[], size_t nRequiredIntermediateVariables,
    fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3IntermediateUpdateCallback);
MBGRT_FMI_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName,
                                                               fmi3String instantiationToken,
                                                               fmi3String resourcePath, fmi3Boolean visible,
                                                               fmi3Boolean loggingOn, fmi3InstanceEnvironment,
                                                               fmi3LogMessageCallback, fmi3ClockUpdateCallback,
                                                               fmi3LockPreemptionCallback,
                                                               fmi3UnlockPreemptionCallback);
MBGRT_FMI_EXPORT void fmi3FreeInstance(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance, fmi3Boolean toleranceDefined,
                                                        fmi3Float64 tolerance, fmi3Float64 startTime,
                                                        fmi3Boolean stopTimeDefined, fmi3Float64 stopTime);
MBGRT_FMI_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3EnterEventMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3Terminate(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3Reset(fmi3Instance);

MBGRT_FMI3_GET_SET(Float32, fmi3Float32)
MBGRT_FMI3_GET_SET(Float64, fmi3Float64)
MBGRT_FMI3_GET_SET(Int8, fmi3Int8)
MBGRT_FMI3_GET_SET(UInt8, fmi3UInt8)
MBGRT_FMI3_GET_SET(Int16, fmi3Int16)
MBGRT_FMI3_GET_SET(UInt16, fmi3UInt16)
MBGRT_FMI3_GET_SET(Int32, fmi3Int32)
MBGRT_FMI3_GET_SET(UInt32, fmi3UInt32)
MBGRT_FMI3_GET_SET(Int64, fmi3Int64)
MBGRT_FMI3_GET_SET(UInt64, fmi3UInt64)
MBGRT_FMI3_GET_SET(Boolean, fmi3Boolean)
MBGRT_FMI3_GET_SET(String, fmi3String)
#undef MBGRT_FMI3_GET_SET
MBGRT_FMI_EXPORT fmi3Status fmi3GetBinary(fmi3Instance, const fmi3ValueReference[], size_t, size_t valueSizes[],
                                          fmi3Binary values[], size_t nValues);
MBGRT_FMI_EXPORT fmi3Status fmi3SetBinary(fmi3Instance, const fmi3ValueReference[], size_t,
                                          const size_t valueSizes[], const fmi3Binary values[], size_t nValues);
MBGRT_FMI_EXPORT fmi3Status fmi3GetClock(fmi3Instance, const fmi3ValueReference[], size_t, fmi3Clock[]);
MBGRT_FMI_EXPORT fmi3Status fmi3SetClock(fmi3Instance, const fmi3ValueReference[], size_t, const fmi3Clock[]);

MBGRT_FMI_EXPORT fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance, fmi3ValueReference,
                                                                size_t* nDependencies);
MBGRT_FMI_EXPORT fmi3Status fmi3GetVariableDependencies(fmi3Instance, fmi3ValueReference dependent,
                                                        size_t elementIndicesOfDependent[],
                                                        fmi3ValueReference independents[],
                                                        size_t elementIndicesOfIndependents[],
                                                        fmi3DependencyKind dependencyKinds[], size_t nDependencies);

MBGRT_FMI_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance, fmi3FMUState*);
MBGRT_FMI_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance, fmi3FMUState);
MBGRT_FMI_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance, fmi3FMUState*);
MBGRT_FMI_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance, fmi3FMUState, size_t* size);
MBGRT_FMI_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance, fmi3FMUState, fmi3Byte serializedState[],
                                                  size_t size);
MBGRT_FMI_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance, const fmi3Byte serializedState[], size_t size,
                                                    fmi3FMUState*);

MBGRT_FMI_EXPORT fmi3Status fmi3GetDirectionalDerivative(fmi3Instance, const fmi3ValueReference unknowns[],
                                                         size_t nUnknowns, const fmi3ValueReference knowns[],
                                                         size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                                         fmi3Float64 sensitivity[], size_t nSensitivity);
MBGRT_FMI_EXPORT fmi3Status fmi3GetAdjointDerivative(fmi3Instance, const fmi3ValueReference unknowns[],
                                                     size_t nUnknowns, const fmi3ValueReference knowns[],
                                                     size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                                     fmi3Float64 sensitivity[], size_t nSensitivity);

MBGRT_FMI_EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3GetIntervalDecimal(fmi3Instance, const fmi3ValueReference[], size_t,
                                                   fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]);
MBGRT_FMI_EXPORT fmi3Status fmi3GetIntervalFraction(fmi3Instance, const fmi3ValueReference[], size_t,
                                                    fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                                    fmi3IntervalQualifier qualifiers[]);
MBGRT_FMI_EXPORT fmi3Status fmi3GetShiftDecimal(fmi3Instance, const fmi3ValueReference[], size_t,
                                                fmi3Float64 shifts[]);
MBGRT_FMI_EXPORT fmi3Status fmi3GetShiftFraction(fmi3Instance, const fmi3ValueReference[], size_t,
                                                 fmi3UInt64 counters[], fmi3UInt64 resolutions[]);
MBGRT_FMI_EXPORT fmi3Status fmi3SetIntervalDecimal(fmi3Instance, const fmi3ValueReference[], size_t,
                                                   const fmi3Float64 intervals[]);
MBGRT_FMI_EXPORT fmi3Status fmi3SetIntervalFraction(fmi3Instance, const fmi3ValueReference[], size_t,
                                                    const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]);
MBGRT_FMI_EXPORT fmi3Status fmi3SetShiftDecimal(fmi3Instance, const fmi3ValueReference[], size_t,
                                                const fmi3Float64 shifts[]);
MBGRT_FMI_EXPORT fmi3Status fmi3SetShiftFraction(fmi3Instance, const fmi3ValueReference[], size_t,
                                                 const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]);
MBGRT_FMI_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance, fmi3Boolean* discreteStatesNeedUpdate,
                                                     fmi3Boolean* terminateSimulation,
                                                     fmi3Boolean* nominalsOfContinuousStatesChanged,
                                                     fmi3Boolean* valuesOfContinuousStatesChanged,
                                                     fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime);

MBGRT_FMI_EXPORT fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3CompletedIntegratorStep(fmi3Instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                                        fmi3Boolean* enterEventMode,
                                                        fmi3Boolean* terminateSimulation);
MBGRT_FMI_EXPORT fmi3Status fmi3SetTime(fmi3Instance, fmi3Float64 time);
MBGRT_FMI_EXPORT fmi3Status fmi3SetContinuousStates(fmi3Instance, const fmi3Float64 continuousStates[],
                                                    size_t nContinuousStates);
MBGRT_FMI_EXPORT fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance, fmi3Float64 derivatives[],
                                                              size_t nContinuousStates);
MBGRT_FMI_EXPORT fmi3Status fmi3GetEventIndicators(fmi3Instance, fmi3Float64 eventIndicators[],
                                                   size_t nEventIndicators);
MBGRT_FMI_EXPORT fmi3Status fmi3GetContinuousStates(fmi3Instance, fmi3Float64 continuousStates[],
                                                    size_t nContinuousStates);
MBGRT_FMI_EXPORT fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance, fmi3Float64 nominals[],
                                                              size_t nContinuousStates);
MBGRT_FMI_EXPORT fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance, size_t* nEventIndicators);
MBGRT_FMI_EXPORT fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance, size_t* nContinuousStates);

MBGRT_FMI_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance);
MBGRT_FMI_EXPORT fmi3Status fmi3GetOutputDerivatives(fmi3Instance, const fmi3ValueReference[], size_t,
                                                     const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues);
MBGRT_FMI_EXPORT fmi3Status fmi3DoStep(fmi3Instance, fmi3Float64 currentCommunicationPoint,
                                       fmi3Float64 communicationStepSize,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean* eventHandlingNeeded, fmi3Boolean* terminateSimulation,
                                       fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime);
MBGRT_FMI_EXPORT fmi3Status fmi3ActivateModelPartition(fmi3Instance, fmi3ValueReference clockReference,
                                                       fmi3Float64 activationTime);

}  // extern "C"
