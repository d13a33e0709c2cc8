// Shader matrices (language_internal.hpp): a matrix is its rows, each a float vector; GLSL's
// column-major habits (constructors by columns, m[i] a column) are read into rows here.
#include "language_internal.hpp"

namespace shaderfit::reference_detail {

namespace {

Value vector_of(std::vector<Reg> regs) { return make_value(regs, Type::Float); }

// The dot product of two float vectors of one width.
Reg dot(ProgramBuilder& b, const Value& x, const Value& y) {
  Reg sum = b.emit(ProgramOp::Mul, x.component(0), y.component(0));
  for (int i = 1; i < x.width; ++i)
    sum = b.emit(ProgramOp::Add, sum, b.emit(ProgramOp::Mul, x.component(i), y.component(i)));
  return sum;
}

}  // namespace

Value make_matrix(Shape shape, std::vector<Value> rows) {
  Value m;
  m.width = 0;
  m.rows = shape.rows;
  m.columns = shape.columns;
  m.glsl = shape.glsl;
  m.members = std::move(rows);
  return m;
}

Value matrix_column(const Value& m, int j) {
  std::vector<Reg> regs;
  for (const Value& row : m.members) regs.push_back(row.component(j));
  return vector_of(regs);
}

Value matrix_subscript(const Value& m, int i) {
  return m.glsl ? matrix_column(m, i) : m.members[static_cast<std::size_t>(i)];
}

Value transpose(const Value& m) {
  Shape t = m.shape();
  std::swap(t.rows, t.columns);
  std::vector<Value> rows;
  for (int j = 0; j < m.columns; ++j) rows.push_back(matrix_column(m, j));
  return make_matrix(t, std::move(rows));
}

std::optional<Value> matrix_product(ProgramBuilder& b, const Value& x, const Value& y) {
  const bool xm = x.is_matrix(), ym = y.is_matrix();
  if (!xm && !ym) {
    if (x.width != y.width) return std::nullopt;
    return Value{dot(b, convert(b, x, Type::Float), convert(b, y, Type::Float)), Type::Float};
  }
  // Sizes: a vector on the left is a row (1 x n), on the right a column (n x 1).
  const int inner_x = xm ? x.columns : x.width, inner_y = ym ? y.rows : y.width;
  if (inner_x != inner_y) return std::nullopt;
  if (xm && !ym) {  // M v: each row's dot product with v
    std::vector<Reg> regs;
    for (const Value& row : x.members) regs.push_back(dot(b, row, convert(b, y, Type::Float)));
    return vector_of(regs);
  }
  if (!xm) {  // v M: v's dot product with each column
    std::vector<Reg> regs;
    for (int j = 0; j < y.columns; ++j)
      regs.push_back(dot(b, convert(b, x, Type::Float), matrix_column(y, j)));
    return vector_of(regs);
  }
  Shape s = x.shape();
  s.columns = y.columns;
  std::vector<Value> rows;
  for (const Value& row : x.members) {
    std::vector<Reg> regs;
    for (int j = 0; j < y.columns; ++j) regs.push_back(dot(b, row, matrix_column(y, j)));
    rows.push_back(vector_of(regs));
  }
  return make_matrix(s, std::move(rows));
}

std::optional<Value> construct_matrix(ProgramBuilder& b, Shape to, std::span<const Value> args) {
  const Reg zero = b.constant(0.0), one = b.constant(1.0);
  // GLSL's mat3(s) and mat3(m): the diagonal, and m within the identity.
  if (to.glsl && args.size() == 1 && (args[0].width == 1 || args[0].is_matrix())) {
    const Value& a = args[0];
    std::vector<Value> rows;
    for (int i = 0; i < to.rows; ++i) {
      std::vector<Reg> regs;
      for (int j = 0; j < to.columns; ++j) {
        if (a.is_matrix() && i < a.rows && j < a.columns) {
          regs.push_back(a.members[static_cast<std::size_t>(i)].component(j));
        } else {
          regs.push_back(i != j ? zero : a.is_matrix() ? one : convert(b, a, Type::Float).reg);
        }
      }
      rows.push_back(vector_of(regs));
    }
    return make_matrix(to, std::move(rows));
  }
  std::vector<Value> parts;
  for (const Value& a : args) scalar_components(a, parts);
  if (parts.size() != static_cast<std::size_t>(to.rows * to.columns)) return std::nullopt;
  // GLSL fills columns: read them as the rows of the transpose.
  Shape filled_shape = to;
  if (to.glsl) std::swap(filled_shape.rows, filled_shape.columns);
  std::size_t at = 0;
  const Value m = *from_components(b, filled_shape, parts, at);
  return to.glsl ? transpose(m) : m;
}

}  // namespace shaderfit::reference_detail
