// Stereo rendering speed on the shipped corridor scene (target: 30 stereo pairs per second), at
// 640x480 (sim_morduc.pbtxt) and at the cameras' native 1280x960 (same lens).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <map>
#include <string>

#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::sim {
namespace {

std::string SourceDir() {
  const char* dir = std::getenv("MOSTAR_SOURCE_DIR");
  return dir ? dir : ".";
}

struct Fixture {
  proto::Scene scene;
  proto::SimConfig config;
  std::unique_ptr<World> world;
  std::unique_ptr<StereoRenderer> renderer;
  explicit Fixture(int width_px) {
    std::string error;
    if (!LoadScene(SourceDir() + "/deploy/scenes/corridor.pbtxt", &scene, &error) ||
        !LoadSimConfig(SourceDir() + "/deploy/config/sim_morduc.pbtxt", &config, &error)) {
      throw std::runtime_error(error + " (set MOSTAR_SOURCE_DIR to the repository root)");
    }
    proto::CameraConfig* camera = config.mutable_camera();
    camera->set_focal_px(camera->focal_px() * width_px / camera->width_px());
    camera->set_height_px(camera->height_px() * width_px / camera->width_px());
    camera->set_width_px(width_px);
    world = std::make_unique<World>(scene);
    renderer = std::make_unique<StereoRenderer>(*world, CameraParams::FromProto(config.camera()),
                                                config.laser().height_m());
  }
};

Fixture& GetFixture(int width_px = 640) {
  static std::map<int, std::unique_ptr<Fixture>> fixtures;
  std::unique_ptr<Fixture>& fixture = fixtures[width_px];
  if (!fixture) fixture = std::make_unique<Fixture>(width_px);
  return *fixture;
}

// CPU time of the whole process (all threads), seconds.
double ProcessCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Both eyes on OpenCV's worker threads, no ground truth: what the simulated camera driver asks
// for. Arg: width. cpu_ms_per_pair counts every thread (on idle cores, wall ~ that / cores).
void BM_RenderStereo(benchmark::State& state) {
  auto& f = GetFixture(static_cast<int>(state.range(0)));
  StereoImages out;
  uint64_t frame = 0;
  const double cpu_start_s = ProcessCpuSeconds();
  for (auto _ : state) {
    const Pose2D pose{0.01 * static_cast<double>(frame % 100), 0.0, 0.002 * (frame % 50)};
    f.renderer->Render(pose, frame++, /*with_truth=*/false, &out);
    benchmark::DoNotOptimize(out.left.data);
  }
  const auto pairs = static_cast<double>(state.iterations());
  state.counters["pairs_per_s"] = benchmark::Counter(pairs, benchmark::Counter::kIsRate);
  state.counters["cpu_ms_per_pair"] = 1e3 * (ProcessCpuSeconds() - cpu_start_s) / pairs;
}
BENCHMARK(BM_RenderStereo)->Arg(640)->Arg(1280)->Unit(benchmark::kMillisecond)->UseRealTime();

// Both eyes with labels and base rows (tests and scoring).
void BM_RenderStereoWithTruth(benchmark::State& state) {
  auto& f = GetFixture();
  StereoImages out;
  uint64_t frame = 0;
  for (auto _ : state) {
    f.renderer->Render(Pose2D{}, frame++, /*with_truth=*/true, &out);
    benchmark::DoNotOptimize(out.left.data);
  }
}
BENCHMARK(BM_RenderStereoWithTruth)->Unit(benchmark::kMillisecond)->UseRealTime();

// One eye on the calling thread. Arg: width.
void BM_RenderOneEye(benchmark::State& state) {
  auto& f = GetFixture(static_cast<int>(state.range(0)));
  uint64_t frame = 0;
  for (auto _ : state) {
    cv::Mat image = f.renderer->RenderEye(Eye::kLeft, Pose2D{}, frame++, nullptr);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_RenderOneEye)->Arg(640)->Arg(1280)->Unit(benchmark::kMillisecond);

// A laser scan (361 beams).
void BM_LaserScan(benchmark::State& state) {
  auto& f = GetFixture();
  LaserRaycaster laser(*f.world, LaserParams::FromProto(f.config.laser()), 1);
  for (auto _ : state) {
    LaserScan scan = laser.Scan(Pose2D{}, Time(), nullptr);
    benchmark::DoNotOptimize(scan.ranges_m.data());
  }
}
BENCHMARK(BM_LaserScan)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mostar::sim
