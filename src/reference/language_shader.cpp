// The shader front end: one GLSL or HLSL function compiled to straight-line code. Both branches
// of an `if` are computed and merged with selects; a `return` sets a "returned" flag that keeps
// later code from overriding the result (and the out parameters' values); calls of the file's own
// functions are inlined, their out and inout arguments written back to the caller's variables;
// `for`, `while` and `do` loops with a constant trip count are unrolled, and `break` and
// `continue` set a "skipped" flag that keeps the rest of the iteration from assigning on the paths
// that took them. A variable declared without a value holds none until assigned (see Defined);
// HLSL's attributes before statements are skipped.
#include "language_shader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <utility>

#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::reference_detail {

using namespace shaderfit::reference;  // the area's public names

namespace {

// Iterations of one unrolled `for` loop at most.
constexpr int kMaxLoopIterations = 64;

enum class Mode { In, Out, InOut };

struct Parameter {
  const Token* name = nullptr;
  const Token* qualifier = nullptr;  // `out`, `inout`, or the `in` of HLSL's `in out`
  Shape type;
  Mode mode = Mode::In;
  std::size_t default_value = 0;  // HLSL's `= value`: where the value's tokens start (0: none)
};

std::string mode_name(Mode m) { return m == Mode::Out ? "out" : "inout"; }

// On which of the paths that have not returned a variable holds a value: a set of these bits.
// Reading one that holds a value on none of them is an error; where only some paths gave it a
// value, theirs stands for it on the others too (reading an unassigned variable is undefined in
// GLSL and HLSL, so any value is allowed there), so no select keeps an undefined operand.
using Defined = std::uint8_t;
constexpr Defined kAssigned = 1;
constexpr Defined kUnassigned = 2;

// A value with the paths on which it is defined.
struct Held {
  Value value;
  Defined defined = kAssigned;
};

// A local array is its elements, each a variable of its own named "name[k]" (so that branches
// and loops merge them as any other), after a variable that stands for the array as a whole.
struct Variable {
  std::string_view name;
  Value value;
  bool is_const = false;
  int line = 0;
  Defined defined = kAssigned;
  bool out = false;     // an out parameter (for messages)
  int array_size = 0;   // an array's elements follow it in its scope
};

// A return taken: on the paths where `taken` (a 0/1 register) holds and no earlier return was
// taken, the function's result is `value`.
struct Return {
  Reg taken = 0;
  Value value;
};

// What the code computed so far: the variables by scope (innermost last), whether the function
// has returned (a 0/1 register), the returns taken in order (the result is the first whose
// `taken` holds: select(t1, v1, select(t2, v2, ...)), a chain for guard clauses where a select
// per return over the result so far would repeat it in the formula), its out parameters'
// values where it has returned, and inside a loop which paths have left the iteration (0/1
// registers): `broken` by break, `continued` by continue, `skipped` either of them or a path the
// loop's start skipped.
struct State {
  std::vector<std::vector<Variable>> scopes;
  Reg returned = 0;
  std::vector<Return> returns;
  std::vector<Held> outs;  // by parameter
  Reg skipped = 0;
  Reg broken = 0;
  Reg continued = 0;
};

// A variable's place: its scope and its index there.
struct Slot {
  std::size_t scope = 0;
  std::size_t index = 0;
};

// What an inlined call gives back: its result (0 for void), and by parameter the value an out or
// inout one writes back.
struct CallResult {
  Value result;
  std::vector<Held> outs;
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

  // The reference's return type (an error at its token for anything but a scalar).
  Type return_type() const {
    const Token& t = tokens_[f_.type];
    if (t.is_word("void"))
      fail("function '" + function_name() + "' returns void: a reference returns a float", t);
    const Shape s = *result_type();
    if (s.record != nullptr) {
      fail("function '" + function_name() + "' returns a struct (" + s.record->name +
               "): a reference returns a float (return one member, or call it from a function "
               "that does)",
           t);
    }
    if (s.width != 1) {
      fail("function '" + function_name() + "' returns a " + std::string(t.text) +
               ": a reference returns a float (return one component, or call it from a function "
               "that does)",
           t);
    }
    return s.type;
  }

  // A helper's return type: a scalar, a vector or a struct, or nullopt for void.
  std::optional<Shape> result_type() const {
    const Token& t = tokens_[f_.type];
    if (const auto s = file_.type_named(t.text)) return *s;
    if (t.is_word("void")) return std::nullopt;
    if (is_vector_type(t.text)) unsupported("matrix types", file_.path(), t);
    fail("unknown return type '" + std::string(t.text) +
             "' (float, half, double, int or bool, or their vectors)",
         t);
  }

  // The parameters, each `[in | out | inout | in out] [const] type name [: semantic]`.
  std::vector<Parameter> parameters() const {
    std::vector<Parameter> out;
    if (f_.parameters == 0) return out;
    std::size_t i = f_.open + 1;
    while (true) {
      Parameter p;
      const Token* in = nullptr;
      bool writes = false, reads = false;
      while (tokens_[i].kind == Token::Ident) {
        const Token& q = tokens_[i];
        if (q.is_word("out") || q.is_word("inout")) {
          if (p.qualifier == nullptr) p.qualifier = in != nullptr ? in : &q;
          writes = true;
          reads = reads || q.is_word("inout");
        } else if (q.is_word("in")) {
          if (in == nullptr) in = &q;
          reads = true;
        } else if (!(q.is_word("const") || q.is_word("uniform") || q.is_word("precise") ||
                     q.is_word("highp") || q.is_word("mediump") || q.is_word("lowp"))) {
          break;
        }
        ++i;
      }
      if (writes) p.mode = reads ? Mode::InOut : Mode::Out;
      p.type = declared_type(tokens_[i]);
      ++i;
      if (tokens_[i].kind != Token::Ident)
        fail("expected a parameter name, found " + describe(tokens_[i]), tokens_[i]);
      p.name = &tokens_[i++];
      if (tokens_[i].is("[")) unsupported("arrays", file_.path(), tokens_[i]);
      if (tokens_[i].is(":") && tokens_[i + 1].kind == Token::Ident) i += 2;
      if (tokens_[i].is("=")) {
        p.default_value = ++i;
        for (int depth = 0; !(depth == 0 && (tokens_[i].is(",") || i == f_.close)); ++i) {
          if (tokens_[i].is("(") || tokens_[i].is("[")) ++depth;
          if (tokens_[i].is(")") || tokens_[i].is("]")) --depth;
        }
      }
      out.push_back(p);
      if (i == f_.close) return out;
      if (!tokens_[i].is(","))
        fail("expected ',' or ')' after a parameter, found " + describe(tokens_[i]), tokens_[i]);
      ++i;
    }
  }

