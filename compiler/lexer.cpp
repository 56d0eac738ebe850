#include "compiler/lexer.h"

#include <fast_float/fast_float.h>

#include <cmath>
#include <cstring>

namespace pbrtc {

namespace {

// Character classes in one table: the scanner tests one byte per step.
enum : uint8_t { kOther = 0, kSpace = 1, kDelim = 2, kBad = 4 };

struct CharTable {
  uint8_t c[256];
  constexpr CharTable() : c() {
    for (int i = 0; i < 256; ++i) c[i] = kOther;
    for (int i = 0; i < 0x20; ++i) c[i] = kBad;
    c[0x7F] = kBad;
    for (int i = 0x80; i < 256; ++i) c[i] = kBad;
    c[int(' ')] = c[int('\t')] = c[int('\n')] = c[int('\r')] = kSpace | kDelim;
    c[int('\f')] = c[int('\v')] = kSpace | kDelim;
    c[int('[')] = c[int(']')] = c[int('"')] = c[int('#')] = kDelim;
  }
};
constexpr CharTable kChars;

inline bool is_space(char ch) {
  return kChars.c[uint8_t(ch)] & kSpace;
}
inline bool is_delim(char ch) {
  return kChars.c[uint8_t(ch)] & (kDelim | kBad);
}
inline bool starts_number(char ch) {
  return (ch >= '0' && ch <= '9') || ch == '-' || ch == '+' || ch == '.';
}

std::string describe_byte(unsigned char ch) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%02X", ch);
  return buf;
}

// Powers of ten that float holds exactly (5^10 < 2^24).
constexpr float kPow10[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f, 1e10f};

}  // namespace

const char* parse_short_float(const char* p, const char* end, float* out) {
  // Clinger's fast path: a mantissa below 2^24 and a power of ten up to 10^10
  // are exact floats, so one multiplication or division rounds correctly: the
  // same float fast_float gives. Anything else returns null and goes to
  // fast_float. The digit loops carry no per-digit checks beyond the bounds.
  bool neg = false;
  if (p < end && (*p == '-' || *p == '+')) neg = *p++ == '-';
  uint64_t m = 0;
  const char* digits = p;
  while (p < end && uint8_t(*p - '0') < 10) m = m * 10 + uint64_t(*p++ - '0');
  ptrdiff_t n = p - digits, frac = 0;
  if (p < end && *p == '.') {
    const char* f = ++p;
    while (p < end && uint8_t(*p - '0') < 10) m = m * 10 + uint64_t(*p++ - '0');
    frac = p - f;
  }
  // 19 digits always fit in 64 bits; more would have wrapped.
  if (n + frac == 0 || n + frac > 19 || m > (uint64_t(1) << 24)) return nullptr;
  ptrdiff_t e10 = -frac;
  if (p < end && (*p == 'e' || *p == 'E')) {
    ++p;
    bool eneg = false;
    if (p < end && (*p == '-' || *p == '+')) eneg = *p++ == '-';
    const char* ed = p;
    int e = 0;
    while (p < end && uint8_t(*p - '0') < 10 && p - ed < 3) e = e * 10 + (*p++ - '0');
    if (p == ed || (p < end && uint8_t(*p - '0') < 10)) return nullptr;
    e10 += eneg ? -e : e;
  }
  if (e10 < -10 || e10 > 10) return nullptr;
  float v = float(m);
  v = e10 >= 0 ? v * kPow10[e10] : v / kPow10[-e10];
  *out = neg ? -v : v;
  return p;
}

namespace {
// A whole token as a number: fast_float, like from_chars, rejects a leading '+'.
template <class T>
bool parse_number_token(std::string_view s, T* v) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b < e && *b == '+') {
    ++b;
    if (b < e && (*b == '+' || *b == '-')) return false;
  }
  if (b == e) return false;
  auto r = fast_float::from_chars(b, e, *v);
  return r.ec == std::errc() && r.ptr == e;
}
}  // namespace

bool parse_float_token(std::string_view s, float* v) {
  return parse_number_token(s, v);
}
bool parse_double_token(std::string_view s, double* v) {
  return parse_number_token(s, v);
}

bool parse_int_token(std::string_view s, int32_t* v) {
  const char* b = s.data();
  const char* e = b + s.size();
  bool neg = false;
  if (b < e && (*b == '+' || *b == '-')) neg = *b++ == '-';
  if (b == e) return false;
  int64_t acc = 0;
  for (; b < e; ++b) {
    if (*b < '0' || *b > '9') return false;
    acc = acc * 10 + (*b - '0');
    if (acc > int64_t(1) << 31) return false;
  }
  if (neg) acc = -acc;
  if (acc > INT32_MAX || acc < INT32_MIN) return false;
  *v = int32_t(acc);
  return true;
}

