/* ----------------------------------------------------------------------
   PERI-NOSPD: the numbers of a command or a material file, read through
   nospd_parse.h, with a LAMMPS error naming the command, the keyword and
   the word when one is refused.  Every number the package reads comes
   through here or through LAMMPS's utils::bounds for type ranges.
------------------------------------------------------------------------- */

#ifndef NOSPD_INPUT_H
#define NOSPD_INPUT_H

#include "error.h"
#include "nospd_parse.h"

#include <climits>
#include <stdexcept>
#include <string>

namespace NOSPD_INPUT {

// error->all where every rank reads the word, error->one where rank 0 alone does
enum class Ranks { ALL, ONE };

inline void refuse(LAMMPS_NS::Error *error, Ranks ranks, const std::string &where,
                   const std::string &key, const char *expects, const std::string &word,
                   NOSPD::Parsed why)
{
  std::string msg;
  if (why == NOSPD::Parsed::NOT_A_NUMBER || why == NOSPD::Parsed::NOT_AN_INTEGER)
    msg = fmt::format("{}: {} expects {}, got '{}'", where, key, expects, word);
  else if (why == NOSPD::Parsed::NOT_FINITE)
    msg = fmt::format("{}: {} must be finite, got {}", where, key, word);
  else
    msg = fmt::format("{}: {} expects {}, got {}: {}", where, key, expects, word,
                      NOSPD::parse_reason(why));
  if (ranks == Ranks::ALL) error->all(FLERR, msg);
  error->one(FLERR, msg);
}

// a finite real within a double's normal range (or 0)
inline double real(LAMMPS_NS::Error *error, const std::string &where, const std::string &key,
                   const std::string &word, Ranks ranks = Ranks::ALL)
{
  double v = 0.0;
  const NOSPD::Parsed p = NOSPD::parse_real(word, v);
  if (p != NOSPD::Parsed::OK) refuse(error, ranks, where, key, "a number", word, p);
  return v;
}

// an integer in [lo, hi], checked before it is narrowed to int
inline int integer(LAMMPS_NS::Error *error, const std::string &where, const std::string &key,
                   const std::string &word, int lo, int hi, Ranks ranks = Ranks::ALL)
{
  long long v = 0;
  const NOSPD::Parsed p = NOSPD::parse_integer(word, lo, hi, v);
  if (p != NOSPD::Parsed::OK) {
    const std::string expects = fmt::format("an integer in [{}, {}]", lo, hi);
    refuse(error, ranks, where, key, expects.c_str(), word, p);
  }
  return static_cast<int>(v);
}

// a type range (N, *, N*, *N, M*N) for utils::bounds, whose std::stol would
// throw on a word past a long and whose int would wrap one past an int
inline void check_type_range(LAMMPS_NS::Error *error, const std::string &where,
                             const std::string &word)
{
  size_t from = 0;
  while (from <= word.size()) {
    const size_t star = word.find('*', from);
    const std::string part = word.substr(from, star == std::string::npos ? star : star - from);
    long long v = 0;
    if (!part.empty() && NOSPD::parse_integer(part, 1, INT_MAX, v) != NOSPD::Parsed::OK)
      error->all(FLERR, "{}: atom type range '{}' expects types (N, *, N*, *N, M*N) with N "
                 "a type from 1, got '{}'", where, word, part);
    if (star == std::string::npos) break;
    from = star + 1;
  }
}

// run evaluate(), LAMMPS's evaluation of variable `name` for `where`: its
// std::stod lets a constant past a double's range (1e999) out as
// std::out_of_range, which becomes this error on the rank that met it
template <class Evaluate>
inline void variable_in_range(LAMMPS_NS::Error *error, const std::string &where,
                              const std::string &name, Evaluate evaluate)
{
  try {
    evaluate();
  } catch (std::out_of_range &e) {
    error->one(FLERR, "{}: v_{}: a number out of a double's range ({})", where, name, e.what());
  }
}

}    // namespace NOSPD_INPUT

#endif
