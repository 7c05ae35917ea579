// Per-frame cost of the edge processing on a simulated 640x480 stereo pair with a 181-beam
// scan (1 degree): contrast stretch + Canny + NED on both images + NESC + classification. The
// pipeline runs the two eyes in parallel: its CPU time counts the calling thread only, so
// compare wall (real) times.
// Run from the repository root or with MOSTAR_SOURCE_DIR set.
#include <benchmark/benchmark.h>

#include <map>
#include <stdexcept>
#include <tuple>

#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

// A simulated pair of `scene_name` at `width` x 3/4 width (the focal length follows the width:
// the same lens) with radial distortion `k1`.
struct Fixture {
  VisionInput input;
  explicit Fixture(const std::string& scene_name = "open_room", int width = 640, double k1 = 0.0) {
    sim::proto::Scene scene;
    std::string error;
    if (!LoadSimScene(scene_name, &scene, &error)) throw std::runtime_error(error);
    sim::proto::SimConfig config;
    config.mutable_laser()->set_resolution(sim::proto::LaserConfig::RES_1_DEG);
    config.mutable_camera()->set_width_px(width);
    config.mutable_camera()->set_height_px(width * 3 / 4);
    config.mutable_camera()->set_focal_px(440.0 * width / 640);
    config.mutable_camera()->set_k1(k1);
    auto world = sim::SimWorld::Create(scene, config, Time(), &error);
    if (world == nullptr) throw std::runtime_error(error);
    const double laser_height_m = world->laser_params().height_m;
    input.left_camera = SimCameraModel(world->calibration(), Eye::kLeft, laser_height_m);
    input.right_camera = SimCameraModel(world->calibration(), Eye::kRight, laser_height_m);
    input.scan = world->ScanAt(Time());
    const sim::StereoImages images = world->StereoAt(Time(), false);
    input.left = images.left;
    input.right = images.right;
    if (input.scan.ranges_m.size() != 181) throw std::runtime_error("expected 181 beams");
  }
};

const Fixture& GetFixture() {
  static const Fixture fixture;
  return fixture;
}

const Fixture& GetFixture(const std::string& scene, int width, double k1) {
  static std::map<std::tuple<std::string, int, double>, Fixture> fixtures;
  const auto key = std::make_tuple(scene, width, k1);
  auto it = fixtures.find(key);
  if (it == fixtures.end()) it = fixtures.emplace(key, Fixture(scene, width, k1)).first;
  return it->second;
}

// Times the whole pipeline with `options` on `f`'s pair; the last result.
VisionResult TimePipeline(benchmark::State& state, const Fixture& f, const VisionOptions& options) {
  VisionPipeline pipeline{options};
  VisionResult result;
  for (auto _ : state) {
    pipeline.Process(f.input, &result);
    benchmark::DoNotOptimize(result.classification.corrected);
  }
  if (!result.ok) state.SkipWithError(result.error.c_str());
  return result;
}

// Argument: 1 = with colour edges (the default), 0 = grey edges only (the thesis).
void BM_StereoPipeline(benchmark::State& state) {
  VisionOptions options;
  options.edges.colour_edges = state.range(0) != 0;
  const VisionResult result = TimePipeline(state, GetFixture(), options);
  state.counters["neps"] = result.nesc.matched + result.nesc.one_eye + result.nesc.disagree;
}
BENCHMARK(BM_StereoPipeline)
    ->ArgName("colour_edges")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The default pipeline on the checkerboard floor, with and without the floor test, at 640x480
// and 1280x960, without and with lens distortion. Args: width, k1 x 100, floor test (0/1).
void BM_StereoPipelineCheckerboard(benchmark::State& state) {
  const Fixture& f = GetFixture("checkerboard_room", static_cast<int>(state.range(0)),
                                static_cast<double>(state.range(1)) / 100.0);
  VisionOptions options;
  options.nearest_edge.floor_stereo.enabled = state.range(2) != 0;
  const VisionResult result = TimePipeline(state, f, options);
  state.counters["floor_edges"] = result.left_ned.floor_edges + result.right_ned.floor_edges;
  state.counters["dots"] = static_cast<double>(result.classification.possible_obstacles.size());
}
BENCHMARK(BM_StereoPipelineCheckerboard)
    ->ArgNames({"width", "k1x100", "floor_test"})
    ->Args({640, 0, 0})
    ->Args({640, 0, 1})
    ->Args({640, -28, 0})
    ->Args({640, -28, 1})
    ->Args({1280, -28, 0})
    ->Args({1280, -28, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_EdgeDetectorOneImage(benchmark::State& state) {
  const Fixture& f = GetFixture();
  const EdgeDetector detector{EdgeDetectorOptions{}};
  EdgeImages out;
  std::string error;
  for (auto _ : state) {
    detector.Detect(f.input.left, &out, &error);
    benchmark::DoNotOptimize(out.edges.data);
  }
}
BENCHMARK(BM_EdgeDetectorOneImage)->Unit(benchmark::kMillisecond)->UseRealTime();

// What the pipeline runs: only the rows the virtual rays reach (below the horizon).
// Argument: colour edges on (1) or off (0).
void BM_EdgeDetectorFloorRows(benchmark::State& state) {
  const Fixture& f = GetFixture();
  EdgeDetectorOptions options;
  options.colour_edges = state.range(0) != 0;
  const EdgeDetector detector{options};
  NearestEdgeFinder finder{NearestEdgeOptions{}};
  std::string error;
  if (!finder.Prepare(f.input.left_camera, f.input.scan, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  EdgeImages out;
  for (auto _ : state) {
    detector.Detect(f.input.left, &out, &error, finder.top_row());
    benchmark::DoNotOptimize(out.edges.data);
  }
  state.counters["first_row"] = finder.top_row();
}
BENCHMARK(BM_EdgeDetectorFloorRows)
    ->ArgName("colour_edges")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_NedOneImage(benchmark::State& state) {
  const Fixture& f = GetFixture();
  EdgeImages edges;
  std::string error;
  EdgeDetector{EdgeDetectorOptions{}}.Detect(f.input.left, &edges, &error);
  NedResult ned;
  NearestEdgeFinder finder{NearestEdgeOptions{}};  // ray pixels cached after the first frame
  for (auto _ : state) {
    finder.Find(edges.edges, f.input.left_camera, f.input.scan, &ned, &error, edges.stretched_grey);
    benchmark::DoNotOptimize(ned.found);
  }
  state.counters["visible_rays"] = ned.visible_rays;
}
BENCHMARK(BM_NedOneImage)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace mostar::vision
