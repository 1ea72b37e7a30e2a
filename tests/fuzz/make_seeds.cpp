// bivo_fuzz_seeds DIR: writes the seed corpus of every fuzz target into DIR/<target>/.
#include <iostream>

#include "harnesses.h"
#include "solvers/error.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: bivo_fuzz_seeds DIR\n";
    return 2;
  }
  try {
    bivo::fuzz::write_seeds(argv[1]);
  } catch (const bivo::Error& e) {
    std::cerr << "bivo_fuzz_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