  // Runs the body with the parameters bound to `args` (an out parameter's is not read), called
  // at `call`; returns the result in the return type and what the out and inout parameters hold
  // at the end.
  CallResult run(std::span<const Held> args, const std::vector<Parameter>& params,
                 const Token& call) {
    result_type_ = result_type();
    ProgramBuilder& b = builder();
    const Reg zero = b.constant(0.0);
    state_.scopes.emplace_back();
    for (std::size_t k = 0; k < params.size(); ++k) {
      const Parameter& p = params[k];
      Variable v{p.name->text, {}, false, p.name->line};
      v.out = p.mode == Mode::Out;
      if (v.out) {
        v.value = unassigned(p.type);
        v.defined = kUnassigned;
      } else {
        v.value = to_shape(args[k].value, p.type, call,
                           "the parameter '" + std::string(p.name->text) + "' of " +
                               function_name());
        v.defined = args[k].defined;
      }
      state_.scopes.back().push_back(v);
    }
    state_.outs.assign(params.size(), Held{{zero, Type::Float}, 0});
    for (std::size_t k = 0; k < params.size(); ++k)
      if (params[k].mode != Mode::In) written_.push_back(k);
    state_.returned = state_.skipped = state_.broken = state_.continued = zero;
    seek(f_.body);
    block();
    const Token& close = tokens_[f_.end];
    const auto returned = b.constant_value(state_.returned);
    if (result_type_ && (!returned || *returned == 0.0)) {
      fail("function '" + function_name() + "' " +
               (returned ? "ends without returning a value"
                         : "can reach its end without returning a value"),
           close);
    }
    CallResult out;
    // The result: the returns' values chained, the last taken wherever the earlier were not.
    if (result_type_ && !state_.returns.empty()) {
      out.result = state_.returns.back().value;
      for (std::size_t k = state_.returns.size() - 1; k-- > 0;)
        out.result = select(b, state_.returns[k].taken, state_.returns[k].value, out.result);
    }
    out.outs.resize(params.size());
    for (const std::size_t k : written_) {
      // At the end: the value at the return where one was taken, else the last one.
      const Variable& v = state_.scopes[0][k];
      const Held now{v.value, v.defined};
      if (is_true(state_.returned)) {
        out.outs[k] = state_.outs[k];
      } else if (is_false(state_.returned)) {
        out.outs[k] = now;
      } else {
        out.outs[k] = pick(state_.returned, state_.outs[k], now);
      }
    }
    return out;
  }

 protected:
  Value name(const Token& t) override {
    if (t.is_word("true") || t.is_word("false"))
      return {builder().constant(t.is_word("true") ? 1.0 : 0.0), Type::Bool};
    if (auto slot = locate(t.text)) {
      if (variable(*slot).array_size > 0) slot = element(*slot, t);
      return read(variable(*slot), t);
    }
    if (Global* g = file_.global(t.text)) {
      if (g->kind == Global::Array) {
        const std::vector<Value>& elements = file_.array_elements(*g);
        return elements[static_cast<std::size_t>(subscript(static_cast<int>(elements.size()), t))];
      }
      return file_.global_value(*g, t);
    }
    if (!file_.find(t.text).empty())
      fail("function '" + std::string(t.text) + "' needs arguments in parentheses", t);
    if (scalar_type(t.text) || is_vector_type(t.text) || file_.is_struct(t.text))
      fail("unexpected type '" + std::string(t.text) + "'", t);
    std::vector<std::string> known = file_.global_names();
    for (const auto& scope : state_.scopes)
      for (const Variable& v : scope) known.emplace_back(v.name);
    const std::string near = closest_name(t.text, known);
    fail("unknown identifier '" + std::string(t.text) + "'" +
             (near.empty() ? "" : " (did you mean " + near + "?)"),
         t);
  }

  // At the name, before the arguments are read (an unknown function's out arguments would
  // otherwise be read as values first).
  void before_call(const Token& t) override {
    if (is_vector_type(t.text) && !shader_type(t.text))
      unsupported("matrix types", file_.path(), t);
    if (is_texture_function(t.text) && file_.find(t.text).empty())
      unsupported("textures", file_.path(), t);
    if (!shader_type(t.text) && !is_matrix_function(t.text) &&
        find_library_function(t.text, kShaderLibrary).empty())
      fail(unknown_function(t), t);
  }

  // The file's own functions are inlined here; the rest is the library's.
  Value call(const Token& t) override {
    if (!file_.find(t.text).empty() && !shader_type(t.text)) return inline_call(t);
    if (t.is_word("sincos")) return sincos(t);
    if (file_.is_struct(t.text)) return construct_struct(t, *file_.struct_type(t.text));
    return ExpressionParser::call(t);
  }

  std::optional<Shape> named_type(std::string_view name) override {
    return file_.type_named(name);
  }

  // Swizzles, members and subscripts are postfix()'s; a texture's methods are an error here.
  void check_postfix() override {
    const Token& t = peek();
    if (t.is(".")) {
      const Token& member = peek(1);
      const std::string shown = "." + std::string(member.kind == Token::Ident ? member.text : "");
      for (const std::string_view m : {"Sample", "SampleLevel", "SampleGrad", "SampleBias",
                                       "SampleCmp", "SampleCmpLevelZero", "Load", "Gather"})
        if (member.is_word(m)) unsupported("textures", file_.path(), t, shown);
      return;  // a swizzle or a struct's member: postfix() reads it
    }
    if (t.is("[")) return;
    if (t.is("++") || t.is("--")) unsupported("increments inside expressions", file_.path(), t);
  }

  std::string unknown_function(const Token& t) override {
    std::vector<std::string> known = library_function_names(kShaderLibrary);
    known.emplace_back("sincos");
    for (const FunctionDef& f : file_.functions()) known.emplace_back(file_.name_of(f));
    const std::string near = closest_name(t.text, known);
    return "unknown function '" + std::string(t.text) + "'" +
           (near.empty() ? " (neither a built-in of the subset nor a function of this file)"
                         : " (did you mean " + near + "?)");
  }

 private:
  std::string function_name() const { return std::string(file_.name_of(f_)); }

  bool is_true(Reg r) const {
    const auto c = file_.builder.constant_value(r);
    return c && ProgramLogic<double>::is_true(*c);
  }
  bool is_false(Reg r) const {
    const auto c = file_.builder.constant_value(r);
    return c && !ProgramLogic<double>::is_true(*c);
  }
  // No path reaches here: every one has returned or left the loop's iteration.
  bool unreachable() const { return is_true(state_.returned) || is_true(state_.skipped); }

  // a && b of 0/1 registers, folded where either is a constant.
  Reg both(Reg a, Reg b) {
    if (is_true(a) || is_false(b)) return b;
    if (is_true(b) || is_false(a)) return a;
    return builder().emit(ProgramOp::And, a, b);
  }

  // a || b of 0/1 registers, folded where either is a constant.
  Reg either(Reg a, Reg b) {
    if (is_true(a) || is_false(b)) return a;
    if (is_true(b) || is_false(a)) return b;
    return builder().emit(ProgramOp::Or, a, b);
  }

  // c ? a : b; a side defined on no path yields to the other (see Defined).
  Held pick(Reg c, const Held& a, const Held& b) {
    const Defined d = a.defined | b.defined;
    if ((a.defined & kAssigned) == 0) return {b.value, d};
    if ((b.defined & kAssigned) == 0) return {a.value, d};
    return {select(builder(), c, a.value, b.value), d};
  }

