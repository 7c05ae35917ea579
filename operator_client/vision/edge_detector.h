// Pre-processing of a camera image for nearest edges discovery (thesis 8.1): grey conversion,
// contrast stretching between two grey thresholds, then Canny edge detection; beyond the thesis,
// also Canny on the red-green opponent-colour channel (colour_edges).
//
// Threading: EdgeDetector is immutable after construction; Detect() is const and may be called
// from several threads at once (each call writes only its own output).
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace mostar::vision {

// Thresholds of the edge-calibration view. Grey levels are 0..255.
struct EdgeDetectorOptions {
  // Contrast stretching (thesis fig. 28): grey < low_threshold -> 0, grey > high_threshold ->
  // 255, linear in between. 0 <= low_threshold < high_threshold <= 255.
  int low_threshold = 60;
  int high_threshold = 200;
  // Canny hysteresis thresholds th1 < th2 on the Sobel gradient magnitude (L1 norm unless
  // l2_gradient) of the stretched image: pixels above th2 are edges, pixels between th1 and th2
  // are edges when connected to one above th2. 0 <= th1 <= th2.
  double canny_threshold1 = 60.0;
  double canny_threshold2 = 150.0;
  // Sobel aperture of Canny: 3, 5 or 7.
  int canny_aperture_px = 3;
  bool l2_gradient = false;
  // Also Canny on the red-green opponent-colour channel R - G of the unstretched image, with the
  // same thresholds, the edges OR'ed with the grey ones; colour input only.
  bool colour_edges = true;

  // True when every constraint above holds; otherwise false and `error` (if not null) names it.
  bool IsValid(std::string* error) const;
};

// Output of EdgeDetector::Detect, both CV_8UC1 of the input's size. These are what the client's
// edge-calibration view shows (thesis fig. 29b).
struct EdgeImages {
  cv::Mat stretched_grey;  // contrast-stretched grey image
  cv::Mat edges;           // 255 = edge pixel, 0 = not an edge
};

class EdgeDetector {
 public:
  // `options` must be valid (asserted); validate outside input with IsValid() first.
  explicit EdgeDetector(const EdgeDetectorOptions& options);

  // Accepts CV_8UC1 (grey), CV_8UC3 (BGR) or CV_8UC4 (BGRA) images of any non-empty size. On
  // other input returns false with `error` set and leaves `out` empty. `out`'s buffers are
  // reused when their size matches (no allocation in steady state).
  //
  // `first_row`: only rows >= first_row are processed (clamped to [0, rows]); the rows above
  // are 0 in both outputs. NED passes the highest row its virtual rays reach (minus a margin):
  // above the horizon there is no floor to search. Canny then treats first_row as the image's
  // top border.
  bool Detect(const cv::Mat& image, EdgeImages* out, std::string* error, int first_row = 0) const;

  // The contrast-stretching lookup table, 256 entries of CV_8U (for the calibration view's
  // plot of fig. 28).
  const cv::Mat& stretch_table() const { return stretch_table_; }
  const EdgeDetectorOptions& options() const { return options_; }

 private:
  EdgeDetectorOptions options_;
  cv::Mat stretch_table_;  // 1x256 CV_8U
};

// The grey value contrast stretching maps `grey` (0..255) to, for the given thresholds.
int StretchGrey(int grey, int low_threshold, int high_threshold);

}  // namespace mostar::vision
