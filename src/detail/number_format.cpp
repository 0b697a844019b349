// Grisu2 and the %g-like layout of nlohmann::json's dump() (nlohmann/detail/conversions/
// to_chars.hpp, version 3.11.2), ported step for step so that the text is the same byte for
// byte; see number_format.hpp for why not std::to_chars.
//
// SPDX-FileCopyrightText: 2009 Florian Loitsch <https://florian.loitsch.com/>
// SPDX-FileCopyrightText: 2013-2022 Niels Lohmann <https://nlohmann.me>
// SPDX-License-Identifier: MIT
//
// Loitsch, "Printing Floating-Point Numbers Quickly and Accurately with Integers", PLDI 2010.

#include "detail/number_format.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace fairspline::detail {
namespace {

/// f * 2^e.
struct DiyFp {
  std::uint64_t f = 0;
  int e = 0;
};

DiyFp sub(DiyFp x, DiyFp y) {
  return {x.f - y.f, x.e};
}

/// x * y rounded to the upper 64 bits of the product (ties up).
DiyFp mul(DiyFp x, DiyFp y) {
#ifdef __SIZEOF_INT128__
  // The same value as the four 32-bit products below (floor((x*y + 2^63) / 2^64)), in one
  // multiplication.
  __extension__ using Uint128 = unsigned __int128;
  const Uint128 p = Uint128{x.f} * y.f + (Uint128{1} << 63u);
  return {static_cast<std::uint64_t>(p >> 64u), x.e + y.e + 64};
#else
  const std::uint64_t u_lo = x.f & 0xFFFFFFFFu, u_hi = x.f >> 32u;
  const std::uint64_t v_lo = y.f & 0xFFFFFFFFu, v_hi = y.f >> 32u;
  const std::uint64_t p0 = u_lo * v_lo, p1 = u_lo * v_hi, p2 = u_hi * v_lo, p3 = u_hi * v_hi;
  std::uint64_t q = (p0 >> 32u) + (p1 & 0xFFFFFFFFu) + (p2 & 0xFFFFFFFFu);
  q += std::uint64_t{1} << 31u;
  return {p3 + (p2 >> 32u) + (p1 >> 32u) + (q >> 32u), x.e + y.e + 64};
#endif
}

/// x.f != 0 shifted until its top bit is set (one shift, not a loop over the bits).
DiyFp normalize(DiyFp x) {
  const int s = std::countl_zero(x.f);
  return {x.f << s, x.e - s};
}

DiyFp normalize_to(DiyFp x, int e) {
  return {x.f << (x.e - e), e};
}

/// The value and the midpoints to its neighbours m- and m+ (sharing m+'s normalized exponent).
struct Boundaries {
  DiyFp w, minus, plus;
};

Boundaries compute_boundaries(double value) {
  constexpr int kPrecision = 53;
  constexpr int kBias = 1075;  // 1023 + 52
  constexpr int kMinExp = 1 - kBias;
  constexpr std::uint64_t kHiddenBit = std::uint64_t{1} << (kPrecision - 1);
  const auto bits = std::bit_cast<std::uint64_t>(value);
  const std::uint64_t biased = bits >> (kPrecision - 1);
  const std::uint64_t fraction = bits & (kHiddenBit - 1);
  const DiyFp v = biased == 0 ? DiyFp{fraction, kMinExp}
                              : DiyFp{fraction + kHiddenBit, static_cast<int>(biased) - kBias};
  const bool lower_boundary_is_closer = fraction == 0 && biased > 1;
  const DiyFp m_plus{2 * v.f + 1, v.e - 1};
  const DiyFp m_minus =
      lower_boundary_is_closer ? DiyFp{4 * v.f - 1, v.e - 2} : DiyFp{2 * v.f - 1, v.e - 1};
  const DiyFp w_plus = normalize(m_plus);
  return {normalize(v), normalize_to(m_minus, w_plus.e), w_plus};
}

constexpr int kAlpha = -60;
constexpr int kGamma = -32;
static_assert(kAlpha >= -60 && kGamma <= -32, "the digit generation needs -60 <= e <= -32");

/// c = f * 2^e ~= 10^k.
struct CachedPower {
  std::uint64_t f;
  int e;
  int k;
};

/// A cached power of ten c such that kAlpha <= c.e + e + 64 <= kGamma.
CachedPower cached_power_for_binary_exponent(int e) {
  constexpr int kMinDecExp = -300;
  constexpr int kDecStep = 8;
  static constexpr std::array<CachedPower, 79> kPowers = {{
      {0xAB70FE17C79AC6CA, -1060, -300}, {0xFF77B1FCBEBCDC4F, -1034, -292},
      {0xBE5691EF416BD60C, -1007, -284}, {0x8DD01FAD907FFC3C, -980, -276},
      {0xD3515C2831559A83, -954, -268},  {0x9D71AC8FADA6C9B5, -927, -260},
      {0xEA9C227723EE8BCB, -901, -252},  {0xAECC49914078536D, -874, -244},
      {0x823C12795DB6CE57, -847, -236},  {0xC21094364DFB5637, -821, -228},
      {0x9096EA6F3848984F, -794, -220},  {0xD77485CB25823AC7, -768, -212},
      {0xA086CFCD97BF97F4, -741, -204},  {0xEF340A98172AACE5, -715, -196},
      {0xB23867FB2A35B28E, -688, -188},  {0x84C8D4DFD2C63F3B, -661, -180},
      {0xC5DD44271AD3CDBA, -635, -172},  {0x936B9FCEBB25C996, -608, -164},
      {0xDBAC6C247D62A584, -582, -156},  {0xA3AB66580D5FDAF6, -555, -148},
      {0xF3E2F893DEC3F126, -529, -140},  {0xB5B5ADA8AAFF80B8, -502, -132},
      {0x87625F056C7C4A8B, -475, -124},  {0xC9BCFF6034C13053, -449, -116},
      {0x964E858C91BA2655, -422, -108},  {0xDFF9772470297EBD, -396, -100},
      {0xA6DFBD9FB8E5B88F, -369, -92},   {0xF8A95FCF88747D94, -343, -84},
      {0xB94470938FA89BCF, -316, -76},   {0x8A08F0F8BF0F156B, -289, -68},
      {0xCDB02555653131B6, -263, -60},   {0x993FE2C6D07B7FAC, -236, -52},
      {0xE45C10C42A2B3B06, -210, -44},   {0xAA242499697392D3, -183, -36},
      {0xFD87B5F28300CA0E, -157, -28},   {0xBCE5086492111AEB, -130, -20},
      {0x8CBCCC096F5088CC, -103, -12},   {0xD1B71758E219652C, -77, -4},
      {0x9C40000000000000, -50, 4},      {0xE8D4A51000000000, -24, 12},
      {0xAD78EBC5AC620000, 3, 20},       {0x813F3978F8940984, 30, 28},
      {0xC097CE7BC90715B3, 56, 36},      {0x8F7E32CE7BEA5C70, 83, 44},
      {0xD5D238A4ABE98068, 109, 52},     {0x9F4F2726179A2245, 136, 60},
      {0xED63A231D4C4FB27, 162, 68},     {0xB0DE65388CC8ADA8, 189, 76},
      {0x83C7088E1AAB65DB, 216, 84},     {0xC45D1DF942711D9A, 242, 92},
      {0x924D692CA61BE758, 269, 100},    {0xDA01EE641A708DEA, 295, 108},
      {0xA26DA3999AEF774A, 322, 116},    {0xF209787BB47D6B85, 348, 124},
      {0xB454E4A179DD1877, 375, 132},    {0x865B86925B9BC5C2, 402, 140},
      {0xC83553C5C8965D3D, 428, 148},    {0x952AB45CFA97A0B3, 455, 156},
      {0xDE469FBD99A05FE3, 481, 164},    {0xA59BC234DB398C25, 508, 172},
      {0xF6C69A72A3989F5C, 534, 180},    {0xB7DCBF5354E9BECE, 561, 188},
      {0x88FCF317F22241E2, 588, 196},    {0xCC20CE9BD35C78A5, 614, 204},
      {0x98165AF37B2153DF, 641, 212},    {0xE2A0B5DC971F303A, 667, 220},
      {0xA8D9D1535CE3B396, 694, 228},    {0xFB9B7CD9A4A7443C, 720, 236},
      {0xBB764C4CA7A44410, 747, 244},    {0x8BAB8EEFB6409C1A, 774, 252},
      {0xD01FEF10A657842C, 800, 260},    {0x9B10A4E5E9913129, 827, 268},
      {0xE7109BFBA19C0C9D, 853, 276},    {0xAC2820D9623BF429, 880, 284},
      {0x80444B5E7AA7CF85, 907, 292},    {0xBF21E44003ACDD2D, 933, 300},
      {0x8E679C2F5E44FF8F, 960, 308},    {0xD433179D9C8CB841, 986, 316},
      {0x9E19DB92B4E31BA9, 1013, 324},
  }};
  // k = ceil((kAlpha - e - 1) * log10(2)) without floating point (exact for |e| <= 1500).
  const int f = kAlpha - e - 1;
  const int k = (f * 78913) / (1 << 18) + static_cast<int>(f > 0);
  const int index = (-kMinDecExp + k + (kDecStep - 1)) / kDecStep;
  return kPowers[static_cast<std::size_t>(index)];
}

constexpr std::array<std::uint32_t, 10> kPow10 = {1,      10,      100,      1000,      10000,
                                                  100000, 1000000, 10000000, 100000000, 1000000000};

/// For n != 0: the number of its decimal digits (1 to 10).
int decimal_digits(std::uint32_t n) {
  int k = 1;
  while (k < 10 && n >= kPow10[static_cast<std::size_t>(k)]) ++k;
  return k;
}

/// The `count` decimal digits of n (leading zeros included) at out, two at a time.
void write_digits(char* out, std::uint32_t n, int count) {
  static constexpr char kPairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  char* p = out + count;
  while (p - out >= 2) {
    const std::uint32_t r = n % 100;
    n /= 100;
    p -= 2;
    std::memcpy(p, kPairs + 2 * r, 2);
  }
  if (p != out) *out = static_cast<char>('0' + n);
}

/// Decrements the last digit while that brings buf * 10^k closer to w.
void grisu2_round(char* buf, int len, std::uint64_t dist, std::uint64_t delta, std::uint64_t rest,
                  std::uint64_t ten_k) {
  while (rest < dist && delta - rest >= ten_k &&
         (rest + ten_k < dist || dist - rest > rest + ten_k - dist)) {
    buf[len - 1]--;
    rest += ten_k;
  }
}

/// grisu2_round for ten_k = 2^shift (the fractional digits' case), without the loop: its count
/// of decrements in closed form, the same count (a loop of 0 to 9 steps whose exit was
/// mispredicted for most numbers). With g = dist − rest > 0, the steps that stay below dist
/// are i0 = ceil(g / ten_k) − 1; one more is taken when it ends closer to dist (2(g − i0·ten_k)
/// > ten_k); no step may pass delta: at most (delta − rest) / ten_k.
void grisu2_round_pow2(char* buf, int len, std::uint64_t dist, std::uint64_t delta,
                       std::uint64_t rest, int shift) {
  if (rest >= dist) return;
  const std::uint64_t ten_k = std::uint64_t{1} << shift;
  const std::uint64_t g = dist - rest;
  const std::uint64_t i0 = ((g + ten_k - 1) >> shift) - 1;
  const std::uint64_t closer = i0 + (2 * (g - i0 * ten_k) > ten_k ? 1 : 0);
  const std::uint64_t room = (delta - rest) >> shift;
  buf[len - 1] = static_cast<char>(buf[len - 1] - static_cast<int>(std::min(closer, room)));
}

/// Digits V = buffer * 10^decimal_exponent with M- <= V <= M+ (shared exponent in
/// [kAlpha, kGamma]).
void grisu2_digit_gen(char* buffer, int& length, int& decimal_exponent, DiyFp m_minus, DiyFp w,
                      DiyFp m_plus) {
  std::uint64_t delta = sub(m_plus, m_minus).f;
  std::uint64_t dist = sub(m_plus, w).f;
  const DiyFp one{std::uint64_t{1} << -m_plus.e, m_plus.e};
  auto p1 = static_cast<std::uint32_t>(m_plus.f >> -one.e);
  std::uint64_t p2 = m_plus.f & (one.f - 1);

  // The integral part p1 (nonzero: m_plus is normalized and e >= -60), digit by digit until
  // the rest is within delta. The interval is ~2^11 units wide and one is >= 2^32, so delta <
  // one.f, and then a rest (p1's dropped digits * one + p2) is within delta only when the dropped
  // digits are zeros and p2 <= delta: all the digits are written at once (two per division by a
  // constant, where the loop divided by a variable power of ten per digit), and the stop is where
  // p1's trailing zeros begin. The loop stays for delta >= one.f, which does not occur.
  if (delta < one.f) {
    const int n = decimal_digits(p1);
    write_digits(buffer + length, p1, n);
    if (p2 <= delta) {
      int zeros = 0;
      for (std::uint32_t q = p1; zeros + 1 < n && q % 10 == 0; q /= 10) ++zeros;
      length += n - zeros;
      decimal_exponent += zeros;
      grisu2_round(buffer, length, dist, delta, p2,
                   std::uint64_t{kPow10[static_cast<std::size_t>(zeros)]} << -one.e);
      return;
    }
    length += n;
  } else {
    int n = decimal_digits(p1);
    std::uint32_t pow10 = kPow10[static_cast<std::size_t>(n - 1)];
    while (n > 0) {
      const std::uint32_t d = p1 / pow10;
      const std::uint32_t r = p1 % pow10;
      buffer[length++] = static_cast<char>('0' + d);
      p1 = r;
      --n;
      const std::uint64_t rest = (std::uint64_t{p1} << -one.e) + p2;
      if (rest <= delta) {
        decimal_exponent += n;
        grisu2_round(buffer, length, dist, delta, rest, std::uint64_t{pow10} << -one.e);
        return;
      }
      pow10 /= 10;
    }
  }

  // The fractional part p2 * 2^e.
  int m = 0;
  for (;;) {
    p2 *= 10;
    const std::uint64_t d = p2 >> -one.e;
    const std::uint64_t r = p2 & (one.f - 1);
    buffer[length++] = static_cast<char>('0' + d);
    p2 = r;
    ++m;
    delta *= 10;
    dist *= 10;
    if (p2 <= delta) break;
  }
  decimal_exponent -= m;
  grisu2_round_pow2(buffer, length, dist, delta, p2, -one.e);
}

/// The digits of finite value > 0: value ~= buf * 10^decimal_exponent, len digits.
void grisu2(char* buf, int& len, int& decimal_exponent, double value) {
  const Boundaries b = compute_boundaries(value);
  const CachedPower cached = cached_power_for_binary_exponent(b.plus.e);
  const DiyFp c_minus_k{cached.f, cached.e};
  const DiyFp w = mul(b.w, c_minus_k);
  const DiyFp w_minus = mul(b.minus, c_minus_k);
  const DiyFp w_plus = mul(b.plus, c_minus_k);
  // Shrunk by one unit on each side for the error of the products: every number in
  // [M-, M+] reads back as value.
  const DiyFp m_minus{w_minus.f + 1, w_minus.e};
  const DiyFp m_plus{w_plus.f - 1, w_plus.e};
  decimal_exponent = -cached.k;
  grisu2_digit_gen(buf, len, decimal_exponent, m_minus, w, m_plus);
}

/// "e" already written: the exponent with a sign and at least two digits ("+05", "-308").
char* append_exponent(char* buf, int e) {
  if (e < 0) {
    e = -e;
    *buf++ = '-';
  } else {
    *buf++ = '+';
  }
  const auto k = static_cast<std::uint32_t>(e);
  if (k < 10) {
    *buf++ = '0';
    *buf++ = static_cast<char>('0' + k);
  } else if (k < 100) {
    *buf++ = static_cast<char>('0' + k / 10);
    *buf++ = static_cast<char>('0' + k % 10);
  } else {
    *buf++ = static_cast<char>('0' + k / 100);
    *buf++ = static_cast<char>('0' + k / 10 % 10);
    *buf++ = static_cast<char>('0' + k % 10);
  }
  return buf;
}

/// Lays out buf[0, len) * 10^decimal_exponent like printf's %g, in fixed notation when the
/// decimal point falls in (min_exp, max_exp], always with a point or an exponent.
char* format_buffer(char* buf, int len, int decimal_exponent, int min_exp, int max_exp) {
  const int k = len;
  const int n = len + decimal_exponent;  // position of the decimal point
  const auto uk = static_cast<std::size_t>(k);
  if (k <= n && n <= max_exp) {  // digits[000].0
    const auto un = static_cast<std::size_t>(n);
    std::memset(buf + k, '0', un - uk);
    buf[n] = '.';
    buf[n + 1] = '0';
    return buf + un + 2;
  }
  if (0 < n && n <= max_exp) {  // dig.its
    const auto un = static_cast<std::size_t>(n);
    for (std::size_t i = uk; i > un; --i) buf[i] = buf[i - 1];  // a few bytes: no memmove call
    buf[n] = '.';
    return buf + uk + 1;
  }
  if (min_exp < n && n <= 0) {  // 0.[000]digits
    const auto zeros = static_cast<std::size_t>(-n);
    // Fixed-size copies (sign, "0.000" and 24 bytes fit in kJsonNumberChars: uk <= 17,
    // zeros <= 3) instead of a memmove and a memset call: 4% of formatting a tangent's value.
    char digits[24];
    std::memcpy(digits, buf, sizeof digits);
    std::memcpy(buf, "0.000", 5);
    std::memcpy(buf + 2 + zeros, digits, sizeof digits);
    return buf + 2 + zeros + uk;
  }
  if (k == 1) {  // de+123
    buf += 1;
  } else {  // d.igitse+123
    std::memmove(buf + 2, buf + 1, uk - 1);
    buf[1] = '.';
    buf += 1 + uk;
  }
  *buf++ = 'e';
  return append_exponent(buf, n - 1);
}

}  // namespace

char* format_json_number(char* first, double v) {
  if (!std::isfinite(v)) {
    std::memcpy(first, "null", 4);
    return first + 4;
  }
  // Without a branch: coordinates' signs are random, and a mispredicted sign cost ~5% of the
  // formatting. (The '-' written in any case is overwritten when the sign is +.)
  *first = '-';
  first += std::signbit(v) ? 1 : 0;
  v = std::abs(v);
  if (v == 0) {
    std::memcpy(first, "0.0", 3);
    return first + 3;
  }
  int len = 0;
  int decimal_exponent = 0;
  grisu2(first, len, decimal_exponent, v);
  constexpr int kMinExp = -4;
  constexpr int kMaxExp = 15;  // std::numeric_limits<double>::digits10, as nlohmann
  return format_buffer(first, len, decimal_exponent, kMinExp, kMaxExp);
}

}  // namespace fairspline::detail
