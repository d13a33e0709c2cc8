// Runs every seed input (fuzz/corpus/<target>/) and every input that once crashed a fuzz target
// (fuzz/regressions/<target>/) through the target's entry function in the normal build, so that
// ctest keeps each fixed crash fixed. The entries catch shaderfit::Error themselves; any other
// exception is a failure here, and a crash fails the test binary.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_targets.hpp"

namespace shaderfit::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().filename().string().front() != '.')
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::uint8_t> bytes_of(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Each target compiled into this program (all of them in shaderfit_tests; the sanitizer part of
// scripts/test holds formula, csv, front, reference and shader).
TEST(FuzzInputs, SeedsAndRegressionsRunClean) {
  const fs::path root = fs::path(SHADERFIT_SOURCE_DIR) / "fuzz";
  ASSERT_FALSE(registered_targets().empty());
  for (const Target& t : registered_targets()) {
    const std::vector<fs::path> seeds = inputs_in(root / "corpus" / t.name);
    EXPECT_FALSE(seeds.empty()) << "no seed inputs in fuzz/corpus/" << t.name;
    std::vector<fs::path> all = seeds;
    for (const fs::path& p : inputs_in(root / "regressions" / t.name)) all.push_back(p);
    for (const fs::path& p : all) {
      const std::vector<std::uint8_t> data = bytes_of(p);
      try {
        t.run(data.data(), data.size());
      } catch (const std::exception& e) {
        ADD_FAILURE() << p.lexically_relative(root).string() << ": " << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace shaderfit::fuzz
