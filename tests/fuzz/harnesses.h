#pragma once
// The fuzz harnesses: each feeds one input (bytes) to one reader of the project and returns
// normally when the reader accepts it or rejects it with bivo::Error. Anything else -- a
// crash, a sanitizer report, another exception (what `bivo` would call "internal error") --
// is a finding. The libFuzzer targets (fuzz_<name>.cpp, clang only) and the regression test
// over tests/fuzz/regressions/<name>/ (every build) call the same functions.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace bivo::fuzz {

void tum_list(const std::uint8_t* data, std::size_t size);    // rgb.txt / depth.txt / associations.txt
void trajectory(const std::uint8_t* data, std::size_t size);  // TUM trajectory + RPE/ATE on it
void png(const std::uint8_t* data, std::size_t size);         // 8-bit colour and 16-bit depth PNG
void conic_json(const std::uint8_t* data, std::size_t size);  // `bivo conic` JSON problem
void cbf(const std::uint8_t* data, std::size_t size);         // `bivo conic` CBF problem

struct Harness {
  const char* name;  // folder name under regressions/ and seeds/, target fuzz_<name>
  void (*run)(const std::uint8_t*, std::size_t);
};
const std::vector<Harness>& harnesses();

// Writes the seed corpus of every harness into <dir>/<name>/ from small files the project
// makes itself (a rendered sequence's lists and ground truth, PNGs, conic problems in JSON
// and CBF). In seeds.cpp, its own library (bivo_fuzz_seeds): it renders, so it links the
// synthetic renderer and the solvers, which the fuzz targets do not need.
void write_seeds(const std::string& dir);

}  // namespace bivo::fuzz
