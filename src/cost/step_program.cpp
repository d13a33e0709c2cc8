#include "cost/step_program.hpp"

#include <algorithm>
#include <array>

#include "shaderfit/core/error.hpp"

namespace shaderfit::cost_detail {

namespace {

// An operand as planned: a DAG node wanted with a sign, or a literal.
struct Want {
  int id = -1;
  bool neg = false;
  bool literal = false;
  float value = 0.0f;
};

struct Plan {
  Op op = Op::Add;
  std::array<Want, 3> args{};
  int arity = 0;
  int cost = 0;          // negations this form asks of operands that cannot give them for free
  int skip = -1;         // a single-use operand folded into this step (Rcp into Div, Log2 into Log)
  bool neg_arg = false;  // Exp in fused programs: exp(-x) with the sign folded into its scale
  bool valid = false;
};

class ProgramBuilder {
 public:
  ProgramBuilder(const Dag& dag, bool fused)
      : dag_(dag),
        fused_(fused),
        n_(dag.nodes.size()),
        fused_slot_(n_, -1),
        fuse_count_(n_, 0),
        skipped_(n_, false),
        want_(n_, {0, 0}),
        chosen_(n_),
        sign_(n_, false) {}

  Program build() {
    if (fused_) choose_fusions();
    for (const DagRef& r : dag_.roots) want_[static_cast<std::size_t>(r.id)][r.neg ? 1 : 0]++;
    for (std::size_t i = n_; i-- > 0;) plan_node(static_cast<int>(i));
    return emit();
  }

 private:
  const DagNode& node(int id) const { return dag_.node(id); }
  bool is_const(int id) const { return dag_.is_const(id); }
  int uses(int id) const { return dag_.uses[static_cast<std::size_t>(id)]; }

  // Each add takes one product operand into an FMA: the one with fewer uses (the first on a tie).
  void choose_fusions() {
    for (std::size_t i = 0; i < n_; ++i) {
      const DagNode& nd = dag_.nodes[i];
      if (!dag_.live(static_cast<int>(i)) || nd.op != Op::Add) continue;
      int slot = -1;
      for (int k = 0; k < 2; ++k) {
        const int c = (k == 0 ? nd.a : nd.b).id;
        if (node(c).op != Op::Mul) continue;
        const int best = slot < 0 ? -1 : (slot == 0 ? nd.a : nd.b).id;
        if (slot < 0 || uses(c) < uses(best)) slot = k;
      }
      if (slot < 0) continue;
      fused_slot_[i] = slot;
      ++fuse_count_[static_cast<std::size_t>((slot == 0 ? nd.a : nd.b).id)];
    }
  }

  // True when the node can be emitted with either sign at no extra cost.
  bool flexible(int id) const {
    const DagNode& nd = node(id);
    switch (nd.op) {
      case Op::Const: return true;
      case Op::Rcp: return true;                                    // -1 / x is one division
      case Op::Div: return is_const(nd.a.id) || is_const(nd.b.id);  // -a / K = a / -K
      case Op::Fma:  // -fma(a, K, L) = fma(a, -K, -L)
        return (is_const(nd.a.id) || is_const(nd.b.id)) && is_const(nd.c.id);
      case Op::Mul: {
        // A product flips for free when a factor does: a literal, or a single-use product or
        // reciprocal that flips (nvcc pushes negations down product chains the same way).
        if (nd.log_scale || is_const(nd.a.id) || is_const(nd.b.id)) return true;
        for (const DagRef& c : {nd.a, nd.b}) {
          const Op op = node(c.id).op;
          if ((op == Op::Mul || op == Op::Rcp) && uses(c.id) == 1 && flexible(c.id)) return true;
        }
        return false;
      }
      case Op::Add: {
        const int slot = fused_slot_[static_cast<std::size_t>(id)];
        if (slot < 0) return nd.b.neg || is_const(nd.a.id) || is_const(nd.b.id);
        const DagNode& m = node((slot == 0 ? nd.a : nd.b).id);
        const int c = (slot == 0 ? nd.b : nd.a).id;
        return (is_const(m.a.id) || is_const(m.b.id)) && is_const(c);
      }
      default: return false;
    }
  }

  Want want(int id, bool neg) const {
    if (is_const(id)) {
      const float v = node(id).value;
      return {id, neg, true, neg ? -v : v};
    }
    return {id, neg, false, 0.0f};
  }
  int neg_cost(const Want& w) const { return w.neg && !w.literal && !flexible(w.id) ? 1 : 0; }

