#include "compiler/diagnostics.h"

#include <ostream>

namespace pbrtc {

Diagnostics::Diagnostics(const SourceFiles* files, std::ostream* out) : files_(files), out_(out) {}

void Diagnostics::error(Loc loc, const std::string& message) {
  report(Severity::kError, loc, message);
}

void Diagnostics::warning(Loc loc, const std::string& message) {
  report(werror ? Severity::kError : Severity::kWarning, loc, message);
}

void Diagnostics::report(Severity s, Loc loc, const std::string& message) {
  if (s == Severity::kError) {
    // Past the limit nothing more is printed: the caller is about to stop.
    if (errors_ >= max_errors) return;
    ++errors_;
  } else {
    ++warnings_;
  }
  std::string text;
  // gcc's include chain: "In file included from a:3,\n                 from b:7:\n".
  if (loc.valid() && files_) {
    Loc parent = files_->included_from(loc.file);
    bool first = true;
    while (parent.valid()) {
      LineCol lc = files_->line_col(parent);
      text += first ? "In file included from " : "                 from ";
      text += files_->display_path(parent.file) + ":" + std::to_string(lc.line);
      parent = files_->included_from(parent.file);
      text += parent.valid() ? ",\n" : ":\n";
      first = false;
    }
  }
  text += files_ ? files_->format(loc) : std::string("<input>");
  text += s == Severity::kError ? ": error: " : ": warning: ";
  text += message;
  bool print = true;
  if (s == Severity::kWarning && warnings_ > max_warnings_printed) print = false;
  if (out_ && print) *out_ << text << "\n";
  if (s == Severity::kWarning && warnings_ == max_warnings_printed + 1 && out_)
    *out_ << "(further warnings are not printed)\n";
  list_.push_back({s, loc, message, std::move(text)});
}

}  // namespace pbrtc
