// pllvo report RUN_DIR: a self-contained HTML page about a `pllvo run` output folder.
#include <cstdio>

#include "commands.h"
#include "pllvo/report/report_page.h"

namespace pllvo::cli {

namespace {

struct ReportArgs {
  std::string run_dir;
  std::string out;
  std::string ground_truth;
};

}  // namespace

void add_report_command(CLI::App& app) {
  auto a = std::make_shared<ReportArgs>();
  auto* cmd = app.add_subcommand("report", "HTML page with trajectory, error, pose and timing plots of a run");
  cmd->add_option("run_dir", a->run_dir, "output folder of `pllvo run --out`")->required();
  cmd->add_option("--out", a->out, "HTML file to write (default: RUN_DIR/report.html)");
  cmd->add_option("--ground-truth", a->ground_truth,
                  "TUM trajectory (T_world_cam0) to compare with (default: the dataset's, found via stats.json)");
  cmd->callback([a] {
    const auto path = report::write_report(a->run_dir, a->out, a->ground_truth);
    std::printf("%s\n", path.string().c_str());
  });
}

}  // namespace pllvo::cli
