/* ----------------------------------------------------------------------
   PERI-NOSPD: strict reading of the numbers of an input line or a
   material file (no LAMMPS headers).

   A real is one whole word that strtod reads completely, finite and within
   a double's normal range: "1e999" (overflow), "1e-400" (underflow to 0 or
   a subnormal), "inf" and "nan" are refused, each with its own reason, so
   that the caller's error names the value instead of an uncaught
   std::out_of_range or an infinite material constant.  A count is a whole
   decimal integer checked against its range before it is narrowed: 2^31
   must not wrap to a negative int, 2^32 + 1 not to 1.
------------------------------------------------------------------------- */

#ifndef NOSPD_PARSE_H
#define NOSPD_PARSE_H

#include <cctype>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <string>

namespace NOSPD {

enum class Parsed { OK, NOT_A_NUMBER, NOT_FINITE, OVERFLOW, UNDERFLOW, NOT_AN_INTEGER, OUT_OF_RANGE };

// why a word was refused, completing "expects ..., got 'w': "
inline const char *parse_reason(Parsed p)
{
  switch (p) {
    case Parsed::OK: return "ok";
    case Parsed::NOT_A_NUMBER: return "not a number";
    case Parsed::NOT_FINITE: return "not a finite number";
    case Parsed::OVERFLOW: return "beyond the largest double (about 1.8e308)";
    case Parsed::UNDERFLOW: return "below the smallest normal double (about 2.2e-308) but not 0";
    case Parsed::NOT_AN_INTEGER: return "not an integer";
    case Parsed::OUT_OF_RANGE: return "outside the allowed range";
  }
  return "?";
}

inline Parsed parse_real(const std::string &word, double &value)
{
  const char *s = word.c_str();
  // strtod skips leading blanks and takes hexadecimal; an input word is neither
  if (word.empty() || std::isspace(static_cast<unsigned char>(s[0]))) return Parsed::NOT_A_NUMBER;
  if (word.find_first_of("xX") != std::string::npos) return Parsed::NOT_A_NUMBER;
  char *end = nullptr;
  errno = 0;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0') return Parsed::NOT_A_NUMBER;
  if (!std::isfinite(v)) return errno == ERANGE ? Parsed::OVERFLOW : Parsed::NOT_FINITE;
  // glibc flags a subnormal or zero result of a non-zero word with ERANGE
  if (errno == ERANGE || (v != 0.0 && std::abs(v) < DBL_MIN)) return Parsed::UNDERFLOW;
  value = v;
  return Parsed::OK;
}

// a decimal integer in [lo, hi] (an optional sign, digits only)
inline Parsed parse_integer(const std::string &word, long long lo, long long hi, long long &value)
{
  size_t k = (!word.empty() && (word[0] == '+' || word[0] == '-')) ? 1 : 0;
  if (k == word.size()) return Parsed::NOT_AN_INTEGER;
  for (size_t m = k; m < word.size(); ++m)
    if (!std::isdigit(static_cast<unsigned char>(word[m]))) {
      double ignored;
      return parse_real(word, ignored) == Parsed::NOT_A_NUMBER ? Parsed::NOT_A_NUMBER
                                                               : Parsed::NOT_AN_INTEGER;
    }
  errno = 0;
  const long long v = std::strtoll(word.c_str(), nullptr, 10);
  if (errno == ERANGE || v < lo || v > hi) return Parsed::OUT_OF_RANGE;
  value = v;
  return Parsed::OK;
}

}    // namespace NOSPD

#endif