Lexer::Lexer(const SourceFiles& files, uint32_t file, Diagnostics* diag)
    : file_(file), diag_(diag) {
  std::string_view t = files.text(file);
  begin_ = t.data();
  p_ = begin_;
  end_ = begin_ + t.size();
  // A UTF-8 byte order mark is not part of the scene.
  if (t.size() >= 3 && std::memcmp(begin_, "\xEF\xBB\xBF", 3) == 0) p_ += 3;
}

void Lexer::fatal(const char* p, const std::string& message) {
  diag_->error(loc_at(p), message);
  broken_ = true;
  p_ = end_;
}

void Lexer::skip_space() {
  for (;;) {
    while (p_ < end_ && is_space(*p_)) ++p_;
    if (p_ < end_ && *p_ == '#') {
      // Comments may hold any text, UTF-8 included.
      const void* nl = std::memchr(p_, '\n', size_t(end_ - p_));
      p_ = nl ? static_cast<const char*>(nl) + 1 : end_;
      continue;
    }
    return;
  }
}

const Token& Lexer::peek() {
  if (!has_peek_) {
    peeked_ = lex();
    has_peek_ = true;
  }
  return peeked_;
}

Token Lexer::next() {
  if (has_peek_) {
    has_peek_ = false;
    return peeked_;
  }
  return lex();
}

Token Lexer::lex() {
  skip_space();
  Token t;
  if (p_ >= end_) {
    t.kind = TokenKind::kEnd;
    t.loc = loc_at(end_);
    return t;
  }
  const char* start = p_;
  t.loc = loc_at(start);
  char ch = *p_;
  if (ch == '[' || ch == ']') {
    ++p_;
    t.kind = ch == '[' ? TokenKind::kLBracket : TokenKind::kRBracket;
    t.text = std::string_view(start, 1);
    return t;
  }
  if (ch == '"') {
    ++p_;
    const char* s = p_;
    bool escaped = false;
    while (p_ < end_ && *p_ != '"') {
      unsigned char c = uint8_t(*p_);
      if (c == '\n' || c == '\r') {
        fatal(start, "unterminated string (a quoted string cannot span lines)");
        t.kind = TokenKind::kEnd;
        return t;
      }
      if (c < 0x20 && c != '\t') {
        fatal(p_, "control byte " + describe_byte(c) + " inside a string: is this a text file?");
        t.kind = TokenKind::kEnd;
        return t;
      }
      if (c == '\\') {
        escaped = true;
        if (p_ + 1 < end_) ++p_;
      }
      ++p_;
    }
    if (p_ >= end_) {
      fatal(start, "unterminated string (end of file inside quotes)");
      t.kind = TokenKind::kEnd;
      return t;
    }
    t.kind = TokenKind::kString;
    t.text = std::string_view(s, size_t(p_ - s));
    ++p_;  // closing quote
    if (escaped) {
      unescaped_.clear();
      for (size_t i = 0; i < t.text.size(); ++i) {
        char c = t.text[i];
        if (c == '\\' && i + 1 < t.text.size()) {
          char e = t.text[++i];
          switch (e) {
            case 'b':
              c = '\b';
              break;
            case 'f':
              c = '\f';
              break;
            case 'n':
              c = '\n';
              break;
            case 'r':
              c = '\r';
              break;
            case 't':
              c = '\t';
              break;
            default:
              c = e;
              break;  // \\ \" \' and anything else stand for themselves
          }
        }
        unescaped_.push_back(c);
      }
      t.text = unescaped_;
    }
    return t;
  }
  if (kChars.c[uint8_t(ch)] & kBad) {
    fatal(start, "unexpected byte " + describe_byte(uint8_t(ch)) +
                     " outside a string or comment: is this a text file?");
    t.kind = TokenKind::kEnd;
    return t;
  }
  while (p_ < end_ && !is_delim(*p_)) ++p_;
  t.text = std::string_view(start, size_t(p_ - start));
  t.kind = starts_number(ch) ? TokenKind::kNumber : TokenKind::kWord;
  return t;
}

bool Lexer::to_float(const Token& tok, float* v) {
  if (!parse_float_token(tok.text, v)) {
    diag_->error(tok.loc, "malformed number '" + std::string(tok.text) + "'");
    return false;
  }
  if (!std::isfinite(*v)) {
    diag_->error(tok.loc, "number '" + std::string(tok.text) + "' is not finite");
    return false;
  }
  return true;
}

bool Lexer::to_double(const Token& tok, double* v) {
  if (!parse_double_token(tok.text, v)) {
    diag_->error(tok.loc, "malformed number '" + std::string(tok.text) + "'");
    return false;
  }
  // Values that only overflow float are as wrong as they are in the rest of the scene.
  if (!std::isfinite(*v) || !std::isfinite(float(*v))) {
    diag_->error(tok.loc, "number '" + std::string(tok.text) + "' is not finite");
    return false;
  }
  return true;
}

