// The shader front end: one GLSL or HLSL function compiled to straight-line code. Both branches
// of an `if` are computed and merged with selects; a `return` sets a "returned" flag that keeps
// later code from overriding the result; calls of the file's own functions are inlined.
#include "language_shader.hpp"

#include <algorithm>
#include <limits>

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

namespace {

struct Parameter {
  const Token* name = nullptr;
  Type type = Type::Float;
};

struct Variable {
  std::string_view name;
  Value value;
  bool is_const = false;
  int line = 0;
};

// What the code computed so far: the variables by scope (innermost last), whether the function
// has returned (a 0/1 register) and its result when it has.
struct State {
  std::vector<std::vector<Variable>> scopes;
  Reg returned = 0;
  Reg result = 0;
};

bool is_assignment(const Token& t) {
  return t.is("=") || t.is("+=") || t.is("-=") || t.is("*=") || t.is("/=") || t.is("%=");
}

class FunctionCompiler : public ExpressionParser {
 public:
  FunctionCompiler(ShaderFile& file, const FunctionDef& f)
      : ExpressionParser(file.tokens(), f.body, file.builder, Dialect::Shader, file.path(),
                         file.nesting),
        file_(file),
        f_(f),
        tokens_(file.tokens()) {}

  // The return type (an error at its token for anything but a scalar).
  Type return_type() const {
    const Token& t = tokens_[f_.type];
    if (const auto s = scalar_type(t.text)) return *s;
    if (t.is_word("void"))
      fail("function '" + function_name() + "' returns void: a reference returns a float", t);
    if (is_vector_type(t.text)) unsupported("vector-valued return types", file_.path(), t);
    fail("unknown return type '" + std::string(t.text) + "' (float, half, double, int or bool)", t);
  }

  // The parameters, each `[in] [const] type name [: semantic]`.
  std::vector<Parameter> parameters() const {
    std::vector<Parameter> out;
    if (f_.parameters == 0) return out;
    std::size_t i = f_.open + 1;
    while (true) {
      while (tokens_[i].kind == Token::Ident &&
             (tokens_[i].is_word("in") || tokens_[i].is_word("const") ||
              tokens_[i].is_word("uniform") || tokens_[i].is_word("precise") ||
              tokens_[i].is_word("highp") || tokens_[i].is_word("mediump") ||
              tokens_[i].is_word("lowp")))
        ++i;
      const Token& type = tokens_[i];
      if (type.is_word("out") || type.is_word("inout"))
        unsupported("out and inout parameters", file_.path(), type);
      Parameter p;
      p.type = declared_type(type);
      ++i;
      if (tokens_[i].kind != Token::Ident)
        fail("expected a parameter name, found " + describe(tokens_[i]), tokens_[i]);
      p.name = &tokens_[i++];
      if (tokens_[i].is("[")) unsupported("arrays", file_.path(), tokens_[i]);
      if (tokens_[i].is(":") && tokens_[i + 1].kind == Token::Ident) i += 2;
      if (tokens_[i].is("=")) unsupported("default parameter values", file_.path(), tokens_[i]);
      out.push_back(p);
      if (i == f_.close) return out;
      if (!tokens_[i].is(","))
        fail("expected ',' or ')' after a parameter, found " + describe(tokens_[i]), tokens_[i]);
      ++i;
    }
  }

  // Runs the body with the parameters bound to `args`; returns the result in the return type.
  Value run(std::span<const Value> args, const std::vector<Parameter>& params) {
    const Type result_type = return_type();
    state_.scopes.emplace_back();
    for (std::size_t k = 0; k < params.size(); ++k) {
      state_.scopes.back().push_back({params[k].name->text,
                                      convert(builder(), args[k], params[k].type), false,
                                      params[k].name->line});
    }
    state_.returned = builder().constant(0.0);
    state_.result = builder().constant(0.0);
    result_type_ = result_type;
    seek(f_.body);
    block();
    const Token& close = tokens_[f_.end];
    const auto returned = builder().constant_value(state_.returned);
    if (!returned || *returned == 0.0) {
      fail("function '" + function_name() + "' " +
               (returned ? "ends without returning a value"
                         : "can reach its end without returning a value"),
           close);
    }
    return {state_.result, result_type};
  }

