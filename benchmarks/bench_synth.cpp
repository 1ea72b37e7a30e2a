// Render time of one synthetic 640x480 RGB-D frame (target: below 100 ms), per category
// and supersampling factor; scene construction (textures) is measured separately.
#include <benchmark/benchmark.h>

#include "odometry/synth/render.h"
#include "odometry/synth/scene.h"

namespace synth = bivo::odometry::synth;

static void BM_SynthRenderFrame(benchmark::State& state, const char* category) {
  const synth::Scene scene = synth::build_scene(synth::parse_category(category), 1);
  synth::RenderSettings settings;
  settings.supersampling = static_cast<int>(state.range(0));
  std::uint64_t frame = 0;
  for (auto _ : state) {
    auto f = synth::render_frame(scene, scene.nominal_T_wc, settings, frame++);
    benchmark::DoNotOptimize(f.rgb.data());
  }
  state.SetLabel("640x480, " + std::to_string(settings.supersampling) + "x" + std::to_string(settings.supersampling) +
                 " colour samples/pixel");
}
BENCHMARK_CAPTURE(BM_SynthRenderFrame, structure_texture_near, "structure_texture_near")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SynthRenderFrame, structure_notexture_far, "structure_notexture_far")
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SynthRenderFrame, nostructure_texture_near, "nostructure_texture_near")
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);

static void BM_SynthBuildScene(benchmark::State& state) {
  for (auto _ : state) {
    auto s = synth::build_scene(synth::parse_category("structure_texture_near"), 1);
    benchmark::DoNotOptimize(s.textures.data());
  }
}
BENCHMARK(BM_SynthBuildScene)->Unit(benchmark::kMillisecond);
