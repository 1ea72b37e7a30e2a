#pragma once
// Numeric flag checks shared by the subcommands. CLI11's PositiveNumber / NonNegativeNumber
// let NaN through (every comparison with NaN is false) and accept infinity; these state the
// accepted range positively, so "--feastol nan" or "--fps inf" is a parse error naming the flag.
#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

namespace bivo::experiments::cli {

inline CLI::Validator finite_number_check(bool allow_zero) {
  return CLI::Validator(
      [allow_zero](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < 0.0 || (!allow_zero && v == 0.0)) {
          return "'" + text + "' must be a finite number " + (allow_zero ? ">= 0" : "> 0");
        }
        return {};
      },
      allow_zero ? "FINITE >= 0" : "FINITE > 0");
}

inline const CLI::Validator kFinitePositive = finite_number_check(false);
inline const CLI::Validator kFiniteNonNegative = finite_number_check(true);

}  // namespace bivo::experiments::cli
