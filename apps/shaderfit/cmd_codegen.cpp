// `shaderfit codegen` (in progress).
#include "shaderfit/cli.hpp"

namespace shaderfit::cli {

void register_codegen_command(CLI::App& app, Context& /*ctx*/) {
  app.add_subcommand("codegen", "(in progress)");
}

}  // namespace shaderfit::cli
