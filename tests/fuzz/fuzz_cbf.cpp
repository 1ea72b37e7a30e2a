// libFuzzer target: the cbf harness (harnesses.h).
#include "harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bivo::fuzz::cbf(data, size);
  return 0;
}
