// EuRoC writer: the files parse back (csv columns, sensor.yaml keys as in EuRoC's files),
// and nothing half-written remains when writing fails or is abandoned.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "pllvo/common/error.h"
#include "pllvo/io/euroc_writer.h"

namespace fs = std::filesystem;
using namespace pllvo;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("pllvo_euroc_writer_" + name);
  fs::remove_all(p);
  fs::remove_all(p.string() + ".partial");
  return p;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& file, std::string* header) {
  std::ifstream f(file);
  std::string line;
  std::getline(f, line);
  if (header) *header = line;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(f, line)) {
    std::vector<std::string> cols;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
    rows.push_back(cols);
  }
  return rows;
}

/// EuRoC's sensor.yaml starts with the OpenCV directive %YAML:1.0, which yaml-cpp rejects.
YAML::Node load_euroc_yaml(const fs::path& file) {
  std::ifstream f(file);
  std::string first, rest;
  std::getline(f, first);
  EXPECT_EQ(first, "%YAML:1.0");
  std::stringstream ss;
  ss << f.rdbuf();
  return YAML::Load(ss.str());
}

std::vector<io::EurocCamera> stereo_rig() {
  auto cam = std::make_shared<camera::PinholeRadtan>(752, 480, camera::PinholeIntrinsics{458.654, 457.296, 367.215, 248.375},
                                                     std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  io::EurocCamera c0{cam, Eigen::Isometry3d::Identity(), 20, ""};
  io::EurocCamera c1 = c0;
  c1.T_body_cam = Eigen::Translation3d(0.11, 0, 0) * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY());
  return {c0, c1};
}

}  // namespace

TEST(EurocWriter, WritesTheEuRoCLayoutThatParsesBack) {
  const fs::path root = fresh_dir("layout");
  const auto rig = stereo_rig();
  {
    io::EurocWriter w(root, rig);
    for (int i = 0; i < 3; ++i) {
      cv::Mat a(480, 752, CV_8UC1, cv::Scalar(10 * i)), b(480, 752, CV_8UC1, cv::Scalar(10 * i + 1));
      w.add_frame(1500000000000000000LL + i * 50000000LL, {a, b});
    }
    for (int i = 0; i < 10; ++i) {
      io::EurocGroundTruth g;
      g.stamp_ns = 1500000000000000000LL + i * 5000000LL;
      g.T_world_body = Eigen::Translation3d(1, 2, 3 + i) * Eigen::AngleAxisd(0.1 * i + 3.0, Eigen::Vector3d(1, 1, 0).normalized());
      g.velocity = Eigen::Vector3d(0.5, -0.25, i);
      w.add_ground_truth(g);
    }
    EXPECT_FALSE(fs::exists(root));  // nothing at the destination before commit
    w.commit();
  }
  EXPECT_FALSE(fs::exists(root.string() + ".partial"));
  for (int c = 0; c < 2; ++c) {
    const fs::path dir = root / "mav0" / ("cam" + std::to_string(c));
    std::string header;
    const auto rows = read_csv(dir / "data.csv", &header);
    EXPECT_EQ(header, "#timestamp [ns],filename");
    ASSERT_EQ(rows.size(), 3u);
    for (size_t i = 0; i < rows.size(); ++i) {
      ASSERT_EQ(rows[i].size(), 2u);
      EXPECT_EQ(rows[i][1], rows[i][0] + ".png");
      const cv::Mat img = cv::imread((dir / "data" / rows[i][1]).string(), cv::IMREAD_UNCHANGED);
      ASSERT_EQ(img.type(), CV_8UC1);
      EXPECT_EQ(img.at<uint8_t>(7, 7), 10 * i + c);
    }
    const YAML::Node y = load_euroc_yaml(dir / "sensor.yaml");
    EXPECT_EQ(y["sensor_type"].as<std::string>(), "camera");
    EXPECT_EQ(y["camera_model"].as<std::string>(), "pinhole");
    EXPECT_EQ(y["distortion_model"].as<std::string>(), "radial-tangential");
    EXPECT_EQ(y["rate_hz"].as<double>(), 20);
    EXPECT_EQ(y["resolution"].as<std::vector<int>>(), (std::vector<int>{752, 480}));
    EXPECT_EQ(y["intrinsics"].as<std::vector<double>>(), (std::vector<double>{458.654, 457.296, 367.215, 248.375}));
    EXPECT_EQ(y["distortion_coefficients"].as<std::vector<double>>(),
              (std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}));
    EXPECT_EQ(y["T_BS"]["rows"].as<int>(), 4);
    EXPECT_EQ(y["T_BS"]["cols"].as<int>(), 4);
    const auto data = y["T_BS"]["data"].as<std::vector<double>>();
    ASSERT_EQ(data.size(), 16u);
    Eigen::Matrix4d T;
    for (int k = 0; k < 16; ++k) T(k / 4, k % 4) = data[k];
    EXPECT_EQ(T, rig[c].T_body_cam.matrix());  // exact: shortest round-trip formatting
  }
  std::string header;
  const auto gt = read_csv(root / "mav0" / "state_groundtruth_estimate0" / "data.csv", &header);
  EXPECT_EQ(header.rfind("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x []", 0), 0u);
  ASSERT_EQ(gt.size(), 10u);
  for (size_t i = 0; i < gt.size(); ++i) {
    ASSERT_EQ(gt[i].size(), 17u);
    EXPECT_EQ(std::stoll(gt[i][0]), 1500000000000000000LL + static_cast<long long>(i) * 5000000LL);
    const Eigen::Quaterniond q(std::stod(gt[i][4]), std::stod(gt[i][5]), std::stod(gt[i][6]), std::stod(gt[i][7]));
    EXPECT_NEAR(q.norm(), 1.0, 1e-11);
    EXPECT_GE(q.w(), 0);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.1 * i + 3.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
    EXPECT_LT((q.toRotationMatrix() - R).norm(), 1e-10);
    EXPECT_NEAR(std::stod(gt[i][3]), 3.0 + i, 1e-9);
    EXPECT_NEAR(std::stod(gt[i][10]), static_cast<double>(i), 1e-9);
    EXPECT_EQ(std::stod(gt[i][16]), 0.0);
  }
  EXPECT_TRUE(fs::exists(root / "mav0" / "body.yaml"));
  fs::remove_all(root);
}

