// FramePrefetcher: the frames of a direct load, in order, at any depth; a frame that cannot be
// loaded fails when the consumer reaches it, and ends the sequence there.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "dataset_test_utils.h"
#include "pllvo/io/frame_prefetcher.h"
#include "pllvo/io/sequence.h"

using namespace pllvo::io;
using namespace pllvo::io::testing;

namespace {

void expect_same_frame(const Frame& got, const Frame& want) {
  EXPECT_EQ(got.index, want.index);
  EXPECT_EQ(got.timestamp, want.timestamp);
  ASSERT_EQ(got.left.size(), want.left.size());
  EXPECT_EQ(cv::norm(got.left, want.left, cv::NORM_INF), 0.0) << "frame " << want.index;
  EXPECT_EQ(got.right.empty(), want.right.empty());
  if (!want.right.empty()) EXPECT_EQ(cv::norm(got.right, want.right, cv::NORM_INF), 0.0) << "frame " << want.index;
}

}  // namespace

TEST(FramePrefetcher, DeliversTheFramesOfADirectLoadInOrderAtAnyDepth) {
  const auto seq = open_sequence(data_path("euroc_V1_01_easy_micro"));
  ASSERT_TRUE(seq->calibration().stereo());
  for (size_t depth : {0u, 1u, 3u}) {
    FramePrefetcher frames(*seq, 5, 17, depth);
    for (size_t i = 5; i < 17; ++i) {
      ASSERT_TRUE(frames.has_next()) << "depth " << depth << ", frame " << i;
      Frame want = seq->frame(i);
      expect_same_frame(frames.next(), want);
    }
    EXPECT_FALSE(frames.has_next());
    EXPECT_THROW(frames.next(), std::out_of_range) << "depth " << depth;
  }
}

TEST(FramePrefetcher, ADroppedPrefetcherStopsItsLoader) {
  const auto seq = open_sequence(data_path("ecd_slider_hdr_close_149"));
  // Left after two of 149 frames with four loaded ahead: the destructor must not wait for the rest.
  auto frames = std::make_unique<FramePrefetcher>(*seq, 0, seq->size(), 4);
  expect_same_frame(frames->next(), seq->frame(0));
  expect_same_frame(frames->next(), seq->frame(1));
  frames.reset();
  // An empty range starts no loader and has nothing to give.
  FramePrefetcher none(*seq, 7, 7, 2);
  EXPECT_FALSE(none.has_next());
  EXPECT_THROW(none.next(), std::out_of_range);
}

TEST(FramePrefetcher, AnUnreadableFrameFailsWhenReachedAndEndsTheSequence) {
  TempDir tmp;
  make_folder_copy(tmp.path(), 6);
  const auto broken = tmp / "images/frame_00000003.png";
  write_file(broken, "this is not a PNG file");
  const auto seq = open_sequence(tmp.path());
  for (size_t depth : {0u, 2u, 8u}) {
    FramePrefetcher frames(*seq, 0, seq->size(), depth);
    for (size_t i = 0; i < 3; ++i) expect_same_frame(frames.next(), seq->frame(i));
    const auto e = expect_input_error([&] { frames.next(); });
    EXPECT_EQ(e.file(), broken.string()) << "depth " << depth;
    EXPECT_FALSE(frames.has_next()) << "depth " << depth << ": frames after the failed one";
  }
}
