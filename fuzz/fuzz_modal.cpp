// fuzz_modal — the modal-data (.mbm) reader: any bytes give the body's data,
// whose mass terms are then formed, or a diagnostic at the file's line.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "flex/modal_file.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mbgc::ir::SourceManager sources;
  const int id = sources.add("fuzz.mbm", std::string(reinterpret_cast<const char*>(data), size));
  mbgc::ir::Diagnostics diags(sources);
  const auto modal = mbgc::flex::read_modal_source(sources, id, diags);
  std::ostringstream rendered;
  diags.render(rendered);
  mbgc::fuzz::check_diagnostics(diags, rendered.str());
  mbgc::fuzz::check(modal.has_value() != diags.has_errors(), "the reader's result and its diagnostics disagree");
  if (modal) (void)mbgc::flex::modal_mass_terms(*modal);
  return 0;
}
