#pragma once
// One exception type for the whole project: messages name the file, line or value at
// fault; `bivo` catches it once in main, prints it and exits non-zero.
#include <stdexcept>
#include <string>

namespace bivo {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace bivo