 protected:
  Value name(const Token& t) override {
    if (t.is_word("true") || t.is_word("false"))
      return {builder().constant(t.is_word("true") ? 1.0 : 0.0), Type::Bool};
    if (const Variable* v = find(t.text)) return v->value;
    if (Global* g = file_.global(t.text)) return file_.global_value(*g, t);
    if (!file_.find(t.text).empty())
      fail("function '" + std::string(t.text) + "' needs arguments in parentheses", t);
    if (scalar_type(t.text) || is_vector_type(t.text))
      fail("unexpected type '" + std::string(t.text) + "'", t);
    std::vector<std::string> known = file_.global_names();
    for (const auto& scope : state_.scopes)
      for (const Variable& v : scope) known.emplace_back(v.name);
    const std::string near = closest_name(t.text, known);
    fail("unknown identifier '" + std::string(t.text) + "'" +
             (near.empty() ? "" : " (did you mean " + near + "?)"),
         t);
  }

  void before_call(const Token& t) override {
    if (is_vector_type(t.text)) unsupported("vector and matrix types", file_.path(), t);
    if (is_texture_function(t.text) && file_.find(t.text).empty())
      unsupported("textures", file_.path(), t);
  }

  std::optional<Value> own_call(const Token& t, std::span<const Value> args) override {
    if (const auto type = scalar_type(t.text)) {
      if (args.size() != 1)
        fail(std::string(t.text) + "(...) takes 1 argument, got " + std::to_string(args.size()), t);
      return convert(builder(), args[0], *type);
    }
    const std::vector<const FunctionDef*> defs = file_.find(t.text);
    if (defs.empty()) return std::nullopt;
    const FunctionDef* def = nullptr;
    for (const FunctionDef* d : defs)
      if (d->parameters == args.size()) def = def == nullptr ? d : def;
    if (def == nullptr) {
      fail(std::string(t.text) + " takes " + std::to_string(defs[0]->parameters) +
               (defs[0]->parameters == 1 ? " argument" : " arguments") + ", got " +
               std::to_string(args.size()),
           t);
    }
    auto& calls = file_.calls;
    if (std::find(calls.begin(), calls.end(), t.text) != calls.end()) {
      std::string chain;
      for (auto it = std::find(calls.begin(), calls.end(), t.text); it != calls.end(); ++it)
        chain += std::string(*it) + " -> ";
      fail("recursion is not supported (" + chain + std::string(t.text) +
               "); the reference subset is listed in docs/reference.md",
           t);
    }
    const Nest nest(*this, t);
    FunctionCompiler callee(file_, *def);
    const std::vector<Parameter> params = callee.parameters();
    calls.push_back(t.text);
    const Value v = callee.run(args, params);
    calls.pop_back();
    return v;
  }

  void check_postfix() override {
    const Token& t = peek();
    if (t.is(".")) {
      const Token& member = peek(1);
      const std::string shown = "." + std::string(member.kind == Token::Ident ? member.text : "");
      for (const std::string_view m : {"Sample", "SampleLevel", "SampleGrad", "SampleBias",
                                       "SampleCmp", "SampleCmpLevelZero", "Load", "Gather"})
        if (member.is_word(m)) unsupported("textures", file_.path(), t, shown);
      unsupported("swizzles and members", file_.path(), t, shown);
    }
    if (t.is("[")) unsupported("arrays", file_.path(), t);
    if (t.is("++") || t.is("--")) unsupported("increments inside expressions", file_.path(), t);
  }

  std::string unknown_function(const Token& t) override {
    std::vector<std::string> known = library_function_names(kShaderLibrary);
    for (const FunctionDef& f : file_.functions()) known.emplace_back(file_.name_of(f));
    const std::string near = closest_name(t.text, known);
    return "unknown function '" + std::string(t.text) + "'" +
           (near.empty() ? " (neither a built-in of the subset nor a function of this file)"
                         : " (did you mean " + near + "?)");
  }

 private:
  std::string function_name() const { return std::string(file_.name_of(f_)); }

  // A declared type: scalar, or an error naming the construct.
  Type declared_type(const Token& t) const {
    if (const auto s = scalar_type(t.text)) return *s;
    if (is_vector_type(t.text)) unsupported("vector and matrix types", file_.path(), t);
    if (is_texture_type(t.text)) unsupported("textures", file_.path(), t);
    if (t.is_word("struct")) unsupported("structs", file_.path(), t);
    if (const Global* g = file_.global(t.text); g != nullptr && g->what == "structs")
      unsupported("structs", file_.path(), t);
    fail("unknown type " + describe(t) + " (float, half, double, int or bool)", t);
  }

  Variable* find(std::string_view n) {
    for (auto scope = state_.scopes.rbegin(); scope != state_.scopes.rend(); ++scope)
      for (Variable& v : *scope)
        if (v.name == n) return &v;
    return nullptr;
  }