  // The two operands of a product with the product's sign put on one of them: on a literal if
  // there is one, else on an operand that can flip for free, else on the first.
  void product_args(DagRef p, DagRef q, bool neg, Plan& pl, int first) const {
    bool neg_p = false, neg_q = false;
    if (neg) {
      if (is_const(p.id))
        neg_p = true;
      else if (is_const(q.id))
        neg_q = true;
      else if (flexible(q.id) && !flexible(p.id))
        neg_q = true;
      else
        neg_p = true;
    }
    pl.args[static_cast<std::size_t>(first)] = want(p.id, neg_p);
    pl.args[static_cast<std::size_t>(first) + 1] = want(q.id, neg_q);
  }

  Plan plan_for(int id, bool s) const {
    const DagNode& nd = node(id);
    Plan pl;
    pl.valid = true;
    auto unary = [&](Op op, Want a) {
      pl.op = op;
      pl.arity = 1;
      pl.args[0] = a;
    };
    switch (nd.op) {
      case Op::Add: {
        const int slot = fused_slot_[static_cast<std::size_t>(id)];
        pl.arity = 2;
        if (slot >= 0) {
          const DagRef mref = slot == 0 ? nd.a : nd.b, c = slot == 0 ? nd.b : nd.a;
          const DagNode& m = node(mref.id);
          pl.op = Op::Fma;
          pl.arity = 3;
          product_args(m.a, m.b, mref.neg != s, pl, 0);
          pl.args[2] = want(c.id, c.neg != s);
        } else if (!s) {
          pl.op = nd.b.neg ? Op::Sub : Op::Add;
          pl.args = {want(nd.a.id, false), want(nd.b.id, false), Want{}};
        } else if (nd.b.neg) {
          pl.op = Op::Sub;  // -(a - b) = b - a
          pl.args = {want(nd.b.id, false), want(nd.a.id, false), Want{}};
        } else {
          pl.op = Op::Sub;  // -(a + b) = -b - a or -a - b
          const bool on_b =
              is_const(nd.b.id) || (!is_const(nd.a.id) && flexible(nd.b.id) && !flexible(nd.a.id));
          pl.args = on_b ? std::array<Want, 3>{want(nd.b.id, true), want(nd.a.id, false), Want{}}
                         : std::array<Want, 3>{want(nd.a.id, true), want(nd.b.id, false), Want{}};
        }
        break;
      }
      case Op::Mul: {
        pl.arity = 2;
        pl.op = Op::Mul;
        const int log2_id = node(nd.a.id).op == Op::Log2 ? nd.a.id : nd.b.id;
        const int rcp_id =
            node(nd.b.id).op == Op::Rcp ? nd.b.id : (node(nd.a.id).op == Op::Rcp ? nd.a.id : -1);
        if (nd.log_scale && !s && uses(log2_id) == 1 &&
            fuse_count_[static_cast<std::size_t>(id)] == 0) {
          const DagRef x = node(log2_id).a;
          unary(Op::Log, want(x.id, x.neg));
          pl.skip = log2_id;
        } else if (!fused_ && !dag_.half && rcp_id >= 0 && nd.a.id != nd.b.id &&
                   uses(rcp_id) == 1) {
          const int other = rcp_id == nd.a.id ? nd.b.id : nd.a.id;
          pl.op = Op::Div;
          pl.args = {want(other, s), want(node(rcp_id).a.id, false), Want{}};
          pl.skip = rcp_id;
        } else {
          product_args(nd.a, nd.b, s, pl, 0);
        }
        break;
      }
      case Op::Div:  // half DAGs: a / b, the sign put on an operand as for a product
        pl.op = Op::Div;
        pl.arity = 2;
        product_args(nd.a, nd.b, s, pl, 0);
        break;
      case Op::Fma:  // half DAGs: -fma(a, b, c) = fma(-a, b, -c)
        pl.op = Op::Fma;
        pl.arity = 3;
        product_args(nd.a, nd.b, s, pl, 0);
        pl.args[2] = want(nd.c.id, nd.c.neg != s);
        break;
      case Op::Rcp:
        pl.op = Op::Div;
        pl.arity = 2;
        pl.args = {Want{-1, false, true, s ? -1.0f : 1.0f}, want(nd.a.id, false), Want{}};
        break;
      case Op::CopySign:  // -copysign(a, b) = copysign(a, -b)
        pl.op = Op::CopySign;
        pl.arity = 2;
        pl.args = {want(nd.a.id, false), want(nd.b.id, s), Want{}};
        break;
      case Op::Select:  // -select(a, b, c) = select(a, -b, -c)
        pl.op = Op::Select;
        pl.arity = 3;
        pl.args = {want(nd.a.id, false), want(nd.b.id, nd.b.neg != s),
                   want(nd.c.id, nd.c.neg != s)};
        pl.neg_arg = nd.a.neg;
        break;
      case Op::Min:
      case Op::Max: {
        const bool is_min = (nd.op == Op::Min) != s;  // -min(a, b) = max(-a, -b)
        pl.op = is_min ? Op::Min : Op::Max;
        pl.arity = 2;
        pl.args = {want(nd.a.id, nd.a.neg != s), want(nd.b.id, nd.b.neg != s), Want{}};
        break;
      }
      default:
        if (s) return Plan{};
        switch (nd.op) {
          case Op::Var:
          case Op::Param: pl.arity = 0; break;
          case Op::Exp:
            unary(Op::Exp, want(nd.a.id, nd.a.neg && !fused_));
            pl.neg_arg = nd.a.neg && fused_;
            break;
          default:
            // The other functions (a leaf, a power or a negation never gets here). An odd or
            // even function's operand is never negated in the DAG: dag.cpp moved its sign.
            if (is_leaf(nd.op) || arity(nd.op) > 2)
              throw Error("internal: unexpected DAG operator");
            pl.op = nd.op;
            pl.arity = arity(nd.op);
            pl.args = {want(nd.a.id, nd.a.neg), pl.arity == 2 ? want(nd.b.id, nd.b.neg) : Want{},
                       Want{}};
            break;
        }
        break;
    }
    // nvcc turns x - 1/y into a full-range division (five SASS instructions); x + -1/y stays one
    // MUFU.RCP. So a fused program never subtracts a reciprocal.
    if (fused_ && pl.op == Op::Sub && !pl.args[1].literal && node(pl.args[1].id).op == Op::Rcp) {
      pl.op = Op::Add;
      pl.args[1].neg = !pl.args[1].neg;
    }
    for (int k = 0; k < pl.arity; ++k) pl.cost += neg_cost(pl.args[static_cast<std::size_t>(k)]);
    // x*x with a sign asks one negation, not two.
    if (pl.arity >= 2 && pl.args[0].id == pl.args[1].id && pl.args[0].neg && pl.args[1].neg &&
        !pl.args[0].literal)
      --pl.cost;
    return pl;
  }

