#include "core/files.hpp"

#include <filesystem>
#include <system_error>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

void make_directories(const std::string& directory) {
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec)
    throw Error("cannot create the directory '" + directory + "': " + ec.message(),
                SourceLocation{directory});
}

}  // namespace shaderfit
