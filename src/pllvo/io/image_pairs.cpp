#include "pllvo/io/image_pairs.h"

#include "pllvo/common/error.h"
#include "pllvo/geometry/pose.h"
#include "pllvo/io/dataset_files.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {

constexpr size_t kFields = 38;

Eigen::Matrix3d read_K(const TextRow& row, size_t first, const fs::path& file) {
  Eigen::Matrix3d K;
  for (int i = 0; i < 9; ++i) K(i / 3, i % 3) = parse_double(row.fields[first + i], file, row.line, "a K entry");
  if (!(K(0, 0) > 0 && K(1, 1) > 0) || K(1, 0) != 0 || K(2, 0) != 0 || K(2, 1) != 0 || K(2, 2) != 1)
    throw InputError(file, row.line, "intrinsics (field " + std::to_string(first + 1) +
                                         " on) are not a pinhole K [fx s cx; 0 fy cy; 0 0 1]");
  return K;
}

Eigen::Isometry3d read_T(const TextRow& row, size_t first, const fs::path& file) {
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = parse_double(row.fields[first + i], file, row.line, "a T_0to1 entry");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  // 5 printed decimals leave R orthonormal to ~1e-5; allow some margin over that.
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9 ||
      (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R.determinant() < 0)
    throw InputError(file, row.line, "T_0to1 is not a rigid transform");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = geometry::nearest_rotation(R);
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

int read_rotation(const TextRow& row, size_t field, const fs::path& file) {
  const auto r = parse_int64(row.fields[field], file, row.line, "an EXIF rotation flag 0..3");
  if (r < 0 || r > 3) throw InputError(file, row.line, "EXIF rotation flag must be 0..3, found " + std::to_string(r));
  return static_cast<int>(r);
}

}  // namespace

std::vector<ImagePair> read_image_pairs(const fs::path& file, const fs::path& image_dir) {
  const fs::path dir = image_dir.empty() ? file.parent_path() / "images" : image_dir;
  std::vector<ImagePair> pairs;
  for (const auto& row : read_text_rows(file, Separator::kWhitespace)) {
    if (row.fields.size() != kFields)
      throw InputError(file, row.line, "expected 38 fields 'name0 name1 rot0 rot1 K0[9] K1[9] T_0to1[16]', found " +
                                           std::to_string(row.fields.size()));
    ImagePair p;
    p.image0 = dir / row.fields[0];
    p.image1 = dir / row.fields[1];
    for (const auto& image : {p.image0, p.image1})
      if (!fs::is_regular_file(image)) throw InputError(file, row.line, "image file not found: " + image.string());
    p.rotation0 = read_rotation(row, 2, file);
    p.rotation1 = read_rotation(row, 3, file);
    p.K0 = read_K(row, 4, file);
    p.K1 = read_K(row, 13, file);
    p.T_cam1_cam0 = read_T(row, 22, file);
    pairs.push_back(p);
  }
  if (pairs.empty()) throw InputError(file, "no image pairs in file");
  return pairs;
}

}  // namespace pllvo::io
