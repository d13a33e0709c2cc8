// `shaderfit cost` (in progress).
#include "shaderfit/cli.hpp"

namespace shaderfit::cli {

void register_cost_command(CLI::App& app, Context& /*ctx*/) {
  app.add_subcommand("cost", "(in progress)");
}

}  // namespace shaderfit::cli
