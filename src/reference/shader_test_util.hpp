// Helpers of the shader front end's tests: a GLSL or HLSL source compiled, its error, the error's
// "line:column: message". Test code only.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_formula.hpp"

namespace shaderfit::reference::testing {

inline Program shader(const std::string& source, const std::string& function = "f",
                      std::vector<std::string> variables = {},
                      const std::string& path = "test.glsl") {
  ReferenceText t;
  t.shader_source = source;
  t.shader_path = path;
  t.function = function;
  t.variables = std::move(variables);
  return compile_reference(t);
}

// The error compiling `source` throws; a test failure where it compiles.
inline Error shader_error(const std::string& source, const std::string& function = "f") {
  try {
    (void)shader(source, function);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "compiled:\n" << source;
  return Error("");
}

// "line:column: message" of the error, without the path.
inline std::string located(const Error& e) {
  return std::to_string(e.where().line) + ":" + std::to_string(e.where().column) + ": " +
         e.message();
}

// float f(float x) { float y = x; STATEMENTS return y; }, STATEMENTS on line 3 from column 3.
inline std::string function_with(const std::string& statements) {
  return "float f(float x) {\n  float y = x;\n  " + statements + "\n  return y;\n}\n";
}

// What errors about constructs outside the subset end with.
inline const std::string kSubsetNote = "; the reference subset is listed in docs/reference.md";

// The program's reference as a formula of the search's operators, in infix ("(none: why)" when
// it has none).
inline std::string formula_of(const Program& p) {
  const ProgramFormula f = program_formula(p, p.inputs);
  return f.formula ? to_infix(*f.formula) : "(none: " + f.why + ")";
}

// The program's reference at one point.
inline double at(const Program& p, std::vector<double> x) { return p.evaluate(x); }

}  // namespace shaderfit::reference::testing
