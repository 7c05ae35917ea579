// Edge processing against the simulator's ground truth: with the true calibration and clean
// images, NEPs land on the rendered obstacle base lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "operator_client/vision/vision_pipeline.h"
#include "robot_server/sim/sim_world.h"
#include "tests/vision/sim_calibration.h"

namespace mostar::vision {
namespace {

const Time kStart = FromUnixNanos(1'700'000'000'000'000'000);

bool IsObstacle(uint8_t label) { return label != sim::kLabelFloor && label < sim::kLabelCeiling; }

// An obstacle pixel directly above a floor pixel (sim::BaseLinePixels).
bool IsBasePixel(const cv::Mat& labels, int col, int row) {
  return row + 1 < labels.rows && IsObstacle(labels.at<uint8_t>(row, col)) &&
         labels.at<uint8_t>(row + 1, col) == sim::kLabelFloor;
}

// What one virtual ray meets first in an image, by the simulator's labels.
enum class RayTruth {
  kVisibleBase,  // a base line with an image step, reached over open floor
  kFaintBase,    // a base line whose grey step Canny cannot start an edge on
  kGrazes,       // the ray passes next to a side or top outline before its base
  kJunction,     // the base pixel touches another obstacle (where outlines of two meet)
  kSide,         // the ray enters an obstacle's silhouette through its side, or the void
  kNone,         // floor all the way
};

struct RayTarget {
  RayTruth truth = RayTruth::kNone;
  int entry_index = -1;  // the first non-floor pixel, index into RayPixels::pixels
};

// `stretched`: the edge detector's stretched grey of the clean image; `min_step`: the smallest
// step of it across a base for which Canny's upper threshold fires (Sobel 3x3 answers an ideal
// step s with 4 s).
RayTarget ClassifyRay(const RayPixels& ray, const cv::Mat& labels, const cv::Mat& stretched,
                      double min_step) {
  RayTarget target;
  bool grazes = false;
  for (size_t k = 0; k < ray.pixels.size(); ++k) {
    const RayPixels::Pixel& px = ray.pixels[k];
    if (labels.at<uint8_t>(px.row, px.col) != sim::kLabelFloor) {
      target.entry_index = static_cast<int>(k);
      break;
    }
    // A floor pixel next to an outline that is not a base line (neither a base pixel nor the
    // pixel above one, the stair step of a sloping base line): Canny marks that outline on the
    // floor pixels beside it, so the ray may stop there, beside the obstacle.
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int r = px.row + dr, c = px.col + dc;
        if (r < 0 || c < 0 || r >= labels.rows || c >= labels.cols) continue;
        if (labels.at<uint8_t>(r, c) != sim::kLabelFloor && !IsBasePixel(labels, c, r) &&
            !IsBasePixel(labels, c, r + 1)) {
          grazes = true;
        }
      }
    }
  }
  if (target.entry_index < 0) return target;
  const int col = ray.pixels[target.entry_index].col, row = ray.pixels[target.entry_index].row;
  if (!IsBasePixel(labels, col, row)) {
    target.truth = RayTruth::kSide;
    return target;
  }
  if (grazes) {
    target.truth = RayTruth::kGrazes;
    return target;
  }
  // Where a side outline meets a base line (a box corner over a wall's baseboard), Canny's
  // non-maximum suppression has no single direction and marks pixels on either outline.
  const uint8_t label = labels.at<uint8_t>(row, col);
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int r = row + dr, c = col + dc;
      if (r < 0 || c < 0 || r >= labels.rows || c >= labels.cols) continue;
      const uint8_t other = labels.at<uint8_t>(r, c);
      if (IsObstacle(other) && other != label) {
        target.truth = RayTruth::kJunction;
        return target;
      }
    }
  }
  // The step 1.5 px either side of the base (past the optical blur) where the labels allow.
  const int above = row > 0 && labels.at<uint8_t>(row - 1, col) == label ? row - 1 : row;
  const int below = row + 2 < labels.rows && labels.at<uint8_t>(row + 2, col) == sim::kLabelFloor
                        ? row + 2
                        : row + 1;
  const int step = std::abs(stretched.at<uint8_t>(above, col) - stretched.at<uint8_t>(below, col));
  target.truth = step >= min_step ? RayTruth::kVisibleBase : RayTruth::kFaintBase;
  return target;
}

class VisionSimTest : public ::testing::TestWithParam<const char*> {};