  // A variable of `shape` that holds no value yet (NaN in every component; see Defined).
  Value unassigned(Shape shape) {
    return filled(builder(), Value{builder().constant(std::numeric_limits<double>::quiet_NaN())},
                  shape);
  }

  // `v` converted to `shape` for `what` (a variable, a parameter, the result): an error at `at`
  // where a vector would widen.
  Value to_shape(const Value& v, Shape shape, const Token& at, const std::string& what) {
    const std::optional<Value> out = convert(builder(), v, shape);
    if (!out) {
      fail("cannot give a " + shape_name(v.shape()) + " to " + what + ", a " + shape_name(shape),
           at);
    }
    return *out;
  }

  // A declared type: scalar or vector, or an error naming the construct.
  Shape declared_type(const Token& t) const {
    if (const auto s = file_.type_named(t.text)) return *s;
    if (is_vector_type(t.text)) unsupported("matrix types", file_.path(), t);
    if (is_texture_type(t.text)) unsupported("textures", file_.path(), t);
    if (t.is_word("struct")) unsupported("structs", file_.path(), t);
    fail("unknown type " + describe(t) + " (float, half, double, int or bool)", t);
  }

  // The constant subscript `[k]` after an array's name `at`, read: k, from 0 to size - 1.
  int subscript(int size, const Token& at) {
    if (!peek().is("[")) {
      fail("the array '" + std::string(at.text) + "' is used whole: only its elements (" +
               std::string(at.text) + "[k]) are values",
           at);
    }
    const Token& open = next();
    return constant_subscript(
        open, size, "'" + std::string(at.text) + "'",
        " (arrays are read at constant places: loops are unrolled, so their counter is one)");
  }

  // The slot of the element of the array at `array` that the subscript after `at` names.
  Slot element(Slot array, const Token& at) {
    const int k = subscript(variable(array).array_size, at);
    return Slot{array.scope, array.index + 1 + static_cast<std::size_t>(k)};
  }

  // "w[2]".
  static std::string element_name(std::string_view array, int k) {
    return std::string(array) + "[" + std::to_string(k) + "]";
  }

  std::optional<Slot> locate(std::string_view n) const {
    for (std::size_t s = state_.scopes.size(); s-- > 0;)
      for (std::size_t k = 0; k < state_.scopes[s].size(); ++k)
        if (state_.scopes[s][k].name == n) return Slot{s, k};
    return std::nullopt;
  }
  Variable& variable(Slot s) { return state_.scopes[s.scope][s.index]; }

  // A variable's value at a use `at`: an error where it holds none on any path that gets here.
  Value read(const Variable& v, const Token& at) const {
    if (v.defined == kUnassigned && !unreachable()) {
      if (v.out) {
        fail("the out parameter '" + std::string(v.name) + "' is read before it is given a value",
             at);
      }
      fail("'" + std::string(v.name) + "' is read before it is given a value (declared at line " +
               std::to_string(v.line) + ")",
           at);
    }
    return v.value;
  }

  // Gives the variable at `s` the value `h` (assigned at `at`) on the paths that reach here;
  // those that left the loop's iteration keep the old one where they read it again.
  void assign(Slot s, Held h, const Token& at) {
    Variable& v = variable(s);
    h.value = to_shape(h.value, v.value.shape(), at, "'" + std::string(v.name) + "'");
    if (is_true(state_.returned)) return;  // no path reads a variable after returning
    // The paths that left: by continue, they run the loop's step and next iteration, which read
    // its own variables; by break, they leave it, and neither reads the body's variables.
    Reg guard = state_.skipped;
    if (!loop_scopes_.empty() && s.scope >= loop_scopes_.back())
      guard = s.scope == loop_scopes_.back() ? state_.continued : builder().constant(0.0);
    if (is_true(guard)) return;
    if (!is_false(guard)) h = pick(guard, {v.value, v.defined}, h);
    v.value = h.value;
    v.defined = h.defined;
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

  // HLSL's attributes before a statement ([branch], [flatten], [unroll], [unroll(4)], [loop],
  // [fastopt], ...): hints to the shader compiler, which change no value; skipped.
  void attributes() {
    while (peek().is("[") && peek(1).kind == Token::Ident) {
      const Token& open = next();
      next();
      if (peek().is("(")) {
        const Token& paren = next();
        for (int depth = 1; depth > 0;) {
          const Token& u = next();
          if (u.kind == Token::End) fail("'(' is not closed", paren);
          if (u.is("(")) ++depth;
          if (u.is(")")) --depth;
        }
      }
      expect("]", "to close the attribute at column " + std::to_string(open.column));
    }
  }

  void statement() {
    attributes();
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
      if (w == "for") return for_statement();
      if (w == "break" || w == "continue") return jump_statement();
      if (w == "while") return while_statement();
      if (w == "do") return do_statement();
      if (w == "switch" || w == "case" || w == "default")
        unsupported("switch statements", file_.path(), t);
      if (w == "discard") unsupported("discard statements", file_.path(), t);
      if (w == "goto") unsupported("goto statements", file_.path(), t);
      if (w == "struct") unsupported("structs declared inside functions", file_.path(), t);
      if (w == "out" || w == "inout") unsupported("out and inout variables", file_.path(), t);
      if (is_declaration_start(t)) return declaration();
      if (at_assignment()) return assignment();
      // A call as a statement: the one place a void function may be called.
      if (peek(1).is("(")) statement_call_ = &t;
    }
    if (at_assignment()) return assignment();
    expression();
    statement_call_ = nullptr;
    expect(";", "after the expression");
  }

  bool is_declaration_start(const Token& t) {
    for (const std::string_view q :
         {"const", "static", "precise", "highp", "mediump", "lowp", "uniform", "in"})
      if (t.is_word(q)) return true;
    if (scalar_type(t.text) || is_vector_type(t.text) || is_texture_type(t.text)) return true;
    // `Name name`: a declaration of a type the subset does not have.
    return peek(1).kind == Token::Ident && !locate(t.text);
  }

  // [const] type name [= value] (, name [= value])* ; a variable without a value holds none
  // until assigned.
  void declaration() {
    bool is_const = false;
    while (peek().is_word("const") || peek().is_word("static") || peek().is_word("precise") ||
           peek().is_word("highp") || peek().is_word("mediump") || peek().is_word("lowp")) {
      is_const = next().is_word("const") || is_const;
    }
    if (peek().is_word("uniform") || peek().is_word("in"))
      fail("unexpected '" + std::string(peek().text) + "' in a function body", peek());
    const Shape type = declared_type(next());
    while (true) {
      const Token& n = next();
      if (n.kind != Token::Ident) fail("expected a variable name, found " + describe(n), n);
      for (const Variable& v : state_.scopes.back())
        if (v.name == n.text)
          fail("'" + std::string(n.text) + "' is already declared in this scope (line " +
                   std::to_string(v.line) + ")",
               n);
      if (peek().is("[")) {
        array_declaration(n, type, is_const);
        if (accept(",")) continue;
        expect(";", "after the declaration");
        return;
      }
      Variable v{n.text, unassigned(type), is_const, n.line, kUnassigned};
      if (peek().is("=")) {
        const Token& eq = next();
        const std::string what = "'" + std::string(n.text) + "'";
        v.value = peek().is("{") ? initializer_list(type, what)
                                 : to_shape(expression(), type, eq, what);
        v.defined = kAssigned;
      } else if (is_const) {
        fail("the constant '" + std::string(n.text) + "' needs a value", n);
      }
      state_.scopes.back().push_back(v);
      if (accept(",")) continue;
      expect(";", "after the declaration");
      return;
    }
  }

