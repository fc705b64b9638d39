// fmi2.cpp — the FMI 2.0 functions of an mbgc FMU, over the same
// fmu::Instance as FMI 3.0's (instance.hpp). FMI 2.0 has no event indicator
// variables and gives the solver enumeration through GetInteger/SetInteger.
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "fmi/fmi2_api.hpp"
#include "fmi/instance.hpp"

using mbgrt::fmu::Instance;
using mbgrt::fmu::Status;

namespace {

fmi2Status to_fmi2(Status s) { return static_cast<fmi2Status>(s); }

template <class Body>
fmi2Status call(fmi2Component c, const char* what, Body&& body) {
  return to_fmi2(mbgrt::fmu::call(c, what, std::forward<Body>(body)));
}

fmi2Status absent(fmi2Component c, const char* what) { return to_fmi2(mbgrt::fmu::absent(c, what)); }

static_assert(std::is_same_v<fmi2ValueReference, std::uint32_t>, "value references are passed on as they are");

}  // namespace

extern "C" {

const char* fmi2GetTypesPlatform(void) { return "default"; }
const char* fmi2GetVersion(void) { return "2.0"; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  return call(c, "fmi2SetDebugLogging", [&](Instance& i) {
    i.set_logging(loggingOn != 0);
    return Status::ok;
  });
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID, fmi2String,
                              const fmi2CallbackFunctions* functions, fmi2Boolean, fmi2Boolean loggingOn) {
  const std::string name = instanceName ? instanceName : "";
  fmi2CallbackLogger log = functions ? functions->logger : nullptr;
  fmi2ComponentEnvironment environment = functions ? functions->componentEnvironment : nullptr;
  auto logger = [log, environment, name](Status s, const char* category, const std::string& message) {
    if (log) log(environment, name.c_str(), to_fmi2(s), category, "%s", message.c_str());
  };
  const auto interface =
      fmuType == fmi2CoSimulation ? mbgrt::fmu::Interface::co_simulation : mbgrt::fmu::Interface::model_exchange;
  return mbgrt::fmu::instantiate(interface, name, fmuGUID, "GUID", logger, loggingOn != 0);
}

void fmi2FreeInstance(fmi2Component c) { delete static_cast<Instance*>(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  return call(c, "fmi2SetupExperiment", [&](Instance& i) {
    return i.setup_experiment(startTime, toleranceDefined != 0, tolerance, stopTimeDefined != 0, stopTime);
  });
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return call(c, "fmi2EnterInitializationMode", [](Instance& i) { return i.enter_initialization(); });
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return call(c, "fmi2ExitInitializationMode", [](Instance& i) { return i.exit_initialization(); });
}

fmi2Status fmi2Terminate(fmi2Component c) {
  return call(c, "fmi2Terminate", [](Instance& i) { return i.terminate(); });
}

fmi2Status fmi2Reset(fmi2Component c) {
  return call(c, "fmi2Reset", [](Instance& i) { return i.reset(); });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return call(c, "fmi2GetReal", [&](Instance& i) { return i.get_float64(vr, nvr, value); });
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  return call(c, "fmi2SetReal", [&](Instance& i) { return i.set_float64(vr, nvr, value); });
}

// The solver setting is an Enumeration: FMI 2.0 gets and sets it as an Integer.
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
  return call(c, "fmi2GetInteger", [&](Instance& i) {
    std::vector<std::int64_t> wide(nvr);
    const Status s = i.get_int64(vr, nvr, wide.data());
    for (size_t k = 0; k < nvr && s == Status::ok; ++k) value[k] = static_cast<fmi2Integer>(wide[k]);
    return s;
  });
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
  return call(c, "fmi2SetInteger", [&](Instance& i) {
    const std::vector<std::int64_t> wide(value, value + nvr);
    return i.set_int64(vr, nvr, wide.data());
  });
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2GetBoolean");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2String[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2GetString");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2SetBoolean");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2String[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2SetString");
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) { return to_fmi2(mbgrt::fmu::get_fmu_state(c, state)); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) { return to_fmi2(mbgrt::fmu::set_fmu_state(c, state)); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* state) { return to_fmi2(mbgrt::fmu::free_fmu_state(c, state)); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t* size) {
  return to_fmi2(mbgrt::fmu::serialized_fmu_state_size(c, state, size));
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
  return to_fmi2(mbgrt::fmu::serialize_fmu_state(c, state, reinterpret_cast<unsigned char*>(bytes), size));
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate* state) {
  return to_fmi2(mbgrt::fmu::deserialize_fmu_state(c, reinterpret_cast<const unsigned char*>(bytes), size, state));
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
  return call(c, "fmi2GetDirectionalDerivative", [&](Instance& i) {
    return i.directional_derivative(vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown, dvUnknown);
  });
}