  // '{' statement* '}'
  void block() {
    const Token& open = next();
    const Nest nest(*this, open);
    state_.scopes.emplace_back();
    while (!peek().is("}")) {
      if (peek().kind == Token::End) fail("'{' is not closed", open);
      statement();
    }
    next();
    state_.scopes.pop_back();
  }

  void statement() {
    const Token& t = peek();
    builder().at(t);
    if (t.kind == Token::Directive)
      fail(
          "preprocessor lines inside functions are not supported; the reference subset is "
          "listed in docs/reference.md",
          t);
    if (t.is("{")) return block();
    if (accept(";")) return;
    if (t.kind == Token::Ident) {
      const std::string_view w = t.text;
      if (w == "if") return if_statement();
      if (w == "return") return return_statement();
      if (w == "for" || w == "while" || w == "do" || w == "break" || w == "continue")
        unsupported("loops", file_.path(), t);
      if (w == "switch" || w == "case" || w == "default")
        unsupported("switch statements", file_.path(), t);
      if (w == "discard") unsupported("discard statements", file_.path(), t);
      if (w == "goto") unsupported("goto statements", file_.path(), t);
      if (w == "struct") unsupported("structs", file_.path(), t);
      if (w == "out" || w == "inout") unsupported("out and inout parameters", file_.path(), t);
      if (is_declaration_start(t)) return declaration();
      if (is_assignment(peek(1)) || peek(1).is("++") || peek(1).is("--")) return assignment();
    }
    if ((t.is("++") || t.is("--")) && peek(1).kind == Token::Ident) return assignment();
    expression();
    expect(";", "after the expression");
  }

  bool is_declaration_start(const Token& t) {
    for (const std::string_view q :
         {"const", "static", "precise", "highp", "mediump", "lowp", "uniform", "in"})
      if (t.is_word(q)) return true;
    if (scalar_type(t.text) || is_vector_type(t.text) || is_texture_type(t.text)) return true;
    // `Name name`: a declaration of a type the subset does not have.
    return peek(1).kind == Token::Ident && find(t.text) == nullptr;
  }

  // [const] type name [= value] (, name [= value])* ;
  void declaration() {
    bool is_const = false;
    while (peek().is_word("const") || peek().is_word("static") || peek().is_word("precise") ||
           peek().is_word("highp") || peek().is_word("mediump") || peek().is_word("lowp")) {
      is_const = next().is_word("const") || is_const;
    }
    if (peek().is_word("uniform") || peek().is_word("in"))
      fail("unexpected '" + std::string(peek().text) + "' in a function body", peek());
    const Type type = declared_type(next());
    while (true) {
      const Token& n = next();
      if (n.kind != Token::Ident) fail("expected a variable name, found " + describe(n), n);
      if (peek().is("[")) unsupported("arrays", file_.path(), peek());
      for (const Variable& v : state_.scopes.back())
        if (v.name == n.text)
          fail("'" + std::string(n.text) + "' is already declared in this scope (line " +
                   std::to_string(v.line) + ")",
               n);
      Value v{builder().constant(std::numeric_limits<double>::quiet_NaN()), type};
      if (accept("=")) {
        v = convert(builder(), expression(), type);
      } else if (is_const) {
        fail("the constant '" + std::string(n.text) + "' needs a value", n);
      }
      state_.scopes.back().push_back({n.text, v, is_const, n.line});
      if (accept(",")) continue;
      expect(";", "after the declaration");
      return;
    }
  }

  // name op value ; | name++ ; | ++name ;
  void assignment() {
    const bool prefix = peek().is("++") || peek().is("--");
    const Token* op = prefix ? &next() : nullptr;
    const Token& n = next();
    if (!prefix) op = &next();
    Variable* v = find(n.text);
    if (v == nullptr) {
      if (const Global* g = file_.global(n.text); g != nullptr && g->kind == Global::Other)
        unsupported(g->what, file_.path(), n);
      if (file_.global(n.text) != nullptr)
        fail("cannot assign to the file-scope constant '" + std::string(n.text) + "'", n);
      fail("unknown variable '" + std::string(n.text) + "'", n);
    }
    if (v->is_const) fail("cannot assign to the constant '" + std::string(n.text) + "'", n);
    Value value;
    if (op->is("++") || op->is("--")) {
      value =
          apply_binary(op->is("++") ? "+" : "-", v->value, {builder().constant(1.0), Type::Int});
    } else {
      const Value rhs = expression();
      value = op->is("=") ? rhs : apply_binary(op->text.substr(0, 1), v->value, rhs);
    }
    v->value = convert(builder(), value, v->value.type);
    expect(";", "after the assignment");
  }