  // name[N] [= {a, b, ...}] or [= type[N](a, b, ...)], N a constant or left out where the values
  // give it: the array's variable, then its elements'.
  void array_declaration(const Token& n, Shape type, bool is_const) {
    const Token& open = next();
    int size = -1;
    if (!peek().is("]")) {
      const Value k = expression();
      const auto c = k.width == 1 ? builder().constant_value(k.reg) : std::nullopt;
      if (!c || *c != std::trunc(*c) || *c < 1 || *c > 4096)
        fail("the size of the array '" + std::string(n.text) + "' must be a constant from 1 to 4096", open);
      size = static_cast<int>(*c);
    }
    expect("]", "to close the size of '" + std::string(n.text) + "'");
    if (peek().is("[")) unsupported("arrays of arrays", file_.path(), peek());
    std::vector<Value> values;
    if (peek().is("=")) {
      next();
      values = array_values(type, size, n);
      size = static_cast<int>(values.size());
    } else if (size < 0) {
      fail("the array '" + std::string(n.text) + "' needs a size or values", open);
    } else if (is_const) {
      fail("the constant '" + std::string(n.text) + "' needs a value", n);
    }
    Variable whole{n.text, unassigned(type), is_const, n.line, kAssigned};
    whole.array_size = size;
    state_.scopes.back().push_back(whole);
    for (int k = 0; k < size; ++k) {
      const std::string_view name = element_names_.emplace_back(element_name(n.text, k));
      Variable v{name, unassigned(type), is_const, n.line, kUnassigned};
      if (!values.empty()) {
        v.value = values[static_cast<std::size_t>(k)];
        v.defined = kAssigned;
      }
      state_.scopes.back().push_back(v);
    }
  }

  // Whether an assignment or an increment starts here.
  bool at_assignment() const {
    if (peek().is("++") || peek().is("--")) return peek(1).kind == Token::Ident;
    if (peek().kind != Token::Ident) return false;
    const std::size_t k = selectors_end(1);
    return is_assignment(peek(k)) || peek(k).is("++") || peek(k).is("--");
  }

  // From the token `k` ahead, past the selectors of a variable's components (.xy, [1]): how far
  // ahead the token after them is.
  std::size_t selectors_end(std::size_t k) const {
    while (true) {
      if (peek(k).is(".") && peek(k + 1).kind == Token::Ident) {
        k += 2;
      } else if (peek(k).is("[")) {
        for (int depth = 0;; ++k) {
          const Token& u = peek(k);
          if (u.kind == Token::End) return k;
          if (u.is("[") || u.is("(")) ++depth;
          if (u.is("]") || u.is(")")) --depth;
          if (depth == 0) break;
        }
        ++k;
      } else {
        return k;
      }
    }
  }

  // The components of a variable of `width` that the selectors after its name pick (.xy, .x,
  // [2]; chained, as in v.zyx.x), for writing: each at most once. Empty: the whole variable.
  std::vector<int> written_components(int width) {
    std::vector<int> picked;
    while (peek().is(".") || peek().is("[")) {
      const Token& at = next();
      const int now = picked.empty() ? width : static_cast<int>(picked.size());
      std::vector<int> local;
      if (at.is(".")) {
        const Token& m = next();
        if (!is_swizzle(m.text)) {
          fail("'." + std::string(m.text) +
                   "' is neither a swizzle nor a member: only structs have members",
               at);
        }
        local = swizzle_components(m.text);
        for (std::size_t k = 0; k < local.size(); ++k) {
          if (local[k] >= now) {
            fail("'." + std::string(m.text) + "' of a " + shape_name(Shape{Type::Float, now}) +
                     ": it has no '" + m.text[k] + "'",
                 m);
          }
          for (std::size_t j = 0; j < k; ++j)
            if (local[j] == local[k])
              fail("'." + std::string(m.text) + "' writes a component twice", m);
        }
      } else {
        if (now == 1) fail("a subscript of a scalar: arrays are not supported", at);
        local = {constant_subscript(at, now, "a " + shape_name(Shape{Type::Float, now}))};
      }
      if (picked.empty()) {
        picked = local;
      } else {
        for (int& c : local) c = picked[static_cast<std::size_t>(c)];
        picked = local;
      }
    }
    return picked;
  }

  // name op value ; | name++ ; | ++name ;
  void assignment() {
    assignment_expression();
    expect(";", "after the assignment");
  }

  // name[selectors] op value | name[selectors]++ | ++name[selectors], without what ends it
  // (';', or ',' and ')' in a for's step).
  void assignment_expression() {
    const bool prefix = peek().is("++") || peek().is("--");
    const Token* op = prefix ? &next() : nullptr;
    const Token& n = next();
    std::optional<Slot> slot = locate(n.text);
    if (!slot) {
      if (const Global* g = file_.global(n.text); g != nullptr && g->kind == Global::Other)
        unsupported(g->what, file_.path(), n);
      if (file_.global(n.text) != nullptr)
        fail("cannot assign to the file-scope constant '" + std::string(n.text) + "'", n);
      fail("unknown variable '" + std::string(n.text) + "'", n);
    }
    const Place place = place_of(*slot, n);
    if (!prefix) op = &next();
    Value value;
    if (op->is("++") || op->is("--")) {
      value = apply_binary(*op, op->is("++") ? "+" : "-", read_place(place, n),
                           {builder().constant(1.0), Type::Int});
    } else {
      const Value rhs = peek().is("{") && place.whole()
                            ? initializer_list(place.shape, "'" + place.written + "'")
                            : expression();
      value = op->is("=") ? rhs
                          : apply_binary(*op, op->text.substr(0, 1), read_place(place, n), rhs);
    }
    write_place(place, {value, kAssigned}, *op);
  }

  // A variable's part that is written: its slot (an array's element), the members on the way
  // (outermost first), then the components of the vector there (each at most once; none: all
  // of it).
  struct Place {
    Slot slot;
    std::vector<int> members;
    std::vector<int> components;
    std::string written;  // "c.inner.ab", for messages
    Shape shape;          // of the member written
    [[nodiscard]] bool whole() const { return members.empty() && components.empty(); }
  };