fmi2Status fmi2EnterEventMode(fmi2Component c) {
  return call(c, "fmi2EnterEventMode", [](Instance& i) { return i.enter_event_mode(); });
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo* info) {
  return call(c, "fmi2NewDiscreteStates", [&](Instance& i) {
    bool changed = false, terminate = false;
    const Status s = i.update_discrete_states(&changed, &terminate);
    if (info) *info = fmi2EventInfo{0, terminate ? 1 : 0, 0, changed ? 1 : 0, 0, 0.0};
    return s;
  });
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
  return call(c, "fmi2EnterContinuousTimeMode", [](Instance& i) { return i.enter_continuous_time_mode(); });
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean, fmi2Boolean* enterEventMode,
                                       fmi2Boolean* terminateSimulation) {
  return call(c, "fmi2CompletedIntegratorStep", [&](Instance& i) {
    bool event = false, terminate = false;
    const Status s = i.completed_integrator_step(&event, &terminate);
    if (enterEventMode) *enterEventMode = event ? 1 : 0;
    if (terminateSimulation) *terminateSimulation = terminate ? 1 : 0;
    return s;
  });
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
  return call(c, "fmi2SetTime", [&](Instance& i) { return i.set_time(time); });
}
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
  return call(c, "fmi2SetContinuousStates", [&](Instance& i) { return i.set_states(x, nx); });
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
  return call(c, "fmi2GetDerivatives", [&](Instance& i) { return i.get_derivatives(derivatives, nx); });
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
  return call(c, "fmi2GetEventIndicators", [&](Instance& i) { return i.get_event_indicators(eventIndicators, ni); });
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
  return call(c, "fmi2GetContinuousStates", [&](Instance& i) { return i.get_states(x, nx); });
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
  return call(c, "fmi2GetNominalsOfContinuousStates", [&](Instance& i) { return i.get_nominals(x_nominal, nx); });
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Integer[],
                                       const fmi2Real[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Integer[],
                                        fmi2Real[]) {
  return nvr == 0 ? fmi2OK : absent(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize, fmi2Boolean) {
  return call(c, "fmi2DoStep", [&](Instance& i) {
    bool terminate = false, early = false;  // (FMI 2.0 has no early return: never allowed)
    double last = currentCommunicationPoint;
    return i.do_step(currentCommunicationPoint, communicationStepSize, &terminate, &early, &last);
  });
}

fmi2Status fmi2CancelStep(fmi2Component c) { return absent(c, "fmi2CancelStep (doStep never returns fmi2Pending)"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) { return absent(c, "fmi2GetStatus"); }

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  return call(c, "fmi2GetRealStatus", [&](Instance& i) {
    if (s != fmi2LastSuccessfulTime) return i.refuse("fmi2GetRealStatus: only fmi2LastSuccessfulTime is a real status");
    *value = i.time();
    return Status::ok;
  });
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) {
  return absent(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean* value) {
  return call(c, "fmi2GetBooleanStatus", [&](Instance& i) {
    if (s != fmi2Terminated) return i.refuse("fmi2GetBooleanStatus: only fmi2Terminated is a boolean status");
    *value = i.phase() == mbgrt::fmu::Phase::failed ? 1 : 0;
    return Status::ok;
  });
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) {
  return absent(c, "fmi2GetStringStatus");
}

}  // extern "C"
