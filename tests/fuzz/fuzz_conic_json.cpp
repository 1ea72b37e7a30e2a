// libFuzzer target: the conic_json harness (harnesses.h).
#include "harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bivo::fuzz::conic_json(data, size);
  return 0;
}
