// fmu/model_description.cpp — see model_description.hpp.
#include "fmu/model_description.hpp"

#include <fmt/format.h>

#include "mbgrt/integrators.hpp"

namespace mbgc::fmu {
namespace {

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        // (control characters are not allowed in XML 1.0 attribute values)
        out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return out;
}

/// A number that reads back as the same double.
std::string number(double v) { return fmt::format("{}", v); }

const char* causality_name(Causality c) {
  switch (c) {
    case Causality::independent: return "independent";
    case Causality::parameter: return "parameter";
    case Causality::calculated_parameter: return "calculatedParameter";
    case Causality::output: return "output";
    case Causality::local: return "local";
  }
  return "local";
}

/// FMI's BaseUnit of a dimension (whole exponents only), or empty.
std::string base_unit(const Unit& u) {
  if (!u.dimension) return {};
  static const struct {
    units::Base base;
    const char* name;
  } kBases[] = {{units::Base::Mass, "kg"},        {units::Base::Length, "m"},     {units::Base::Time, "s"},
                {units::Base::Current, "A"},      {units::Base::Temperature, "K"}, {units::Base::Amount, "mol"},
                {units::Base::Luminosity, "cd"}, {units::Base::Angle, "rad"}};
  std::string attributes;
  for (const auto& b : kBases) {
    const units::Rational e = (*u.dimension)[b.base];
    if (e.den != 1) return {};
    if (e.num != 0) attributes += fmt::format(" {}=\"{}\"", b.name, e.num);
  }
  if (u.factor != 1.0) attributes += fmt::format(" factor=\"{}\"", number(u.factor));
  return "<BaseUnit" + attributes + "/>";
}

std::string attribute(const char* name, const std::string& value) {
  return value.empty() ? std::string() : fmt::format(" {}=\"{}\"", name, xml_escape(value));
}

std::string unit_definitions(const Interface& fmu) {
  if (fmu.units.empty()) return {};
  std::string x = "  <UnitDefinitions>\n";
  for (const Unit& u : fmu.units) {
    const std::string base = base_unit(u);
    if (base.empty()) x += fmt::format("    <Unit name=\"{}\"/>\n", xml_escape(u.name));
    else x += fmt::format("    <Unit name=\"{}\">{}</Unit>\n", xml_escape(u.name), base);
  }
  return x + "  </UnitDefinitions>\n";
}

std::string log_categories_and_experiment(const Interface& fmu) {
  std::string x =
      "  <LogCategories>\n"
      "    <Category name=\"logEvents\" description=\"events: modes switched, impacts, contacts made and lost\"/>\n"
      "    <Category name=\"logStatusWarning\"/>\n"
      "    <Category name=\"logStatusError\" description=\"why a call failed: the run's stop report\"/>\n"
      "  </LogCategories>\n";
  const mbgrt::Settings& d = fmu.defaults;
  return x + fmt::format("  <DefaultExperiment startTime=\"{}\" stopTime=\"{}\" tolerance=\"{}\" stepSize=\"{}\"/>\n",
                         number(d.t_start_s), number(d.t_end_s), number(d.rtol), number(d.interval_s));
}

/// ` variability="..."`; none for an enumeration (its default, discrete).
std::string variability(const Variable& v) {
  switch (v.variability) {
    case Variability::fixed: return " variability=\"fixed\"";
    case Variability::constant: return " variability=\"constant\"";
    case Variability::continuous: break;
  }
  return v.type == Type::enumeration ? "" : " variability=\"continuous\"";
}

/// ` dependencies="..."`: what `v` reads, by value reference (FMI 3.0,
/// `base` 0) or 1-based index (FMI 2.0, `base` 1, where every variable
/// before the event indicators has index value reference + 1); empty where
/// not known.
std::string dependencies(const Variable& v, unsigned base) {
  if (!v.dependencies) return {};
  std::string list;
  for (unsigned known : *v.dependencies) list += (list.empty() ? "" : " ") + std::to_string(known + base);
  return fmt::format(" dependencies=\"{}\"", list);
}

/// The solver's items: name, value (mbgrt::Solver + 1), description.
template <class Item>
std::string solver_items(Item&& item) {
  std::string x;
  for (const mbgrt::IntegratorInfo& i : mbgrt::kIntegrators) x += item(i.name, static_cast<int>(i.solver) + 1, xml_escape(i.method));
  return x;
}

std::string v3(const Interface& fmu, const Offer& offer, const std::string& token, const std::string& generator) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format("<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{}\" instantiationToken=\"{}\"{} "
                   "generationTool=\"{}\" variableNamingConvention=\"flat\">\n",
                   xml_escape(fmu.model_name), token, attribute("description", fmu.description), xml_escape(generator));
  const std::string id = xml_escape(fmu.model_name);
  if (offer.model_exchange)
    x += fmt::format("  <ModelExchange modelIdentifier=\"{}\" needsCompletedIntegratorStep=\"true\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\" providesDirectionalDerivatives=\"true\" "
                     "canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\"/>\n",
                     id);
  if (offer.co_simulation)
    x += fmt::format("  <CoSimulation modelIdentifier=\"{}\" canHandleVariableCommunicationStepSize=\"true\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\" hasEventMode=\"false\" mightReturnEarlyFromDoStep=\"true\" "
                     "providesDirectionalDerivatives=\"true\" "
                     "canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\"/>\n",
                     id);
  x += unit_definitions(fmu);
  x += "  <TypeDefinitions>\n    <EnumerationType name=\"Solver\">\n";
  x += solver_items([](const char* name, int value, const std::string& description) {
    return fmt::format("      <Item name=\"{}\" value=\"{}\" description=\"{}\"/>\n", name, value, description);
  });
  x += "    </EnumerationType>\n  </TypeDefinitions>\n";
  x += log_categories_and_experiment(fmu);
  x += "  <ModelVariables>\n";
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Variable& v = fmu.variables[vr];
    const bool enumeration = v.type == Type::enumeration;
    std::string a = fmt::format("name=\"{}\" valueReference=\"{}\"", xml_escape(v.name), vr);
    if (enumeration) a += " declaredType=\"Solver\"";
    a += attribute("description", v.description);
    a += fmt::format(" causality=\"{}\"", causality_name(v.causality));
    a += variability(v);
    if (v.start) a += fmt::format(" start=\"{}\"", enumeration ? fmt::format("{}", static_cast<long>(*v.start)) : number(*v.start));
    // states, derivatives and indicators come out of the initialisation
    if (v.kind == Kind::state || v.kind == Kind::derivative || v.kind == Kind::calculated) a += " initial=\"calculated\"";
    if (v.derivative_of >= 0) a += fmt::format(" derivative=\"{}\"", v.derivative_of);
    a += attribute("unit", v.unit);
    x += fmt::format("    <{} {}/>\n", enumeration ? "Enumeration" : "Float64", a);
  }
  x += "  </ModelVariables>\n  <ModelStructure>\n";
  const auto unknown = [&](const char* element, std::size_t vr) {
    return fmt::format("    <{} valueReference=\"{}\"{}/>\n", element, vr, dependencies(fmu.variables[vr], 0));
  };
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::output) x += unknown("Output", vr);
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::derivative) x += unknown("ContinuousStateDerivative", vr);
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Kind k = fmu.variables[vr].kind;
    if (k == Kind::output || k == Kind::state || k == Kind::derivative || k == Kind::calculated)
      x += fmt::format("    <InitialUnknown valueReference=\"{}\"/>\n", vr);
  }
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::event_indicator) x += unknown("EventIndicator", vr);
  x += "  </ModelStructure>\n</fmiModelDescription>\n";
  return x;
}


