#include "ir/diagnostics.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace mbgc::ir {

int SourceManager::add(std::string display_path, std::string text) {
  SourceFile f;
  f.display_path = std::move(display_path);
  f.text = std::move(text);
  f.line_starts.push_back(0);
  for (std::size_t i = 0; i < f.text.size(); ++i)
    if (f.text[i] == '\n') f.line_starts.push_back(i + 1);
  files_.push_back(std::move(f));
  return static_cast<int>(files_.size()) - 1;
}

std::string SourceManager::line_text(int file_id, int line) const {
  const SourceFile& f = file(file_id);
  if (line < 1 || static_cast<std::size_t>(line) > f.line_starts.size()) return {};
  std::size_t begin = f.line_starts[static_cast<std::size_t>(line - 1)];
  std::size_t end = f.text.find('\n', begin);
  if (end == std::string::npos) end = f.text.size();
  std::string s = f.text.substr(begin, end - begin);
  if (!s.empty() && s.back() == '\r') s.pop_back();
  return s;
}

std::string SourceManager::where(const SourceLoc& loc) const {
  if (!loc.valid()) return tool_name_;
  return fmt::format("{}:{}:{}", file(loc.file).display_path, loc.line, loc.col);
}

Diagnostic& Diagnostics::error(SourceLoc loc, std::string message, std::string hint) {
  ++errors_;
  list_.push_back({Severity::Error, loc, std::move(message), std::move(hint), {}});
  return list_.back();
}

Diagnostic& Diagnostics::warning(SourceLoc loc, std::string message, std::string hint) {
  list_.push_back({Severity::Warning, loc, std::move(message), std::move(hint), {}});
  return list_.back();
}

Diagnostic& Diagnostics::note(SourceLoc loc, std::string message, std::string hint) {
  list_.push_back({Severity::Note, loc, std::move(message), std::move(hint), {}});
  return list_.back();
}

static const char* severity_name(Severity s) {
  switch (s) {
    case Severity::Error: return "error";
    case Severity::Warning: return "warning";
    case Severity::Note: return "note";
  }
  return "error";
}

void Diagnostics::render_one(std::ostream& out, Severity sev, const SourceLoc& loc,
                             const std::string& message) const {
  out << sources_->where(loc) << ": " << severity_name(sev) << ": " << message << "\n";
  if (!loc.valid()) return;
  std::string text = sources_->line_text(loc.file, loc.line);
  std::string gutter = fmt::format("{:>5} | ", loc.line);
  out << gutter << text << "\n";
  std::string caret(gutter.size() - 2, ' ');
  caret += "| ";
  // Keep tabs so the caret lines up under tab-indented source.
  for (int i = 0; i + 1 < loc.col && static_cast<std::size_t>(i) < text.size(); ++i)
    caret += text[static_cast<std::size_t>(i)] == '\t' ? '\t' : ' ';
  caret += '^';
  if (loc.length > 1) caret += std::string(static_cast<std::size_t>(loc.length - 1), '~');
  out << caret << "\n";
}

void Diagnostics::render(std::ostream& out) const {
  for (const Diagnostic& d : list_) {
    render_one(out, d.severity, d.loc, d.message);
    for (const auto& [loc, text] : d.notes) render_one(out, Severity::Note, loc, text);
    if (!d.hint.empty()) out << "      = hint: " << d.hint << "\n";
  }
}

static std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string closest_name(const std::string& wrong, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, wrong.size() / 3) + 1;
  for (const std::string& c : candidates) {
    std::size_t d = edit_distance(wrong, c);
    if (d < best_d || (d == best_d && !best.empty() && c < best)) {
      if (d < best_d) best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace mbgc::ir
