#include "data_source.hpp"

#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/csv.hpp"
#include "shaderfit/data/fresnel_seed.hpp"

namespace shaderfit::cli {

std::string DataSource::describe() const {
  if (!path.empty()) return path;
  return dataset + " (seed " + std::to_string(seed) + ")";
}

void add_data_options(CLI::App* cmd, DataSource& src, bool seed_alias) {
  cmd->add_option("--data", src.path, "CSV file with a header row of column names");
  std::string names;
  for (const auto& n : builtin_dataset_names()) names += (names.empty() ? "" : ", ") + n;
  cmd->add_option("--dataset", src.dataset, "built-in data set instead of --data (" + names + ")");
  auto* seed = cmd->add_option(seed_alias ? "--data-seed,--seed" : "--data-seed", src.seed,
                               "seed of the built-in data set's generator (default 1)");
  seed->each([&src](const std::string&) { src.seed_given = true; });
}

Dataset load_data(const DataSource& src) {
  if (src.path.empty() == src.dataset.empty()) {
    throw Error(src.path.empty() ? "no data: give --data FILE.csv or --dataset NAME"
                                 : "give either --data or --dataset, not both",
                SourceLocation{src.path.empty() ? "--data" : "--dataset"});
  }
  if (!src.path.empty()) return read_csv(src.path);
  Rng rng(src.seed);
  std::optional<Dataset> d = make_builtin_dataset(src.dataset, rng);
  if (!d) {
    std::string names;
    for (const auto& n : builtin_dataset_names()) names += (names.empty() ? "" : ", ") + n;
    throw Error("unknown data set '" + src.dataset + "' (built-in: " + names + ")",
                SourceLocation{"--dataset"});
  }
  return std::move(*d);
}

}  // namespace shaderfit::cli
