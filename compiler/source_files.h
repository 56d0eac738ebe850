// compiler/source_files.h — the scene text files of one compile, and locations in them.
//
// Every token, parameter and scene entity carries a Loc: a file index and a byte
// offset. Line and column are worked out only when a message is printed or a
// record's provenance is written (a line index per file is built on first use),
// so the lexer's hot loop never counts newlines. Files are memory-mapped and stay
// mapped until the SourceFiles object dies: token views point into them.
//
// Paths are kept as the user gave them (the top-level path as typed, an Include
// joined to the top-level file's directory), so messages name files the user can
// open. Not thread-safe; one SourceFiles per compile.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace pbrtc {

inline constexpr uint32_t kNoFile = 0xFFFFFFFFu;

struct Loc {
  uint32_t file = kNoFile;
  uint64_t offset = 0;
  bool valid() const { return file != kNoFile; }
};

struct LineCol {
  uint32_t line = 0;    // 1-based
  uint32_t column = 0;  // 1-based, counted in bytes
};

class SourceFiles {
 public:
  SourceFiles();
  ~SourceFiles();
  SourceFiles(const SourceFiles&) = delete;
  SourceFiles& operator=(const SourceFiles&) = delete;

  // Maps a file. On failure returns kNoFile and sets *error (strerror text).
  // display_path is what messages print; included_from is the Include
  // directive's location (invalid for a top-level file).
  uint32_t open(const std::string& path, const std::string& display_path, Loc included_from,
                std::string* error);
  // Adds text held in memory (standard input, tests) as a file.
  uint32_t add_memory(std::string display_path, std::string text, Loc included_from);

  std::string_view text(uint32_t file) const;
  const std::string& display_path(uint32_t file) const;
  Loc included_from(uint32_t file) const;
  size_t size() const;

  LineCol line_col(Loc loc) const;
  // "path:line:col" for messages.
  std::string format(Loc loc) const;

 private:
  struct File;
  std::vector<std::unique_ptr<File>> files_;
};

}  // namespace pbrtc
