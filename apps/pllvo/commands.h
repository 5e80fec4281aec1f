#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and registers itself on the app.
// The CLI stays thin: parse options, call the library, print.
#include <CLI/CLI.hpp>

namespace pllvo::cli {

void add_eval_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_lines_eval_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_synth_command(CLI::App& app);
void add_extract_command(CLI::App& app);
void add_match_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_config_command(CLI::App& app);
void add_calibrate_command(CLI::App& app);

}  // namespace pllvo::cli