bool Lexer::read_doubles(std::vector<double>* out) {
  for (;;) {
    Token t = next();
    if (t.kind == TokenKind::kRBracket) return true;
    if (t.kind != TokenKind::kNumber) return bad_array_token(t, "a number", nullptr);
    double v;
    if (!to_double(t, &v)) return false;
    out->push_back(v);
  }
}

bool Lexer::to_int(const Token& tok, int32_t* v) {
  if (parse_int_token(tok.text, v)) return true;
  float f;
  if (!parse_float_token(tok.text, &f)) {
    diag_->error(tok.loc, "malformed number '" + std::string(tok.text) + "'");
    return false;
  }
  // A whole number spelled as a float ("2.0", "1e3") is still an integer.
  bool whole = std::isfinite(f) && std::floor(f) == f;
  if (whole && f >= -2147483648.0f && f < 2147483648.0f) {
    *v = int32_t(f);
    return true;
  }
  if (whole || !std::isfinite(f))
    diag_->error(tok.loc, "integer '" + std::string(tok.text) + "' is out of range");
  else
    diag_->error(tok.loc, "expected an integer, got '" + std::string(tok.text) + "'");
  return false;
}

bool Lexer::read_numbers(std::vector<float>* out, Loc* first_bad) {
  // Callers come here straight after '[', so normally no token is pending.
  if (has_peek_) {
    Token t = next();
    if (t.kind == TokenKind::kRBracket) return true;
    if (t.kind != TokenKind::kNumber) return bad_array_token(t, "a number", first_bad);
    float v;
    if (!to_float(t, &v)) return false;
    out->push_back(v);
  }
  const char* p = p_;
  const char* end = end_;
  for (;;) {
    while (p < end && is_space(*p)) ++p;
    if (p < end && starts_number(*p)) {
      const char* start = p;
      float v;
      if (const char* q = parse_short_float(p, end, &v); q && (q == end || is_delim(*q))) {
        out->push_back(v);
        p = q;
        continue;
      }
      if (*p == '+') ++p;
      auto r = fast_float::from_chars(p, end, v);
      if (__builtin_expect(
              r.ec != std::errc() || (r.ptr < end && !is_delim(*r.ptr)) || !std::isfinite(v), 0)) {
        p_ = start;
        while (p_ < end_ && !is_delim(*p_)) ++p_;
        Token t{TokenKind::kNumber, std::string_view(start, size_t(p_ - start)), loc_at(start)};
        if (first_bad) *first_bad = t.loc;
        to_float(t, &v);  // reports
        return false;
      }
      out->push_back(v);
      p = r.ptr;
      continue;
    }
    if (p < end && *p == ']') {
      p_ = p + 1;
      return true;
    }
    // A comment, the end of the file or something that is not a number.
    p_ = p;
    Token t = next();
    if (t.kind == TokenKind::kRBracket) return true;
    if (t.kind != TokenKind::kNumber) return bad_array_token(t, "a number", first_bad);
    float v;
    if (!to_float(t, &v)) return false;
    out->push_back(v);
    p = p_;
  }
}

bool Lexer::bad_array_token(const Token& t, const char* expected, Loc* first_bad) {
  if (first_bad) *first_bad = t.loc;
  if (t.kind == TokenKind::kEnd && !broken_)
    diag_->error(t.loc, "unterminated '[' array at end of file");
  else if (t.kind != TokenKind::kEnd)
    diag_->error(
        t.loc, std::string("expected ") + expected + " or ']', got '" + std::string(t.text) + "'");
  return false;
}

bool Lexer::read_integers(std::vector<uint32_t>* out) {
  for (;;) {
    if (!has_peek_) {
      const char* p = p_;
      const char* end = end_;
      // Fast path for plain decimal integers separated by white space.
      for (;;) {
        while (p < end && is_space(*p)) ++p;
        if (p >= end) break;
        bool neg = *p == '-';
        const char* q = p + neg;
        const char* digits = q;
        uint64_t acc = 0;
        while (q < end && uint8_t(*q - '0') < 10 && q - digits < 10)
          acc = acc * 10 + uint8_t(*q++ - '0');
        if (q == digits || (q < end && !is_space(*q) && *q != ']') ||
            acc > (neg ? uint64_t(1) << 31 : uint64_t(INT32_MAX)))
          break;
        out->push_back(uint32_t(neg ? int32_t(-int64_t(acc)) : int32_t(acc)));
        p = q;
      }
      p_ = p;
    }
    Token t = next();
    if (t.kind == TokenKind::kRBracket) return true;
    if (t.kind == TokenKind::kNumber) {
      int32_t v;
      if (!to_int(t, &v)) return false;
      out->push_back(uint32_t(v));
      continue;
    }
    return bad_array_token(t, "an integer", nullptr);
  }
}

}  // namespace pbrtc
