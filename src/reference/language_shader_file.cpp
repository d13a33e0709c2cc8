// Reading a shader source's file scope (language_shader.hpp): the preprocessed tokens, functions,
// constants, and the declarations the subset leaves out.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "language_shader.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

namespace {

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

bool is_qualifier(std::string_view w) {
  for (const std::string_view q :
       {"const",   "static",    "uniform",  "extern",   "in",          "out",           "inout",
        "varying", "attribute", "buffer",   "shared",   "groupshared", "highp",         "mediump",
        "lowp",    "precise",   "volatile", "flat",     "smooth",      "noperspective", "centroid",
        "inline",  "layout",    "readonly", "writeonly"})
    if (w == q) return true;
  return false;
}

// The construct a file-scope declaration with these qualifiers and type is, as errors name it.
std::string construct(const std::vector<std::string_view>& qualifiers, std::string_view type,
                      bool array) {
  auto has = [&](std::string_view q) {
    return std::find(qualifiers.begin(), qualifiers.end(), q) != qualifiers.end();
  };
  if (has("uniform")) return "uniforms";
  if (has("in") || has("out") || has("varying") || has("attribute") || has("buffer"))
    return "shader inputs and outputs";
  if (is_texture_type(type)) return "textures";
  if (is_vector_type(type) && !shader_type(type)) return "matrix types";
  if (array) return "arrays";
  if (!shader_type(type)) return "types other than float, half, double, int and bool and their vectors";
  return "global variables";
}

}  // namespace

void unsupported(const std::string& what, const std::string& path, const Token& at,
                 std::string_view shown) {
  fail_at(what + " are not supported (" + std::string(shown.empty() ? at.text : shown) +
              "); the reference subset is listed in docs/reference.md",
          path, at);
}

bool is_vector_type(std::string_view name) {
  for (const std::string_view p : {"vec", "ivec", "uvec", "bvec", "dvec"}) {
    if (starts_with(name, p) && name.size() == p.size() + 1 && name.back() >= '2' &&
        name.back() <= '4')
      return true;
  }
  for (const std::string_view p : {"mat", "dmat"}) {
    if (!starts_with(name, p)) continue;
    const std::string_view rest = name.substr(p.size());
    if (rest.size() == 1 && rest[0] >= '2' && rest[0] <= '4') return true;
    if (rest.size() == 3 && rest[1] == 'x') return true;
  }
  for (const std::string_view p : {"float", "half", "double", "int", "uint", "bool", "min16float",
                                   "min10float", "min16int", "min12int", "min16uint", "dword"}) {
    if (!starts_with(name, p) || name.size() == p.size()) continue;
    const std::string_view rest = name.substr(p.size());
    const bool n = rest[0] >= '1' && rest[0] <= '4';
    if (n && rest.size() == 1) return true;
    if (n && rest.size() == 3 && rest[1] == 'x' && rest[2] >= '1' && rest[2] <= '4') return true;
  }
  return name == "vector" || name == "matrix";
}

bool is_texture_type(std::string_view name) {
  for (const std::string_view p :
       {"sampler", "isampler", "usampler", "Sampler", "Texture", "RWTexture", "image", "iimage",
        "uimage", "Buffer", "RWBuffer", "StructuredBuffer", "RWStructuredBuffer",
        "ByteAddressBuffer", "texture1D", "texture2D", "texture3D", "textureCube"})
    if (starts_with(name, p)) return true;
  return false;
}

bool is_texture_function(std::string_view name) {
  if (starts_with(name, "texture") || starts_with(name, "texel")) return true;
  // HLSL's tex1D, tex2D, tex3D, texCUBE and their variants.
  return starts_with(name, "tex") && name.size() > 3 &&
         (std::isdigit(static_cast<unsigned char>(name[3])) != 0 ||
          std::isupper(static_cast<unsigned char>(name[3])) != 0);
}

ShaderFile::ShaderFile(const ReferenceText& text, ProgramBuilder& b)
    : builder(b), path_(text.shader_path.empty() ? "shader" : text.shader_path) {
  PreprocessedSource source = preprocess(text.shader_source, path_);
  tokens_ = std::move(source.tokens);
  scan();
}

std::vector<const FunctionDef*> ShaderFile::find(std::string_view name) const {
  std::vector<const FunctionDef*> out;
  for (const FunctionDef& f : functions_)
    if (name_of(f) == name) out.push_back(&f);
  return out;
}

Global* ShaderFile::global(std::string_view name) {
  const auto it = globals_.find(name);
  return it == globals_.end() ? nullptr : &it->second;
}

std::vector<std::string> ShaderFile::global_names() const {
  std::vector<std::string> out;
  for (const auto& [name, g] : globals_)
    if (name.find('[') == std::string::npos) out.push_back(name);
  return out;
}

