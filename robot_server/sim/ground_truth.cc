#include "robot_server/sim/ground_truth.h"

#include <cmath>

namespace mostar::sim {

std::array<double, 12> LaserCameraCalibration::CameraFromLaser(Eye eye) const {
  const double c = std::cos(tilt_rad), s = std::sin(tilt_rad);
  // Rows: the camera axes expressed in the laser frame, for the unrolled camera; then turned by
  // the roll about the optical axis (the rolled x and y axes: p_camera = RotZ(-roll) p_unrolled).
  const double u[3][3] = {{0, -1, 0}, {-s, 0, -c}, {c, 0, -s}};
  const double cr = std::cos(Roll(eye)), sr = std::sin(Roll(eye));
  double r[3][3];
  for (int j = 0; j < 3; ++j) {
    r[0][j] = cr * u[0][j] + sr * u[1][j];
    r[1][j] = -sr * u[0][j] + cr * u[1][j];
    r[2][j] = u[2][j];
  }
  const double p[3] = {camera_x_m, EyeYm(eye), camera_z_m};
  std::array<double, 12> m{};
  for (int i = 0; i < 3; ++i) {
    double t = 0;
    for (int j = 0; j < 3; ++j) {
      m[i * 4 + j] = r[i][j];
      t -= r[i][j] * p[j];
    }
    m[i * 4 + 3] = t;
  }
  return m;
}

bool ProjectLaserPoint(const LaserCameraCalibration& k, Eye eye, double x, double y, double z,
                       double* u, double* v) {
  const auto m = k.CameraFromLaser(eye);
  const double xc = m[0] * x + m[1] * y + m[2] * z + m[3];
  const double yc = m[4] * x + m[5] * y + m[6] * z + m[7];
  const double zc = m[8] * x + m[9] * y + m[10] * z + m[11];
  if (zc <= 1e-3) return false;
  const double xn = xc / zc, yn = yc / zc;
  const double r2 = xn * xn + yn * yn;
  const double d = 1 + k.k1 * r2 + k.k2 * r2 * r2;
  *u = k.cx_px + k.focal_px * xn * d;
  *v = k.Cy(eye) + k.focal_px * yn * d;
  return true;
}

namespace {
bool IsObstacle(uint8_t label) { return label != kLabelFloor && label < kLabelCeiling; }
}  // namespace

void ComputeBaseRows(ImageGroundTruth* truth) {
  const cv::Mat& l = truth->labels;
  truth->base_row_px.assign(l.cols, -1);
  truth->base_obstacle_id.assign(l.cols, 0);
  for (int c = 0; c < l.cols; ++c) {
    for (int r = l.rows - 2; r >= 0; --r) {
      const uint8_t here = l.at<uint8_t>(r, c);
      if (IsObstacle(here) && l.at<uint8_t>(r + 1, c) == kLabelFloor) {
        truth->base_row_px[c] = r;
        truth->base_obstacle_id[c] = here;
        break;
      }
    }
  }
}

std::vector<cv::Point> BaseLinePixels(const cv::Mat& l) {
  std::vector<cv::Point> out;
  for (int r = 0; r + 1 < l.rows; ++r) {
    for (int c = 0; c < l.cols; ++c) {
      if (IsObstacle(l.at<uint8_t>(r, c)) && l.at<uint8_t>(r + 1, c) == kLabelFloor) {
        out.emplace_back(c, r);
      }
    }
  }
  return out;
}

}  // namespace mostar::sim