/// FMI 2.0: ScalarVariables, event indicators counted (not variables), and
/// ModelStructure by 1-based index into ModelVariables. The event indicators
/// are the last value references, so every other variable's index is its
/// value reference + 1.
std::string v2(const Interface& fmu, const Offer& offer, const std::string& guid, const std::string& generator,
               const std::vector<std::string>& sources) {
  std::string files;
  if (!sources.empty()) {
    files = "    <SourceFiles>\n";
    for (const std::string& file : sources) files += fmt::format("      <File name=\"{}\"/>\n", xml_escape(file));
    files += "    </SourceFiles>\n";
  }
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format("<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{}\"{} generationTool=\"{}\" "
                   "variableNamingConvention=\"flat\" numberOfEventIndicators=\"{}\">\n",
                   xml_escape(fmu.model_name), guid, attribute("description", fmu.description), xml_escape(generator),
                   fmu.event_indicators);
  const std::string id = xml_escape(fmu.model_name);
  if (offer.model_exchange)
    x += fmt::format("  <ModelExchange modelIdentifier=\"{}\" completedIntegratorStepNotNeeded=\"false\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" "
                     "providesDirectionalDerivative=\"true\" canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\">\n{}"
                     "  </{}>\n",
                     id, files, "ModelExchange");
  if (offer.co_simulation)
    x += fmt::format("  <CoSimulation modelIdentifier=\"{}\" canHandleVariableCommunicationStepSize=\"true\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" "
                     "providesDirectionalDerivative=\"true\" canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\">\n{}"
                     "  </{}>\n",
                     id, files, "CoSimulation");
  x += unit_definitions(fmu);
  x += "  <TypeDefinitions>\n    <SimpleType name=\"Solver\">\n      <Enumeration>\n";
  x += solver_items([](const char* name, int value, const std::string& description) {
    return fmt::format("        <Item name=\"{}\" value=\"{}\" description=\"{}\"/>\n", name, value, description);
  });
  x += "      </Enumeration>\n    </SimpleType>\n  </TypeDefinitions>\n";
  x += log_categories_and_experiment(fmu);
  x += "  <ModelVariables>\n";
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Variable& v = fmu.variables[vr];
    if (v.kind == Kind::event_indicator) continue;
    const bool enumeration = v.type == Type::enumeration;
    std::string a = fmt::format("name=\"{}\" valueReference=\"{}\"", xml_escape(v.name), vr);
    a += attribute("description", v.description);
    a += fmt::format(" causality=\"{}\"", causality_name(v.causality));
    a += variability(v);
    if (v.kind == Kind::state || v.kind == Kind::derivative || v.kind == Kind::calculated) a += " initial=\"calculated\"";
    std::string type;
    if (enumeration) type = "<Enumeration declaredType=\"Solver\"";
    else type = "<Real";
    if (v.start) type += fmt::format(" start=\"{}\"", enumeration ? fmt::format("{}", static_cast<long>(*v.start)) : number(*v.start));
    if (v.derivative_of >= 0) type += fmt::format(" derivative=\"{}\"", v.derivative_of + 1);
    type += attribute("unit", v.unit) + "/>";
    x += fmt::format("    <ScalarVariable {}>{}</ScalarVariable>\n", a, type);
  }
  x += "  </ModelVariables>\n  <ModelStructure>\n";
  auto list = [&](const char* element, auto&& wanted, bool with_dependencies = true) {
    std::string items;
    for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
      if (wanted(fmu.variables[vr].kind))
        items += fmt::format("      <Unknown index=\"{}\"{}/>\n", vr + 1,
                             with_dependencies ? dependencies(fmu.variables[vr], 1) : std::string());
    if (!items.empty()) x += fmt::format("    <{0}>\n{1}    </{0}>\n", element, items);
  };
  list("Outputs", [](Kind k) { return k == Kind::output; });
  list("Derivatives", [](Kind k) { return k == Kind::derivative; });
  // (an initial unknown depends on the parameters too: not stated, so on every known)
  list("InitialUnknowns",
       [](Kind k) { return k == Kind::output || k == Kind::state || k == Kind::derivative || k == Kind::calculated; },
       false);
  x += "  </ModelStructure>\n</fmiModelDescription>\n";
  return x;
}

}  // namespace

std::string model_description(const Interface& fmu, FmiVersion version, const Offer& offer, const std::string& token,
                              const std::string& generator, const std::vector<std::string>& sources) {
  return version == FmiVersion::v2 ? v2(fmu, offer, token, generator, sources) : v3(fmu, offer, token, generator);
}

}  // namespace mbgc::fmu
