#pragma once
// The bench result as one text table (stdout), as CSV and as JSON. Rows: each sequence x
// method (median over the repeats, spread = max - min in brackets where it matters), then one
// "mean" row per method over the sequences.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "pllvo/report/bench_runner.h"

namespace pllvo::report {

/// Per method, the mean over sequences of each cell's median (failed cells left out).
std::map<std::string, double> method_means(const BenchResult& result, const std::string& method);

std::string format_bench_table(const BenchResult& result);
std::string format_bench_csv(const BenchResult& result);
nlohmann::json bench_json(const BenchResult& result, const std::vector<BenchMethod>& methods);

/// Writes `text` to `path` through a temporary file and a rename.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace pllvo::report
