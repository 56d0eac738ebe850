#include "format/byte_shuffle.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PBRTA_SHUFFLE_AVX2 1  // built with a target attribute, chosen at run time
#endif

namespace pbrta {

void shuffle4_block(const uint8_t* src, uint8_t* dst, uint64_t size) {
  const uint64_t words = size / 4;
  uint8_t* d0 = dst;
  uint8_t* d1 = dst + words;
  uint8_t* d2 = dst + 2 * words;
  uint8_t* d3 = dst + 3 * words;
  for (uint64_t w = 0; w < words; ++w) {
    d0[w] = src[4 * w + 0];
    d1[w] = src[4 * w + 1];
    d2[w] = src[4 * w + 2];
    d3[w] = src[4 * w + 3];
  }
  std::memcpy(dst + 4 * words, src + 4 * words, size - 4 * words);
}

namespace {

// Unshuffles words [w0, w1) of a block of `words` whole words. With kCheck, returns whether one of
// them is >= limit (limit > 0).
template <bool kCheck>
bool unshuffle_words(const uint8_t* src, uint8_t* dst, uint64_t words, uint64_t w0, uint64_t w1,
                     uint32_t limit) {
  const uint8_t* s0 = src;
  const uint8_t* s1 = src + words;
  const uint8_t* s2 = src + 2 * words;
  const uint8_t* s3 = src + 3 * words;
  uint64_t w = w0;
  uint32_t over = 0;
#if defined(__SSE2__)
  // 16 words at a time: interleave bytes of lanes 0/1 and 2/3, then the 16-bit pairs. SSE2 has
  // no unsigned compare: x >= limit is (x ^ 2^31) > ((limit - 1) ^ 2^31) signed.
  const __m128i bias = _mm_set1_epi32(INT32_MIN);
  const __m128i top = _mm_set1_epi32(static_cast<int32_t>((limit - 1) ^ 0x80000000u));
  __m128i any = _mm_setzero_si128();
  for (; w + 16 <= w1; w += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s0 + w));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s1 + w));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s2 + w));
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s3 + w));
    const __m128i ab_lo = _mm_unpacklo_epi8(a, b), ab_hi = _mm_unpackhi_epi8(a, b);
    const __m128i cd_lo = _mm_unpacklo_epi8(c, d), cd_hi = _mm_unpackhi_epi8(c, d);
    const __m128i v0 = _mm_unpacklo_epi16(ab_lo, cd_lo), v1 = _mm_unpackhi_epi16(ab_lo, cd_lo);
    const __m128i v2 = _mm_unpacklo_epi16(ab_hi, cd_hi), v3 = _mm_unpackhi_epi16(ab_hi, cd_hi);
    __m128i* out = reinterpret_cast<__m128i*>(dst + 4 * w);
    _mm_storeu_si128(out + 0, v0);
    _mm_storeu_si128(out + 1, v1);
    _mm_storeu_si128(out + 2, v2);
    _mm_storeu_si128(out + 3, v3);
    if constexpr (kCheck) {
      any = _mm_or_si128(any, _mm_cmpgt_epi32(_mm_xor_si128(v0, bias), top));
      any = _mm_or_si128(any, _mm_cmpgt_epi32(_mm_xor_si128(v1, bias), top));
      any = _mm_or_si128(any, _mm_cmpgt_epi32(_mm_xor_si128(v2, bias), top));
      any = _mm_or_si128(any, _mm_cmpgt_epi32(_mm_xor_si128(v3, bias), top));
    }
  }
  if constexpr (kCheck) over = static_cast<uint32_t>(_mm_movemask_epi8(any));
#endif
  for (; w < w1; ++w) {
    dst[4 * w + 0] = s0[w];
    dst[4 * w + 1] = s1[w];
    dst[4 * w + 2] = s2[w];
    dst[4 * w + 3] = s3[w];
    if constexpr (kCheck) {
      uint32_t v;
      std::memcpy(&v, dst + 4 * w, 4);
      over |= static_cast<uint32_t>(v >= limit);
    }
  }
  return over != 0;
}

