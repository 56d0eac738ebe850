// compiler/diagnostics.h — errors and warnings about scene text.
//
// Every message reads "path:line:col: error: message" (or "warning:"), preceded
// by gcc's "In file included from path:line" chain when the location lies inside
// an Include. Errors mark the compile as failed but parsing goes on to the next
// directive, so one run reports many; after max_errors the caller stops. With
// werror set, warnings count as errors. Messages go to a stream (stderr in
// pbrtc) and are also kept in a list so tests can assert them exactly.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "compiler/source_files.h"

namespace pbrtc {

enum class Severity { kWarning, kError };

struct Diagnostic {
  Severity severity;
  Loc loc;
  std::string message;
  std::string text;  // the whole printed form, include chain included
};

class Diagnostics {
 public:
  explicit Diagnostics(const SourceFiles* files, std::ostream* out = nullptr);

  void error(Loc loc, const std::string& message);
  void warning(Loc loc, const std::string& message);

  int error_count() const { return errors_; }
  int warning_count() const { return warnings_; }
  bool failed() const { return errors_ > 0; }
  // True once max_errors errors were reported: the caller should stop.
  bool should_stop() const { return errors_ >= max_errors; }
  const std::vector<Diagnostic>& all() const { return list_; }

  bool werror = false;
  int max_errors = 20;
  // Identical warnings (same text, e.g. one per instance of a shape) are
  // printed once; the count of suppressed ones is still kept.
  int max_warnings_printed = 100;

 private:
  void report(Severity s, Loc loc, const std::string& message);

  const SourceFiles* files_;
  std::ostream* out_;
  std::vector<Diagnostic> list_;
  int errors_ = 0;
  int warnings_ = 0;
};

}  // namespace pbrtc
