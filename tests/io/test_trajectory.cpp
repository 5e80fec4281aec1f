#include <gtest/gtest.h>

#include <fstream>

#include "pllvo/common/error.h"
#include "pllvo/common/fixtures.h"
#include "pllvo/io/trajectory.h"

namespace fs = std::filesystem;
using namespace pllvo::io;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / ("pllvo_traj_" + name);
  std::ofstream(p) << text;
  return p;
}

long error_line(const fs::path& file, Trajectory (*reader)(const fs::path&)) {
  try {
    reader(file);
  } catch (const pllvo::InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    return e.line();
  }
  ADD_FAILURE() << "no error for " << file;
  return -1;
}
}  // namespace

TEST(Trajectory, ReadsEvoReferenceInAllThreeFormats) {
  const auto dir = pllvo::shared_path("testvectors/eval");
  const auto tum = read_tum(dir / "ref.txt");
  const auto euroc = read_euroc_csv(dir / "ref_euroc.csv");
  const auto kitti = read_kitti(dir / "ref_kitti.txt");
  ASSERT_EQ(tum.size(), 600u);
  ASSERT_EQ(euroc.size(), 600u);
  ASSERT_EQ(kitti.size(), 600u);
  EXPECT_FALSE(kitti.has_stamps());
  EXPECT_DOUBLE_EQ(tum.stamps[0], 1403636580.8385556);
  for (size_t i = 0; i < 600; ++i) {
    EXPECT_EQ(tum.stamps[i], euroc.stamps[i]);  // README: bit-identical after ns/1e9
    EXPECT_LT((tum.poses[i].matrix() - euroc.poses[i].matrix()).norm(), 1e-12);
    EXPECT_LT((tum.poses[i].matrix() - kitti.poses[i].matrix()).norm(), 1e-9);
  }
  EXPECT_EQ(read_trajectory(dir / "ref_kitti.txt").size(), 600u);
  EXPECT_TRUE(read_trajectory(dir / "ref_euroc.csv").has_stamps());
}

TEST(Trajectory, QuaternionSignAndScaleDoNotMatter) {
  const Eigen::Matrix3d R = rotation_from_quaternion(0.3, -0.5, 0.2, 0.7);
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((rotation_from_quaternion(-0.6, 1.0, -0.4, -1.4) - R).norm(), 1e-12);
  const Eigen::Quaterniond q(0.3, -0.5, 0.2, 0.7);
  EXPECT_LT((q.normalized().toRotationMatrix() - R).norm(), 1e-12);
  EXPECT_EQ(rotation_from_quaternion(0, 0, 0, 0), Eigen::Matrix3d::Identity());
}

TEST(Trajectory, TumRoundTrip) {
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(i, -2.5 * i, 1e-3 * i);
    t.push_back(1403636580.8385556 + 0.05 * i, T);
  }
  const auto file = fs::temp_directory_path() / "pllvo_traj_rt" / "t.tum";
  write_tum(t, file);
  const auto back = read_tum(file);
  ASSERT_EQ(back.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(back.stamps[i], t.stamps[i]);
    EXPECT_LT((back.poses[i].matrix() - t.poses[i].matrix()).norm(), 1e-14);
  }
}

TEST(Trajectory, BadInputNamesFileAndLine) {
  EXPECT_EQ(error_line(write_temp("nan.txt", "# c\n0 0 0 0 0 0 0 1\n1 nan 0 0 0 0 0 1\n"), read_tum), 3);
  EXPECT_EQ(error_line(write_temp("short.txt", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n"), read_tum), 2);
  EXPECT_EQ(error_line(write_temp("word.txt", "0 0 0 0 0 0 0 1\n1 0 x 0 0 0 0 1\n"), read_tum), 2);
  EXPECT_EQ(error_line(write_temp("dbl.txt", "0 0 0 0 0 0 0 1\n1  0 0 0 0 0 0 1\n"), read_tum), 2);
  EXPECT_EQ(error_line(write_temp("order.txt", "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n"), read_tum), 2);
  EXPECT_EQ(error_line(write_temp("euroc.csv", "#h\n1,0,0,0,1,0,0,0\n2,0,0,0,1,0,0\n"),
                       [](const fs::path& p) { return read_euroc_csv(p); }),
            3);
  EXPECT_EQ(error_line(write_temp("kitti.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n"), read_kitti), 2);
  EXPECT_EQ(error_line(write_temp("empty.txt", "# only a comment\n"), read_tum), 0);
  EXPECT_THROW(read_tum("/nonexistent/traj.txt"), pllvo::InputError);
}

TEST(Trajectory, EurocBodyToCameraConversion) {
  const auto file = write_temp("gt.csv", "#ts\n1000000000,1,2,3,1,0,0,0,0,0,0\n");
  Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
  T_bc.translation() = Eigen::Vector3d(0.1, 0, 0);
  T_bc.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto traj = read_euroc_csv(file, &T_bc);
  EXPECT_DOUBLE_EQ(traj.stamps[0], 1.0);
  EXPECT_LT((traj.poses[0].translation() - Eigen::Vector3d(1.1, 2, 3)).norm(), 1e-12);
  EXPECT_LT((traj.poses[0].linear() - T_bc.linear()).norm(), 1e-12);
}
