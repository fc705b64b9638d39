// fmi3.cpp — the FMI 3.0 functions of an mbgc FMU: each translates its
// arguments and calls fmu::Instance (instance.hpp). No exception leaves a C
// function: one becomes fmi3Error with the reason logged.
#include <fmt/format.h>

#include <string>
#include <utility>

#include "fmi/fmi3_api.hpp"
#include "fmi/instance.hpp"

using mbgrt::fmu::Instance;
using mbgrt::fmu::Status;

namespace {

fmi3Status to_fmi3(Status s) { return static_cast<fmi3Status>(s); }

template <class Body>
fmi3Status call(fmi3Instance instance, const char* what, Body&& body) {
  return to_fmi3(mbgrt::fmu::call(instance, what, std::forward<Body>(body)));
}

fmi3Status absent(fmi3Instance instance, const char* what) { return to_fmi3(mbgrt::fmu::absent(instance, what)); }

fmi3Instance instantiate(mbgrt::fmu::Interface interface, fmi3String name, fmi3String token, fmi3Boolean logging_on,
                         fmi3InstanceEnvironment environment, fmi3LogMessageCallback log) {
  const std::string instance_name = name ? name : "";
  auto logger = [environment, log](Status s, const char* category, const std::string& message) {
    if (log) log(environment, to_fmi3(s), category, message.c_str());
  };
  return mbgrt::fmu::instantiate(interface, instance_name, token, "instantiation token", logger, logging_on);
}

}  // namespace

