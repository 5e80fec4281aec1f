// pllvo: point-line visual odometry. One executable, one subcommand per job.
#include <cstdio>
#include <exception>

#include <spdlog/spdlog.h>

#include "commands.h"
#include "pllvo/common/error.h"

int main(int argc, char** argv) {
  CLI::App app{"pllvo: point-line visual odometry (PLL-VO) with neural points and lines"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pllvo 0.1.0");
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "debug logging");
  app.parse_complete_callback([&] { spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info); });

  pllvo::cli::add_eval_command(app);
  pllvo::cli::add_info_command(app);
  pllvo::cli::add_lines_eval_command(app);
  pllvo::cli::add_run_command(app);
  pllvo::cli::add_synth_command(app);
  pllvo::cli::add_extract_command(app);
  pllvo::cli::add_match_command(app);
  pllvo::cli::add_bench_command(app);
  pllvo::cli::add_report_command(app);
  pllvo::cli::add_demo_command(app);
  pllvo::cli::add_config_command(app);
  pllvo::cli::add_calibrate_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const pllvo::InputError& e) {
    std::fprintf(stderr, "pllvo: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pllvo: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
