#include "shaderfit/expr/expression.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

void Expression::update_lengths() {
  // A stack of subtree sizes replays the postfix order.
  std::vector<std::uint32_t> sizes;
  sizes.reserve(nodes.size());
  for (Node& n : nodes) {
    const int a = arity(n.op);
    if (static_cast<int>(sizes.size()) < a) {
      throw Error("malformed expression: operator '" + std::string(op_info(n.op).name) +
                  "' lacks operands");
    }
    std::uint32_t total = 0;
    for (int k = 0; k < a; ++k) {
      total += sizes.back();
      sizes.pop_back();
    }
    n.arity = static_cast<std::uint8_t>(a);
    n.length = total;
    sizes.push_back(total + 1);
  }
  if (sizes.size() != 1) throw Error("malformed expression: not a single tree");
}

void Expression::child_indices(std::size_t i, std::span<std::size_t> out) const {
  const int a = nodes[i].arity;
  std::size_t j = i - 1;
  for (int k = a - 1; k >= 0; --k) {
    out[static_cast<std::size_t>(k)] = j;
    if (k > 0) j = j - nodes[j].length - 1;
  }
}

void Expression::drop_unused_variables() {
  std::vector<int> remap(variables.size(), -1);
  for (const Node& n : nodes)
    if (n.op == Op::Var) remap.at(static_cast<std::size_t>(n.index)) = 0;
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < variables.size(); ++i) {
    if (remap[i] < 0) continue;
    remap[i] = static_cast<int>(kept.size());
    kept.push_back(variables[i]);
  }
  for (Node& n : nodes)
    if (n.op == Op::Var) n.index = static_cast<std::int16_t>(remap[static_cast<std::size_t>(n.index)]);
  variables = std::move(kept);
}

Expression Expression::subtree(std::size_t i) const {
  Expression s;
  s.nodes.assign(nodes.begin() + static_cast<std::ptrdiff_t>(subtree_begin(i)),
                 nodes.begin() + static_cast<std::ptrdiff_t>(i) + 1);
  s.variables = variables;
  s.parameters = parameters;
  s.parameter_values = parameter_values;
  return s;
}

namespace {

std::uint64_t mix(std::uint64_t h) {
  // splitmix64 finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

std::uint64_t hash_string(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

}  // namespace

std::vector<std::uint64_t> subtree_hashes(const Expression& e) {
  std::vector<std::uint64_t> h(e.nodes.size());
  std::size_t kids[3];
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    std::uint64_t v = mix(static_cast<std::uint64_t>(n.op) + 0x9e3779b97f4a7c15ULL);
    switch (n.op) {
      case Op::Const: {
        double d = n.value == 0.0 ? 0.0 : n.value;  // +0 and -0 hash alike
        v = mix(v ^ std::bit_cast<std::uint64_t>(d));
        break;
      }
      case Op::Var:
        v = mix(v ^ hash_string(e.variables.at(static_cast<std::size_t>(n.index))));
        break;
      case Op::Param:
        v = mix(v ^ hash_string(e.parameters.at(static_cast<std::size_t>(n.index))));
        break;
      case Op::IPow: v = mix(v ^ static_cast<std::uint64_t>(n.index + 1000)); break;
      default: break;
    }
    if (n.arity > 0) {
      e.child_indices(i, std::span<std::size_t>(kids, n.arity));
      if (op_info(n.op).commutative) {
        std::uint64_t sum = 0, x = 0;
        for (int k = 0; k < n.arity; ++k) {
          sum += h[kids[k]];
          x ^= mix(h[kids[k]]);
        }
        v = mix(v ^ mix(sum) ^ (x << 1));
      } else {
        for (int k = 0; k < n.arity; ++k) v = mix(v * 31 + h[kids[k]]);
      }
    }
    h[i] = v;
  }
  return h;
}

std::uint64_t structural_hash(const Expression& e) {
  if (e.nodes.empty()) return 0;
  return subtree_hashes(e).back();
}

std::string unused_name_prefix(const Expression& e, char letter) {
  std::string prefix(1, letter);
  const auto taken = [&](const std::string& n) {
    return n.size() > prefix.size() && n.starts_with(prefix) &&
           std::all_of(n.begin() + static_cast<std::ptrdiff_t>(prefix.size()), n.end(),
                       [](char c) { return c >= '0' && c <= '9'; });
  };
  while (std::any_of(e.variables.begin(), e.variables.end(), taken) ||
         std::any_of(e.parameters.begin(), e.parameters.end(), taken))
    prefix.insert(prefix.begin(), '_');
  return prefix;
}

std::size_t operator_count(const Expression& e) {
  return static_cast<std::size_t>(
      std::count_if(e.nodes.begin(), e.nodes.end(), [](const Node& n) { return n.arity > 0; }));
}

bool operator==(const Expression& a, const Expression& b) {
  if (a.nodes.size() != b.nodes.size()) return false;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const Node& x = a.nodes[i];
    const Node& y = b.nodes[i];
    if (!(x == y)) return false;
    if (x.op == Op::Var && a.variables.at(static_cast<std::size_t>(x.index)) !=
                               b.variables.at(static_cast<std::size_t>(y.index)))
      return false;
    if (x.op == Op::Param && a.parameters.at(static_cast<std::size_t>(x.index)) !=
                                 b.parameters.at(static_cast<std::size_t>(y.index)))
      return false;
  }
  return true;
}

Op op_from_name(std::string_view name) {
  for (int i = 0; i < kOpCount; ++i) {
    const Op op = static_cast<Op>(i);
    if (is_leaf(op) || op == Op::Neg || op == Op::IPow) continue;
    if (kOpInfo[i].name == name) return op;
  }
  return Op::Count_;
}

double inverse_erf(double y) {
  if (std::isnan(y) || std::fabs(y) > 1) return std::numeric_limits<double>::quiet_NaN();
  if (std::fabs(y) == 1) return std::copysign(std::numeric_limits<double>::infinity(), y);
  const double a = std::fabs(y);
  double x = 0;
  if (a <= 0.5) {
    // Newton's method on erf(x) = a from the first term of erf's series.
    x = a * std::sqrt(std::numbers::pi) / 2;
    for (int i = 0; i < 50; ++i) {
      const double step = (std::erf(x) - a) / (2 / std::sqrt(std::numbers::pi) * std::exp(-x * x));
      x -= step;
      if (std::fabs(step) <= 1e-16 * x) break;
    }
  } else {
    // On log erfc(x) = log(1 - a), nearly a parabola in x: 1 - a is exact here, and the
    // logarithm keeps the steps good far in the tail.
    const double target = std::log(1 - a);
    x = std::sqrt(-target);
    for (int i = 0; i < 100; ++i) {
      const double e = std::erfc(x);
      const double slope = -2 / std::sqrt(std::numbers::pi) * std::exp(-x * x) / e;
      const double step = (std::log(e) - target) / slope;
      x = std::max(x - step, 0.5 * x);
      if (std::fabs(step) <= 1e-16 * x) break;
    }
  }
  return std::copysign(x, y);
}

}  // namespace shaderfit
