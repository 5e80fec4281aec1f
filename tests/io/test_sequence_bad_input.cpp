// Every kind of bad dataset input gets one InputError naming the file and the line or key.
// The broken datasets are small copies of fixture files in a temp folder.
#include <gtest/gtest.h>

#include "dataset_test_utils.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

namespace {

bool mentions(const pllvo::InputError& e, const std::string& text) {
  return std::string(e.what()).find(text) != std::string::npos;
}

/// ECD-style folder with `frames` images from the fixture and its images.txt lines.
fs::path make_folder_copy(const fs::path& dir, size_t frames) {
  const auto src = data_path("ecd_slider_hdr_close_149");
  copy_into(src / "camera.yaml", dir / "camera.yaml");
  const auto lines = read_lines(src / "images.txt");
  write_lines(dir / "images.txt", {lines.begin(), lines.begin() + frames});
  for (size_t i = 0; i < frames; ++i) {
    const std::string rel = lines[i].substr(lines[i].find(' ') + 1);
    copy_into(src / rel, dir / rel);
  }
  return dir;
}

}  // namespace

TEST(SequenceBadInput, MissingDirectory) {
  TempDir tmp;
  const auto missing = tmp / "no_such_dataset";
  auto e = expect_input_error([&] { open_sequence(missing); });
  EXPECT_EQ(e.file(), missing.string());
  EXPECT_TRUE(mentions(e, "not found")) << e.what();
  SequenceOptions kitti;
  kitti.format = "kitti";
  e = expect_input_error([&] { open_sequence(missing, kitti); });
  EXPECT_EQ(e.file(), missing.string());
}

TEST(SequenceBadInput, MissingDataCsv) {
  TempDir tmp;
  make_euroc_copy(tmp.path(), 2);
  fs::remove(tmp / "mav0/cam1/data.csv");
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "mav0/cam1/data.csv").string());
  EXPECT_TRUE(mentions(e, "file not found")) << e.what();
  fs::remove_all(tmp / "mav0/cam0");
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "mav0/cam0/data.csv").string());
}

TEST(SequenceBadInput, MalformedCsvLine) {
  TempDir tmp;
  make_euroc_copy(tmp.path(), 3);
  const auto csv = tmp / "mav0/cam0/data.csv";
  auto lines = read_lines(csv);
  lines[2] = "14037152743621429x6,1403715274362142976.png";
  write_lines(csv, lines);
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), csv.string());
  EXPECT_EQ(e.line(), 3);
  EXPECT_TRUE(mentions(e, "14037152743621429x6")) << e.what();

  lines[2] = "1403715274362142976";  // filename column missing
  write_lines(csv, lines);
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.line(), 3);

  // A malformed ground-truth line is reported the same way.
  make_euroc_copy(tmp.path(), 3);
  const auto gt = tmp / "mav0/state_groundtruth_estimate0/data.csv";
  auto gt_lines = read_lines(gt);
  gt_lines[5] = "1403715274332140000,0.878,2.14,nan,0.06,-0.82,-0.05,-0.55,0,0,0,0,0,0,0,0,0";
  write_lines(gt, gt_lines);
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), gt.string());
  EXPECT_EQ(e.line(), 6);
}

TEST(SequenceBadInput, MalformedYaml) {
  TempDir tmp;
  make_euroc_copy(tmp.path(), 2);
  const auto yaml = tmp / "mav0/cam0/sensor.yaml";
  const std::string good = read_file(yaml);
  // Unclosed flow sequence on line 20 (intrinsics): a syntax error with its line.
  std::string text = good;
  text.replace(text.find("248.375]"), 8, "248.375");
  write_file(yaml, text);
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), yaml.string());
  EXPECT_GT(e.line(), 0);
  EXPECT_TRUE(mentions(e, "malformed YAML")) << e.what();

  // Valid YAML, wrong content: the key is named.
  text = good;
  text.replace(text.find("[458.654, 457.296, 367.215, 248.375]"), 36, "[458.654, 457.296, 367.215]");
  write_file(yaml, text);
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.key(), "intrinsics");
  text = good;
  text.replace(text.find("rows: 4"), 7, "rows: 3");
  write_file(yaml, text);
  EXPECT_EQ(expect_input_error([&] { open_sequence(tmp.path()); }).key(), "T_BS.data");

  // pllvo's camera YAML (folder / TUM): a value of the wrong type names its key.
  TempDir tmp2;
  make_folder_copy(tmp2.path(), 2);
  write_file(tmp2 / "camera.yaml", "width: 240\nheight: 180\nfx: fast\nfy: 300\ncx: 120\ncy: 90\n");
  e = expect_input_error([&] { open_sequence(tmp2.path()); });
  EXPECT_EQ(e.file(), (tmp2 / "camera.yaml").string());
  EXPECT_EQ(e.key(), "fx");
}

