// The data options every command shares: a CSV file (--data) or a built-in generator
// (--dataset NAME with --data-seed N), and loading them into a Dataset.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "shaderfit/data/dataset.hpp"

namespace shaderfit::cli {

struct DataSource {
  std::string path;         // --data
  std::string dataset;      // --dataset
  std::uint64_t seed = 1;   // --data-seed (for generators)
  bool seed_given = false;  // set when the user named a seed

  // "data.csv" or "fresnel-seed (seed 1)": for headers of reports.
  [[nodiscard]] std::string describe() const;
};

// Adds --data, --dataset and --data-seed (alias --seed when `seed_alias`) to `cmd`.
void add_data_options(CLI::App* cmd, DataSource& src, bool seed_alias);

// Loads the CSV or runs the generator. Throws shaderfit::Error for a missing or bad file, an
// unknown generator name, or when neither or both of --data and --dataset are given.
Dataset load_data(const DataSource& src);

}  // namespace shaderfit::cli