TEST_P(VisionSimTest, NepsLandOnTheGroundTruthBaseLines) {
  sim::proto::Scene scene;
  std::string error;
  ASSERT_TRUE(LoadSimScene(GetParam(), &scene, &error)) << error;
  sim::proto::SimConfig config;  // proto defaults = the MORDUC simulator, made clean:
  config.mutable_camera()->set_noise_sigma(0.0);
  config.mutable_camera()->set_contact_shadows(false);
  auto world = sim::SimWorld::Create(scene, config, kStart, &error);
  ASSERT_NE(world, nullptr) << error;
  const double laser_height_m = world->laser_params().height_m;

  VisionInput input;
  input.left_camera = SimCameraModel(world->calibration(), Eye::kLeft, laser_height_m);
  input.right_camera = SimCameraModel(world->calibration(), Eye::kRight, laser_height_m);
  const VisionOptions options;
  VisionPipeline pipeline{options};
  const double min_step = options.edges.canny_threshold2 / 4.0;

  int truth_count[6] = {};  // found NEPs per RayTruth
  int visible_rays = 0, visible_found = 0, visible_on_base = 0;
  std::string misses;
  world->SetVelocity(0.0, 0.5);  // turn on the spot: several views of the scene
  for (int frame = 0; frame < 4; ++frame) {
    const Time t = kStart + FromSeconds(1.5 * frame);
    input.scan = world->ScanAt(t);
    const sim::StereoImages images = world->StereoAt(t, /*with_truth=*/true);
    input.left = images.left;
    input.right = images.right;
    const VisionResult result = pipeline.Process(input);
    ASSERT_TRUE(result.ok) << result.error;
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      const bool left = eye == Eye::kLeft;
      const cv::Mat& labels = left ? images.left_truth.labels : images.right_truth.labels;
      const cv::Mat distance = DistanceToBaseLines(labels);
      const cv::Mat& stretched =
          left ? result.left_edges.stretched_grey : result.right_edges.stretched_grey;
      ASSERT_FALSE(stretched.empty());
      const NedResult& ned = left ? result.left_ned : result.right_ned;
      const auto& camera = left ? input.left_camera : input.right_camera;
      for (size_t i = 0; i < ned.neps.size(); ++i) {
        const RayPixels ray = TraceRayPixels(*camera, input.scan.AngleOf(i), options.nearest_edge);
        const RayTarget target = ClassifyRay(ray, labels, stretched, min_step);
        const Nep& nep = ned.neps[i];
        if (target.truth == RayTruth::kVisibleBase) ++visible_rays;
        if (!nep.found) continue;
        ++truth_count[static_cast<int>(target.truth)];
        if (target.truth != RayTruth::kVisibleBase) continue;
        ++visible_found;
        // On a base line (within a pixel) and not beyond the ray's first base: next to a pixel
        // walked up to one past the base pixel (NED also reads the corner pixel of diagonal
        // steps, which is not in `ray.pixels`).
        const cv::Point nep_px(static_cast<int>(nep.pixel.x()), static_cast<int>(nep.pixel.y()));
        const float d = distance.at<float>(nep_px);
        const auto last =
            ray.pixels.begin() + std::min<size_t>(ray.pixels.size(), target.entry_index + 2);
        const bool not_beyond = std::any_of(ray.pixels.begin(), last, [&](const auto& p) {
          return std::abs(p.col - nep_px.x) <= 1 && std::abs(p.row - nep_px.y) <= 1;
        });
        if (d <= 1.0f && not_beyond) {
          ++visible_on_base;
        } else if (misses.size() < 2000) {
          misses += "frame " + std::to_string(frame) + (left ? " left" : " right") + " beam " +
                    std::to_string(i) + ": NEP (" + std::to_string(nep.pixel.x()) + ", " +
                    std::to_string(nep.pixel.y()) + "), " + std::to_string(d) +
                    " px from a base line, base entered at (" +
                    std::to_string(ray.pixels[target.entry_index].col) + ", " +
                    std::to_string(ray.pixels[target.entry_index].row) + ")\n";
        }
      }
    }
  }
  // Every NEP of a ray whose first obstacle is a visible base line lies within a pixel of that
  // base line. Rays are left out, by the labels and the clean image, when
  //  - they graze a side or top outline on their way (beside a thin leg or a box corner):
  //    Canny marks such an outline on the floor pixels next to it, a real image edge the NEP
  //    may stop at;
  //  - they meet the base where it touches another obstacle's outline (a T junction);
  //  - they enter the silhouette through its side (no base line on the ray);
  //  - the base's grey step is below what Canny's upper threshold fires on (an obstacle about as
  //    bright as the floor, e.g. the brown crate on the grey floor): no edge to find there.
  int found = 0;
  for (const int n : truth_count) found += n;
  EXPECT_EQ(visible_on_base, visible_found) << misses;
  // The rule leaves out few NEPs, and NED finds nearly every visible base.
  EXPECT_GE(visible_found, 0.85 * found)
      << "faint " << truth_count[1] << ", grazing " << truth_count[2] << ", junction "
      << truth_count[3] << ", side " << truth_count[4] << ", none " << truth_count[5] << " of "
      << found;
  EXPECT_GE(visible_found, 0.98 * visible_rays) << visible_found << " of " << visible_rays;
  EXPECT_GT(visible_found, 600);
  std::printf(
      "NEPs %d: visible base %d (%d within 1 px), faint %d, grazing %d, junction %d, "
      "side %d, none %d; visible-base rays %d\n",
      found, visible_found, visible_on_base, truth_count[1], truth_count[2], truth_count[3],
      truth_count[4], truth_count[5], visible_rays);
}

// The plain floor. Patterned floors give real floor edges (tile joints) that are not obstacle
// bases: they are scored by vision_groundtruth_bench instead.
INSTANTIATE_TEST_SUITE_P(Scenes, VisionSimTest, ::testing::Values("open_room"));

}  // namespace
}  // namespace mostar::vision
