// libFuzzer target: the trajectory harness (harnesses.h).
#include "harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bivo::fuzz::trajectory(data, size);
  return 0;
}
