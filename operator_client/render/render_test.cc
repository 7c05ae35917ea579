// Real OpenGL (Mesa llvmpipe under Xvfb in CI): the overlay lands where the camera model says,
// and the stereo display modes put each eye where it belongs. Skipped without an X display.
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/math/camera_model.h"
#include "operator_client/fusion/sonar_features.h"
#include "operator_client/render/eye_renderer.h"
#include "operator_client/render/eye_viewports.h"
#include "operator_client/render/gl.h"
#include "operator_client/render/screenshot.h"
#include "operator_client/render/stereo_compositor.h"
#include "operator_client/render/stereo_view.h"
#include "operator_client/render/texture.h"
#include "operator_client/ui/window.h"

namespace mostar::render {
namespace {

class RenderTest : public ::testing::Test {
 protected:
  // One window (and X connection) for the whole suite: an X server may reset when its last
  // client disconnects, which would make the next connection fail.
  static void SetUpTestSuite() {
    if (std::getenv("DISPLAY") == nullptr) return;
    ui::WindowOptions options;
    options.width = 640;
    options.height = 480;
    options.visible = false;
    window_ = ui::Window::Create(options, &window_error_).release();
  }
  static void TearDownTestSuite() {
    delete window_;
    window_ = nullptr;
  }

  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run under xvfb-run (as deploy/test.sh does)";
    }
    ASSERT_NE(window_, nullptr) << window_error_;
    std::string error;
    ASSERT_TRUE(eyes_[0].Init(&error)) << error;
    ASSERT_TRUE(eyes_[1].Init(&error)) << error;
    ASSERT_TRUE(compositor_.Init(&error)) << error;
  }

  // The eye framebuffer as BGR8, row 0 at the top.
  static cv::Mat ReadEye(const EyeRenderer& eye) {
    cv::Mat rgba(eye.height(), eye.width(), CV_8UC4);
    glBindTexture(GL_TEXTURE_2D, eye.texture());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_BGRA, GL_UNSIGNED_BYTE, rgba.data);
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_BGRA2BGR);
    cv::flip(bgr, bgr, 0);
    return bgr;
  }

  // The eye's view for `calibration` with `alignment` (shared model).
  static EyeView View(const math::LaserCameraCalibration& calibration,
                      const EyeAlignment& alignment = {},
                      AlignmentModel model = AlignmentModel::kSharedModel) {
    std::string error;
    const std::optional<EyeGeometry> geometry =
        MakeEyeGeometry(calibration, math::Eye::kLeft, alignment, model, &error);
    EXPECT_TRUE(geometry.has_value()) << error;
    return MakeEyeView(*geometry);
  }

  void RenderPlainEyes(const cv::Scalar& left_bgr, const cv::Scalar& right_bgr) {
    const EyeView view = View(math::LaserCameraCalibration{});
    eyes_[0].Render(cv::Mat(480, 640, CV_8UC3, left_bgr), view, {}, {});
    eyes_[1].Render(cv::Mat(480, 640, CV_8UC3, right_bgr), view, {}, {});
  }

  cv::Mat Compose(DisplayMode mode) {
    compositor_.Compose(mode, eyes_[0].texture(), eyes_[1].texture(), 640, 480, false);
    return ReadFramebuffer(640, 480);
  }

  static ui::Window* window_;
  static std::string window_error_;
  EyeRenderer eyes_[2];
  StereoCompositor compositor_;
};

ui::Window* RenderTest::window_ = nullptr;
std::string RenderTest::window_error_;

