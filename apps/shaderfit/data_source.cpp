#include "data_source.hpp"

#include <sstream>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/scene/scene.hpp"

namespace shaderfit::cli {

namespace {

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

std::vector<std::string> input_names(const DataSource& src) { return split_names(src.inputs); }

bool DataSource::given() const {
  return !problem.csv_path.empty() || !problem.dataset.empty() ||
         !problem.reference.formula.empty() || !reference_file.empty();
}

void add_data_options(CLI::App* cmd, DataSource& src, unsigned options) {
  if (options & DataFiles) {
    cmd->add_option("--data", src.problem.csv_path, "CSV file with a header row of column names");
    cmd->add_flag("--drop-missing", src.problem.drop_missing_rows,
                  "drop the CSV rows with an empty or non-number cell in a column of numbers "
                  "(default: an error naming the cell)");
    std::string names;
    for (const auto& n : builtin_dataset_names()) names += (names.empty() ? "" : ", ") + n;
    cmd->add_option("--dataset", src.problem.dataset,
                    "built-in data set instead of --data (" + names + ")");
    auto* seed = cmd->add_option((options & SeedAlias) ? "--data-seed,--seed" : "--data-seed",
                                 src.problem.dataset_seed,
                                 "seed of the built-in data set's generator (default 1)");
    seed->each([&src](const std::string&) { src.seed_given = true; });
  }
  if (options & References) {
    cmd->add_option("--reference", src.problem.reference.formula,
                    "the function to approximate, a formula: acos(x), erf(x / sqrt(2)), "
                    "fresnel_exact(cos_theta, 1.5, 0), ... (docs/reference.md); with --domain");
    cmd->add_option("--reference-file", src.reference_file,
                    "the function to approximate as a GLSL or HLSL function in this file "
                    "(with --function and --domain)");
    cmd->add_option("--function", src.problem.reference.function,
                    "the function of --reference-file to approximate");
    cmd->add_option("--domain", src.problem.domain,
                    "a variable's domain name=lo:hi (repeat per variable; :count[:endpoints] "
                    "for a regular grid)")
        ->allow_extra_args(false);
    cmd->add_option("--define", src.problem.reference.definitions,
                    "an intermediate quantity 'name = formula' the reference may use (repeat)")
        ->allow_extra_args(false);
    cmd->add_option("--samples", src.problem.samples,
                    "points sampled on the domain (default: 10,001 in one variable, about 4,400 "
                    "in two, 9,000 in three or more; docs/reference.md)")
        ->check(CLI::Validator(
            [](const std::string& v) {
              return v.find_first_not_of("0 ") == std::string::npos
                         ? std::string("at least 1 (leave --samples out for the default)")
                         : std::string();
            },
            "N >= 1"));
  }
  if (options & (References | NonFinite))
    cmd->add_flag("--drop-nonfinite", src.problem.drop_nonfinite,
                  "drop the points where the reference is NaN or infinite (default: an error)");
  if (options & Scenes) {
    cmd->add_option("--scene", src.scene,
                    std::string("with --reference, no domain: the picture whose pixels feed it (") +
                        std::string(scene_kind_names()) + "; docs/scenes.md)");
    cmd->add_option("--term", src.term,
                    "with --scene: the factor of the specular term the reference stands for: F, "
                    "V, D or FV (default: a built-in reference's own)");
    cmd->add_option("--scene-size", src.scene_size,
                    "with --scene: pixels per sphere, or the plane's height (default 96)");
    cmd->add_option("--exposure", src.exposure,
                    "with --scene: linear radiance is multiplied by this before the tonemap "
                    "(default 1)");
  }
  if (options & Inputs)
    cmd->add_option("--inputs", src.inputs,
                    "input columns, comma-separated (default: the data set's own, a reference's "
                    "variables, or every CSV column but the target)");
  if (options & Target) {
    cmd->add_option("--target", src.problem.target,
                    "target column (default: the data set's own, the reference, or a CSV's column "
                    "named y or target, else its last)");
  }
}

Problem load_problem(const DataSource& src, ProblemSource* used) {
  ProblemSource s = src.problem;
  // Errors in the formulas point at the flags that gave them.
  s.reference.formula_source = "--reference";
  s.reference.definitions_source = "--define";
  s.inputs = input_names(src);
  if (!src.reference_file.empty()) {
    s.reference.shader_source = reference::read_shader_file(src.reference_file);
    s.reference.shader_path = src.reference_file;
    if (s.reference.function.empty())
      throw Error("name the function of the reference file to approximate",
                  SourceLocation{"--function"});
  } else if (!s.reference.function.empty()) {
    throw Error("--function names a function of --reference-file, which is not given",
                SourceLocation{"--function"});
  }
  if (!src.scene.empty()) {
    SceneSpec spec = scene_spec_from_names(src.scene, src.term);
    spec.size = src.scene_size;
    spec.exposure = src.exposure;
    s.scene = spec;
  } else if (!src.term.empty() || src.scene_size != 0 || src.exposure != 1.0) {
    throw Error("--term, --scene-size and --exposure are for a scene: give --scene",
                SourceLocation{"--scene"});
  }
  Problem p = shaderfit::load_problem(s);
  if (used != nullptr) {
    *used = std::move(s);
    used->inputs = p.inputs;
    used->target = p.target;
    if (p.scene) used->scene = p.scene->spec;  // as rendered: defaults and the term filled in
  }
  return p;
}

std::string problem_notes(const Problem& problem, const std::string& prefix) {
  std::string out;
  for (const std::string& n : problem.notes) out += prefix + n + '\n';
  return out;
}

}  // namespace shaderfit::cli
