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

std::string v3(const Interface& fmu, const Offer& offer, const std::string& token, const std::string& generator) {
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format("<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{}\" instantiationToken=\"{}\"{} "
                   "generationTool=\"{}\" variableNamingConvention=\"flat\">\n",
                   xml_escape(fmu.model_name), token, attribute("description", fmu.description), xml_escape(generator));
  const std::string id = xml_escape(fmu.model_name);
  if (offer.model_exchange)
    x += fmt::format("  <ModelExchange modelIdentifier=\"{}\" needsCompletedIntegratorStep=\"true\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\"/>\n",
                     id);
  if (offer.co_simulation)
    x += fmt::format("  <CoSimulation modelIdentifier=\"{}\" canHandleVariableCommunicationStepSize=\"true\" "
                     "canBeInstantiatedOnlyOncePerProcess=\"false\" hasEventMode=\"false\"/>\n",
                     id);
  if (!fmu.units.empty()) {
    x += "  <UnitDefinitions>\n";
    for (const Unit& u : fmu.units) {
      const std::string base = base_unit(u);
      if (base.empty()) x += fmt::format("    <Unit name=\"{}\"/>\n", xml_escape(u.name));
      else x += fmt::format("    <Unit name=\"{}\">{}</Unit>\n", xml_escape(u.name), base);
    }
    x += "  </UnitDefinitions>\n";
  }
  x += "  <TypeDefinitions>\n    <EnumerationType name=\"Solver\">\n";
  for (const mbgrt::IntegratorInfo& i : mbgrt::kIntegrators) {
    x += fmt::format("      <Item name=\"{}\" value=\"{}\" description=\"{}\"/>\n", i.name,
                     static_cast<int>(i.solver) + 1, xml_escape(i.method));
  }
  x += "    </EnumerationType>\n  </TypeDefinitions>\n";
  x += "  <LogCategories>\n"
       "    <Category name=\"logEvents\" description=\"events: modes switched, impacts, contacts made and lost\"/>\n"
       "    <Category name=\"logStatusWarning\"/>\n"
       "    <Category name=\"logStatusError\" description=\"why a call failed: the run's stop report\"/>\n"
       "  </LogCategories>\n";
  const mbgrt::Settings& d = fmu.defaults;
  x += fmt::format("  <DefaultExperiment startTime=\"{}\" stopTime=\"{}\" tolerance=\"{}\" stepSize=\"{}\"/>\n",
                   number(d.t_start_s), number(d.t_end_s), number(d.rtol), number(d.interval_s));
  x += "  <ModelVariables>\n";
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Variable& v = fmu.variables[vr];
    const bool enumeration = v.type == Type::enumeration;
    std::string a = fmt::format("name=\"{}\" valueReference=\"{}\"", xml_escape(v.name), vr);
    if (enumeration) a += " declaredType=\"Solver\"";
    a += attribute("description", v.description);
    a += fmt::format(" causality=\"{}\"", causality_name(v.causality));
    if (v.variability == Variability::fixed) a += " variability=\"fixed\"";
    else if (!enumeration) a += " variability=\"continuous\"";
    if (v.start) a += fmt::format(" start=\"{}\"", enumeration ? fmt::format("{}", static_cast<long>(*v.start)) : number(*v.start));
    // states, derivatives and indicators come out of the initialisation
    if (v.kind == Kind::state || v.kind == Kind::derivative) a += " initial=\"calculated\"";
    if (v.derivative_of >= 0) a += fmt::format(" derivative=\"{}\"", v.derivative_of);
    a += attribute("unit", v.unit);
    x += fmt::format("    <{} {}/>\n", enumeration ? "Enumeration" : "Float64", a);
  }
  x += "  </ModelVariables>\n  <ModelStructure>\n";
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::output) x += fmt::format("    <Output valueReference=\"{}\"/>\n", vr);
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::derivative)
      x += fmt::format("    <ContinuousStateDerivative valueReference=\"{}\"/>\n", vr);
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr) {
    const Kind k = fmu.variables[vr].kind;
    if (k == Kind::output || k == Kind::state || k == Kind::derivative)
      x += fmt::format("    <InitialUnknown valueReference=\"{}\"/>\n", vr);
  }
  for (std::size_t vr = 0; vr < fmu.variables.size(); ++vr)
    if (fmu.variables[vr].kind == Kind::event_indicator)
      x += fmt::format("    <EventIndicator valueReference=\"{}\"/>\n", vr);
  x += "  </ModelStructure>\n</fmiModelDescription>\n";
  return x;
}

}  // namespace

std::string model_description(const Interface& fmu, FmiVersion version, const Offer& offer, const std::string& token,
                              const std::string& generator) {
  (void)version;  // FMI 2.0: fmu/model_description.cpp writes 3.0 only so far
  return v3(fmu, offer, token, generator);
}

}  // namespace mbgc::fmu