void ShaderFile::add(const std::string& name, Global g) {
  g.order = static_cast<int>(globals_.size());
  globals_.insert_or_assign(name, std::move(g));
}

std::size_t ShaderFile::matching(std::size_t open) const {
  const bool brace = tokens_[open].is("{");
  const std::string_view o = brace ? "{" : "(", c = brace ? "}" : ")";
  int depth = 0;
  for (std::size_t i = open; i < tokens_.size(); ++i) {
    if (tokens_[i].is(o)) ++depth;
    if (tokens_[i].is(c) && --depth == 0) return i;
    if (tokens_[i].kind == Token::End) break;
  }
  fail_at("'" + std::string(o) + "' is not closed", path_, tokens_[open]);
}

// File scope: functions (`type name(parameters) [: semantic] { body }`) and declarations up to
// their ';' (structs, cbuffers and interface blocks with their braces), in order, so that a
// constant's value may use the names declared before it.
void ShaderFile::scan() {
  std::size_t i = 0;
  while (true) {
    if (tokens_[i].kind == Token::End) break;
    const Token& t = tokens_[i];
    if (t.is(";")) {
      ++i;
      continue;
    }
    const std::size_t begin = i;
    const bool block_only = t.is_word("cbuffer") || t.is_word("tbuffer");
    // A '(' after a name before any '=': a function, its prototype, or a layout qualifier.
    bool function_shape = false, saw_equals = false;  // '=' or ':' (a semantic, a register)
    int bracket = 0;
    bool done = false;
    while (!done) {
      const Token& u = tokens_[i];
      if (u.kind == Token::End) fail_at("expected ';' to end this declaration", path_, t);
      if (u.is("[")) ++bracket;
      if (u.is("]")) --bracket;
      if ((u.is("=") || u.is(":")) && bracket == 0) saw_equals = true;
      if (u.is("(") && bracket == 0) {
        const std::size_t close = matching(i);
        if (!function_shape && !saw_equals && !block_only && i > begin &&
            tokens_[i - 1].kind == Token::Ident) {
          function_shape = true;
          // A function: its ')' followed by '{', or by an HLSL semantic and '{'.
          std::size_t body = close + 1;
          if (tokens_[body].is(":") && tokens_[body + 1].kind == Token::Ident) body += 2;
          if (tokens_[body].is("{")) {
            FunctionDef f;
            f.name = i - 1;
            f.type = i >= begin + 2 ? i - 2 : i - 1;
            f.open = i;
            f.close = close;
            f.body = body;
            f.end = matching(body);
            if (close > i + 1 && !(close == i + 2 && tokens_[i + 1].is_word("void"))) {
              f.parameters = 1;
              int depth = 0;
              for (std::size_t k = i + 1; k < close; ++k) {
                if (tokens_[k].is("(") || tokens_[k].is("[")) ++depth;
                if (tokens_[k].is(")") || tokens_[k].is("]")) --depth;
                if (depth == 0 && tokens_[k].is(",")) ++f.parameters;
              }
            }
            functions_.push_back(f);
            i = f.end + 1;
            break;
          }
        }
        i = close + 1;
        continue;
      }
      if (u.is("{")) {
        i = matching(i) + 1;
        if (block_only) done = true;
        continue;
      }
      if (u.is(";")) {
        if (!function_shape) {
          declaration(begin, i);
        }
        done = true;
      }
      ++i;
    }
  }
}

