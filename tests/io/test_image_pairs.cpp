#include <gtest/gtest.h>

#include "dataset_test_utils.h"
#include "pllvo/io/gray_image.h"
#include "pllvo/io/image_pairs.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

TEST(ImagePairs, ReadsScannetSamplePairs) {
  const auto file = data_path("scannet_pairs/scannet_sample_pairs_with_gt.txt");
  const auto pairs = read_image_pairs(file);
  ASSERT_EQ(pairs.size(), 15u);
  const auto& p = pairs[0];
  EXPECT_EQ(p.image0, file.parent_path() / "images" / "scene0711_00_frame-001680.jpg");
  EXPECT_EQ(p.image1.filename(), "scene0711_00_frame-001995.jpg");
  EXPECT_EQ(p.rotation0, 0);
  EXPECT_EQ(p.rotation1, 0);
  Eigen::Matrix3d K;
  K << 1163.45, 0, 653.626, 0, 1164.79, 481.6, 0, 0, 1;
  EXPECT_EQ(p.K0, K);
  EXPECT_EQ(p.K1, K);
  // T_0to1 of line 1, rotation printed to 5 decimals.
  Eigen::Matrix3d R;
  R << 0.78593, -0.35128, 0.50884, 0.39215, 0.91944, 0.02904, -0.47805, 0.17672, 0.86037;
  EXPECT_EQ(p.T_cam1_cam0.translation(), Eigen::Vector3d(-1.51061, -0.05367, 0.056));
  EXPECT_LT((p.T_cam1_cam0.linear() - R).cwiseAbs().maxCoeff(), 2e-5);
  for (const auto& q : pairs) {
    const Eigen::Matrix3d Rq = q.T_cam1_cam0.linear();
    EXPECT_LT((Rq * Rq.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(Rq.determinant(), 1.0, 1e-12);
    EXPECT_EQ(q.rotation0 + q.rotation1, 0);
  }
  // README: translations between the two views span 0.42 to 6.42 m.
  double tmin = 1e9, tmax = 0;
  for (const auto& q : pairs) {
    tmin = std::min(tmin, q.T_cam1_cam0.translation().norm());
    tmax = std::max(tmax, q.T_cam1_cam0.translation().norm());
  }
  EXPECT_NEAR(tmin, 0.42, 0.01);
  EXPECT_NEAR(tmax, 6.42, 0.01);
  EXPECT_EQ(read_gray_image(pairs[14].image1, {1296, 968}).type(), CV_8UC1);
}

TEST(ImagePairs, MalformedLineIsNamed) {
  TempDir tmp;
  auto lines = read_lines(data_path("scannet_pairs/scannet_sample_pairs_with_gt.txt"));
  lines.resize(3);
  lines[1] = lines[1].substr(0, lines[1].rfind(' '));  // 37 fields
  write_lines(tmp / "pairs.txt", lines);
  const auto images = data_path("scannet_pairs/images");
  auto e = expect_input_error([&] { read_image_pairs(tmp / "pairs.txt", images); });
  EXPECT_EQ(e.file(), (tmp / "pairs.txt").string());
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(std::string(e.what()).find("38 fields"), std::string::npos) << e.what();

  lines.resize(1);
  write_lines(tmp / "pairs.txt", lines);
  EXPECT_EQ(read_image_pairs(tmp / "pairs.txt", images).size(), 1u);
  e = expect_input_error([&] { read_image_pairs(tmp / "pairs.txt"); });  // no images/ beside it
  EXPECT_EQ(e.line(), 1);
  EXPECT_NE(std::string(e.what()).find("scene0711_00_frame-001680.jpg"), std::string::npos) << e.what();
}
