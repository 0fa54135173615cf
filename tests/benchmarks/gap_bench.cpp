// Gap decision latency (issue 9 target: <= 50 us for 20 vehicles): our policy and the HCM
// reference on 64 fixed random scenes of N vehicles on a 2-lane, 7 m, 50 km/h road (positions
// within 200 m each way, 10-16 m/s in the lane's direction). Pure computation, no DB.
// Run: build/release/tests/benchmarks/gap_bench --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "roadcross/gap.hpp"

namespace {

using roadcross::TrackedVehicle;

roadcross::GapCrossing crossing() {
  roadcross::GapCrossing c;
  c.start = {458800.0, 5546700.0};
  c.centre = {458800.0, 5546704.0};
  c.heading_rad = roadcross::geo::kPi / 2;
  c.road_width_m = 7.0;
  c.lanes = 2;
  return c;
}

std::vector<std::vector<TrackedVehicle>> scenes(int vehicles) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> along(-200.0, 200.0), speed(10.0, 16.0);
  std::vector<std::vector<TrackedVehicle>> out(64);
  for (auto& scene : out) {
    for (int i = 0; i < vehicles; ++i) {
      const bool far_lane = i % 2 == 1;  // near lane drives east, far lane west
      TrackedVehicle v;
      v.x_m = 458800.0 + along(random);
      v.y_m = 5546700.0 + (far_lane ? 6.25 : 2.75);
      v.vx_mps = (far_lane ? -1.0 : 1.0) * speed(random);
      v.time_s = -0.1;
      scene.push_back(v);
    }
  }
  return out;
}

template <typename Decide>
void run(benchmark::State& state, Decide&& decide) {
  const auto all = scenes(static_cast<int>(state.range(0)));
  const auto c = crossing();
  std::size_t i = 0;
  for (auto _ : state) {
    auto d = decide(c, all[i++ % all.size()]);
    benchmark::DoNotOptimize(d);
  }
}

void BM_GapDecision(benchmark::State& state) {
  run(state, [](const auto& c, const auto& v) {
    return roadcross::gap_decision(c, roadcross::RobotMotion{}, v, 0.0);
  });
}
BENCHMARK(BM_GapDecision)->Arg(1)->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_HcmGapDecision(benchmark::State& state) {
  run(state, [](const auto& c, const auto& v) {
    return roadcross::hcm_gap_decision(c, roadcross::RobotMotion{}, v, 0.0);
  });
}
BENCHMARK(BM_HcmGapDecision)->Arg(20)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
