// Helpers for tests of the command-line tool: run it in-process, write scratch files.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"

namespace shaderfit::cli::testing {

struct CliResult {
  int status = -1;
  std::string out, err;
};

inline CliResult run(std::vector<std::string> args) {
  args.insert(args.begin(), "shaderfit");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  CliResult r;
  r.status = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

// A file under the test's scratch folder with the given contents; returns its path. The folder is
// the process's own: ctest runs tests in parallel, each in its own process.
inline std::string scratch_file(const std::string& name, const std::string& contents) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("shaderfit_cli_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary) << contents;
  return path.string();
}

inline int line_count(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// The command with `args` fails as bad input: exit status 2 and one line on stderr holding
// `text`.
inline void expect_bad_input(const std::vector<std::string>& args, const std::string& text) {
  const CliResult r = run(args);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
}

}  // namespace shaderfit::cli::testing
