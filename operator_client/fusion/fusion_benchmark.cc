// Scan processing + AR geometry per scan. Goal: <= 0.2 ms per scan for 181 and 361 beams.
#include <benchmark/benchmark.h>

#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/predicted_path.h"
#include "operator_client/fusion/test_scenes.h"

namespace mostar::fusion {
namespace {

testing::Scene Cluttered() {
  testing::Scene scene = testing::BoxBeforeWall();
  for (const testing::Circle& leg : testing::Legs().circles) scene.circles.push_back(leg);
  scene.segments.push_back({-1.0, 2.5, 6.0, 2.5});
  scene.segments.push_back({-1.0, -2.5, 6.0, -2.5});
  return scene;
}

void BM_BuildArFeatures(benchmark::State& state) {
  ArFeatureOptions options;
  options.vertical_lines_enabled = true;
  const ArFeatureBuilder builder(options);
  LaserScan scan = testing::MakeScan(Cluttered(), static_cast<int>(state.range(0)));
  scan.ranges_m[scan.ranges_m.size() / 3] = 0.7f;  // an outlier
  ArFeatures features;
  for (auto _ : state) {
    builder.Build(scan, &features);
    benchmark::DoNotOptimize(features.walls.positions.data());
    benchmark::ClobberMemory();
  }
  state.counters["walls"] = static_cast<double>(features.drawn_walls);
}
BENCHMARK(BM_BuildArFeatures)->Arg(181)->Arg(361)->Unit(benchmark::kMicrosecond);

void BM_SegmentScan(benchmark::State& state) {
  const LaserScan scan = testing::MakeScan(Cluttered(), static_cast<int>(state.range(0)));
  ScanSegmentation segmentation;
  for (auto _ : state) {
    SegmentScan(scan, SegmentationOptions{}, &segmentation);
    benchmark::DoNotOptimize(segmentation.clusters.data());
  }
}
BENCHMARK(BM_SegmentScan)->Arg(181)->Arg(361)->Unit(benchmark::kMicrosecond);

void BM_PredictedPath(benchmark::State& state) {
  VertexArray path;
  for (auto _ : state) {
    BuildPredictedPath(0.5, 0.3, PredictedPathOptions{}, &path);
    benchmark::DoNotOptimize(path.positions.data());
  }
}
BENCHMARK(BM_PredictedPath)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mostar::fusion
