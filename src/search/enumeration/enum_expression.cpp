// Turning an enumerated class back into a formula, with its sign pushed to where it prints best.
#include "search/enumeration/enumerator.hpp"

namespace shaderfit::search_detail {

namespace {

class Builder {
 public:
  Builder(const ClassStore& store, std::span<const double> literals,
          std::span<const Expression> terminals, std::size_t inputs)
      : store_(store), literals_(literals), terminals_(terminals), inputs_(inputs) {}

  // Appends the postfix nodes of class id, negated when `neg`.
  void build(std::uint32_t id, bool neg) {
    const ClassRecord& r = store_.record(id);
    const bool neg_b = r.has(ClassRecord::kNegB);
    switch (r.kind) {
      case EKind::Var:
        if (static_cast<std::size_t>(r.k) >= inputs_) {
          const Expression& t = terminals_[static_cast<std::size_t>(r.k) - inputs_];
          nodes.insert(nodes.end(), t.nodes.begin(), t.nodes.end());
        } else {
          nodes.push_back(Node::variable(r.k));
        }
        if (neg) nodes.push_back(Node::op_node(Op::Neg));
        return;
      case EKind::Literal: {
        const double v = literals_[static_cast<std::size_t>(r.k)];
        nodes.push_back(Node::constant(neg ? -v : v));
        return;
      }
      case EKind::Unary:
        build(r.a, r.has(ClassRecord::kNegA));
        nodes.push_back(Node::op_node(r.op));
        if (neg) nodes.push_back(Node::op_node(Op::Neg));
        return;
      case EKind::IPow: {
        const bool into_base = neg && (r.k % 2 != 0) && absorbs_negation(r.a);
        build(r.a, into_base);
        nodes.push_back(Node::ipow(r.k));
        if (neg && !into_base) nodes.push_back(Node::op_node(Op::Neg));
        return;
      }
      case EKind::AddSub:
      case EKind::FusedAdd:
        if (!neg) {
          build(r.a, false);
          build(r.b, false);
          nodes.push_back(Node::op_node(neg_b ? Op::Sub : Op::Add));
        } else if (neg_b) {  // -(a - b) = b - a
          build(r.b, false);
          build(r.a, false);
          nodes.push_back(Node::op_node(Op::Sub));
        } else {  // -(a + b) = -a - b
          build(r.a, true);
          build(r.b, false);
          nodes.push_back(Node::op_node(Op::Sub));
        }
        return;
      case EKind::Mul:
      case EKind::Div: {
        const Op op = r.kind == EKind::Mul ? Op::Mul : Op::Div;
        const bool into_a = neg && absorbs_negation(r.a);
        const bool into_b = neg && !into_a && absorbs_negation(r.b);
        build(r.a, into_a);
        build(r.b, into_b);
        nodes.push_back(Node::op_node(op));
        if (neg && !into_a && !into_b) nodes.push_back(Node::op_node(Op::Neg));
        return;
      }
      case EKind::Min:
      case EKind::Max: {
        // -min(a, b) = max(-a, -b)
        const bool is_min = (r.kind == EKind::Min) != neg;
        build(r.a, neg);
        build(r.b, neg_b != neg);
        nodes.push_back(Node::op_node(is_min ? Op::Min : Op::Max));
        return;
      }
      case EKind::Pow:
        build(r.a, false);
        build(r.b, neg_b);
        nodes.push_back(Node::op_node(Op::Pow));
        if (neg) nodes.push_back(Node::op_node(Op::Neg));
        return;
      case EKind::CopySign:  // -copysign(a, b) = copysign(a, -b)
        build(r.a, false);
        build(r.b, neg_b != neg);
        nodes.push_back(Node::op_node(Op::CopySign));
        return;
      case EKind::Atan2:  // -atan2(a, b) = atan2(-a, b)
        build(r.a, neg);
        build(r.b, neg_b);
        nodes.push_back(Node::op_node(Op::Atan2));
        return;
    }
  }

  std::vector<Node> nodes;

 private:
  // A class whose negation prints without a minus sign: a difference, or a literal.
  [[nodiscard]] bool absorbs_negation(std::uint32_t id) const {
    const ClassRecord& r = store_.record(id);
    if (r.kind == EKind::Literal) return true;
    return (r.kind == EKind::AddSub || r.kind == EKind::FusedAdd) && r.has(ClassRecord::kNegB);
  }

  const ClassStore& store_;
  std::span<const double> literals_;
  std::span<const Expression> terminals_;
  std::size_t inputs_;
};

Expression finish(std::vector<Node> nodes, const std::vector<std::string>& variables) {
  Expression e;
  e.nodes = std::move(nodes);
  e.variables = variables;
  e.update_lengths();
  return e;
}

}  // namespace

Expression build_fused_expression(const ClassStore& store, std::uint32_t m, std::uint32_t leaf,
                                  bool neg_leaf, bool negate,
                                  const std::vector<std::string>& variables,
                                  std::span<const double> literals,
                                  std::span<const Expression> terminals) {
  // As build() does for FusedAdd records: m + c, m - c, -(m + c) = -m - c, -(m - c) = c - m.
  Builder b(store, literals, terminals, variables.size());
  if (!negate) {
    b.build(m, false);
    b.build(leaf, false);
    b.nodes.push_back(Node::op_node(neg_leaf ? Op::Sub : Op::Add));
  } else if (neg_leaf) {
    b.build(leaf, false);
    b.build(m, false);
    b.nodes.push_back(Node::op_node(Op::Sub));
  } else {
    b.build(m, true);
    b.build(leaf, false);
    b.nodes.push_back(Node::op_node(Op::Sub));
  }
  return finish(std::move(b.nodes), variables);
}

Expression build_class_expression(const ClassStore& store, std::uint32_t id, bool negate,
                                  const std::vector<std::string>& variables,
                                  std::span<const double> literals,
                                  std::span<const Expression> terminals) {
  Builder b(store, literals, terminals, variables.size());
  b.build(id, negate);
  return finish(std::move(b.nodes), variables);
}

}  // namespace shaderfit::search_detail
