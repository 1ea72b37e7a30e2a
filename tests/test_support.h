#pragma once
// Helpers shared by the test files.
#include <string>

#include "solvers/error.h"

namespace bivo::testing {

// The message of the bivo::Error that f() throws, or "" when it throws none (other
// exceptions propagate and fail the test).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace bivo::testing
