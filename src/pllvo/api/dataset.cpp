#include "pllvo/api/dataset.h"

#include "pllvo/io/sequence.h"

namespace pllvo {
namespace {

std::unique_ptr<io::Sequence> open(const std::filesystem::path& folder, bool mono) {
  io::SequenceOptions options;
  options.mono = mono;
  return io::open_sequence(folder, options);
}

}  // namespace

Dataset::Dataset(const std::filesystem::path& folder, bool mono)
    : sequence_(open(folder, mono)),
      calibration_(std::make_shared<const io::Calibration>(sequence_->calibration())) {}

Dataset::~Dataset() = default;
Dataset::Dataset(Dataset&&) noexcept = default;
Dataset& Dataset::operator=(Dataset&&) noexcept = default;

size_t Dataset::size() const { return sequence_->size(); }

DatasetFrame Dataset::frame(size_t i) const {
  io::Frame f = sequence_->frame(i);
  return DatasetFrame{f.timestamp, f.left, f.right, f.depth};
}

std::vector<StampedPose> Dataset::ground_truth() const {
  std::vector<StampedPose> out;
  if (!sequence_->ground_truth()) return out;
  const io::Trajectory& t = *sequence_->ground_truth();
  for (size_t i = 0; i < t.size(); ++i)
    out.push_back(StampedPose{t.has_stamps() ? t.stamps[i] : 0.0, t.poses[i].matrix()});
  return out;
}

}  // namespace pllvo
