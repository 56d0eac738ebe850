// compiler/lexer.h — tokens of the pbrt-v3 scene language.
//
// The lexer walks one memory-mapped file and hands out std::string_view tokens
// that point into it; nothing is allocated per token. The one exception is a
// quoted string with backslash escapes: it is unescaped into a buffer owned by
// the lexer, and that view dies at the next call to next() — callers that keep a
// string copy it. Locations are byte offsets (see source_files.h).
//
// Tokens: quoted strings (no newline inside), numbers (every spelling fast_float
// reads, plus a leading '+'), bare words (directive names), '[' and ']'. '#'
// starts a comment to the end of the line; CR, tabs and a UTF-8 byte order mark
// are whitespace. Control bytes or non-ASCII bytes outside strings and comments
// mean the file is not scene text; they are reported once and end the file.
//
// read_numbers() is the hot path for mesh data: it parses a bracketed run of
// numbers straight from the buffer without building tokens.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/source_files.h"

namespace pbrtc {

enum class TokenKind : uint8_t { kEnd, kString, kNumber, kWord, kLBracket, kRBracket };

struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string_view text;  // for strings: the contents, without quotes
  Loc loc;
};

class Lexer {
 public:
  Lexer(const SourceFiles& files, uint32_t file, Diagnostics* diag);

  // The next token; kEnd at end of file (or after a fatal lexical error).
  Token next();
  // The next token without consuming it.
  const Token& peek();

  // After a '[' was consumed: appends numbers to *out until the matching ']'
  // (consumed). Returns false after reporting an error (a non-number inside,
  // an unterminated array, a NaN/Inf or out-of-range value). With integers set,
  // values must be whole numbers in the int32 range and go to *ints instead.
  bool read_numbers(std::vector<float>* out, Loc* first_bad = nullptr);
  bool read_integers(std::vector<uint32_t>* out);  // two's-complement bits

  // Converts a kNumber token. Report errors at tok.loc and return false.
  bool to_float(const Token& tok, float* v);
  // Transforms are read in double precision, so a transform written by
  // pbrtc --dump with 17 digits reads back bit for bit.
  bool to_double(const Token& tok, double* v);
  bool read_doubles(std::vector<double>* out);
  bool to_int(const Token& tok, int32_t* v);

  // True if s points into this lexer's unescape buffer (and so dies at the
  // next token).
  bool owns(std::string_view s) const {
    return !unescaped_.empty() && s.data() >= unescaped_.data() &&
           s.data() <= unescaped_.data() + unescaped_.size();
  }
  // True once a lexical error ended the file.
  bool broken() const { return broken_; }
  uint32_t file() const { return file_; }

 private:
  Token lex();
  void skip_space();
  Loc loc_at(const char* p) const { return Loc{file_, uint64_t(p - begin_)}; }
  void fatal(const char* p, const std::string& message);
  bool bad_array_token(const Token& t, const char* expected, Loc* first_bad);

  const char* begin_;
  const char* p_;
  const char* end_;
  uint32_t file_;
  Diagnostics* diag_;
  bool has_peek_ = false;
  bool broken_ = false;
  Token peeked_;
  std::string unescaped_;
};

// Shared number rules, also used by the fuzzer and tests: parses a whole token.
bool parse_float_token(std::string_view s, float* v);
bool parse_double_token(std::string_view s, double* v);
// The fast path for short decimals (at most 7 significant digits, exponent within
// 10): returns the end of the number, or null if it must go to fast_float. The
// result is always the float fast_float would give.
const char* parse_short_float(const char* p, const char* end, float* out);
bool parse_int_token(std::string_view s, int32_t* v);

}  // namespace pbrtc
