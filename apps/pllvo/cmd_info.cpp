// `pllvo info DATASET`: what a dataset folder holds, as pllvo reads it.
#include <cstdio>

#include "commands.h"
#include "pllvo/io/sequence.h"
#include "pllvo/io/sequence_info.h"

namespace pllvo::cli {

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "info", "describe a dataset: format, frames, duration, rate, resolution, cameras, baseline, ground truth");
  struct Args {
    std::string dataset;
    io::SequenceOptions options;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("DATASET", args->dataset, "dataset folder (EuRoC, TUM RGB-D, KITTI odometry or image folder)")
      ->required();
  cmd->add_option("--format", args->options.format, "dataset format (default: detected from the folder)")
      ->check(CLI::IsMember({"auto", "euroc", "tum", "kitti", "folder"}))
      ->capture_default_str();
  cmd->add_option("--camera-yaml", args->options.camera_yaml,
                  "camera YAML for TUM / image folders (default: camera.yaml in the dataset folder)");
  cmd->add_flag("--mono", args->options.mono, "ignore the right camera of a stereo dataset");
  cmd->callback([args] {
    const auto seq = io::open_sequence(args->dataset, args->options);
    std::fputs(io::describe_sequence(*seq).c_str(), stdout);
  });
}

}  // namespace pllvo::cli
