// The reference language: how a user states the function to approximate, as a formula or as a
// GLSL or HLSL function from a shader, compiled to a Program (reference/program.hpp). The
// syntax is docs/reference.md's; in short:
//
//   formula:  the approximation's syntax (expr/parse.hpp: + - * / ^, unary minus, pi, calls,
//             select(X cmp Y, a, b)) where `^` takes any exponent (an integer literal stays an
//             exact integer power), plus comparisons < <= > >= == !=, && || !, c ? a : b, and the
//             C math library in double: abs fabs sign sqrt cbrt exp exp2 expm1 log log2 log10
//             log1p sin cos tan asin acos atan atan2 sinh cosh tanh asinh acosh atanh erf erfc
//             floor ceil trunc round pow hypot fmod fmin fmax min max copysign clamp saturate,
//             and the built-in references by name with '_' for '-' (fresnel_exact(cos_theta,
//             ior_n, ior_k), smith_ggx_g1(n_dot_v, alpha), ...; reference/builtin.hpp). The whole
//             text may also be one built-in's name (fresnel-exact or fresnel_exact): it is called
//             with its argument names as variables. Every formula expr/parse.hpp reads means the
//             same here but that one, with pow read as C's pow and select(X >= Y, ...) as a
//             comparison (the same except where X - Y is NaN).
//   shader:   one function of a GLSL or HLSL source: float (or half, double) parameters and
//             return value, local variables, assignments (= += -= *= /=), if / else, return
//             anywhere, ?:, calls of the other functions of the same file (inlined; out and
//             inout arguments), for, while and do loops with a constant trip count (unrolled), the
//             preprocessor (#define with arguments, #if / #ifdef), vectors inside the function
//             (vec3, float3, swizzles, dot, normalize, ...), constant tables and local arrays
//             read at constant places, and the shading languages'
//             built-ins (saturate, mix, lerp, smoothstep, step, clamp, fract, frac, mod, fmod,
//             rsqrt, inversesqrt, rcp, radians, degrees, exp2, log2, pow, ...). Loops without
//             a constant trip count, matrices, textures, #include, recursion and anything else
//             outside this subset is an Error at its line and column (docs/reference.md).
//
//   ReferenceText t;
//   t.formula = "2.5 * sqrt((a - b)^2 + c^2)";
//   t.variables = {"a", "b", "c"};
//   Program p = compile_reference(t);  // outputs: "reference"
//
//   ReferenceText g;
//   g.shader_source = read_file("smith.glsl");  // float G1(float NdotV, float roughness) {...}
//   g.shader_path = "smith.glsl";
//   g.function = "G1";
//   Program q = compile_reference(g);  // inputs NdotV, roughness (the parameters, in order)
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/reference/program.hpp"

namespace shaderfit::reference {

// The name of the output that holds the reference in programs compile_reference makes.
inline constexpr std::string_view kReferenceOutput = "reference";

struct ReferenceText {
  // Either a formula in the reference language ...
  std::string formula;
  // ... or a shader source, the file it came from (for error locations) and its function.
  std::string shader_source;
  std::string shader_path;
  std::string function;
  // The formula's variables, in argument order; empty: every identifier that is not a function,
  // a constant (pi) or a definition, in order of first use (definitions first, then the
  // formula). For a shader function: empty (its parameters, in order), or names that must match
  // them as a set (then in this order).
  std::vector<std::string> variables;
  // Intermediate quantities "name = formula" (reference language), in order, each over the
  // variables and the names defined before it; the reference formula may use them.
  std::vector<std::string> definitions;
  // Names errors are located at: the formula's source ("reference"), the definitions' source
  // ("definitions", with the 1-based position as the line).
  std::string formula_source = "reference";
  std::string definitions_source = "definitions";
};

// The program: inputs the variables; outputs the variables themselves (in order), then each
// definition (named by it), then the reference (kReferenceOutput). Throws shaderfit::Error located
// at the formula's source, line and column (or the shader file's, or the definition's position)
// for: a syntax error, an unknown function or variable (the message lists the known ones), a
// wrong number of arguments, a definition that redefines a name, a shader construct outside the
// subset, a function that is not in the file, recursion, nesting deeper than expr/parse.hpp's
// kMaxFormulaNesting (256 levels of parentheses, calls, signs, ?:, blocks and inlined calls), a
// program of more than 2^18 instructions (a shader's inlined calls). Constant subexpressions are
// folded, and instructions no output uses dropped.
Program compile_reference(const ReferenceText& text);

// A constant expression of the reference language ("pi/2", "85*pi/180", "1e-3"), for domain
// bounds and parameter values. Throws Error located at `source` when the text does not parse,
// names a variable, or is not finite.
double evaluate_constant(std::string_view text, const std::string& source);

// The text of a shader source file (ReferenceText::shader_source from its shader_path). Throws
// shaderfit::Error located at the file when it cannot be opened or read.
std::string read_shader_file(const std::string& path);

// Every function name the formula language knows (for messages and docs), sorted.
std::vector<std::string> reference_function_names();

}  // namespace shaderfit::reference