TEST(SequenceBadInput, UnreadableImage) {
  TempDir tmp;
  make_folder_copy(tmp.path(), 3);
  const auto image = tmp / "images/frame_00000001.png";
  write_file(image, "this is not a PNG file");
  const auto seq = open_sequence(tmp.path());
  EXPECT_NO_THROW(seq->frame(0));
  auto e = expect_input_error([&] { seq->frame(1); });
  EXPECT_EQ(e.file(), image.string());
  EXPECT_TRUE(mentions(e, "cannot read")) << e.what();

  // A listed image that does not exist is caught when the dataset is opened, with its line.
  fs::remove(image);
  e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "images.txt").string());
  EXPECT_EQ(e.line(), 2);
  EXPECT_TRUE(mentions(e, image.string())) << e.what();
}

TEST(SequenceBadInput, ImageSizeMismatchWithCalibration) {
  TempDir tmp;
  make_folder_copy(tmp.path(), 2);
  std::string yaml = read_file(tmp / "camera.yaml");
  yaml.replace(yaml.find("width: 240"), 10, "width: 320");
  write_file(tmp / "camera.yaml", yaml);
  const auto seq = open_sequence(tmp.path());
  const auto e = expect_input_error([&] { seq->frame(0); });
  EXPECT_EQ(e.file(), (tmp / "images/frame_00000000.png").string());
  EXPECT_TRUE(mentions(e, "240x180")) << e.what();
  EXPECT_TRUE(mentions(e, "320x180")) << e.what();
}

TEST(SequenceBadInput, TimestampsOutOfOrder) {
  TempDir tmp;
  const auto src = data_path("tum_fr3_office_snippet");
  copy_into(src / "camera.yaml", tmp / "camera.yaml");
  auto lines = read_lines(src / "rgb.txt");  // 3 comment lines, then frames
  lines.resize(8);
  std::swap(lines[5], lines[6]);
  write_lines(tmp / "rgb.txt", lines);
  for (size_t i = 3; i < lines.size(); ++i) {
    const std::string rel = lines[i].substr(lines[i].find(' ') + 1);
    copy_into(src / rel, tmp / rel);
  }
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "rgb.txt").string());
  EXPECT_EQ(e.line(), 7);
  EXPECT_TRUE(mentions(e, "increase strictly")) << e.what();

  // EuRoC nanosecond stamps: a repeated stamp is out of order too.
  TempDir tmp2;
  make_euroc_copy(tmp2.path(), 3, false);
  const auto csv = tmp2 / "mav0/cam0/data.csv";
  auto csv_lines = read_lines(csv);
  csv_lines[3] = csv_lines[2].substr(0, csv_lines[2].find(',')) + csv_lines[3].substr(csv_lines[3].find(','));
  write_lines(csv, csv_lines);
  e = expect_input_error([&] { open_sequence(tmp2.path()); });
  EXPECT_EQ(e.file(), csv.string());
  EXPECT_EQ(e.line(), 4);
}

TEST(SequenceBadInput, EmptySequence) {
  TempDir tmp;
  make_euroc_copy(tmp.path(), 0, false);
  auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), (tmp / "mav0/cam0/data.csv").string());
  EXPECT_TRUE(mentions(e, "empty sequence")) << e.what();

  TempDir tmp2;
  make_folder_copy(tmp2.path(), 0);
  e = expect_input_error([&] { open_sequence(tmp2.path()); });
  EXPECT_EQ(e.file(), (tmp2 / "images.txt").string());
  fs::remove(tmp2 / "images.txt");
  fs::create_directories(tmp2 / "images");
  e = expect_input_error([&] { open_sequence(tmp2.path()); });
  EXPECT_EQ(e.file(), (tmp2 / "images").string());
  EXPECT_TRUE(mentions(e, "empty sequence")) << e.what();
}