TEST_F(RenderTest, WallBaseLandsOnTheProjectedImageRow) {
  const math::LaserCameraCalibration calibration;
  const math::CameraModel model(calibration, math::Eye::kLeft);
  const EyeView view = View(calibration);
  const float floor_z = static_cast<float>(-calibration.laser_height_m);
  for (const float distance_m : {1.5f, 2.5f, 4.0f}) {
    OverlayGeometry overlay;
    const fusion::Rgba red{1, 0, 0, 1};
    // A wall across the view at `distance_m`, from the floor up 0.3 m.
    const float y0 = -1.f, y1 = 1.f, z0 = floor_z, z1 = floor_z + 0.3f;
    for (const auto& v : {std::array<float, 3>{distance_m, y0, z0},
                          {distance_m, y1, z0},
                          {distance_m, y1, z1},
                          {distance_m, y0, z0},
                          {distance_m, y1, z1},
                          {distance_m, y0, z1}}) {
      overlay.triangles.Add(v[0], v[1], v[2], red);
    }
    eyes_[0].Render(cv::Mat(480, 640, CV_8UC3, cv::Scalar(128, 128, 128)), view, overlay, {});
    const cv::Mat image = ReadEye(eyes_[0]);
    const auto base = model.ProjectUndistorted(Eigen::Vector3d(distance_m, 0, z0));
    ASSERT_TRUE(base.has_value());
    const int column = static_cast<int>(std::lround((*base)(0)));
    int lowest_red = -1;
    for (int row = 0; row < image.rows; ++row) {
      const cv::Vec3b p = image.at<cv::Vec3b>(row, column);
      if (p[2] > 200 && p[1] < 60) lowest_red = row;
    }
    ASSERT_GE(lowest_red, 0) << "wall not drawn at " << distance_m << " m";
    EXPECT_NEAR(lowest_red, (*base)(1), 1.5) << "wall at " << distance_m << " m";
  }
}

// A sonar echo the laser does not see: a translucent sector on the floor up to the echo, outlined
// in magenta, and nothing beyond it.
TEST_F(RenderTest, SonarSectorLiesOnTheFloorUpToItsEcho) {
  const math::LaserCameraCalibration calibration;
  const math::CameraModel model(calibration, math::Eye::kLeft);
  SonarRanges ring;
  SonarRange sonar;
  sonar.mount.x_m = 0.2;
  sonar.range_m = 1.5f;
  sonar.min_range_m = 0.03f;
  sonar.max_range_m = 6.f;
  sonar.field_of_view_rad = 0.6f;
  ring.ranges.push_back(sonar);
  fusion::ArFeatureOptions colors;
  colors.laser_height_m = static_cast<float>(calibration.laser_height_m);
  fusion::SonarFeatures features;
  const fusion::LaserFieldOfView ahead{-1.5708f, 1.5708f};
  fusion::BuildSonarFeatures(ring, {}, ahead, colors, fusion::SonarFeatureOptions{}, &features);
  ASSERT_EQ(features.unseen, 1u);
  OverlayGeometry overlay;
  overlay.triangles = features.fans;
  overlay.lines = features.outlines;
  eyes_[0].Render(cv::Mat(480, 640, CV_8UC3, cv::Scalar(60, 60, 60)), View(calibration), overlay,
                  {});
  const cv::Mat image = ReadEye(eyes_[0]);
  const float floor_z = -colors.laser_height_m;
  auto pixel_at = [&](double x, double y) {
    const auto p = model.ProjectUndistorted(Eigen::Vector3d(x, y, floor_z));
    EXPECT_TRUE(p.has_value());
    return cv::Point(static_cast<int>(std::lround((*p)(0))),
                     static_cast<int>(std::lround((*p)(1))));
  };
  // Inside the sector: the grey floor tinted towards the echo's (orange-yellow) colour.
  const cv::Vec3b inside = image.at<cv::Vec3b>(pixel_at(1.55, 0.0));
  EXPECT_GT(inside[2], 120) << "red of the sector";
  EXPECT_GT(inside[1], 90) << "green of the sector";
  EXPECT_LT(inside[0], 60) << "blue below the floor's";
  // Beyond the echo: the plain floor.
  const cv::Vec3b beyond = image.at<cv::Vec3b>(pixel_at(2.6, 0.0));
  EXPECT_EQ(beyond, cv::Vec3b(60, 60, 60));
  // The echo arc on the sonar's axis: a magenta line within a pixel or two.
  const cv::Point arc = pixel_at(0.2 + 1.5, 0.0);
  int magenta = 0;
  for (int dv = -2; dv <= 2; ++dv) {
    const cv::Vec3b p = image.at<cv::Vec3b>(arc.y + dv, arc.x);
    if (p[2] > 200 && p[0] > 200 && p[1] < 100) ++magenta;
  }
  EXPECT_GE(magenta, 1) << "no magenta echo arc near " << arc;
}

