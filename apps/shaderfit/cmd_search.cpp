// `shaderfit search` (in progress).
#include "shaderfit/cli.hpp"

namespace shaderfit::cli {

void register_search_command(CLI::App& app, Context& /*ctx*/) {
  app.add_subcommand("search", "(in progress)");
}

}  // namespace shaderfit::cli