  // The place that the selectors after a variable's name `n` (read; its slot `slot`) name: an
  // array's subscript, members, swizzles and subscripts of a vector. An error for a constant.
  Place place_of(Slot slot, const Token& n) {
    if (variable(slot).array_size > 0) slot = element(slot, n);
    if (variable(slot).is_const)
      fail("cannot assign to the constant '" + std::string(n.text) + "'", n);
    Place p{slot, {}, {}, std::string(n.text), variable(slot).value.shape()};
    while (p.shape.record != nullptr && peek().is(".")) {
      next();
      const Token& m = next();
      const int k = member_of(*p.shape.record, m);
      p.members.push_back(k);
      p.written += "." + std::string(m.text);
      p.shape = p.shape.record->members[static_cast<std::size_t>(k)].shape;
    }
    if (p.shape.record != nullptr && peek().is("[")) {
      fail("a subscript of a " + p.shape.record->name + ": a struct has members, not components",
           peek());
    }
    if (p.shape.is_matrix() && (peek().is("[") || peek().is("."))) {
      fail("writing part of a " + shape_name(p.shape) +
               " is not supported: a matrix is assigned whole",
           peek());
    }
    p.components = written_components(p.shape.width);
    return p;
  }

  // The member of `whole` on the way to a place.
  static Value& member_at(const Place& p, Value& whole) {
    Value* v = &whole;
    for (const int k : p.members) v = &v->members[static_cast<std::size_t>(k)];
    return *v;
  }

  // The part of the variable's value `whole` at a place.
  static Value value_at(const Place& p, Value whole) {
    const Value part = member_at(p, whole);
    if (p.components.empty()) return part;
    std::vector<Reg> regs;
    for (const int c : p.components) regs.push_back(part.component(c));
    return make_value(regs, part.type);
  }

  // The value at a place now (read at `at`: an error where the variable holds none).
  Value read_place(const Place& p, const Token& at) {
    return value_at(p, read(variable(p.slot), at));
  }

  // Writes `h` at a place (at `at`); the rest of the variable keeps its value, or 0 where it
  // holds none yet (any value is allowed there, see Defined).
  void write_place(const Place& p, Held h, const Token& at) {
    if (p.whole()) return assign(p.slot, h, at);
    const Variable& v = variable(p.slot);
    Value whole = v.value;
    if ((v.defined & kAssigned) == 0)
      whole = filled(builder(), Value{builder().constant(0.0)}, v.value.shape());
    Value& part = member_at(p, whole);
    if (p.components.empty()) {
      part = to_shape(h.value, part.shape(), at, "'" + p.written + "'");
    } else {
      const Value given = to_shape(h.value, Shape{part.type, static_cast<int>(p.components.size())},
                                   at, "components of '" + p.written + "'");
      for (std::size_t k = 0; k < p.components.size(); ++k)
        part.set_component(p.components[k], given.component(static_cast<int>(k)));
    }
    assign(p.slot, {whole, kAssigned}, at);
  }

  // if ( condition ) statement [else statement]: both branches run, their variables merge by
  // the condition.
  void if_statement() {
    const Token& t = next();
    const Nest nest(*this, t);
    expect("(", "after 'if'");
    const Value condition = expression();
    if (condition.width != 1)
      fail("the condition of 'if' is a " + shape_name(condition.shape()) + ", not a scalar", t);
    const Reg c = condition.reg;
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
    // A branch where every path has returned leaves the variables to the other.
    const bool then_returned = is_true(then.returned), else_returned = is_true(state_.returned);
    for (std::size_t s = 0; s < state_.scopes.size(); ++s) {
      for (std::size_t k = 0; k < state_.scopes[s].size(); ++k) {
        Variable& v = state_.scopes[s][k];
        const Variable& w = then.scopes[s][k];
        Held h{v.value, v.defined};
        if (else_returned && !then_returned) {
          h = {w.value, w.defined};
        } else if (!then_returned) {
          h = pick(c, {w.value, w.defined}, h);
        }
        v.value = h.value;
        v.defined = h.defined;
      }
    }
    // The result and the out parameters' values at the returns matter only on the paths that
    // returned, where neither branch changes those of the paths that returned before it: a branch
    // that returned on no new path leaves them to the other. (So guard clauses, `if (c) return
    // k;` one after another, make a chain, not a tree that doubles with each.)
    const bool then_new = then.returned != before.returned,
               else_new = state_.returned != before.returned;
    for (const std::size_t k : written_) {
      if (!then_new) continue;
      state_.outs[k] = else_new ? pick(c, then.outs[k], state_.outs[k]) : then.outs[k];
    }
    // The branches' new returns, each taken where its branch is (they exclude each other).
    std::vector<Return> returns(then.returns.begin(),
                                then.returns.begin() +
                                    static_cast<std::ptrdiff_t>(before.returns.size()));
    for (std::size_t k = before.returns.size(); k < then.returns.size(); ++k)
      returns.push_back({both(c, then.returns[k].taken), then.returns[k].value});
    if (state_.returns.size() > before.returns.size()) {
      const Reg not_c = b.emit(ProgramOp::Not, c);
      for (std::size_t k = before.returns.size(); k < state_.returns.size(); ++k)
        returns.push_back({both(not_c, state_.returns[k].taken), state_.returns[k].value});
    }
    state_.returns = std::move(returns);
    state_.returned = b.emit(ProgramOp::Select, c, then.returned, state_.returned);
    state_.skipped = b.emit(ProgramOp::Select, c, then.skipped, state_.skipped);
    state_.broken = b.emit(ProgramOp::Select, c, then.broken, state_.broken);
    state_.continued = b.emit(ProgramOp::Select, c, then.continued, state_.continued);
  }

  // A branch's statement in a scope of its own.
  void branch() {
    state_.scopes.emplace_back();
    statement();
    state_.scopes.pop_back();
  }

  // return [value] ; : the result and the out parameters' values, on the paths that have not
  // returned and not left the loop's iteration.
  void return_statement() {
    const Token& t = next();
    Value v;
    if (!result_type_) {
      if (!peek().is(";"))
        fail("function '" + function_name() + "' returns void: return takes no value", peek());
    } else {
      if (peek().is(";")) fail("return needs a value in function '" + function_name() + "'", t);
      v = to_shape(expression(), *result_type_, t, "the result of " + function_name());
    }
    expect(";", "after the returned value");
    if (unreachable()) return;
    ProgramBuilder& b = builder();
    const Reg skipped = state_.skipped;
    const bool some_skipped = !is_false(skipped);
    if (result_type_) {
      // Taken on the paths still here: those that returned before took an earlier return.
      state_.returns.push_back({some_skipped ? b.emit(ProgramOp::Not, skipped) : b.constant(1.0), v});
    }
    for (const std::size_t k : written_) {
      const Variable& p = state_.scopes[0][k];
      Held& out = state_.outs[k];
      Held h = pick(state_.returned, out, {p.value, p.defined});
      if (is_false(state_.returned)) h = {p.value, p.defined};
      out = some_skipped ? pick(skipped, out, h) : h;
    }
    const Reg one = b.constant(1.0);
    state_.returned = some_skipped ? b.emit(ProgramOp::Select, skipped, state_.returned, one) : one;
  }

  // break ; | continue ; : the paths that reach it skip the rest of the loop's iteration (and,
  // by break, the iterations after it).
  void jump_statement() {
    const Token& t = next();
    const bool is_break = t.is_word("break");
    expect(";", "after '" + std::string(t.text) + "'");
    if (loop_scopes_.empty())
      fail("'" + std::string(t.text) +
               "' outside a loop (break and continue end a loop's iteration)",
           t);
    if (unreachable()) return;
    ProgramBuilder& b = builder();
    const Reg one = b.constant(1.0);
    Reg& flag = is_break ? state_.broken : state_.continued;
    flag = b.emit(ProgramOp::Select, state_.skipped, flag, one);
    state_.skipped = one;
  }

