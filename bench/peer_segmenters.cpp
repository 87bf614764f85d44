#include "peer_segmenters.h"

#include <cstdint>
#include <memory>

#include <opencv2/rgbd.hpp>
#include <pcl/features/integral_image_normal.h>
#include <pcl/segmentation/organized_multi_plane_segmentation.h>

namespace planemap {

std::vector<DetectedPlane> PclOrganizedMultiPlanes(const Cloud::ConstPtr& cloud) {
  pcl::IntegralImageNormalEstimation<pcl::PointXYZRGB, pcl::Normal> ne;
  ne.setNormalEstimationMethod(ne.COVARIANCE_MATRIX);
  ne.setMaxDepthChangeFactor(0.02f);
  ne.setNormalSmoothingSize(10.0f);
  ne.setInputCloud(cloud);
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  ne.compute(*normals);
  pcl::OrganizedMultiPlaneSegmentation<pcl::PointXYZRGB, pcl::Normal, pcl::Label> mps;
  mps.setMinInliers(400);
  mps.setAngularThreshold(6.0 * M_PI / 180.0);
  mps.setDistanceThreshold(0.05);
  mps.setInputNormals(normals);
  mps.setInputCloud(cloud);
  std::vector<pcl::ModelCoefficients> coefficients;
  std::vector<pcl::PointIndices> inliers;
  mps.segment(coefficients, inliers);
  std::vector<DetectedPlane> planes;
  for (size_t i = 0; i < inliers.size(); ++i) {
    DetectedPlane p;
    p.id = static_cast<int>(i);
    const auto& c = coefficients[i].values;
    p.plane = {Eigen::Vector3d(c[0], c[1], c[2]), c[3]};
    p.inliers.assign(inliers[i].indices.begin(), inliers[i].indices.end());
    planes.push_back(std::move(p));
  }
  return planes;
}

std::vector<DetectedPlane> OpenCvRgbdPlanes(const DepthImage& depth, const CameraIntrinsics& camera) {
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat depth_mat(depth.height(), depth.width(), CV_32FC1, const_cast<float*>(depth.data()));
  cv::Mat points;
  cv::rgbd::depthTo3d(depth_mat, K, points);
  cv::rgbd::RgbdPlane plane_finder(cv::rgbd::RgbdPlane::RGBD_PLANE_METHOD_DEFAULT, 40, 400, 0.02, 0.0075, 0,
                                   0);
  cv::Mat mask, coefficients;
  plane_finder(points, mask, coefficients);
  std::vector<DetectedPlane> planes(coefficients.rows);
  for (int i = 0; i < coefficients.rows; ++i) {
    const cv::Vec4f c = coefficients.at<cv::Vec4f>(i);
    planes[i].id = i;
    planes[i].plane = {Eigen::Vector3d(c[0], c[1], c[2]), c[3]};
  }
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      const int label = mask.at<std::uint8_t>(v, u);
      if (label < coefficients.rows) planes[label].inliers.push_back(v * mask.cols + u);
    }
  }
  return planes;
}

}  // namespace planemap