// A file-scope declaration, tokens [begin, end) before its ';'.
void ShaderFile::declaration(std::size_t begin, std::size_t end) {
  std::size_t i = begin;
  if (tokens_[i].is_word("struct")) {
    // struct Name { members } [variables];
    if (tokens_[i + 1].kind == Token::Ident && tokens_[i + 2].is("{")) {
      StructDef def;
      def.open = i + 2;
      def.close = matching(def.open);
      structs_.insert_or_assign(std::string(tokens_[i + 1].text), std::move(def));
      for (std::size_t k = matching(i + 2) + 1; k < end; ++k)
        if (tokens_[k].kind == Token::Ident)
          add(std::string(tokens_[k].text), Global{Global::Other, "global variables", tokens_[k]});
    }
    return;
  }
  if (tokens_[i].is_word("precision")) return;
  std::vector<std::string_view> qualifiers;
  while (i < end && tokens_[i].kind == Token::Ident && is_qualifier(tokens_[i].text)) {
    qualifiers.push_back(tokens_[i].text);
    ++i;
  }
  if (i + 1 >= end || tokens_[i].kind != Token::Ident) return;  // precision statements and such
  const Token& type = tokens_[i++];
  const bool is_const =
      std::find(qualifiers.begin(), qualifiers.end(), "const") != qualifiers.end();
  // Declarators: name ['[' ... ']'] ['=' value] separated by ','.
  while (i < end) {
    if (tokens_[i].kind != Token::Ident) return;
    const Token& name = tokens_[i++];
    const bool array = i < end && tokens_[i].is("[");
    std::size_t value = 0, value_end = i;
    int depth = 0;
    for (; value_end < end; ++value_end) {
      const Token& u = tokens_[value_end];
      if (u.is("(") || u.is("[") || u.is("{")) ++depth;
      if (u.is(")") || u.is("]") || u.is("}")) --depth;
      if (depth == 0 && u.is("=") && value == 0) value = value_end + 1;
      if (depth == 0 && u.is(",")) break;
    }
    const std::optional<Shape> shape = shader_type(type.text);
    const bool record = is_struct(type.text);
    const std::string what = construct(qualifiers, record ? "float" : type.text, array);
    const bool constant = is_const && value != 0 && (shape || record) &&
                          construct(qualifiers, "float", false) == "global variables";
    std::size_t size_end = i;  // an array's ']'
    if (array) {
      size_end = i;
      for (int d = 0; !(d == 1 && tokens_[size_end].is("]")); ++size_end) {
        if (tokens_[size_end].is("[")) ++d;
        if (tokens_[size_end].is("]")) --d;
      }
    }
    if (constant && !(array && tokens_[size_end + 1].is("["))) {
      // A constant, or a constant array (Unity's `static const ParamsLogC LogC = { ... };`,
      // `static const float3 k[2] = { ... };`).
      Global g{array ? Global::Array : Global::Constant, "", name,
               record ? Shape{Type::Float, 0} : *shape};
      if (record) g.struct_name = type.text;
      g.value_tokens = std::span<const Token>(tokens_).subspan(value, value_end + 1 - value);
      if (array) g.size_tokens = std::span<const Token>(tokens_).subspan(i + 1, size_end - i);
      add(std::string(name.text), std::move(g));
    } else {
      add(std::string(name.text),
          Global{Global::Other, array && constant ? "arrays of arrays" : what, name});
    }
    i = value_end + 1;
  }
}

bool ShaderFile::is_struct(std::string_view name) const {
  return structs_.find(name) != structs_.end();
}

std::optional<Shape> ShaderFile::type_named(std::string_view name) {
  if (const std::optional<Shape> s = shader_type(name)) return s;
  if (const StructType* t = struct_type(name)) return Shape{Type::Float, 0, t};
  return std::nullopt;
}

const StructType* ShaderFile::struct_type(std::string_view name) {
  const auto it = structs_.find(name);
  if (it == structs_.end()) return nullptr;
  StructDef& def = it->second;
  if (!def.type) {
    if (def.reading) {
      fail_at("struct '" + it->first + "' contains itself", path_, tokens_[def.open - 1]);
    }
    def.reading = true;
    def.type = read_struct(def.open, def.close, it->first);
    def.reading = false;
  }
  return &*def.type;
}

// A struct's members, tokens (open, close): `[qualifiers] type name [: semantic] (, name)* ;`.
StructType ShaderFile::read_struct(std::size_t open, std::size_t close, const std::string& name) {
  StructType out;
  out.name = name;
  std::size_t i = open + 1;
  while (i < close) {
    if (tokens_[i].is(";")) {
      ++i;
      continue;
    }
    // Interpolation and precision qualifiers change no value.
    while (tokens_[i].kind == Token::Ident &&
           (is_qualifier(tokens_[i].text) || tokens_[i].is_word("linear") ||
            tokens_[i].is_word("nointerpolation") || tokens_[i].is_word("sample")))
      ++i;
    const Token& type = tokens_[i];
    Shape shape;
    if (const std::optional<Shape> s = type_named(type.text)) {
      shape = *s;
    } else if (type.is_word("struct")) {
      unsupported("structs declared inside structs", path_, type);
    } else {
      const std::string what = construct({}, type.text, false);
      if (what != "global variables") unsupported(what, path_, type);
      fail_at("unknown type " + describe(type, Dialect::Shader) + " of a member of '" + name + "'",
              path_, type);
    }
    ++i;
    while (true) {
      const Token& member = tokens_[i];
      if (member.kind != Token::Ident) {
        fail_at("expected a member name in struct '" + name + "', found " +
                    describe(member, Dialect::Shader),
                path_, member);
      }
      ++i;
      if (tokens_[i].is("(")) unsupported("functions inside structs", path_, member);
      if (tokens_[i].is("["))
        unsupported("arrays inside structs", path_, member, std::string(member.text) + "[]");
      if (out.member(member.text) >= 0) {
        fail_at("struct '" + name + "' has two members called '" + std::string(member.text) + "'",
                path_, member);
      }
      out.members.push_back({std::string(member.text), shape});
      if (tokens_[i].is(":") && tokens_[i + 1].kind == Token::Ident) i += 2;  // a semantic
      if (tokens_[i].is(",")) {
        ++i;
        continue;
      }
      if (!tokens_[i].is(";")) {
        fail_at("expected ';' after a member of struct '" + name + "', found " +
                    describe(tokens_[i], Dialect::Shader),
                path_, tokens_[i]);
      }
      ++i;
      break;
    }
  }
  if (out.members.empty()) fail_at("struct '" + name + "' has no members", path_, tokens_[open]);
  return out;
}

