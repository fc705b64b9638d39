// fmi2_api.hpp — the FMI 2.0 C interface an FMU exports, declared from the
// standard (Functional Mock-up Interface 2.0, section 2.1: platform types,
// status, callbacks and the functions' signatures). Only the FMU's side: the
// functions defined in fmi2.cpp, with C linkage and default visibility.
#pragma once

#include <cstddef>

extern "C" {

using fmi2Component = void*;
using fmi2ComponentEnvironment = void*;
using fmi2FMUstate = void*;
using fmi2ValueReference = unsigned int;
using fmi2Real = double;
using fmi2Integer = int;
using fmi2Boolean = int;
using fmi2Char = char;
using fmi2String = const fmi2Char*;
using fmi2Byte = char;

typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated } fmi2StatusKind;

typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String instanceName, fmi2Status, fmi2String category,
                                   fmi2String message, ...);
typedef void* (*fmi2CallbackAllocateMemory)(size_t nobj, size_t size);
typedef void (*fmi2CallbackFreeMemory)(void* obj);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);

typedef struct {
  fmi2CallbackLogger logger;
  fmi2CallbackAllocateMemory allocateMemory;
  fmi2CallbackFreeMemory freeMemory;
  fmi2StepFinished stepFinished;
  fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

typedef struct {
  fmi2Boolean newDiscreteStatesNeeded;
  fmi2Boolean terminateSimulation;
  fmi2Boolean nominalsOfContinuousStatesChanged;
  fmi2Boolean valuesOfContinuousStatesChanged;
  fmi2Boolean nextEventTimeDefined;
  fmi2Real nextEventTime;
} fmi2EventInfo;

#define MBGRT_FMI2_EXPORT __attribute__((visibility("default")))

MBGRT_FMI2_EXPORT const char* fmi2GetTypesPlatform(void);
MBGRT_FMI2_EXPORT const char* fmi2GetVersion(void);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component, fmi2Boolean loggingOn, size_t nCategories,
                                                 const fmi2String categories[]);
MBGRT_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                                fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                                                fmi2Boolean visible, fmi2Boolean loggingOn);
MBGRT_FMI2_EXPORT void fmi2FreeInstance(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                                 fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime);
MBGRT_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component);

MBGRT_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component, const fmi2ValueReference[], size_t, fmi2Real[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component, const fmi2ValueReference[], size_t, fmi2Integer[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component, const fmi2ValueReference[], size_t, fmi2Boolean[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component, const fmi2ValueReference[], size_t, fmi2String[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component, const fmi2ValueReference[], size_t, const fmi2Real[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component, const fmi2ValueReference[], size_t, const fmi2Integer[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component, const fmi2ValueReference[], size_t, const fmi2Boolean[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component, const fmi2ValueReference[], size_t, const fmi2String[]);

MBGRT_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component, fmi2FMUstate*);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component, fmi2FMUstate);
MBGRT_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component, fmi2FMUstate*);
MBGRT_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component, fmi2FMUstate, size_t* size);
MBGRT_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component, fmi2FMUstate, fmi2Byte[], size_t size);
MBGRT_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component, const fmi2Byte serializedState[], size_t size,
                                                     fmi2FMUstate*);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component, const fmi2ValueReference vUnknown_ref[],
                                                          size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                                          size_t nKnown, const fmi2Real dvKnown[],
                                                          fmi2Real dvUnknown[]);

MBGRT_FMI2_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component, fmi2EventInfo*);
MBGRT_FMI2_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                                         fmi2Boolean* enterEventMode,
                                                         fmi2Boolean* terminateSimulation);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetTime(fmi2Component, fmi2Real time);
MBGRT_FMI2_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component, const fmi2Real x[], size_t nx);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component, fmi2Real derivatives[], size_t nx);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component, fmi2Real eventIndicators[], size_t ni);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component, fmi2Real x[], size_t nx);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component, fmi2Real x_nominal[], size_t nx);

MBGRT_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component, const fmi2ValueReference[], size_t,
                                                         const fmi2Integer order[], const fmi2Real value[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component, const fmi2ValueReference[], size_t,
                                                          const fmi2Integer order[], fmi2Real value[]);
MBGRT_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component, fmi2Real currentCommunicationPoint,
                                        fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint);
MBGRT_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component, const fmi2StatusKind, fmi2Status*);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component, const fmi2StatusKind, fmi2Real*);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component, const fmi2StatusKind, fmi2Integer*);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component, const fmi2StatusKind, fmi2Boolean*);
MBGRT_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component, const fmi2StatusKind, fmi2String*);

}  // extern "C"
