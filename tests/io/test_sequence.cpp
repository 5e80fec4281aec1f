#include <gtest/gtest.h>

#include "dataset_test_utils.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

TEST(Sequence, DetectsTheFormatOfEveryFixture) {
  EXPECT_EQ(detect_format(data_path("euroc_V1_01_easy_micro")), "euroc");
  EXPECT_EQ(detect_format(data_path("euroc_V1_01_easy_micro/mav0")), "euroc");
  EXPECT_EQ(detect_format(data_path("tum_fr3_office_snippet")), "tum");
  EXPECT_EQ(detect_format(data_path("kitti_04_mono51")), "kitti");
  EXPECT_EQ(detect_format(data_path("kitti_04_mono51/sequences/04")), "kitti");
  EXPECT_EQ(detect_format(data_path("ecd_slider_hdr_close_149")), "folder");
}

TEST(Sequence, ExplicitFormatIsObeyed) {
  // The ECD folder read as TUM: there is no rgb.txt, and the error says so.
  SequenceOptions tum;
  tum.format = "tum";
  const auto root = data_path("ecd_slider_hdr_close_149");
  const auto e = expect_input_error([&] { open_sequence(root, tum); });
  EXPECT_EQ(e.file(), (root / "rgb.txt").string());
  SequenceOptions folder;
  folder.format = "folder";
  EXPECT_EQ(open_sequence(root, folder)->size(), 149u);
  SequenceOptions bad;
  bad.format = "rosbag";
  EXPECT_THROW(open_sequence(root, bad), pllvo::InputError);
}

TEST(Sequence, UnknownLayoutNamesTheFolder) {
  TempDir tmp;
  write_file(tmp / "notes.txt", "nothing here\n");
  const auto e = expect_input_error([&] { open_sequence(tmp.path()); });
  EXPECT_EQ(e.file(), tmp.path().string());
  EXPECT_NE(std::string(e.what()).find("cannot tell the dataset format"), std::string::npos) << e.what();
}
