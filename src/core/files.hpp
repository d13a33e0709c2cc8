// Files the library writes into a directory the user names.
#pragma once

#include <string>

namespace shaderfit {

// Creates `directory` and its parents if missing; an Error naming it when that fails.
void make_directories(const std::string& directory);

}  // namespace shaderfit
