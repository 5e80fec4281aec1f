// cpp_minimal DATASET [OUT]: the odometry over a dataset folder, one pose per frame on stdout.
#include <cstdio>

#include <pllvo/api/dataset.h>
#include <pllvo/api/odometry.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DATASET [OUT]\n", argv[0]);
    return 2;
  }
  try {
    const pllvo::Dataset dataset(argv[1]);
    pllvo::Odometry odometry(dataset.calibration());
    for (size_t i = 0; i < dataset.size(); ++i) {
      const pllvo::DatasetFrame frame = dataset.frame(i);
      const pllvo::TrackResult r = odometry.track(frame.timestamp, frame.left, frame.right);
      const auto& T = r.T_world_cam0;
      std::printf("%.6f %s %.4f %.4f %.4f\n", r.timestamp, pllvo::to_string(r.state), T(0, 3), T(1, 3), T(2, 3));
    }
    odometry.finish();
    if (argc > 2) odometry.save(argv[2]);
  } catch (const pllvo::InputError& e) {
    std::fprintf(stderr, "cpp_minimal: %s\n", e.what());
    return 1;
  }
  return 0;
}
