// ir/diagnostics.hpp — source files, locations and clang-style diagnostics.
//
// Every pass reports problems here instead of throwing; the driver stops after
// the first pass that reported an error and renders them all:
//
//   model.mbg:12:17: error: unknown element `rotr`
//      12 |   bond speed -> rotr
//         |                 ^~~~
//      hint: did you mean `rotor`?
#pragma once

#include <stdexcept>
#include <ostream>
#include <string>
#include <vector>

namespace mbgc::ir {

struct SourceLoc {
  int file = -1;   ///< index into SourceManager; -1: no location
  int line = 0;    ///< 1-based
  int col = 0;     ///< 1-based, in bytes
  int length = 1;  ///< caret span
  bool valid() const { return file >= 0; }
};

struct SourceFile {
  std::string display_path;  ///< as the user named it (goldens stay path-independent)
  std::string text;
  std::vector<std::size_t> line_starts;
};

class SourceManager {
 public:
  int add(std::string display_path, std::string text);
  const SourceFile& file(int id) const { return files_.at(static_cast<std::size_t>(id)); }
  int count() const { return static_cast<int>(files_.size()); }
  /// The text of `line` (1-based) without its newline.
  std::string line_text(int file, int line) const;
  /// "path:line:col", or the tool's name for a message without a place
  std::string where(const SourceLoc& loc) const;
  /// The name shown for messages without a place (the command line): "mbgc" unless set.
  void set_tool_name(std::string name) { tool_name_ = std::move(name); }

 private:
  std::vector<SourceFile> files_;
  std::string tool_name_ = "mbgc";
};

enum class Severity { Error, Warning, Note };

struct Diagnostic {
  Severity severity = Severity::Error;
  SourceLoc loc;
  std::string message;
  std::string hint;                                       ///< how to fix it (may be empty)
  std::vector<std::pair<SourceLoc, std::string>> notes;   ///< related places
};

class Diagnostics {
 public:
  explicit Diagnostics(const SourceManager& sources) : sources_(&sources) {}

  Diagnostic& error(SourceLoc loc, std::string message, std::string hint = {});
  Diagnostic& warning(SourceLoc loc, std::string message, std::string hint = {});
  /// Information about a deliberate choice (what the compiler did with it); never fails a build.
  Diagnostic& note(SourceLoc loc, std::string message, std::string hint = {});

  bool has_errors() const { return errors_ > 0; }
  int error_count() const { return errors_; }
  const std::vector<Diagnostic>& all() const { return list_; }
  /// The files the locations point into (a scratch Diagnostics over the same files).
  const SourceManager& sources() const { return *sources_; }
  void render(std::ostream& out) const;

 private:
  void render_one(std::ostream& out, Severity sev, const SourceLoc& loc,
                  const std::string& message) const;
  const SourceManager* sources_;
  std::vector<Diagnostic> list_;
  int errors_ = 0;
};

/// A mistake of the compiler's own (a pass wrote what the next cannot read),
/// never the user's: the driver reports it as an internal error.
struct InternalError : std::logic_error {
  using std::logic_error::logic_error;
};

/// Closest candidate by edit distance (for "did you mean"); empty if none is close.
std::string closest_name(const std::string& wrong, const std::vector<std::string>& candidates);

}  // namespace mbgc::ir