TEST_F(RenderTest, ImageIsShownUprightAndUnshifted) {
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  image.rowRange(0, 100).setTo(cv::Scalar(255, 255, 255));  // white band at the top
  eyes_[0].Render(image, View(math::LaserCameraCalibration{}), {}, {});
  const cv::Mat out = ReadEye(eyes_[0]);
  EXPECT_GT(out.at<cv::Vec3b>(50, 320)[0], 200);
  EXPECT_LT(out.at<cv::Vec3b>(300, 320)[0], 50);
}

TEST_F(RenderTest, ColourAnaglyphTakesRedFromLeftAndCyanFromRight) {
  RenderPlainEyes(cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));  // left white, right black
  cv::Mat out = Compose(DisplayMode::kAnaglyphColor);
  cv::Vec3b p = out.at<cv::Vec3b>(240, 320);  // BGR
  EXPECT_GT(p[2], 240);
  EXPECT_LT(p[1], 15);
  EXPECT_LT(p[0], 15);
  RenderPlainEyes(cv::Scalar(0, 0, 0), cv::Scalar(255, 255, 255));  // left black, right white
  out = Compose(DisplayMode::kAnaglyphColor);
  p = out.at<cv::Vec3b>(240, 320);
  EXPECT_LT(p[2], 15);
  EXPECT_GT(p[1], 240);
  EXPECT_GT(p[0], 240);
}

TEST_F(RenderTest, GreyAnaglyphUsesLuminanceOfEachEye) {
  RenderPlainEyes(cv::Scalar(0, 255, 0), cv::Scalar(0, 0, 0));  // left pure green
  const cv::Vec3b p = Compose(DisplayMode::kAnaglyphGrey).at<cv::Vec3b>(240, 320);
  EXPECT_NEAR(p[2], 0.587 * 255, 3);  // red channel = luma of the left eye
  EXPECT_LT(p[1], 5);
}

TEST_F(RenderTest, SideBySideAndTopBottomPlaceEachEye) {
  RenderPlainEyes(cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));
  cv::Mat out = Compose(DisplayMode::kSideBySideHalf);
  EXPECT_GT(out.at<cv::Vec3b>(240, 100)[0], 240);
  EXPECT_LT(out.at<cv::Vec3b>(240, 540)[0], 15);
  out = Compose(DisplayMode::kTopBottom);
  EXPECT_GT(out.at<cv::Vec3b>(100, 320)[0], 240);
  EXPECT_LT(out.at<cv::Vec3b>(380, 320)[0], 15);
  out = Compose(DisplayMode::kMonoRight);
  EXPECT_LT(out.at<cv::Vec3b>(240, 320)[0], 15);
}

TEST_F(RenderTest, RowInterlacedAlternatesEyes) {
  RenderPlainEyes(cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));
  const cv::Mat out = Compose(DisplayMode::kRowInterlaced);
  for (int row = 200; row < 210; ++row) {
    const uint8_t v = out.at<cv::Vec3b>(row, 320)[0];
    if (row % 2 == 0) {
      EXPECT_GT(v, 240) << row;
    } else {
      EXPECT_LT(v, 15) << row;
    }
  }
}

TEST_F(RenderTest, QuadBufferFallsBackToLeftEyeWithoutStereoContext) {
  RenderPlainEyes(cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));
  ASSERT_FALSE(window_->quad_buffer());
  const cv::Mat out = Compose(DisplayMode::kQuadBuffer);
  EXPECT_GT(out.at<cv::Vec3b>(240, 320)[0], 240);
}

TEST_F(RenderTest, AlignmentShiftsAndCrops) {
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar(255, 255, 255));
  EyeAlignment alignment;
  alignment.offset_x_px = 20;
  alignment.crop_left_px = 20;
  eyes_[0].Render(image, View(math::LaserCameraCalibration{}, alignment), {}, alignment);
  const cv::Mat out = ReadEye(eyes_[0]);
  EXPECT_LT(out.at<cv::Vec3b>(240, 10)[0], 15);   // cropped
  EXPECT_GT(out.at<cv::Vec3b>(240, 30)[0], 240);  // shifted image
}

