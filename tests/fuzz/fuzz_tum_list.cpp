// libFuzzer target: the tum_list harness (harnesses.h).
#include "harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bivo::fuzz::tum_list(data, size);
  return 0;
}