extern "C" {

const char* fmi3GetVersion(void) { return "3.0"; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t, const fmi3String[]) {
  return call(instance, "SetDebugLogging", [&](Instance& i) {
    i.set_logging(loggingOn);
    return Status::ok;
  });
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken, fmi3String,
                                          fmi3Boolean, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
  return instantiate(mbgrt::fmu::Interface::model_exchange, instanceName, instantiationToken, loggingOn,
                     instanceEnvironment, logMessage);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken, fmi3String,
                                         fmi3Boolean, fmi3Boolean loggingOn, fmi3Boolean, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference[], size_t,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback) {
  fmi3Instance i = instantiate(mbgrt::fmu::Interface::co_simulation, instanceName, instantiationToken, loggingOn,
                               instanceEnvironment, logMessage);
  if (i) static_cast<Instance*>(i)->allow_early_return(earlyReturnAllowed);
  return i;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback,
                                               fmi3LockPreemptionCallback, fmi3UnlockPreemptionCallback) {
  if (logMessage)
    logMessage(instanceEnvironment, fmi3Error, "logStatusError",
               "this FMU supports model exchange and co-simulation, not scheduled execution");
  return nullptr;
}

void fmi3FreeInstance(fmi3Instance instance) { delete static_cast<Instance*>(instance); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
  return call(instance, "EnterInitializationMode", [&](Instance& i) {
    const Status s = i.setup_experiment(startTime, toleranceDefined, tolerance, stopTimeDefined, stopTime);
    return s == Status::ok ? i.enter_initialization() : s;
  });
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
  return call(instance, "ExitInitializationMode", [](Instance& i) { return i.exit_initialization(); });
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
  return call(instance, "EnterEventMode", [](Instance& i) { return i.enter_event_mode(); });
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
  return call(instance, "Terminate", [](Instance& i) { return i.terminate(); });
}

fmi3Status fmi3Reset(fmi3Instance instance) {
  return call(instance, "Reset", [](Instance& i) { return i.reset(); });
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
  return call(instance, "GetFloat64", [&](Instance& i) {
    if (nValues != nvr) return i.refuse(fmt::format("GetFloat64: {} values for {} value references", nValues, nvr));
    return i.get_float64(vr, nvr, values);
  });
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
  return call(instance, "SetFloat64", [&](Instance& i) {
    if (nValues != nvr) return i.refuse(fmt::format("SetFloat64: {} values for {} value references", nValues, nvr));
    return i.set_float64(vr, nvr, values);
  });
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 values[],
                        size_t nValues) {
  return call(instance, "GetInt64", [&](Instance& i) {
    if (nValues != nvr) return i.refuse(fmt::format("GetInt64: {} values for {} value references", nValues, nvr));
    return i.get_int64(vr, nvr, values);
  });
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int64 values[],
                        size_t nValues) {
  return call(instance, "SetInt64", [&](Instance& i) {
    if (nValues != nvr) return i.refuse(fmt::format("SetInt64: {} values for {} value references", nValues, nvr));
    return i.set_int64(vr, nvr, values);
  });
}

// The types this FMU has no variables of.
#define MBGRT_FMI3_ABSENT_TYPE(Name, Type)                                                                       \
  fmi3Status fmi3Get##Name(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, Type[], size_t) {      \
    return nvr == 0 ? fmi3OK : absent(instance, "Get" #Name);                                                    \
  }                                                                                                              \
  fmi3Status fmi3Set##Name(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, const Type[], size_t) { \
    return nvr == 0 ? fmi3OK : absent(instance, "Set" #Name);                                                    \
  }
MBGRT_FMI3_ABSENT_TYPE(Float32, fmi3Float32)
MBGRT_FMI3_ABSENT_TYPE(Int8, fmi3Int8)
MBGRT_FMI3_ABSENT_TYPE(UInt8, fmi3UInt8)
MBGRT_FMI3_ABSENT_TYPE(Int16, fmi3Int16)
MBGRT_FMI3_ABSENT_TYPE(UInt16, fmi3UInt16)
MBGRT_FMI3_ABSENT_TYPE(Int32, fmi3Int32)
MBGRT_FMI3_ABSENT_TYPE(UInt32, fmi3UInt32)
MBGRT_FMI3_ABSENT_TYPE(UInt64, fmi3UInt64)
MBGRT_FMI3_ABSENT_TYPE(Boolean, fmi3Boolean)
MBGRT_FMI3_ABSENT_TYPE(String, fmi3String)
#undef MBGRT_FMI3_ABSENT_TYPE

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, size_t[], fmi3Binary[], size_t) {
  return nvr == 0 ? fmi3OK : absent(instance, "GetBinary");
}
fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, const size_t[],
                         const fmi3Binary[], size_t) {
  return nvr == 0 ? fmi3OK : absent(instance, "SetBinary");
}
fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, fmi3Clock[]) {
  return nvr == 0 ? fmi3OK : absent(instance, "GetClock");
}
fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, const fmi3Clock[]) {
  return nvr == 0 ? fmi3OK : absent(instance, "SetClock");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference, size_t*) {
  return absent(instance, "GetNumberOfVariableDependencies");
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference, size_t[], fmi3ValueReference[],
                                       size_t[], fmi3DependencyKind[], size_t) {
  return absent(instance, "GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* state) {
  return to_fmi3(mbgrt::fmu::get_fmu_state(instance, state));
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
  return to_fmi3(mbgrt::fmu::set_fmu_state(instance, state));
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* state) {
  return to_fmi3(mbgrt::fmu::free_fmu_state(instance, state));
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t* size) {
  return to_fmi3(mbgrt::fmu::serialized_fmu_state_size(instance, state, size));
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size) {
  return to_fmi3(mbgrt::fmu::serialize_fmu_state(instance, state, bytes, size));
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState* state) {
  return to_fmi3(mbgrt::fmu::deserialize_fmu_state(instance, bytes, size, state));
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
  return call(instance, "GetDirectionalDerivative", [&](Instance& i) {
    if (nSeed != nKnowns || nSensitivity != nUnknowns)
      return i.refuse(fmt::format("GetDirectionalDerivative: {} seeds for {} knowns, {} sensitivities for {} unknowns",
                                  nSeed, nKnowns, nSensitivity, nUnknowns));
    return i.directional_derivative(unknowns, nUnknowns, knowns, nKnowns, seed, sensitivity);
  });
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference[], size_t,
                                    const fmi3ValueReference[], size_t, const fmi3Float64[], size_t, fmi3Float64[],
                                    size_t) {
  return absent(instance, "GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) { return absent(instance, "EnterConfigurationMode"); }
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) { return absent(instance, "ExitConfigurationMode"); }
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference[], size_t, fmi3Float64[],
                                  fmi3IntervalQualifier[]) {
  return absent(instance, "GetIntervalDecimal");
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference[], size_t, fmi3UInt64[],
                                   fmi3UInt64[], fmi3IntervalQualifier[]) {
  return absent(instance, "GetIntervalFraction");
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference[], size_t, fmi3Float64[]) {
  return absent(instance, "GetShiftDecimal");
}
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference[], size_t, fmi3UInt64[],
                                fmi3UInt64[]) {
  return absent(instance, "GetShiftFraction");
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return absent(instance, "SetIntervalDecimal");
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                   const fmi3UInt64[]) {
  return absent(instance, "SetIntervalFraction");
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return absent(instance, "SetShiftDecimal");
}
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                const fmi3UInt64[]) {
  return absent(instance, "SetShiftFraction");
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) { return absent(instance, "EvaluateDiscreteStates"); }

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
                                    fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged,
                                    fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined,
                                    fmi3Float64* nextEventTime) {
  return call(instance, "UpdateDiscreteStates", [&](Instance& i) {
    bool changed = false, terminate = false;
    const Status s = i.update_discrete_states(&changed, &terminate);
    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = false;
    if (terminateSimulation) *terminateSimulation = terminate;
    if (nominalsOfContinuousStatesChanged) *nominalsOfContinuousStatesChanged = false;
    if (valuesOfContinuousStatesChanged) *valuesOfContinuousStatesChanged = changed;
    if (nextEventTimeDefined) *nextEventTimeDefined = false;
    if (nextEventTime) *nextEventTime = 0.0;
    return s;
  });
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
  return call(instance, "EnterContinuousTimeMode", [](Instance& i) { return i.enter_continuous_time_mode(); });
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean, fmi3Boolean* enterEventMode,
                                       fmi3Boolean* terminateSimulation) {
  return call(instance, "CompletedIntegratorStep", [&](Instance& i) {
    bool event = false, terminate = false;
    const Status s = i.completed_integrator_step(&event, &terminate);
    if (enterEventMode) *enterEventMode = event;
    if (terminateSimulation) *terminateSimulation = terminate;
    return s;
  });
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
  return call(instance, "SetTime", [&](Instance& i) { return i.set_time(time); });
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t n) {
  return call(instance, "SetContinuousStates", [&](Instance& i) { return i.set_states(x, n); });
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 dx[], size_t n) {
  return call(instance, "GetContinuousStateDerivatives", [&](Instance& i) { return i.get_derivatives(dx, n); });
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 g[], size_t n) {
  return call(instance, "GetEventIndicators", [&](Instance& i) { return i.get_event_indicators(g, n); });
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t n) {
  return call(instance, "GetContinuousStates", [&](Instance& i) { return i.get_states(x, n); });
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t n) {
  return call(instance, "GetNominalsOfContinuousStates", [&](Instance& i) { return i.get_nominals(nominals, n); });
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* n) {
  return call(instance, "GetNumberOfEventIndicators", [&](Instance& i) {
    *n = i.event_indicator_count();
    return Status::ok;
  });
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* n) {
  return call(instance, "GetNumberOfContinuousStates", [&](Instance& i) {
    *n = i.state_count();
    return Status::ok;
  });
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
  return call(instance, "EnterStepMode", [](Instance& i) { return i.enter_step_mode(); });
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference[], size_t nvr, const fmi3Int32[],
                                    fmi3Float64[], size_t) {
  return nvr == 0 ? fmi3OK : absent(instance, "GetOutputDerivatives");
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean, fmi3Boolean* eventHandlingNeeded,
                      fmi3Boolean* terminateSimulation, fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime) {
  return call(instance, "DoStep", [&](Instance& i) {
    bool terminate = false, early = false;
    double last = currentCommunicationPoint;
    const Status s = i.do_step(currentCommunicationPoint, communicationStepSize, &terminate, &early, &last);
    if (eventHandlingNeeded) *eventHandlingNeeded = false;  // events are handled inside the step
    if (terminateSimulation) *terminateSimulation = terminate;
    if (earlyReturn) *earlyReturn = early;
    if (lastSuccessfulTime) *lastSuccessfulTime = last;
    return s;
  });
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference, fmi3Float64) {
  return absent(instance, "ActivateModelPartition");
}

}  // extern "C"
