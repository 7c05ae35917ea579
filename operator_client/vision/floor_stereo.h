// Ground-plane stereo (inverse perspective mapping, as in the GOLD system of Bertozzi and
// Broggi): with both eyes' calibrations the floor maps from one eye's image to the other's by a
// known warp (a homography without lens distortion; per-pixel maps here, distortion included).
// Floor texture agrees under it; anything standing on the floor does not, increasingly with its
// height above the floor.
//
// NED uses it to tell a floor edge (a tile border, tape) from an obstacle's base: at a candidate
// edge, the region beyond it along the ray, up to the next edge, is judged under two hypotheses:
// more floor (the other eye's pixel from the floor warp) or a surface standing on the edge (the
// other eye's pixel shifted as at the edge itself, as for a surface facing the camera). Only
// pixels with a horizontal gradient can be judged (the baseline is horizontal: a horizontal edge
// looks the same under any disparity, the aperture problem), and only where the hypotheses put
// the other eye's pixel at least min_separation_px apart (they part slowly, by about baseline x
// rows / camera height pixels). Where enough judged pixels agree with the floor and few with the
// standing surface, the edge lies on the floor; otherwise (a uniform face, a plain floor, a
// region too short to part the hypotheses) NED keeps the edge, as without the test.
//
// Frames and pixels as in nearest_edge.h. Pure: FloorWarp is not thread-safe (one per eye).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "common/math/camera_model.h"

namespace mostar::vision {

struct FloorStereoOptions {
  // Off: NED as without the test (the thesis' profile keeps it off).
  bool enabled = false;
  // The judged region: ray pixels from near_px beyond the edge up to the next edge pixel (at
  // least 3 beyond), at most far_px (the two hypotheses part by about baseline x rows / camera
  // height pixels, so the region must reach well beyond the edge); across the ray on each side,
  // half_width_m of floor (the pixels it spans at the region's floor distance, at least 4, at
  // most half_width_px). near_px in [1, 100], far_px in (near_px, 200], half_width_px in
  // [4, 200], half_width_m in (0, 2].
  int near_px = 2;
  int far_px = 60;
  int half_width_px = 120;
  double half_width_m = 0.3;
  // A pixel is judged when its horizontal Sobel gradient (stretched grey) reaches this; in
  // [1, 1020].
  int min_gradient = 60;
  // A pixel is judged only where the two hypotheses put it this far apart in the other eye,
  // pixels; in [1, 20].
  double min_separation_px = 2.5;
  // A hypothesis agrees with a judged pixel when its grey lies within this many levels of the
  // other eye's grey where the hypothesis puts the pixel, or one pixel beside it (calibration
  // slack); in [1, 255].
  int max_difference = 30;
  // Judged pixels needed for a verdict; in [1, 10000].
  int min_judged = 16;
  // Floor: at least floor_share of the judged pixels agree with the floor, and that share
  // exceeds the standing surface's by at least margin (a two-tone texture agrees with either
  // hypothesis half the time by chance); standing the other way round. floor_share in [0, 1],
  // margin in (0, 1].
  double floor_share = 0.8;
  double margin = 0.25;

  bool IsValid(std::string* error) const;
};

enum class FloorVerdict { kUndecided, kFloor, kStanding };

// The other eye's image seen through the floor: for each pixel of this eye's image at or below
// `top_row`, where the floor point it shows appears in the other eye. Rows above top_row, pixels
// above the horizon and floor points outside the other image read 0 and are never judged.
// shift() holds, per pixel, that point's offset in the other eye (other pixel - this pixel).
class FloorWarp {
 public:
  // Builds the maps, or keeps them for the same camera objects (compared by pointer), size and
  // top row. False with `error` when a camera is missing or the sizes differ.
  bool Prepare(const std::shared_ptr<const math::CameraModel>& self,
               const std::shared_ptr<const math::CameraModel>& other, int top_row,
               std::string* error);
  // `other_grey` (CV_8UC1, the other eye's size) warped into this eye; `valid` (CV_8UC1) is
  // non-zero where a pixel has a floor point seen by the other eye.
  void Warp(const cv::Mat& other_grey, cv::Mat* warped) const;
  const cv::Mat& valid() const { return valid_; }
  const cv::Mat& shift() const { return shift_; }  // CV_32FC2, whole image (0 where not valid)
  int top_row() const { return top_row_; }

 private:
  std::shared_ptr<const math::CameraModel> self_;
  std::shared_ptr<const math::CameraModel> other_;
  int top_row_ = -1;
  cv::Mat map_fixed_;    // CV_16SC2, cv::convertMaps fixed point: rows [top_row, height)
  cv::Mat map_weights_;  // CV_16UC1
  cv::Mat valid_;        // CV_8UC1, whole image
  cv::Mat shift_;        // CV_32FC2, whole image
};

// One eye's images for the test: its stretched grey image, the other eye's stretched grey image
// (`other`) and that image warped into this one through the floor (FloorWarp::Warp), all
// CV_8UC1 of one size; FloorWarp::valid() and FloorWarp::shift().
struct FloorStereoImages {
  cv::Mat grey;
  cv::Mat other;
  cv::Mat warped;
  cv::Mat valid;
  cv::Mat shift;
  double focal_px = 1.0;  // this eye's horizontal focal length
};

// Judged pixels of a region, and how many agree with each hypothesis.
struct FloorEvidence {
  int judged = 0;
  int floor_agreeing = 0;
  int standing_agreeing = 0;
};

// Adds pixel (col, row) to `evidence` when it can be judged: inside the image and the warp,
// horizontal gradient >= min_gradient, and the floor's shift there at least min_separation_px
// from `edge_shift` (the shift at the edge: the standing surface's). A hypothesis agrees when the
// pixel's grey lies within max_difference of the other eye's grey where it puts the pixel, or
// one pixel beside it.
void JudgePixel(const FloorStereoImages& images, int col, int row, const cv::Vec2f& edge_shift,
                const FloorStereoOptions& options, FloorEvidence* evidence);

// The verdict on a region's evidence.
FloorVerdict Verdict(const FloorEvidence& evidence, const FloorStereoOptions& options);

}  // namespace mostar::vision