  void plan_node(int id) {
    const auto i = static_cast<std::size_t>(id);
    if (is_const(id) || skipped_[i] || (want_[i][0] == 0 && want_[i][1] == 0)) return;
    const Plan pos = plan_for(id, false), neg = plan_for(id, true);
    const int cost_pos = pos.cost + (want_[i][1] > 0 ? 1 : 0);
    const int cost_neg = neg.valid ? neg.cost + (want_[i][0] > 0 ? 1 : 0) : 1 << 20;
    const bool s = cost_neg < cost_pos || (cost_neg == cost_pos && want_[i][1] > want_[i][0]);
    chosen_[i] = s ? neg : pos;
    sign_[i] = s;
    const Plan& pl = chosen_[i];
    if (pl.skip >= 0) skipped_[static_cast<std::size_t>(pl.skip)] = true;
    for (int k = 0; k < pl.arity; ++k) {
      const Want& w = pl.args[static_cast<std::size_t>(k)];
      if (!w.literal && w.id >= 0) ++want_[static_cast<std::size_t>(w.id)][w.neg ? 1 : 0];
    }
  }

  Operand resolve(const Want& w) const {
    if (w.literal) return {Operand::Kind::Const, 0, w.value};
    const Operand& o = value_[static_cast<std::size_t>(w.id)][w.neg ? 1 : 0];
    if (o.kind == Operand::Kind::None) throw Error("internal: operand sign not emitted");
    return o;
  }

  int push(Step st) {
    prog_.steps.push_back(st);
    return static_cast<int>(prog_.steps.size()) - 1;
  }

