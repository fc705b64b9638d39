// An importer of our own for the FMI tests: an FMU's shared object loaded with
// dlopen (as importers do) and its FMI 3.0 functions called directly; or,
// compiled with MBGC_FMI_IN_PROCESS="MODEL", the FMI functions of the test
// program itself, which links that model's FMU source and the runtime.
#pragma once

#include <dlfcn.h>
#include <unistd.h>

#include <regex>

#include "fmi/fmi3_api.hpp"
#include "fmi_support.hpp"

namespace fmi_test {

/// The messages an instance logged, in order.
struct Log {
  std::vector<std::string> messages;
  std::string all() const {
    std::string out;
    for (const std::string& m : messages) out += m + "\n";
    return out;
  }
  bool mentions(const std::string& text) const { return all().find(text) != std::string::npos; }
};

inline void log_message(fmi3InstanceEnvironment environment, fmi3Status, fmi3String, fmi3String message) {
  static_cast<Log*>(environment)->messages.push_back(message ? message : "");
}

/// An FMU unzipped and its shared object loaded: the FMI functions by name,
/// value references by variable name (from its modelDescription.xml).
class Fmu {
 public:
  explicit Fmu(const std::string& name) {
    // (a directory of this process's own: ctest runs the tests side by side)
    dir_ = std::string(WORK_DIR) + "/calls_" + name + "_" + std::to_string(::getpid());
    const std::string fmu = std::string(FMU_DIR) + "/fmu3_" + name + ".fmu";
    const std::string command = "rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "' && cd '" + dir_ + "' && unzip -q '" + fmu + "'";
    if (std::system(command.c_str()) != 0) return;
    description_ = slurp(dir_ + "/modelDescription.xml");
#ifdef MBGC_FMI_IN_PROCESS
    // the test program is the FMU (its source and the runtime's FMU library
    // linked in, the FMI functions exported): the calls go to it
    if (name == MBGC_FMI_IN_PROCESS) handle_ = dlopen(nullptr, RTLD_NOW);
#else
    handle_ = dlopen((dir_ + "/binaries/x86_64-linux/" + name + ".so").c_str(), RTLD_NOW | RTLD_LOCAL);
#endif
  }
  ~Fmu() {
    if (handle_) dlclose(handle_);
    const int removed = std::system(("rm -rf '" + dir_ + "'").c_str());
    (void)removed;
  }
  Fmu(const Fmu&) = delete;
  Fmu& operator=(const Fmu&) = delete;

  bool loaded() const { return handle_ != nullptr; }
  const std::string& description() const { return description_; }
  template <class F>
  F* function(const char* name) const {
    return reinterpret_cast<F*>(dlsym(handle_, name));
  }
  fmi3ValueReference reference(const std::string& variable) const {
    const std::string key = "name=\"" + variable + "\" valueReference=\"";
    const std::size_t at = description_.find(key);
    EXPECT_NE(at, std::string::npos) << "no variable " << variable;
    return at == std::string::npos ? 0 : static_cast<fmi3ValueReference>(std::stoul(description_.substr(at + key.size())));
  }
  /// The states' value references and their derivatives', in the states' order.
  void states(std::vector<fmi3ValueReference>& states, std::vector<fmi3ValueReference>& derivatives) const {
    const std::regex derivative_of("valueReference=\"([0-9]+)\"[^>]*derivative=\"([0-9]+)\"");
    for (auto it = std::sregex_iterator(description_.begin(), description_.end(), derivative_of);
         it != std::sregex_iterator(); ++it) {
      derivatives.push_back(static_cast<fmi3ValueReference>(std::stoul((*it)[1])));
      states.push_back(static_cast<fmi3ValueReference>(std::stoul((*it)[2])));
    }
  }
  std::string token() const {
    std::smatch m;
    std::regex_search(description_, m, std::regex("instantiationToken=\"([^\"]+)\""));
    return m.empty() ? "" : m[1].str();
  }

  fmi3Instance co_simulation(Log& log, const std::string& token) const {
    return function<decltype(fmi3InstantiateCoSimulation)>("fmi3InstantiateCoSimulation")(
        "calls", token.c_str(), "", false, true, false, false, nullptr, 0, &log, log_message, nullptr);
  }
  /// A co-simulation instance through its initialisation (null if that failed).
  fmi3Instance started_co_simulation(Log& log) const {
    fmi3Instance i = co_simulation(log, token());
    if (i && (enter_initialization(i) != fmi3OK || exit_initialization(i) != fmi3OK)) {
      free(i);
      return nullptr;
    }
    return i;
  }
  fmi3Instance model_exchange(Log& log) const {
    return function<decltype(fmi3InstantiateModelExchange)>("fmi3InstantiateModelExchange")(
        "calls", token().c_str(), "", false, true, &log, log_message);
  }
  fmi3Status enter_initialization(fmi3Instance i) const {
    return function<decltype(fmi3EnterInitializationMode)>("fmi3EnterInitializationMode")(i, false, 0.0, 0.0, false, 0.0);
  }
  fmi3Status exit_initialization(fmi3Instance i) const {
    return function<decltype(fmi3ExitInitializationMode)>("fmi3ExitInitializationMode")(i);
  }
  fmi3Status set(fmi3Instance i, fmi3ValueReference vr, double value) const {
    return function<decltype(fmi3SetFloat64)>("fmi3SetFloat64")(i, &vr, 1, &value, 1);
  }
  fmi3Status get(fmi3Instance i, fmi3ValueReference vr, double& value) const {
    return function<decltype(fmi3GetFloat64)>("fmi3GetFloat64")(i, &vr, 1, &value, 1);
  }
  fmi3Status step(fmi3Instance i, double t, double h) const {
    fmi3Boolean event = false, terminate = false, early = false;
    double last = 0;
    return function<decltype(fmi3DoStep)>("fmi3DoStep")(i, t, h, true, &event, &terminate, &early, &last);
  }
  void free(fmi3Instance i) const { function<decltype(fmi3FreeInstance)>("fmi3FreeInstance")(i); }

 private:
  std::string dir_, description_;
  void* handle_ = nullptr;
};

/// Model exchange at (t, x): initialised, in Continuous-Time Mode.
inline fmi3Instance model_exchange_at(const Fmu& fmu, Log& log, const std::vector<double>& x) {
  fmi3Instance i = fmu.model_exchange(log);
  EXPECT_NE(i, nullptr);
  EXPECT_EQ(fmu.enter_initialization(i), fmi3OK);
  EXPECT_EQ(fmu.exit_initialization(i), fmi3OK);
  fmi3Boolean update = false, terminate = false, nominals = false, values = false, next_defined = false;
  double next = 0;
  EXPECT_EQ(fmu.function<decltype(fmi3UpdateDiscreteStates)>("fmi3UpdateDiscreteStates")(
                i, &update, &terminate, &nominals, &values, &next_defined, &next),
            fmi3OK);
  EXPECT_EQ(fmu.function<decltype(fmi3EnterContinuousTimeMode)>("fmi3EnterContinuousTimeMode")(i), fmi3OK);
  EXPECT_EQ(fmu.function<decltype(fmi3SetContinuousStates)>("fmi3SetContinuousStates")(i, x.data(), x.size()), fmi3OK);
  return i;
}

}  // namespace fmi_test
