// A GLSL or HLSL source as the shader front end sees it (internal to src/reference/): its tokens,
// its functions (found by shape, their bodies read only when the reference calls them), its
// file-scope constants (evaluated when first used), and the other file-scope names, kept so that
// using one is a clear error. The tokens are the preprocessor's
// (language_shader_preprocessor.hpp): conditional groups resolved, macros expanded.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "language_internal.hpp"
#include "language_shader_preprocessor.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

// Throws "<what> are not supported (<shown>); the reference subset is listed in
// docs/reference.md" at the token; `shown` is the token's text unless given.
[[noreturn]] void unsupported(const std::string& what, const std::string& path, const Token& at,
                              std::string_view shown = {});

bool is_vector_type(std::string_view name);       // vec3, float3, mat2, float4x4, ...
bool is_texture_type(std::string_view name);      // sampler2D, Texture2D, SamplerState, ...
bool is_texture_function(std::string_view name);  // texture, texture2D, tex2D, texelFetch, ...

struct FunctionDef {
  std::size_t type = 0;        // the return type's token
  std::size_t name = 0;        // the name's token
  std::size_t open = 0;        // '(' of the parameters
  std::size_t close = 0;       // its ')'
  std::size_t body = 0;        // '{' of the body
  std::size_t end = 0;         // its '}'
  std::size_t parameters = 0;  // how many
};

// A file-scope name: a constant, a constant array, or another declaration (kept for its message).
struct Global {
  enum Kind { Constant, Array, Other } kind = Other;
  std::string what;  // Other: the construct, as errors name it ("uniforms")
  Token at;          // where it is declared
  Shape type;
  // Constant and Array: the tokens of its value, ending with the token after it (',', ';').
  std::span<const Token> value_tokens;
  // Array: the tokens of its size between the brackets and the ']' (only ']': none given).
  std::span<const Token> size_tokens;
  int order = 0;  // declaration order: a value may use the names declared before it
  std::string_view struct_name;  // its (element) type when a struct, read when first used
  std::optional<Value> value;                 // Constant: once evaluated
  std::optional<std::vector<Value>> elements;  // Array: once evaluated
  bool evaluating = false;
};

class ShaderFile {
 public:
  // Reads the source: throws for a preprocessor line outside the subset or in error (see
  // preprocess()), an unclosed brace, or a malformed token.
  ShaderFile(const ReferenceText& text, ProgramBuilder& builder);
  ShaderFile(const ShaderFile&) = delete;
  ShaderFile& operator=(const ShaderFile&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::span<const Token> tokens() const { return tokens_; }
  [[nodiscard]] const std::vector<FunctionDef>& functions() const { return functions_; }
  [[nodiscard]] std::string_view name_of(const FunctionDef& f) const {
    return tokens_[f.name].text;
  }
  [[nodiscard]] std::vector<const FunctionDef*> find(std::string_view name) const;
  // The file-scope name, or nullptr.
  Global* global(std::string_view name);
  // A constant's value, evaluated on first use (at `use`); an error for the rest.
  Value global_value(Global& g, const Token& use);
  // A constant array's elements, evaluated on first use.
  const std::vector<Value>& array_elements(Global& g);
  // The names a message may suggest: the file-scope ones.
  [[nodiscard]] std::vector<std::string> global_names() const;
  // Whether the file declares a struct called `name`.
  [[nodiscard]] bool is_struct(std::string_view name) const;
  // The struct called `name`, its members read on first use; nullptr where there is none, an
  // error at the member for one outside the subset (arrays, matrices, textures, functions).
  const StructType* struct_type(std::string_view name);
  // The type a name stands for: shader_type's scalars, vectors and matrices, and the file's
  // structs (read as struct_type reads them); nullopt for any other name.
  std::optional<Shape> type_named(std::string_view name);

  ProgramBuilder& builder;
  int nesting = 0;                      // shared by every parser of this file
  std::vector<const FunctionDef*> calls;  // the functions being inlined, outermost first

 private:
  void scan();
  void declaration(std::size_t begin, std::size_t end);
  // Where a constant is evaluated: its struct type read, and a loop in its definition an error.
  void begin_evaluating(Global& g);
  // An error unless every component of the value of `g` is a constant.
  void require_constant(const Value& v, const Global& g);
  std::size_t matching(std::size_t open) const;  // the '}' or ')' closing tokens_[open]
  void add(const std::string& name, Global g);
  StructType read_struct(std::size_t open, std::size_t close, const std::string& name);

  // A struct's declaration: its name and the braces of its members, read when first used.
  struct StructDef {
    std::size_t open = 0, close = 0;
    std::optional<StructType> type;
    bool reading = false;
  };

  std::string path_;
  std::vector<Token> tokens_;
  std::vector<FunctionDef> functions_;
  std::map<std::string, Global, std::less<>> globals_;
  std::map<std::string, StructDef, std::less<>> structs_;
};

}  // namespace shaderfit::reference_detail
