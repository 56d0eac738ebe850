// runtime/film/atomic_file.h — files that appear whole or not at all.
//
// Writers write to temporary_name(path), a hidden name beside the target unique to
// this process and call, and commit_file() renames it over the target once the
// file is complete (a rename within a folder is atomic), so a reader — or a render
// killed mid-write — never sees half a file.
#pragma once

#include <string>

namespace rt {

std::string temporary_name(const std::string& path);
// Renames tmp over path; on failure removes tmp and says why ("cannot rename the
// finished <what> into place").
bool commit_file(const std::string& tmp, const std::string& path, const std::string& what,
                 std::string* error);
// Before the work that will write it: the folder exists and takes a new file (tried).
bool check_writable(const std::string& path, const std::string& what, std::string* error);
// Writes the bytes through a temporary file and commit_file().
bool write_file_atomically(const std::string& path, const std::string& bytes,
                           const std::string& what, std::string* error);

}  // namespace rt