  // The first token at this nesting level of a for's header from `from` that is ';' or the ')'
  // closing the header.
  std::size_t header_end(std::size_t from) const {
    int depth = 0;
    for (std::size_t i = from;; ++i) {
      const Token& u = tokens_[i];
      if (u.kind == Token::End || u.is("{") || u.is("}"))
        fail("expected ')' to close the '(' of 'for', found " + describe(u), u);
      if (depth == 0 && (u.is(";") || u.is(")"))) return i;
      if (u.is("(") || u.is("[")) ++depth;
      if (u.is(")") || u.is("]")) --depth;
    }
  }

  // for ( [declaration | assignment] ; condition ; [assignment (, assignment)*] ) statement,
  // unrolled: before each iteration the condition must be a constant (so must the loop's
  // variable be), and the loop may run kMaxLoopIterations times at most.
  void for_statement() {
    const Token& t = next();
    const Nest nest(*this, t);
    expect("(", "after 'for'");
    state_.scopes.emplace_back();  // the variables the loop declares
    bool declares = false;         // the loop's variable is its own
    if (!accept(";")) {
      const Token& s = peek();
      if (s.kind == Token::Ident && is_declaration_start(s)) {
        declaration();
        declares = true;
      } else if (at_assignment()) {
        assignment();
      } else {
        fail("expected a declaration or an assignment to start 'for', found " + describe(s), s);
      }
    }
    const std::size_t condition = position();
    const std::size_t condition_end = header_end(condition);
    if (!token_at(condition_end).is(";"))
      fail("expected ';' after the condition of 'for', found ')'", token_at(condition_end));
    if (condition_end == condition) {
      fail(
          "a for loop needs a condition: loops are unrolled, so their trip count must be a "
          "constant",
          token_at(condition));
    }
    const std::size_t step = condition_end + 1;
    const std::size_t body = header_end(step) + 1;
    if (!token_at(body - 1).is(")"))
      fail("expected ')' after the step of 'for', found ';'", token_at(body - 1));

    unroll({"for", t, condition, ";", step, body, true, declares});
    state_.scopes.pop_back();
  }

  // while ( condition ) statement: unrolled as a for loop with only its condition.
  void while_statement() {
    const Token& t = next();
    const Nest nest(*this, t);
    const auto [condition, close] = while_condition("while");
    state_.scopes.emplace_back();
    unroll({"while", t, condition, ")", 0, close + 1, true, false});
    state_.scopes.pop_back();
  }

  // `( condition )` after `while` (of a while or a do loop `kind`): where the condition starts,
  // and its ')'.
  std::pair<std::size_t, std::size_t> while_condition(std::string_view kind) {
    expect("(", "after 'while'");
    const std::size_t condition = position();
    const std::size_t close = header_end(condition);
    if (!token_at(close).is(")"))
      fail("expected ')' to close the condition of 'while', found ';'", token_at(close));
    if (close == condition)
      fail("a " + std::string(kind) + " loop needs a condition", token_at(condition));
    return {condition, close};
  }

  // do statement while ( condition ) ; : unrolled, the condition checked after each iteration.
  void do_statement() {
    const Token& t = next();
    const Nest nest(*this, t);
    const std::size_t body = position();
    // The body's end, where `while` stands: read once on no path, for its extent.
    {
      const State kept = state_;
      loop_scopes_.push_back(state_.scopes.size());
      state_.returned = builder().constant(1.0);
      branch();
      loop_scopes_.pop_back();
      state_ = kept;
    }
    if (!peek().is_word("while"))
      fail("expected 'while' after the body of 'do', found " + describe(peek()), peek());
    next();
    const auto [condition, close] = while_condition("do");
    state_.scopes.emplace_back();
    unroll({"do", t, condition, ")", 0, body, false, false});
    state_.scopes.pop_back();
    seek(close + 1);
    expect(";", "after the condition of 'do ... while'");
  }

  struct Loop {
    std::string_view kind;      // "for", "while", "do" (for messages)
    const Token& at;            // its keyword
    std::size_t condition = 0;  // where the condition starts
    std::string_view close;     // the token after it
    std::size_t step = 0;       // a for's step (0: none)
    std::size_t body = 0;       // the body's statement
    bool test_first = true;     // false: do (the first iteration runs unconditionally)
    bool declares = false;      // the loop's variable is its own (declared in a for's header)
  };

  // The iterations of a loop, unrolled: before each (after the first, for do) the condition must
  // be a constant (so must the loop's variable be), and the loop may run kMaxLoopIterations times
  // at most. Leaves the position at the body's end.
  void unroll(const Loop& loop) {
    const Reg outer_skipped = state_.skipped, outer_broken = state_.broken,
              outer_continued = state_.continued;
    loop_scopes_.push_back(state_.scopes.size() - 1);
    const bool reachable = !unreachable();
    ProgramBuilder& b = builder();
    state_.broken = state_.continued = b.constant(0.0);
    std::size_t end = 0;  // the body's end, once read
    bool step_read = false;
    const std::string name = std::string(loop.kind) + " loop";
    for (int n = 0;; ++n) {
      if (n > 0 || loop.test_first) {
        seek(loop.condition);
        const Token& at = peek();
        const Value c = expression();
        expect(loop.close, "after the condition of '" + std::string(loop.kind) + "'");
        if (!reachable) break;
        if (c.width != 1)
          fail("the condition of this " + name + " is a " + shape_name(c.shape()) + ", not a scalar",
               at);
        const auto value = b.constant_value(c.reg);
        if (!value) {
          // A variable declared before the loop keeps, on the paths that broke, its value at the
          // break: so it stops being a constant there.
          const bool hint = !loop.declares && !is_false(state_.broken);
          fail("the condition of this " + name +
                   " is not a constant: loops are unrolled, so their trip count must be a "
                   "constant" +
                   std::string(hint ? " (a loop that breaks on some paths must declare its "
                                      "variable in its header: for (int i = ...))"
                                    : ""),
               at);
        }
        if (!ProgramLogic<double>::is_true(*value)) break;
      } else if (!reachable) {
        break;
      }
      if (n == kMaxLoopIterations) {
        fail("this " + name + " runs more than " + std::to_string(kMaxLoopIterations) +
                 " iterations, the most that is unrolled",
             loop.at);
      }
      seek(loop.body);
      branch();
      end = position();
      if (is_true(state_.returned) || is_true(state_.broken)) break;
      // The paths that continued run the step and the next iteration; those that broke do not.
      state_.continued = b.constant(0.0);
      state_.skipped = either(outer_skipped, state_.broken);
      if (loop.step != 0) {
        seek(loop.step);
        for_step();
      }
      step_read = true;
    }
    if (end == 0 || !step_read) {
      // What never ran is read for its errors only, on no path.
      const State kept = state_;
      state_.returned = b.constant(1.0);
      if (loop.step != 0) {
        seek(loop.step);
        for_step();
      }
      seek(loop.body);
      branch();
      end = position();
      state_ = kept;
    }
    seek(end);
    loop_scopes_.pop_back();
    state_.skipped = outer_skipped;
    state_.broken = outer_broken;
    state_.continued = outer_continued;
  }

