// fe/text_reader.cpp
#include "text_reader.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

namespace mbgc::fe {

bool TextReader::open(const std::string& path, char comment) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    diags_.error({}, fmt::format("cannot read `{}`", path), "check the path; it is taken relative to the working directory");
    return false;
  }
  std::ostringstream buf;
  buf << in.rdbuf();
  file_ = sources_.add(path, buf.str());
  text_ = sources_.file(file_).text;
  comment_ = comment;
  return true;
}

bool TextReader::raw_line() {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
  line_ = text_.substr(pos_, end - pos_);
  if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
  pos_ = end + 1;
  ++line_no_;
  return true;
}

bool TextReader::next_line(std::vector<Word>& words) {
  words.clear();
  while (raw_line()) {
    std::size_t i = 0;
    while (i < line_.size()) {
      const char c = line_[i];
      if (c == comment_) break;
      if (c == ' ' || c == '\t' || c == ',') {
        ++i;
        continue;
      }
      const std::size_t start = i;
      while (i < line_.size() && line_[i] != ' ' && line_[i] != '\t' && line_[i] != ',' && line_[i] != comment_) ++i;
      words.push_back({line_.substr(start, i - start),
                       ir::SourceLoc{file_, line_no_, static_cast<int>(start) + 1, static_cast<int>(i - start)}});
    }
    if (!words.empty()) return true;
  }
  return false;
}

std::optional<double> TextReader::number(const Word& w, const char* what) {
  const std::string text(w.text);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || text.empty()) {
    diags_.error(w.loc, fmt::format("expected a number for {}, found `{}`", what, text));
    return std::nullopt;
  }
  if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1)) {
    diags_.error(w.loc, fmt::format("`{}` ({}) is not a finite double", text, what),
                 "numbers must lie within about ±1.8e308");
    return std::nullopt;
  }
  return v;
}

std::optional<long long> TextReader::integer(const Word& w, const char* what, long long lowest, long long highest) {
  const std::string text(w.text);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || text.empty() || errno == ERANGE) {
    diags_.error(w.loc, fmt::format("expected a whole number for {}, found `{}`", what, text));
    return std::nullopt;
  }
  if (v < lowest || v > highest) {
    diags_.error(w.loc, fmt::format("{} is {}, outside {}..{}", what, text, lowest, highest));
    return std::nullopt;
  }
  return v;
}

}  // namespace mbgc::fe
