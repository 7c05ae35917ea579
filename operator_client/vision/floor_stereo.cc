#include "operator_client/vision/floor_stereo.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace mostar::vision {

bool FloorStereoOptions::IsValid(std::string* error) const {
  std::ostringstream why;
  if (near_px < 1 || near_px > 100 || far_px <= near_px || far_px > 200) {
    why << "floor_stereo: near_px must be in [1, 100] and far_px in (near_px, 200] (got " << near_px
        << ", " << far_px << ")";
  } else if (!(min_separation_px >= 1.0 && min_separation_px <= 20.0)) {
    why << "floor_stereo: min_separation_px must be in [1, 20] (got " << min_separation_px << ")";
  } else if (half_width_px < 4 || half_width_px > 200 ||
             !(half_width_m > 0.0 && half_width_m <= 2.0)) {
    why << "floor_stereo: half_width_px must be in [4, 200] and half_width_m in (0, 2] (got "
        << half_width_px << ", " << half_width_m << ")";
  } else if (min_gradient < 1 || min_gradient > 1020 || max_difference < 1 ||
             max_difference > 255 || min_judged < 1 || min_judged > 10000) {
    why << "floor_stereo: min_gradient in [1, 1020], max_difference in [1, 255], min_judged in "
           "[1, 10000] (got "
        << min_gradient << ", " << max_difference << ", " << min_judged << ")";
  } else if (!(floor_share >= 0.0 && floor_share <= 1.0 && margin > 0.0 && margin <= 1.0)) {
    why << "floor_stereo: floor_share must be in [0, 1] and margin in (0, 1] (got " << floor_share
        << ", " << margin << ")";
  } else {
    return true;
  }
  if (error != nullptr) *error = why.str();
  return false;
}

bool FloorWarp::Prepare(const std::shared_ptr<const math::CameraModel>& self,
                        const std::shared_ptr<const math::CameraModel>& other, int top_row,
                        std::string* error) {
  if (self == nullptr || other == nullptr) {
    if (error != nullptr) *error = "floor stereo: missing camera model";
    return false;
  }
  if (self->width_px() != other->width_px() || self->height_px() != other->height_px()) {
    if (error != nullptr) *error = "floor stereo: the eyes' images differ in size";
    return false;
  }
  const int width = self->width_px();
  const int height = self->height_px();
  top_row = std::clamp(top_row, 0, height);
  if (self == self_ && other == other_ && top_row == top_row_) return true;
  self_ = self;
  other_ = other;
  top_row_ = top_row;
  cv::Mat map(height - top_row, width, CV_32FC2, cv::Scalar(-10.f, -10.f));
  valid_ = cv::Mat::zeros(height, width, CV_8UC1);
  shift_ = cv::Mat::zeros(height, width, CV_32FC2);
  for (int row = top_row; row < height; ++row) {
    auto* out = map.ptr<cv::Vec2f>(row - top_row);
    for (int col = 0; col < width; ++col) {
      const auto floor = self->UnprojectToFloor(Eigen::Vector2d(col, row));
      if (!floor) continue;
      const auto seen = other->Project(*floor);
      // One pixel of margin: the agreement test reads the neighbours.
      if (!seen || seen->x() < 1.0 || seen->y() < 0.0 || seen->x() > width - 2.0 ||
          seen->y() > height - 1.0) {
        continue;
      }
      out[col] = cv::Vec2f(static_cast<float>(seen->x()), static_cast<float>(seen->y()));
      valid_.ptr<uint8_t>(row)[col] = 255;
      shift_.ptr<cv::Vec2f>(row)[col] =
          cv::Vec2f(static_cast<float>(seen->x() - col), static_cast<float>(seen->y() - row));
    }
  }
  if (map.empty()) {
    map_fixed_ = cv::Mat();
    map_weights_ = cv::Mat();
  } else {
    cv::convertMaps(map, cv::Mat(), map_fixed_, map_weights_, CV_16SC2);
  }
  return true;
}

void FloorWarp::Warp(const cv::Mat& other_grey, cv::Mat* warped) const {
  warped->create(other_grey.size(), CV_8UC1);
  if (top_row_ > 0) warped->rowRange(0, std::min(top_row_, warped->rows)).setTo(0);
  if (map_fixed_.empty()) return;
  cv::Mat below = warped->rowRange(top_row_, warped->rows);
  cv::remap(other_grey, below, map_fixed_, map_weights_, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(0));
}

namespace {

// How far `grey` lies outside the range of `row`'s pixels col - 1 .. col + 1 (0 inside).
int DifferenceWithSlack(int grey, const uint8_t* row, int col) {
  const int lo = std::min({row[col - 1], row[col], row[col + 1]});
  const int hi = std::max({row[col - 1], row[col], row[col + 1]});
  return grey < lo ? lo - grey : (grey > hi ? grey - hi : 0);
}

}  // namespace

void JudgePixel(const FloorStereoImages& images, int col, int row, const cv::Vec2f& edge_shift,
                const FloorStereoOptions& options, FloorEvidence* evidence) {
  const cv::Mat& grey = images.grey;
  if (col < 1 || col >= grey.cols - 1 || row < 1 || row >= grey.rows - 1) return;
  if (images.valid.ptr<uint8_t>(row)[col] == 0) return;
  const cv::Vec2f floor_shift = images.shift.ptr<cv::Vec2f>(row)[col];
  if (cv::norm(floor_shift - edge_shift) < options.min_separation_px) return;
  // The standing surface's pixel in the other eye, with its one pixel of slack inside.
  const int other_col = col + static_cast<int>(std::lround(edge_shift[0]));
  const int other_row = row + static_cast<int>(std::lround(edge_shift[1]));
  if (other_col < 1 || other_col >= grey.cols - 1 || other_row < 0 || other_row >= grey.rows) {
    return;
  }
  // Horizontal Sobel: what a horizontal baseline can see.
  const uint8_t* up = grey.ptr<uint8_t>(row - 1);
  const uint8_t* mid = grey.ptr<uint8_t>(row);
  const uint8_t* down = grey.ptr<uint8_t>(row + 1);
  const int gx = (up[col + 1] - up[col - 1]) + 2 * (mid[col + 1] - mid[col - 1]) +
                 (down[col + 1] - down[col - 1]);
  if (std::abs(gx) < options.min_gradient) return;
  ++evidence->judged;
  const int self = mid[col];
  if (DifferenceWithSlack(self, images.warped.ptr<uint8_t>(row), col) <= options.max_difference) {
    ++evidence->floor_agreeing;
  }
  if (DifferenceWithSlack(self, images.other.ptr<uint8_t>(other_row), other_col) <=
      options.max_difference) {
    ++evidence->standing_agreeing;
  }
}

FloorVerdict Verdict(const FloorEvidence& evidence, const FloorStereoOptions& options) {
  if (evidence.judged < options.min_judged) return FloorVerdict::kUndecided;
  const double floor = static_cast<double>(evidence.floor_agreeing) / evidence.judged;
  const double standing = static_cast<double>(evidence.standing_agreeing) / evidence.judged;
  if (floor >= options.floor_share && floor - standing >= options.margin) {
    return FloorVerdict::kFloor;
  }
  if (standing >= options.floor_share && standing - floor >= options.margin) {
    return FloorVerdict::kStanding;
  }
  return FloorVerdict::kUndecided;
}

}  // namespace mostar::vision
