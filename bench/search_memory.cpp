// The search's own peak memory on N x k random inputs, measured in-process: the reference the
// Python layer's overhead is measured against (bench/python/overhead.py). Prints one JSON line:
// the resident set before the search (problem built) and its peak during it, in MiB.
//
//   build/release/bench/search_memory 1000000 4
#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "shaderfit/core/random.hpp"
#include "shaderfit/search/search.hpp"

namespace {

// A field of /proc/self/status in MiB ("VmRSS", "VmHWM").
double status_mib(const std::string& field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(field + ":", 0) == 0) return std::stod(line.substr(field.size() + 1)) / 1024.0;
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t rows = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1'000'000;
  const std::size_t inputs = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 4;
  if (rows < 2 || inputs < 3) {
    std::cerr << "usage: search_memory ROWS INPUTS (ROWS >= 2, INPUTS >= 3)\n";
    return 2;
  }
  shaderfit::Rng rng(1);
  shaderfit::SearchProblem problem;
  problem.inputs.assign(inputs, std::vector<double>(rows));
  for (std::size_t i = 0; i < inputs; ++i) {
    problem.input_names.push_back("x" + std::to_string(i));
    for (double& v : problem.inputs[i]) v = shaderfit::uniform01(rng);
  }
  problem.target.resize(rows);
  for (std::size_t r = 0; r < rows; ++r)
    problem.target[r] = problem.inputs[0][r] * problem.inputs[1][r] + problem.inputs[2][r];
  // The options of overhead.py's memory case: the smallest search, so that the peak is the data
  // the search holds rather than its work.
  shaderfit::SearchOptions o;
  o.time_limit_s = 60;
  o.threads = 1;
  o.max_candidates = 200;
  o.evolve = false;
  o.max_enumeration_cost = 1;
  std::ofstream("/proc/self/clear_refs") << "5";  // VmHWM := VmRSS (Linux)
  const double before = status_mib("VmRSS");
  shaderfit::SearchSummary summary;
  shaderfit::run_search(o, problem, &summary);
  std::cout << fmt::format(R"({{"before_mib": {:.2f}, "peak_mib": {:.2f}}})", before,
                           status_mib("VmHWM"))
            << '\n';
  return 0;
}
