// The plain-value filter, two ValueRecords per 256-bit step (format/plain_values.h).
#include "format/plain_values.h"

#include <immintrin.h>

namespace pbrta {

std::vector<PlainLanes> plain_lanes(const TypeSpec& type) {
  std::vector<PlainLanes> lanes;
  for (uint32_t p = 0; p < type.num_params; ++p) {
    const ParamSpec& ps = type.params[p];
    const bool text = ps.kind == Kind::kString;
    lanes.push_back({uint32_t(kind_width(ps.kind)), text ? 0u : ps.arity,
                     !text && ps.arity == 0 ? ~0u : 0u, 0});
  }
  if (lanes.size() % 2 != 0) lanes.push_back({});  // loaded, but its lane is masked off
  return lanes;
}

bool plain_filter_available() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

// Each step sets all ones in every 32-bit field of a value (offset, count, texture, flags) that
// breaks a rule, against its lanes (width, arity, any_count).
[[gnu::target("avx2")]] bool plain_values(const ValueRecord* values, const PlainLanes* lanes,
                                          uint32_t n, uint64_t num_words) {
  static_assert(sizeof(ValueRecord) == 16 && sizeof(PlainLanes) == 16);
  const __m256i zero = _mm256_setzero_si256(), ones = _mm256_cmpeq_epi32(zero, zero);
  const __m256i words = _mm256_set1_epi64x(int64_t(num_words));
  const __m256i known = _mm256_set1_epi64x(int64_t(~(uint64_t(kValueGiven) << 32)));
  const __m256i none = _mm256_set1_epi64x(0xffffffff);
  const __m256i offset_lanes = _mm256_setr_epi64x(-1, 0, -1, 0);
  const __m256i count_fields = _mm256_setr_epi32(0, -1, 0, 0, 0, -1, 0, 0);
  __m256i bad = zero;
  for (uint32_t p = 0; p < n; p += 2) {
    const bool pair = p + 1 < n;  // else the last value alone: the next may lie past the section
    const __m256i keep = pair ? ones : _mm256_setr_epi64x(-1, -1, 0, 0);
    const __m256i v = pair ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(values + p))
                           : _mm256_maskload_epi32(reinterpret_cast<const int*>(values + p), keep);
    const __m256i l = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(lanes + p));
    // Words: offset + count * width, 64-bit, against the words section.
    const __m256i used =
        _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(v, 32), l), _mm256_and_si256(v, none));
    const __m256i far = _mm256_and_si256(_mm256_cmpgt_epi64(used, words), offset_lanes);
    // Count: the arity, 0, or any (any_count moved into the count's field).
    const __m256i count_ok =
        _mm256_or_si256(_mm256_or_si256(_mm256_cmpeq_epi32(v, l), _mm256_cmpeq_epi32(v, zero)),
                        _mm256_shuffle_epi32(l, _MM_SHUFFLE(3, 2, 2, 0)));
    const __m256i count = _mm256_andnot_si256(count_ok, count_fields);
    // Texture none and no flag but kValueGiven, in the texture/flags half.
    const __m256i rest = _mm256_andnot_si256(
        _mm256_or_si256(offset_lanes, _mm256_cmpeq_epi64(_mm256_and_si256(v, known), none)), ones);
    bad = _mm256_or_si256(
        bad, _mm256_and_si256(keep, _mm256_or_si256(far, _mm256_or_si256(count, rest))));
  }
  return _mm256_testz_si256(bad, bad) != 0;
}

}  // namespace pbrta