  // A for's step: assignments separated by ',', up to its ')'.
  void for_step() {
    while (!peek().is(")")) {
      const Token& s = peek();
      if (!at_assignment())
        fail("expected an assignment or an increment in the step of 'for', found " + describe(s),
             s);
      assignment_expression();
      if (!accept(",")) break;
    }
    expect(")", "after the step of 'for'");
  }

  // HLSL's sincos(x, out s, out c), a statement of its own: s = sin(x), c = cos(x), component
  // by component.
  Value sincos(const Token& t) {
    const Token& open = next();
    const Value x = expression();
    expect(",", "after the angle of sincos");
    const Place s = out_argument("the sine, sincos's second argument,");
    expect(",", "after the second argument of sincos");
    const Place c = out_argument("the cosine, sincos's third argument,");
    if (!peek().is(")")) {
      fail("expected ')' to close the '(' at column " + std::to_string(open.column) +
               " (sincos takes 3 arguments), found " + describe(peek()),
           peek());
    }
    next();
    if (!(&t == statement_call_ && peek().is(";")))
      fail("sincos returns void: its call is a statement of its own, not a value", t);
    Value sin_x = x, cos_x = x;
    sin_x.type = cos_x.type = Type::Float;
    for (int i = 0; i < x.width; ++i) {
      sin_x.set_component(i, builder().emit(op_from_name("sin"), x.component(i)));
      cos_x.set_component(i, builder().emit(op_from_name("cos"), x.component(i)));
    }
    write_place(s, {sin_x, kAssigned}, t);
    write_place(c, {cos_x, kAssigned}, t);
    return Value{builder().constant(0.0)};
  }

  // A call of the file's own function, inlined: in arguments are values; out and inout ones are
  // variables of the caller, written back after the call in parameter order.
  Value inline_call(const Token& t) {
    const std::vector<const FunctionDef*> defs = file_.find(t.text);
    const std::size_t count = argument_count();
    // The definition taking `count` arguments, its last parameters' default values (HLSL) for
    // the ones not given.
    std::vector<const FunctionDef*> fitting;
    std::size_t fewest = defs[0]->parameters;
    for (const FunctionDef* d : defs) {
      const std::size_t least = required(*d);
      if (count <= d->parameters && count >= least) fitting.push_back(d);
      fewest = std::min(fewest, least);
    }
    const FunctionDef* def = fitting.empty()      ? nullptr
                             : fitting.size() == 1 ? fitting[0]
                                                   : by_argument_types(t, fitting);
    if (def == nullptr) {
      const std::size_t most = defs[0]->parameters;
      const std::string takes = fewest == most ? std::to_string(most)
                                               : std::to_string(fewest) + " to " + std::to_string(most);
      fail(std::string(t.text) + " takes " + takes + (most == 1 ? " argument" : " arguments") +
               ", got " + std::to_string(count),
           t);
    }
    FunctionCompiler callee(file_, *def);
    const std::vector<Parameter> params = callee.parameters();
    std::vector<Held> args;
    std::vector<Place> places(params.size());
    arguments(t, [&](int i) {
      const auto k = static_cast<std::size_t>(i);
      if (k < params.size() && params[k].mode != Mode::In) {
        const Token& a = peek();
        places[k] = out_argument("the " + mode_name(params[k].mode) + " parameter '" +
                                std::string(params[k].name->text) + "' of " +
                                std::string(t.text));
        const Place& place = places[k];
        const Variable& v = variable(place.slot);
        // An inout argument is read: one that holds no value is an error here, but for a
        // struct, which the callee may fill (Unreal's Init(Context, ...)): its members hold
        // none until written.
        if (params[k].mode == Mode::InOut && v.value.record == nullptr) (void)read(v, a);
        args.push_back({value_at(place, v.value), v.defined});
      } else {
        args.push_back({expression(), kAssigned});
      }
    });
    const std::size_t after = position();
    for (std::size_t k = args.size(); k < params.size(); ++k) {
      seek(params[k].default_value);
      args.push_back({expression(), kAssigned});
    }
    seek(after);
    next();
    const bool is_void = !callee.result_type();
    if (is_void && !(&t == statement_call_ && peek().is(";"))) {
      fail("function '" + std::string(t.text) +
               "' returns void: its call is a statement of its own, not a value",
           t);
    }
    auto& calls = file_.calls;
    // Recursion: the same definition (an overload may call another of its name).
    if (const auto it = std::find(calls.begin(), calls.end(), def); it != calls.end()) {
      std::string chain;
      for (auto c = it; c != calls.end(); ++c) chain += std::string(file_.name_of(**c)) + " -> ";
      fail("recursion is not supported (" + chain + std::string(t.text) +
               "); the reference subset is listed in docs/reference.md",
           t);
    }
    const Nest nest(*this, t);
    calls.push_back(def);
    const CallResult r = callee.run(args, params, t);
    calls.pop_back();
    for (std::size_t k = 0; k < params.size(); ++k)
      if (params[k].mode != Mode::In) write_place(places[k], r.outs[k], t);
    return r.result;
  }

  // Of overloads that take as many arguments, the one whose parameters' types the arguments
  // (read ahead, with no effect on the variables) fit best: the same type, then another
  // scalar type of the same shape, then a scalar that fills a vector; an error where none
  // fits or two fit alike (HLSL's rule, in short). The current token is the call's '('.
  const FunctionDef* by_argument_types(const Token& t, std::span<const FunctionDef* const> defs) {
    const State kept = state_;
    const std::size_t open = position();
    std::vector<Shape> given;
    arguments(t, [&](int) {
      const Token& a = peek();
      std::optional<Slot> slot;
      if (a.kind == Token::Ident && (peek(1).is(",") || peek(1).is(")"))) slot = locate(a.text);
      if (slot && variable(*slot).array_size == 0) {
        given.push_back(variable(*slot).value.shape());  // not read: it may be an out argument
        next();
      } else {
        given.push_back(expression().shape());
      }
    });
    seek(open);
    state_ = kept;
    // The cost of passing a value of shape `a` for a parameter of shape `p` (-1: it cannot).
    auto cost = [](const Shape& a, const Shape& p) {
      if (a.record != p.record || a.rows != p.rows || a.columns != p.columns) return -1;
      if (a.width == p.width) return a.type == p.type ? 0 : 1;
      return a.width == 1 ? 2 : -1;
    };
    const FunctionDef* best = nullptr;
    int best_cost = -1;
    bool tie = false;
    std::string each;
    for (const FunctionDef* d : defs) {
      const std::vector<Parameter> params = FunctionCompiler(file_, *d).parameters();
      std::string shapes;
      for (const Parameter& p : params) shapes += (shapes.empty() ? "" : ", ") + shape_name(p.type);
      each += (each.empty() ? "" : ", ") + std::string(t.text) + "(" + shapes + ") at line " +
              std::to_string(tokens_[d->name].line);
      int total = 0;
      for (std::size_t k = 0; k < given.size() && total >= 0; ++k) {
        const int c = cost(given[k], params[k].type);
        total = c < 0 ? -1 : total + c;
      }
      if (total < 0) continue;
      if (best == nullptr || total < best_cost) {
        best = d;
        best_cost = total;
        tie = false;
      } else if (total == best_cost) {
        tie = true;
      }
    }
    std::string args;
    for (const Shape& g : given) args += (args.empty() ? "" : ", ") + shape_name(g);
    if (best == nullptr || tie) {
      fail("the call " + std::string(t.text) + "(" + args + ") " +
               (tie ? "fits two of its overloads alike" : "fits none of its overloads") + " (" +
               each + ")",
           t);
    }
    return best;
  }

