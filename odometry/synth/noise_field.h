#pragma once
// Spatially correlated sensor noise: a structured-light camera matches its dot pattern over
// a window of pixels, so neighbouring depth errors are alike (real fr3 depth is mostly flat
// plateaus between quantization steps, docs/synthetic.md "Sensor model").
#include <cstdint>
#include <vector>

namespace bivo::odometry::synth {

// A width x height field of standard normal values (mean 0, variance 1 at every pixel)
// whose correlation between pixels at distance d falls off like exp(-d^2 / (4 s^2)),
// s = correlation_px: white noise (counter-based, from `key`) blurred by a separable
// Gaussian of standard deviation s and renormalized. s = 0 gives white noise.
std::vector<float> correlated_normal_field(std::uint64_t key, int width, int height, double correlation_px);

}  // namespace bivo::odometry::synth
