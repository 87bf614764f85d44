#include "opencv_odometry.h"

#include <chrono>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>
#include <optional>

#include "planemap/core/error.h"

namespace planemap {
namespace {

using Clock = std::chrono::steady_clock;

cv::Ptr<cv::rgbd::Odometry> MakeOdometry(const std::string& method, const cv::Mat& K) {
  if (method == "ICPOdometry") return cv::rgbd::ICPOdometry::create(K);
  if (method == "RgbdOdometry") return cv::rgbd::RgbdOdometry::create(K);
  if (method == "RgbdICPOdometry") return cv::rgbd::RgbdICPOdometry::create(K);
  if (method == "FastICPOdometry") return cv::rgbd::FastICPOdometry::create(K);
  throw InputError("unknown OpenCV odometry method '" + method + "'");
}

cv::Mat CameraMatrix(const CameraIntrinsics& c) {
  return (cv::Mat_<float>(3, 3) << c.fx, 0.f, c.cx, 0.f, c.fy, c.cy, 0.f, 0.f, 1.f);
}

// The frame as OpenCV's odometry takes it: 8-bit gray and depth in metres (CV_32F) with NaN where
// there is no measurement, as OpenCV's own sample (rgbd/samples/odometry_evaluation.cpp) prepares
// it: parts of the odometry (correspondences, the depth pyramid) test for NaN, not the mask, and
// take a 0 for a point at 0 m. With zeros, RgbdOdometry's ATE on icl_office_kt0 was 5.7 cm, with
// NaN 2.0 cm (RgbdICPOdometry 1.21 and 1.07 cm).
cv::Ptr<cv::rgbd::OdometryFrame> MakeOdometryFrame(const RgbdFrame& frame) {
  const cv::Mat rgb(frame.color.height(), frame.color.width(), CV_8UC3,
                    const_cast<Rgb8*>(frame.color.data()));
  cv::Mat gray;
  cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
  cv::Mat depth =
      cv::Mat(frame.depth.height(), frame.depth.width(), CV_32FC1, const_cast<float*>(frame.depth.data()))
          .clone();
  depth.setTo(std::numeric_limits<float>::quiet_NaN(), depth <= 0.0f);
  return cv::rgbd::OdometryFrame::create(gray, depth);
}

Pose3 PoseOf(const cv::Mat& Rt) {
  Pose3 T = Pose3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = Rt.at<double>(r, c);
  }
  return T;
}

// compute(src, dst, Rt) returns the motion with dst_p = Rt * src_p (OpenCV's documentation), so
// with src = the previous frame Rt = T_current_previous, and
//   T_world_current = T_world_previous * T_previous_current = T_world_previous * Rt^-1.
// Checked against ground truth by the first-to-last relative pose error (ATE barely tells: its
// rigid alignment nearly maps one composition onto the other; on fr3 both ATEs agreed to 0.1 cm):
// - fr1_xyz pair (3.8 cm of true motion in 0.1 s): with Rt^-1 the four methods are 0.2-0.5 cm and
//   0.1-0.8 deg off, with Rt 7.4-7.7 cm and 3.5-4.0 deg (the motion reversed);
// - tum_fr3_snt_far_head from its first frame with ground truth: over 10 frames the true motion
//   (1.8 cm) is below the methods' drift and the translation decides nothing, the rotation does
//   (Rt^-1 0.9-1.3 deg off, Rt 2.3-2.6 deg); over 60 frames (34 cm) Rt^-1 is 11-21 cm off, Rt 47-57 cm.
// The unit test RealTable.RgbdIcpOdometryRecoversTheFr1XyzMotion pins it.
Pose3 ComposeOdometryStep(const Pose3& T_world_previous, const cv::Mat& Rt) {
  return T_world_previous * PoseOf(Rt).inverse();
}

std::optional<RgbdFrame> LoadOrSkip(const TumSequence& sequence, size_t index) {
  try {
    return sequence.LoadFrame(index);
  } catch (const InputError& e) {  // as planemap map: named, skipped, counted
    std::fprintf(stderr, "bench_real: frame %zu skipped: %s\n", index, e.what());
    return std::nullopt;
  }
}

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

const std::vector<std::string>& OpenCvOdometryMethods() {
  static const std::vector<std::string> kMethods = {"ICPOdometry", "RgbdOdometry", "RgbdICPOdometry",
                                                    "FastICPOdometry"};
  return kMethods;
}

OdometryRun RunOpenCvOdometry(const std::string& method, const TumSequence& sequence,
                              const std::vector<size_t>& frames, const Pose3& T_world_first) {
  OdometryRun run;
  try {
    const cv::Ptr<cv::rgbd::Odometry> odometry = MakeOdometry(method, CameraMatrix(sequence.camera()));
    cv::Ptr<cv::rgbd::OdometryFrame> previous;
    Pose3 T_world_previous = T_world_first;
    for (const size_t index : frames) {
      const std::optional<RgbdFrame> frame = LoadOrSkip(sequence, index);
      if (!frame) {
        ++run.unreadable;
        continue;
      }
      cv::Ptr<cv::rgbd::OdometryFrame> current = MakeOdometryFrame(*frame);
      ++run.frames;
      const auto start = Clock::now();
      odometry->prepareFrameCache(current, cv::rgbd::OdometryFrame::CACHE_ALL);
      if (previous) {
        cv::Mat Rt;
        if (odometry->compute(previous, current, Rt)) {
          T_world_previous = ComposeOdometryStep(T_world_previous, Rt);
        } else {
          ++run.failures;  // documented fallback: keep the previous pose
        }
        run.step_ms.push_back(MillisecondsSince(start));
      }
      run.trajectory.push_back({frame->stamp, T_world_previous});
      previous = current;
    }
  } catch (const cv::Exception& e) {
    run.error = "OpenCV: " + e.msg;
  }
  return run;
}

}  // namespace planemap