  // The arguments of the call whose '(' is the current token, counted by their commas.
  std::size_t argument_count() const {
    std::size_t i = position() + 1, count = 0;
    int depth = 0;
    for (; tokens_[i].kind != Token::End; ++i) {
      const Token& u = tokens_[i];
      if (depth == 0 && u.is(")")) break;
      if (u.is("(") || u.is("[") || u.is("{")) ++depth;
      if (u.is(")") || u.is("]") || u.is("}")) --depth;
      if (depth == 0 && u.is(",")) ++count;
      if (count == 0) count = 1;
    }
    return count;
  }

  // How many arguments a call of `d` needs: its parameters but the last ones with a default.
  std::size_t required(const FunctionDef& d) const {
    const std::vector<Parameter> params = FunctionCompiler(file_, d).parameters();
    std::size_t n = params.size();
    while (n > 0 && params[n - 1].default_value != 0) --n;
    return n;
  }

  // An out or inout argument, for `what` (the parameter, in messages): a variable of the caller,
  // or a member, an array's element or a vector's components of one (`s.c`, `w[1]`, `v.xy`).
  Place out_argument(const std::string& what) {
    const Token& a = peek();
    const std::size_t after = selectors_end(1);
    if (a.kind == Token::Ident && (peek(after).is(",") || peek(after).is(")"))) {
      if (const auto slot = locate(a.text)) {
        if (variable(*slot).is_const)
          fail("cannot pass the constant '" + std::string(a.text) + "' to " + what, a);
        next();
        return place_of(*slot, a);
      }
      if (const Global* g = file_.global(a.text)) {
        if (g->kind == Global::Other) unsupported(g->what, file_.path(), a);
        fail("cannot pass the file-scope constant '" + std::string(a.text) + "' to " + what, a);
      }
      if (!a.is_word("true") && !a.is_word("false")) (void)name(a);  // unknown: its message
    }
    fail(what + " writes its argument: it must be a variable (a local or a parameter, or a "
                "member, element or component of one), found " +
             describe(a),
         a);
  }

  ShaderFile& file_;
  const FunctionDef& f_;
  std::span<const Token> tokens_;
  std::deque<std::string> element_names_;  // the names of the arrays' elements ("w[2]")
  State state_;
  std::optional<Shape> result_type_;
  std::vector<std::size_t> written_;       // the out and inout parameters
  std::vector<std::size_t> loop_scopes_;   // the scope of each enclosing loop's variables
  const Token* statement_call_ = nullptr;  // the call that is a statement of its own
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
  std::vector<const FunctionDef*> defs = file.find(wanted);
  // Overloads: the one whose parameters are the variables.
  if (defs.size() > 1 && !text.variables.empty()) {
    std::vector<std::string> want = text.variables;
    std::sort(want.begin(), want.end());
    std::vector<const FunctionDef*> matching;
    for (const FunctionDef* d : defs) {
      std::vector<std::string> have;
      for (const Parameter& p : FunctionCompiler(file, *d).parameters())
        have.emplace_back(p.name->text);
      std::sort(have.begin(), have.end());
      if (have == want) matching.push_back(d);
    }
    if (matching.size() == 1) defs = matching;
  }
  // Of overloads still alike, those that can be a reference: float parameters (in), a scalar
  // result (Unity's SRGBToLinear(float c) beside SRGBToLinear(float3 c)).
  if (defs.size() > 1) {
    std::vector<const FunctionDef*> scalar;
    for (const FunctionDef* d : defs) {
      const std::optional<Shape> result = shader_type(file.tokens()[d->type].text);
      bool ok = result && result->width == 1;
      for (const Parameter& p : FunctionCompiler(file, *d).parameters())
        ok = ok && p.mode == Mode::In && p.type.width == 1 && p.type.type == Type::Float;
      if (ok) scalar.push_back(d);
    }
    if (!scalar.empty()) defs = scalar;
  }
  if (defs.empty()) {
    throw Error("function '" + wanted + "' is not in " + file.path() + " (its functions: " +
                    (names.empty() ? std::string("none") : join_names(names)) + ")",
                where);
  }
  const FunctionDef& def = *defs.back();
  const Token& at = file.tokens()[def.name];
  if (defs.size() > 1) {
    std::string each;
    for (const FunctionDef* d : defs) {
      std::vector<std::string> parameters;
      for (const Parameter& p : FunctionCompiler(file, *d).parameters())
        parameters.push_back(shape_name(p.type) + " " + std::string(p.name->text));
      each += std::string(each.empty() ? "" : ", ") + wanted + "(" + join_names(parameters) +
              ") at line " + std::to_string(file.tokens()[d->name].line);
    }
    fail_at("function '" + wanted + "' is defined " + std::to_string(defs.size()) + " times (" +
                each + "): the variables pick one, by its parameters' names",
            file.path(), at);
  }
  FunctionCompiler compiler(file, def);
  (void)compiler.return_type();
  const std::vector<Parameter> params = compiler.parameters();
  std::vector<std::string> param_names;
  for (const Parameter& p : params) {
    if (p.mode != Mode::In) {
      fail_at("parameter '" + std::string(p.name->text) + "' of " + wanted + " is " +
                  mode_name(p.mode) +
                  ": the reference's parameters are its inputs and its one result is the float "
                  "it returns (call " +
                  wanted + " from a function that returns the value)",
              file.path(), *p.qualifier);
    }
    if (p.type.width != 1) {
      fail_at("parameter '" + std::string(p.name->text) + "' is a " + shape_name(p.type) +
                  ": the function's parameters are the reference's variables, each a float (give "
                  "the components as floats, or call " +
                  wanted + " from a function that takes them)",
              file.path(), *p.name);
    }
    if (p.type.type != Type::Float) {
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
  std::vector<Held> args;
  for (const std::string& p : param_names) {
    const auto k =
        static_cast<std::size_t>(std::find(order.begin(), order.end(), p) - order.begin());
    args.push_back({{out.inputs[k], Type::Float}, kAssigned});
  }
  file.calls.push_back(&def);
  b.fold_zero_products(true);
  out.result = compiler.run(args, params, at).result.reg;
  b.fold_zero_products(false);
  return out;
}

}  // namespace shaderfit::reference_detail
