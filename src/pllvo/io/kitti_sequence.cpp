#include "pllvo/io/kitti_sequence.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>

#include "pllvo/common/error.h"
#include "pllvo/io/dataset_files.h"
#include "pllvo/io/gray_image.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

struct Projection {
  long line = 0;
  std::vector<double> P;  // 3x4 row-major
};

camera::PinholeIntrinsics intrinsics_of(const Projection& p, const fs::path& file) {
  const auto& P = p.P;
  if (!(P[0] > 0 && P[5] > 0) || P[1] != 0 || P[4] != 0 || P[8] != 0 || P[9] != 0 || P[10] != 1)
    throw InputError(file, p.line, "not a rectified projection matrix [fx 0 cx tx; 0 fy cy ty; 0 0 1 tz]");
  return {P[0], P[5], P[2], P[6]};
}

/// The sequence folder: `root` itself, or the only folder under root/sequences/.
fs::path sequence_folder(const fs::path& root) {
  if (fs::exists(root / "times.txt") || fs::is_directory(root / "image_0")) return root;
  const fs::path seqs = root / "sequences";
  if (!fs::is_directory(seqs))
    throw InputError(root, "not a KITTI odometry folder: no times.txt, image_0/ or sequences/");
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(seqs))
    if (e.is_directory()) found.push_back(e.path());
  std::sort(found.begin(), found.end());
  if (found.empty()) throw InputError(seqs, "holds no sequence folder");
  if (found.size() > 1) {
    std::string names;
    for (const auto& f : found) names += (names.empty() ? "" : ", ") + f.filename().string();
    throw InputError(seqs, "holds " + std::to_string(found.size()) + " sequences (" + names +
                               "): pass the path of one, e.g. " + found.front().string());
  }
  return found.front();
}

std::string frame_name(size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.png", i);
  return name;
}

}  // namespace

KittiCalibration read_kitti_calib(const fs::path& file) {
  std::map<std::string, Projection> found;
  for (const auto& row : read_text_rows(file, Separator::kWhitespace)) {
    const std::string& key = row.fields[0];
    if (key.size() < 2 || key.back() != ':')
      throw InputError(file, row.line, "expected 'KEY: numbers' (e.g. 'P0: 12 numbers'), found '" + key + "'");
    const std::string name = key.substr(0, key.size() - 1);
    if (name != "P0" && name != "P1") continue;
    if (row.fields.size() != 13)
      throw InputError(file, row.line, name + " needs 12 numbers (a 3x4 matrix), found " +
                                           std::to_string(row.fields.size() - 1));
    Projection p{row.line, {}};
    for (size_t i = 1; i < row.fields.size(); ++i)
      p.P.push_back(parse_double(row.fields[i], file, row.line, "a matrix entry"));
    found[name] = p;
  }
  if (!found.count("P0")) throw InputError(file, std::string("P0"), "missing (the left camera's projection matrix)");
  KittiCalibration calib;
  calib.cam0 = intrinsics_of(found["P0"], file);
  if (found.count("P1")) {
    calib.cam1 = intrinsics_of(found["P1"], file);
    calib.baseline = found["P0"].P[3] / calib.cam0.fx - found["P1"].P[3] / calib.cam1->fx;
    if (!(calib.baseline > 0))
      throw InputError(file, found["P1"].line, "P1 does not place the right camera to the right of P0's");
  }
  return calib;
}

KittiSequence::KittiSequence(const fs::path& root, const SequenceOptions& options) : Sequence(root) {
  if (!fs::is_directory(root)) throw InputError(root, "dataset folder not found");
  // poses/XX.txt is found from the folder's name, so "sequences/04/" and "." must name it too.
  fs::path normal = fs::absolute(root).lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();
  const fs::path seq = sequence_folder(normal);
  const KittiCalibration calib = read_kitti_calib(seq / "calib.txt");

  const fs::path times = seq / "times.txt";
  std::vector<long> lines;
  for (const auto& row : read_text_rows(times, Separator::kWhitespace)) {
    if (row.fields.size() != 1)
      throw InputError(times, row.line, "expected one timestamp per line, found " +
                                            std::to_string(row.fields.size()) + " fields");
    stamps_.push_back(parse_double(row.fields[0], times, row.line, "a timestamp in seconds"));
    lines.push_back(row.line);
  }
  if (stamps_.empty()) throw InputError(times, "no frames listed (empty sequence)");
  require_strictly_increasing(stamps_, lines, times);

  const bool stereo = !options.mono && fs::is_directory(seq / "image_1");
  for (size_t i = 0; i < stamps_.size(); ++i)
    for (int cam = 0; cam < (stereo ? 2 : 1); ++cam) {
      const fs::path image = seq / (cam == 0 ? "image_0" : "image_1") / frame_name(i);
      if (!fs::is_regular_file(image))
        throw InputError(times, lines[i], "image file not found for this frame: " + image.string());
      (cam == 0 ? left_files_ : right_files_).push_back(image);
    }

  const cv::Size size = read_gray_image(left_files_.front()).size();
  calib_.cam0 = std::make_shared<camera::PinholeRadtan>(size.width, size.height, calib.cam0);
  if (stereo) {
    if (!calib.cam1)
      throw InputError(seq / "calib.txt", std::string("P1"), "missing, but image_1/ holds right images (use mono)");
    calib_.cam1 = std::make_shared<camera::PinholeRadtan>(size.width, size.height, *calib.cam1);
    calib_.T_body_cam1.translation() = Eigen::Vector3d(calib.baseline, 0, 0);
  }
  calib_.rate_hz = mean_rate(stamps_);

  const fs::path poses = seq.parent_path().parent_path() / "poses" / (seq.filename().string() + ".txt");
  if (fs::exists(poses)) {
    Trajectory gt = read_kitti(poses);
    if (gt.size() != stamps_.size())
      throw InputError(poses, "has " + std::to_string(gt.size()) + " poses for " + std::to_string(stamps_.size()) +
                                  " frames in " + times.string());
    gt.stamps = stamps_;
    ground_truth_ = std::move(gt);
  }
}

}  // namespace pllvo::io
