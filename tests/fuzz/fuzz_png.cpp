// libFuzzer target: the png harness (harnesses.h).
#include "harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bivo::fuzz::png(data, size);
  return 0;
}