namespace {

// A constant's value: names resolve to the constants declared before it.
class ConstantParser : public ExpressionParser {
 public:
  ConstantParser(ShaderFile& file, const Global& g)
      : ExpressionParser(g.value_tokens, 0, file.builder, Dialect::Shader, file.path(),
                         file.nesting),
        file_(file),
        global_(g) {}

 protected:
  Value name(const Token& t) override {
    if (t.is_word("true") || t.is_word("false"))
      return {builder().constant(t.is_word("true") ? 1.0 : 0.0), Type::Bool};
    Global* g = file_.global(t.text);
    if (g == nullptr || g->order >= global_.order) {
      fail("unknown identifier '" + std::string(t.text) + "' in the value of '" +
               std::string(global_.at.text) + "' (it may use the constants declared before it)",
           t);
    }
    return file_.global_value(*g, t);
  }

  // A struct's constructor (GLSL's `const Params P = Params(...)`).
  Value call(const Token& t) override {
    if (file_.is_struct(t.text)) return construct_struct(t, *file_.struct_type(t.text));
    return ExpressionParser::call(t);
  }

 private:
  ShaderFile& file_;
  const Global& global_;
};

}  // namespace

void ShaderFile::begin_evaluating(Global& g) {
  if (g.evaluating)
    fail_at("'" + std::string(g.at.text) + "' is defined in terms of itself", path_, g.at);
  g.evaluating = true;
  if (!g.struct_name.empty()) g.type = *type_named(g.struct_name);
}

void ShaderFile::require_constant(const Value& v, const Global& g) {
  std::vector<Value> parts;
  scalar_components(v, parts);
  for (const Value& part : parts) {
    if (!builder.constant_value(part.reg)) {
      fail_at("the value of '" + std::string(g.at.text) + "' is not a constant expression", path_,
              g.at);
    }
  }
}

Value ShaderFile::global_value(Global& g, const Token& use) {
  if (g.kind == Global::Other) unsupported(g.what, path_, use);
  if (g.kind == Global::Array) {
    fail_at("the array '" + std::string(g.at.text) + "' is used whole: only its elements (" +
                std::string(g.at.text) + "[k]) are values",
            path_, use);
  }
  if (g.value) return *g.value;
  begin_evaluating(g);
  ConstantParser parser(*this, g);
  Value v = g.value_tokens[0].is("{")
                ? parser.initializer_list(g.type, "'" + std::string(g.at.text) + "'")
                : parser.expression();
  if (parser.position() + 1 != g.value_tokens.size()) {
    parser.fail("unexpected " + describe(parser.peek(), Dialect::Shader) + " in the value of '" +
                    std::string(g.at.text) + "'",
                parser.peek());
  }
  require_constant(v, g);
  const std::optional<Value> c = convert(builder, v, g.type);
  if (!c) {
    fail_at("the value of '" + std::string(g.at.text) + "' is a " + shape_name(v.shape()) +
                ", not a " + shape_name(g.type),
            path_, g.at);
  }
  g.evaluating = false;
  g.value = *c;
  return *g.value;
}

const std::vector<Value>& ShaderFile::array_elements(Global& g) {
  if (g.elements) return *g.elements;
  begin_evaluating(g);
  int size = -1;
  if (g.size_tokens.size() > 1) {
    Global count = g;
    count.value_tokens = g.size_tokens;
    ConstantParser parser(*this, count);
    const Token& at = parser.peek();
    const Value k = parser.expression();
    const auto c = k.width == 1 ? builder.constant_value(k.reg) : std::nullopt;
    if (!c || *c != std::trunc(*c) || *c < 1 || *c > 4096 ||
        parser.position() + 1 != g.size_tokens.size()) {
      fail_at("the size of the array '" + std::string(g.at.text) +
                  "' must be a constant from 1 to 4096",
              path_, at);
    }
    size = static_cast<int>(*c);
  }
  ConstantParser parser(*this, g);
  std::vector<Value> elements = parser.array_values(g.type, size, g.at);
  if (parser.position() + 1 != g.value_tokens.size()) {
    parser.fail("unexpected " + describe(parser.peek(), Dialect::Shader) + " in the values of '" +
                    std::string(g.at.text) + "'",
                parser.peek());
  }
  for (const Value& v : elements) require_constant(v, g);
  g.evaluating = false;
  g.elements = std::move(elements);
  return *g.elements;
}

}  // namespace shaderfit::reference_detail