// A textured image with a wall, rays and points over it: what the pixel comparisons draw.
cv::Mat TexturedImage() {
  cv::Mat image(480, 640, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::GaussianBlur(image, image, cv::Size(5, 5), 1.5);
  return image;
}

OverlayGeometry WallRayAndPoints(const math::LaserCameraCalibration& calibration) {
  OverlayGeometry overlay;
  const float z0 = static_cast<float>(-calibration.laser_height_m);
  const float z1 = z0 + 0.4f;
  const fusion::Rgba wall{0.2f, 0.9f, 0.3f, 0.5f};
  for (const auto& v : {std::array<float, 3>{2.f, -0.8f, z0},
                        {2.f, 0.8f, z0},
                        {2.f, 0.8f, z1},
                        {2.f, -0.8f, z0},
                        {2.f, 0.8f, z1},
                        {2.f, -0.8f, z1}}) {
    overlay.triangles.Add(v[0], v[1], v[2], wall);
  }
  overlay.lines.Add(0.f, 0.f, 0.f, {1, 0, 0, 1});
  overlay.lines.Add(2.5f, 0.5f, z0, {1, 0, 0, 1});
  overlay.points.Add(1.5f, -0.3f, z0, {1, 0, 1, 1});
  overlay.point_size_px = 6.f;
  return overlay;
}

// Mono, in a window the image's size: drawing the eye in place gives the composed pixels.
TEST_F(RenderTest, DrawingInPlaceGivesTheComposedPixels) {
  const math::LaserCameraCalibration calibration;
  EyeAlignment alignment;
  alignment.offset_x_px = 12;
  alignment.crop_left_px = 12.5f;
  alignment.crop_top_px = 7;
  const EyeView view = View(calibration, alignment);
  const cv::Mat image = TexturedImage();
  const OverlayGeometry overlay = WallRayAndPoints(calibration);
  eyes_[0].Render(image, view, overlay, alignment);
  const cv::Mat composed = Compose(DisplayMode::kMonoLeft);
  ASSERT_TRUE(DrawsEyesInPlace(DisplayMode::kMonoLeft));
  StereoCompositor::ClearWindow(640, 480);
  eyes_[0].RenderInto({0, 0, 640, 480}, image, view, overlay, alignment);
  const cv::Mat in_place = ReadFramebuffer(640, 480);
  // The blended overlay may round differently (an RGBA eye framebuffer against the window's).
  EXPECT_LE(cv::norm(composed, in_place, cv::NORM_INF), 1.0);
  EXPECT_LT(cv::mean(cv::abs(composed - in_place))[0], 0.5);
  // The comparison can fail: the wall and the crop are there.
  EXPECT_LT(in_place.at<cv::Vec3b>(240, 5)[0], 5) << "cropped column";
  StereoCompositor::ClearWindow(640, 480);
  eyes_[0].RenderInto({0, 0, 640, 480}, image, view, {}, alignment);
  const cv::Mat without_overlay = ReadFramebuffer(640, 480);
  EXPECT_GT(cv::norm(without_overlay, in_place, cv::NORM_L1), 1e5) << "overlay not drawn";
  // The image alone: the same pixels, also when a framebuffer object is drawn after the window
  // with the same program (Mesa 22 may leave gl_FragCoord's window transform in place).
  eyes_[0].Render(image, view, {}, alignment);
  EXPECT_LE(cv::norm(Compose(DisplayMode::kMonoLeft), without_overlay, cv::NORM_INF), 1.0);
  EXPECT_LT(cv::norm(Compose(DisplayMode::kMonoLeft), without_overlay, cv::NORM_L1), 1e3);
}

// Side by side (half): each eye drawn in place fills its half, scaled, crop included, as the
// compositor shows it.
TEST_F(RenderTest, SideBySideInPlaceScalesEachEyeIntoItsHalf) {
  const math::LaserCameraCalibration calibration;
  cv::Mat left(480, 640, CV_8UC3, cv::Scalar(255, 255, 255));
  left.rowRange(0, 120).setTo(cv::Scalar(0, 0, 0));  // a black band at the top
  const cv::Mat right(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  EyeAlignment crop;
  crop.crop_left_px = 40;  // 20 window pixels at half width
  const EyeView view = View(calibration);
  StereoCompositor::ClearWindow(640, 480);
  for (const EyeViewport& v : EyeViewports(DisplayMode::kSideBySideHalf, 640, 480)) {
    const bool is_left = v.eye == math::Eye::kLeft;
    eyes_[is_left ? 0 : 1].RenderInto({v.x_px, v.GlY(480), v.width_px, v.height_px},
                                      is_left ? left : right, view, {},
                                      is_left ? crop : EyeAlignment{});
  }
  const cv::Mat in_place = ReadFramebuffer(640, 480);
  EXPECT_LT(in_place.at<cv::Vec3b>(240, 10)[0], 5) << "cropped";
  EXPECT_GT(in_place.at<cv::Vec3b>(240, 30)[0], 250) << "left eye, white";
  EXPECT_LT(in_place.at<cv::Vec3b>(50, 100)[0], 5) << "left eye's band at the top";
  EXPECT_LT(in_place.at<cv::Vec3b>(240, 500)[0], 5) << "right eye, black";
  eyes_[0].Render(left, view, {}, crop);
  eyes_[1].Render(right, view, {}, {});
  const cv::Mat composed = Compose(DisplayMode::kSideBySideHalf);
  // Bilinear sampling of the image instead of the eye framebuffer: edges may differ by a pixel.
  EXPECT_LT(cv::mean(cv::abs(composed - in_place))[0], 1.0);
}

// StereoView picks the path by mode: mono in place (the window shows the eye, no compositor
// pass needed), the colour anaglyph through the eye framebuffers and the compositor.
TEST_F(RenderTest, StereoViewDrawsMonoInPlaceAndBlendsTheAnaglyph) {
  StereoView view;
  std::string error;
  ASSERT_TRUE(view.Init(&error)) << error;
  const cv::Mat white(480, 640, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Mat black(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  const EyeView eye_view = View(math::LaserCameraCalibration{});
  const std::array<EyeInput, 2> eyes = {EyeInput{&white, eye_view, {}},
                                        EyeInput{&black, eye_view, {}}};
  view.DrawEyes(DisplayMode::kMonoRight, false, 640, 480, eyes, {});
  EXPECT_LT(ReadFramebuffer(640, 480).at<cv::Vec3b>(240, 320)[0], 15) << "the right eye, black";
  view.Compose(DisplayMode::kMonoRight, false, 640, 480);  // nothing to do: still the right eye
  EXPECT_LT(ReadFramebuffer(640, 480).at<cv::Vec3b>(240, 320)[0], 15);
  view.DrawEyes(DisplayMode::kAnaglyphColor, false, 640, 480, eyes, {});
  view.Compose(DisplayMode::kAnaglyphColor, false, 640, 480);
  const cv::Vec3b p = ReadFramebuffer(640, 480).at<cv::Vec3b>(240, 320);  // BGR
  EXPECT_GT(p[2], 240) << "red from the white left eye";
  EXPECT_LT(p[1], 15) << "cyan from the black right eye";
  // No image: the grey background, drawn in place.
  const std::array<EyeInput, 2> none = {EyeInput{nullptr, eye_view, {}},
                                        EyeInput{nullptr, eye_view, {}}};
  view.DrawEyes(DisplayMode::kMonoLeft, false, 640, 480, none, {});
  EXPECT_NEAR(ReadFramebuffer(640, 480).at<cv::Vec3b>(240, 320)[0], 64, 3);
}

// The texture's level 0 as `format` (GL_BGR or GL_RED), rows as uploaded.
cv::Mat ReadTexture(const Texture& texture, int type, unsigned format) {
  cv::Mat out(texture.height(), texture.width(), type);
  glBindTexture(GL_TEXTURE_2D, texture.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, format, GL_UNSIGNED_BYTE, out.data);
  return out;
}

bool Identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST_F(RenderTest, TextureUploadsColourImagesInBgrOrder) {
  // An odd width in an ROI: rows neither 4-byte aligned nor contiguous.
  cv::Mat big(60, 90, CV_8UC3);
  cv::randu(big, cv::Scalar::all(0), cv::Scalar::all(256));
  const cv::Mat image = big(cv::Rect(3, 5, 37, 21));
  Texture texture;
  EXPECT_EQ(texture.id(), 0u);
  texture.Upload(image);
  ASSERT_NE(texture.id(), 0u);
  EXPECT_EQ(texture.width(), 37);
  EXPECT_EQ(texture.height(), 21);
  EXPECT_TRUE(Identical(ReadTexture(texture, CV_8UC3, GL_BGR), image));
}

TEST_F(RenderTest, TextureUploadsGreyImagesAndReusesItsName) {
  cv::Mat big(40, 50, CV_8UC1);
  cv::randu(big, cv::Scalar::all(0), cv::Scalar::all(256));
  const cv::Mat grey = big(cv::Rect(1, 2, 33, 17));
  Texture texture;
  texture.Upload(cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
  const unsigned id = texture.id();
  texture.Upload(grey);
  EXPECT_EQ(texture.id(), id);
  EXPECT_EQ(texture.width(), 33);
  EXPECT_TRUE(Identical(ReadTexture(texture, CV_8UC1, GL_RED), grey));
  // Sampled as grey: every colour channel reads the red one.
  GLint swizzle[4] = {};
  glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  EXPECT_EQ(swizzle[0], GL_RED);
  EXPECT_EQ(swizzle[1], GL_RED);
  EXPECT_EQ(swizzle[2], GL_RED);
  EXPECT_EQ(swizzle[3], GL_ONE);
}

TEST_F(RenderTest, TextureRewritesAnImageOfTheSameSizeAndKindInPlace) {
  cv::Mat first(21, 37, CV_8UC3);
  cv::randu(first, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::Mat big(60, 90, CV_8UC3);
  cv::randu(big, cv::Scalar::all(0), cv::Scalar::all(256));
  const cv::Mat second = big(cv::Rect(7, 3, 37, 21));  // same size, another stride
  Texture texture;
  texture.Upload(first);
  texture.Upload(second);
  EXPECT_TRUE(Identical(ReadTexture(texture, CV_8UC3, GL_BGR), second));
  // Then a grey image of that size: new storage of the grey kind.
  cv::Mat grey(21, 37, CV_8UC1);
  cv::randu(grey, cv::Scalar::all(0), cv::Scalar::all(256));
  texture.Upload(grey);
  EXPECT_TRUE(Identical(ReadTexture(texture, CV_8UC1, GL_RED), grey));
  // And a larger colour one: reallocated.
  texture.Upload(big);
  EXPECT_EQ(texture.width(), 90);
  EXPECT_TRUE(Identical(ReadTexture(texture, CV_8UC3, GL_BGR), big));
}

TEST_F(RenderTest, TextureMoveHandsOverTheName) {
  Texture a;
  a.Upload(cv::Mat(4, 4, CV_8UC3, cv::Scalar(9, 9, 9)));
  const unsigned id = a.id();
  Texture b(std::move(a));
  EXPECT_EQ(b.id(), id);
  EXPECT_EQ(a.id(), 0u);  // NOLINT(bugprone-use-after-move): moved-from state is specified
  EXPECT_TRUE(glIsTexture(id));
}

TEST(DisplayModeTest, NamesRoundTrip) {
  for (const char* name : {"mono-left", "mono-right", "anaglyph", "anaglyph-color", "sbs",
                           "sbs-half", "top-bottom", "interlaced", "quad-buffer"}) {
    DisplayMode mode;
    ASSERT_TRUE(ParseDisplayMode(name, &mode)) << name;
    EXPECT_STREQ(DisplayModeName(mode), name);
  }
  DisplayMode mode;
  EXPECT_FALSE(ParseDisplayMode("hologram", &mode));
  int w = 0, h = 0;
  WindowSizeFor(DisplayMode::kSideBySideFull, 640, 480, &w, &h);
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 480);
}

}  // namespace
}  // namespace mostar::render