TEST(EurocWriter, AbandonedWriterLeavesNothingAndExistingOutputIsKept) {
  const fs::path root = fresh_dir("abandon");
  {
    io::EurocWriter w(root, stereo_rig());
    w.add_frame(1, {cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)), cv::Mat(480, 752, CV_8UC1, cv::Scalar(0))});
    EXPECT_TRUE(fs::exists(w.staging_root()));
    // An exception unwinds here in real use; the destructor cleans up.
  }
  EXPECT_FALSE(fs::exists(root));
  EXPECT_FALSE(fs::exists(root.string() + ".partial"));

  fs::create_directories(root);
  std::ofstream(root / "keep.txt") << "x";
  EXPECT_THROW(io::EurocWriter(root, stereo_rig()), InputError);
  EXPECT_TRUE(fs::exists(root / "keep.txt"));
  {
    io::EurocWriter w(root, stereo_rig(), /*overwrite=*/true);
    EXPECT_TRUE(fs::exists(root / "keep.txt"));  // replaced only on commit
    w.commit();
  }
  EXPECT_FALSE(fs::exists(root / "keep.txt"));
  EXPECT_TRUE(fs::exists(root / "mav0" / "cam1" / "sensor.yaml"));
  fs::remove_all(root);
}

TEST(EurocWriter, CameraYamlMatchesEuRoCsText) {
  const auto rig = stereo_rig();
  const std::string text = io::euroc_camera_yaml(rig[0], "VI-Sensor cam0 (MT9M034)");
  EXPECT_NE(text.find("%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\n"), std::string::npos);
  EXPECT_NE(text.find("T_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, 0.0,\n         0.0, 1.0,"), std::string::npos);
  EXPECT_NE(text.find("rate_hz: 20\nresolution: [752, 480]\ncamera_model: pinhole\n"), std::string::npos);
  EXPECT_NE(text.find("intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv\n"), std::string::npos);
  EXPECT_NE(text.find("distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"),
            std::string::npos);
}
