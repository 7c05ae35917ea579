// Runs the camera pipeline on a paced 640x480 stereo source at 30 Hz (the fake camera, or a
// file camera with --left/--right globs) and prints capture-to-compressed latency (p50, p95)
// and the process CPU time per second of wall time (getrusage), per JPEG setting.
//
//   camera_pipeline_bench [--seconds N] [--left 'dir/left_*.png' --right 'dir/right_*.png']
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/stats/percentile.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/camera/fake_stereo_camera.h"
#include "robot_server/camera/file_stereo_camera.h"

namespace mostar::camera {
namespace {

double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

struct Row {
  std::string name;
  int quality;
  bool parallel;
};

int Main(int argc, char** argv) {
  double seconds = 5;
  std::string left, right;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--seconds")) seconds = std::atof(argv[i + 1]);
    if (!std::strcmp(argv[i], "--left")) left = argv[i + 1];
    if (!std::strcmp(argv[i], "--right")) right = argv[i + 1];
  }
  const Row rows[] = {
      {"q80 parallel", 80, true}, {"q80 serial", 80, false}, {"q50 parallel", 50, true}};
  std::printf("source: %s, 640x480 stereo, 30 Hz paced, %.0f s per row\n",
              left.empty() ? "fake camera" : "file camera", seconds);
  std::printf("%-14s %8s %8s %9s %9s %10s %10s\n", "setting", "pairs", "fps", "p50 ms", "p95 ms",
              "cpu %/s", "KB/pair");
  for (const Row& row : rows) {
    std::unique_ptr<StereoCamera> camera;
    if (left.empty()) {
      FakeStereoCamera::Options options;
      options.free_run = true;
      options.paced = true;
      camera = std::make_unique<FakeStereoCamera>(options);
    } else {
      FileStereoCamera::Options options;
      options.left = left;
      options.right = right;
      options.paced = true;
      options.loop = true;
      camera = std::make_unique<FileStereoCamera>(options);
    }
    CameraPipelineOptions options;
    options.parallel_compression = row.parallel;
    options.bitrate.initial_quality = row.quality;
    options.bitrate.min_quality = row.quality;  // fixed quality: no adaptation in the bench
    options.bitrate.max_quality = row.quality;
    std::mutex mutex;
    std::vector<double> latencies_ms;
    double bytes = 0;
    const Clock& clock = SystemClock::Instance();
    CameraPipeline pipeline(std::move(camera), options, [&](const CompressedStereoPair& pair) {
      const double latency_ms = ToSeconds(clock.Now() - pair.left.stamp) * 1e3;
      std::lock_guard<std::mutex> lock(mutex);
      latencies_ms.push_back(latency_ms);
      bytes += static_cast<double>(pair.left.data.size() + pair.right.data.size());
      return Delivery::kSent;
    });
    pipeline.Start();
    std::this_thread::sleep_for(std::chrono::milliseconds(700));  // warm-up (image cache)
    {
      std::lock_guard<std::mutex> lock(mutex);
      latencies_ms.clear();
      bytes = 0;
    }
    const double cpu_start = CpuSeconds();
    const auto wall_start = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(FromSeconds(seconds));
    const double cpu = CpuSeconds() - cpu_start;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    pipeline.Stop();
    std::lock_guard<std::mutex> lock(mutex);
    const double pairs = static_cast<double>(latencies_ms.size());
    std::printf("%-14s %8.0f %8.1f %9.2f %9.2f %10.1f %10.1f\n", row.name.c_str(), pairs,
                pairs / wall, Percentile(latencies_ms, 0.5).value_or(0),
                Percentile(latencies_ms, 0.95).value_or(0), 100.0 * cpu / wall,
                pairs > 0 ? bytes / pairs / 1024.0 : 0.0);
  }
  return 0;
}

}  // namespace
}  // namespace mostar::camera

int main(int argc, char** argv) { return mostar::camera::Main(argc, argv); }
