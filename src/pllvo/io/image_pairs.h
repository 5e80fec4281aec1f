#pragma once
// Image pairs with intrinsics and ground-truth relative pose, in SuperGlue's pairs-file
// format (e.g. scannet_sample_pairs_with_gt.txt), one pair per line, 38 fields:
//   name0 name1 rot0 rot1 K0[9] K1[9] T_0to1[16]      (matrices row-major)
#include <filesystem>
#include <vector>

#include <Eigen/Geometry>

namespace pllvo::io {

struct ImagePair {
  std::filesystem::path image0, image1;
  /// EXIF rotation flag of each image, 0..3 = 0/90/180/270 deg clockwise. Images and K are
  /// returned as stored; a non-zero flag means the caller must rotate both (SuperGlue's rot90).
  int rotation0 = 0, rotation1 = 0;
  Eigen::Matrix3d K0 = Eigen::Matrix3d::Identity(), K1 = Eigen::Matrix3d::Identity();
  /// T_0to1: maps camera-0 points to camera 1 (X_1 = R X_0 + t), metres. The file prints
  /// R to 5 decimals; it is snapped to the nearest rotation.
  Eigen::Isometry3d T_cam1_cam0 = Eigen::Isometry3d::Identity();
};

/// Image names are resolved in `image_dir` (default: images/ beside the pairs file) and must
/// exist. InputError naming the file and line for anything malformed.
std::vector<ImagePair> read_image_pairs(const std::filesystem::path& file,
                                        const std::filesystem::path& image_dir = {});

}  // namespace pllvo::io