  // if ( condition ) statement [else statement]: both branches run, their variables merge by
  // the condition.
  void if_statement() {
    const Token& t = next();
    const Nest nest(*this, t);
    expect("(", "after 'if'");
    const Reg c = expression().reg;
    expect(")", "after the condition of 'if'");
    const State before = state_;
    branch();
    State then = std::move(state_);
    state_ = before;
    if (peek().is_word("else")) {
      next();
      branch();
    }
    ProgramBuilder& b = builder();
    for (std::size_t s = 0; s < state_.scopes.size(); ++s) {
      for (std::size_t k = 0; k < state_.scopes[s].size(); ++k) {
        Value& v = state_.scopes[s][k].value;
        v.reg = b.emit(ProgramOp::Select, c, then.scopes[s][k].value.reg, v.reg);
      }
    }
    state_.result = b.emit(ProgramOp::Select, c, then.result, state_.result);
    state_.returned = b.emit(ProgramOp::Select, c, then.returned, state_.returned);
  }

  // A branch's statement in a scope of its own.
  void branch() {
    state_.scopes.emplace_back();
    statement();
    state_.scopes.pop_back();
  }

  // return value ; : the result, unless the function has returned already.
  void return_statement() {
    const Token& t = next();
    if (peek().is(";")) fail("return needs a value in function '" + function_name() + "'", t);
    const Value v = convert(builder(), expression(), result_type_);
    expect(";", "after the returned value");
    state_.result = builder().emit(ProgramOp::Select, state_.returned, state_.result, v.reg);
    state_.returned = builder().constant(1.0);
  }

  ShaderFile& file_;
  const FunctionDef& f_;
  std::span<const Token> tokens_;
  State state_;
  Type result_type_ = Type::Float;
};

}  // namespace

ShaderFunction compile_shader_function(const ReferenceText& text, ProgramBuilder& b,
                                       Program& program) {
  ShaderFile file(text, b);
  const SourceLocation where{file.path()};
  std::vector<std::string> names;
  for (const FunctionDef& f : file.functions()) names.emplace_back(file.name_of(f));
  std::string wanted = text.function;
  if (wanted.empty()) {
    if (file.functions().size() != 1) {
      throw Error("name the function to approximate (the functions of " + file.path() + ": " +
                      (names.empty() ? std::string("none") : join_names(names)) + ")",
                  where);
    }
    wanted = names[0];
  }
  const std::vector<const FunctionDef*> defs = file.find(wanted);
  if (defs.empty()) {
    throw Error("function '" + wanted + "' is not in " + file.path() + " (its functions: " +
                    (names.empty() ? std::string("none") : join_names(names)) + ")",
                where);
  }
  const FunctionDef& def = *defs.back();
  const Token& at = file.tokens()[def.name];
  if (defs.size() > 1) {
    fail_at("function '" + wanted + "' is defined " + std::to_string(defs.size()) +
                " times: the reference must be one function",
            file.path(), at);
  }
  FunctionCompiler compiler(file, def);
  (void)compiler.return_type();
  const std::vector<Parameter> params = compiler.parameters();
  std::vector<std::string> param_names;
  for (const Parameter& p : params) {
    if (p.type != Type::Float) {
      fail_at("parameter '" + std::string(p.name->text) +
                  "' is not a float: the function's parameters are the reference's variables "
                  "(float, half or double)",
              file.path(), *p.name);
    }
    param_names.emplace_back(p.name->text);
  }
  // The inputs: the parameters, in the order of text.variables when given.
  std::vector<std::string> order = text.variables.empty() ? param_names : text.variables;
  std::vector<std::string> sorted_order = order, sorted_params = param_names;
  std::sort(sorted_order.begin(), sorted_order.end());
  std::sort(sorted_params.begin(), sorted_params.end());
  if (sorted_order != sorted_params) {
    fail_at("the variables (" + join_names(order) + ") are not the parameters of " + wanted + " (" +
                join_names(param_names) + ")",
            file.path(), at);
  }
  ShaderFunction out;
  out.name = wanted;
  for (std::size_t i = 0; i < order.size(); ++i) {
    program.inputs.push_back(order[i]);
    out.inputs.push_back(b.input(static_cast<int>(i)));
  }
  std::vector<Value> args;
  for (const std::string& p : param_names) {
    const auto k =
        static_cast<std::size_t>(std::find(order.begin(), order.end(), p) - order.begin());
    args.push_back({out.inputs[k], Type::Float});
  }
  file.calls.push_back(file.name_of(def));
  out.result = compiler.run(args, params).reg;
  return out;
}

}  // namespace shaderfit::reference_detail