#if defined(PBRTA_SHUFFLE_AVX2)
// The same with AVX2, 32 words at a time, the rest by the SSE2 version. The unpacks work within
// each 16-byte half, so the halves of the four results are regrouped into consecutive words.
// AVX2 has an unsigned max: x >= limit is max(x, limit) == x.
template <bool kCheck>
__attribute__((target("avx2"))) bool unshuffle_words_avx2(const uint8_t* src, uint8_t* dst,
                                                          uint64_t words, uint64_t w0, uint64_t w1,
                                                          uint32_t limit, bool stream) {
  const uint8_t* s0 = src;
  const uint8_t* s1 = src + words;
  const uint8_t* s2 = src + 2 * words;
  const uint8_t* s3 = src + 3 * words;
  const __m256i lim = _mm256_set1_epi32(static_cast<int32_t>(limit));
  __m256i any = _mm256_setzero_si256();
  uint64_t w = w0;
  bool over = false;
  if (stream) {
    // Streamed stores need 32-byte aligned destinations: the words up to the first aligned one
    // (a mesh's indices start anywhere) go the ordinary way; each step below is then 128 bytes.
    const uintptr_t at = reinterpret_cast<uintptr_t>(dst + 4 * w0);
    stream = at % 4 == 0 && w1 - w0 >= 64;
    if (stream) {
      const uint64_t lead = std::min<uint64_t>((32 - at % 32) % 32 / 4, w1 - w0);
      over = unshuffle_words<kCheck>(src, dst, words, w0, w0 + lead, limit);
      w = w0 + lead;
    }
  }
  for (; w + 32 <= w1; w += 32) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s0 + w));
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s1 + w));
    const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s2 + w));
    const __m256i d = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s3 + w));
    const __m256i ab_lo = _mm256_unpacklo_epi8(a, b), ab_hi = _mm256_unpackhi_epi8(a, b);
    const __m256i cd_lo = _mm256_unpacklo_epi8(c, d), cd_hi = _mm256_unpackhi_epi8(c, d);
    // Words 0-3 | 16-19, 4-7 | 20-23, 8-11 | 24-27, 12-15 | 28-31.
    const __m256i v0 = _mm256_unpacklo_epi16(ab_lo, cd_lo);
    const __m256i v1 = _mm256_unpackhi_epi16(ab_lo, cd_lo);
    const __m256i v2 = _mm256_unpacklo_epi16(ab_hi, cd_hi);
    const __m256i v3 = _mm256_unpackhi_epi16(ab_hi, cd_hi);
    const __m256i o0 = _mm256_permute2x128_si256(v0, v1, 0x20);
    const __m256i o1 = _mm256_permute2x128_si256(v2, v3, 0x20);
    const __m256i o2 = _mm256_permute2x128_si256(v0, v1, 0x31);
    const __m256i o3 = _mm256_permute2x128_si256(v2, v3, 0x31);
    __m256i* out = reinterpret_cast<__m256i*>(dst + 4 * w);
    if (stream) {
      _mm256_stream_si256(out + 0, o0);
      _mm256_stream_si256(out + 1, o1);
      _mm256_stream_si256(out + 2, o2);
      _mm256_stream_si256(out + 3, o3);
    } else {
      _mm256_storeu_si256(out + 0, o0);
      _mm256_storeu_si256(out + 1, o1);
      _mm256_storeu_si256(out + 2, o2);
      _mm256_storeu_si256(out + 3, o3);
    }
    if constexpr (kCheck) {
      any = _mm256_or_si256(any, _mm256_cmpeq_epi32(_mm256_max_epu32(o0, lim), o0));
      any = _mm256_or_si256(any, _mm256_cmpeq_epi32(_mm256_max_epu32(o1, lim), o1));
      any = _mm256_or_si256(any, _mm256_cmpeq_epi32(_mm256_max_epu32(o2, lim), o2));
      any = _mm256_or_si256(any, _mm256_cmpeq_epi32(_mm256_max_epu32(o3, lim), o3));
    }
  }
  if (stream) _mm_sfence();  // ordered before whatever this thread publishes next
  if constexpr (kCheck) over = over || _mm256_movemask_epi8(any) != 0;
  return unshuffle_words<kCheck>(src, dst, words, w, w1, limit) || over;
}
#endif

ShuffleKernel best_kernel() {
#if defined(PBRTA_SHUFFLE_AVX2)
  if (__builtin_cpu_supports("avx2")) return ShuffleKernel::kAvx2;
#endif
  return ShuffleKernel::kPortable;
}

}  // namespace

bool shuffle_kernel_available(ShuffleKernel kernel) {
  return kernel == ShuffleKernel::kPortable || best_kernel() == kernel;
}

void unshuffle4_block_with(ShuffleKernel kernel, const uint8_t* src, uint8_t* dst, uint64_t size,
                           WordBound* bounds, uint64_t num_bounds, bool stream) {
  const uint64_t words = size / 4;
  auto run = [&](uint64_t w0, uint64_t w1, uint32_t limit, bool check) {
#if defined(PBRTA_SHUFFLE_AVX2)
    if (kernel == ShuffleKernel::kAvx2)
      return check ? unshuffle_words_avx2<true>(src, dst, words, w0, w1, limit, stream)
                   : unshuffle_words_avx2<false>(src, dst, words, w0, w1, 0, stream);
#endif
    return check ? unshuffle_words<true>(src, dst, words, w0, w1, limit)
                 : unshuffle_words<false>(src, dst, words, w0, w1, 0);
  };
  uint64_t w = 0;
  for (uint64_t k = 0; k < num_bounds; ++k) {
    WordBound& b = bounds[k];
    const uint64_t b0 = b.begin / 4, b1 = b.end / 4;
    run(w, b0, 0, false);
    // limit 0: every value exceeds it (and the biased compare needs limit >= 1).
    b.exceeded = run(b0, b1, b.limit, true) || (b.limit == 0 && b1 > b0);
    w = b1;
  }
  run(w, words, 0, false);
  std::memcpy(dst + 4 * words, src + 4 * words, size - 4 * words);
}

void unshuffle4_block(const uint8_t* src, uint8_t* dst, uint64_t size, WordBound* bounds,
                      uint64_t num_bounds, bool stream) {
  static const ShuffleKernel kernel = best_kernel();
  unshuffle4_block_with(kernel, src, dst, size, bounds, num_bounds, stream);
}

void shuffle4(const uint8_t* src, uint8_t* dst, uint64_t size) {
  for (uint64_t at = 0; at < size; at += kShuffleBlock)
    shuffle4_block(src + at, dst + at, std::min(kShuffleBlock, size - at));
}

}  // namespace pbrta