  Program emit() {
    prog_.fused = fused_;
    value_.assign(n_, {});
    for (std::size_t i = 0; i < n_; ++i) {
      const int id = static_cast<int>(i);
      if (is_const(id) || skipped_[i] || (want_[i][0] == 0 && want_[i][1] == 0)) continue;
      const Plan& pl = chosen_[i];
      const bool s = sign_[i];
      Operand self;
      if (pl.arity == 0) {
        self = {node(id).op == Op::Var ? Operand::Kind::Var : Operand::Kind::Param, node(id).index,
                0.0f};
      } else {
        Step st;
        st.op = pl.op;
        st.arity = pl.arity;
        st.dag_id = id;
        st.negated = s;
        st.neg_arg = pl.neg_arg;
        for (int k = 0; k < pl.arity; ++k)
          st.args[k] = resolve(pl.args[static_cast<std::size_t>(k)]);
        self = {Operand::Kind::Step, push(st), 0.0f};
      }
      value_[i][s ? 1 : 0] = self;
      if (want_[i][s ? 0 : 1] > 0) {
        Step ng;
        ng.op = Op::Neg;
        ng.arity = 1;
        ng.args[0] = self;
        ng.dag_id = id;
        ng.negated = !s;
        value_[i][s ? 0 : 1] = {Operand::Kind::Step, push(ng), 0.0f};
      }
    }
    for (const DagRef& root : dag_.roots) prog_.results.push_back(resolve(want(root.id, root.neg)));
    for (Step& st : prog_.steps) {
      for (int k = 0; k < st.arity; ++k)
        if (st.args[k].kind == Operand::Kind::Step)
          ++prog_.steps[static_cast<std::size_t>(st.args[k].index)].uses;
    }
    for (const Operand& r : prog_.results)
      if (r.kind == Operand::Kind::Step) ++prog_.steps[static_cast<std::size_t>(r.index)].uses;
    if (!dag_.half) mark_compared();
    return std::move(prog_);
  }

  // Step.compared: a difference every reader of which compares it with zero (half programs
  // keep their differences: evaluate_half rounds them).
  void mark_compared() {
    std::vector<int> as_condition(prog_.steps.size(), 0);
    for (const Step& st : prog_.steps) {
      if (st.op != Op::Select) continue;
      if (st.args[0].kind == Operand::Kind::Step) ++as_condition[static_cast<std::size_t>(st.args[0].index)];
      for (int k : {1, 2})  // also read as a branch: computed
        if (st.args[k].kind == Operand::Kind::Step) as_condition[static_cast<std::size_t>(st.args[k].index)] = -kMaxUses;
    }
    for (std::size_t i = 0; i < prog_.steps.size(); ++i) {
      Step& st = prog_.steps[i];
      const bool literal_sum = st.op == Op::Add && (st.args[0].kind == Operand::Kind::Const ||
                                                    st.args[1].kind == Operand::Kind::Const);
      if ((st.op == Op::Sub || literal_sum) && as_condition[i] > 0 && as_condition[i] == st.uses) st.compared = true;
    }
  }
  static constexpr int kMaxUses = 1 << 30;

  const Dag& dag_;
  bool fused_;
  std::size_t n_;
  std::vector<int> fused_slot_, fuse_count_;
  std::vector<bool> skipped_;
  std::vector<std::array<int, 2>> want_;
  std::vector<Plan> chosen_;
  std::vector<bool> sign_;
  std::vector<std::array<Operand, 2>> value_;
  Program prog_;
};

}  // namespace

Program build_program(const Dag& dag, bool fused) {
  return ProgramBuilder(dag, fused && !dag.half).build();
}

Comparison select_comparison(const Program& p, const Step& select) {
  const Operand& a = select.args[0];
  if (a.kind == Operand::Kind::Step) {
    const Step& d = p.steps[static_cast<std::size_t>(a.index)];
    if (d.compared) {
      if (d.op == Op::Sub) return {d.args[0], d.args[1]};
      // a + K >= 0 is a >= -K.
      const int k = d.args[0].kind == Operand::Kind::Const ? 0 : 1;
      Operand rhs = d.args[k];
      rhs.value = -rhs.value;
      return {d.args[1 - k], rhs};
    }
  }
  return {a, Operand{Operand::Kind::Const, 0, 0.0f}};
}

StepReaders::StepReaders(const Program& p) : p_(p), readers_(p.steps.size()) {
  for (std::size_t i = 0; i < p.steps.size(); ++i)
    for (int k = 0; k < p.steps[i].arity; ++k)
      if (p.steps[i].args[k].kind == Operand::Kind::Step)
        readers_[static_cast<std::size_t>(p.steps[i].args[k].index)].push_back(static_cast<int>(i));
}

bool StepReaders::is_result(int s) const {
  return std::any_of(p_.results.begin(), p_.results.end(),
                     [&](const Operand& r) { return r.kind == Operand::Kind::Step && r.index == s; });
}

int StepReaders::only_reader(int s) const {
  const auto& r = of(s);
  return p_.steps[static_cast<std::size_t>(s)].uses == 1 && r.size() == 1 ? r[0] : -1;
}

}  // namespace shaderfit::cost_detail
