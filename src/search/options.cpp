// The description of SearchOptions (one entry per field) and what is generated from it:
// validation, text (checkpoints, defaults in help) and reading text back.
#include "shaderfit/search/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <type_traits>

#include "core/overloaded.hpp"

namespace shaderfit {

namespace {

// The enumeration builds every unary and binary one; select (ternary) only the evolution does.
bool searchable(Op op) { return static_cast<int>(op) < kOpCount && op_info(op).search > 0; }

std::string_view list_name(Op op) { return op == Op::IPow ? "^" : op_info(op).name; }

// The searchable operators in their order in op.hpp's search column.
std::string known_operators() {
  std::vector<std::string_view> names;
  for (int i = 0; i < kOpCount; ++i) {
    const int place = op_info(static_cast<Op>(i)).search;
    if (place == 0) continue;
    if (names.size() < static_cast<std::size_t>(place))
      names.resize(static_cast<std::size_t>(place));
    names[static_cast<std::size_t>(place - 1)] = list_name(static_cast<Op>(i));
  }
  std::string s;
  for (std::string_view name : names) {
    if (!s.empty()) s += ' ';
    s += name;
  }
  return s;
}

// Checks, as captureless lambdas the table turns into function pointers.
template <auto Member>
std::string in_range(const SearchOptions& o, double lo, double hi) {
  const double v = static_cast<double>(o.*Member);
  if (v >= lo && v <= hi) return {};
  return hi == std::numeric_limits<double>::infinity() ? fmt::format("must be at least {}", lo)
                                                       : fmt::format("must be in [{}, {}]", lo, hi);
}

std::string searchable_ops(const std::vector<Op>& ops) {
  if (is_auto_operators(ops)) return {};
  for (Op op : ops)
    if (op == Op::Count_) return "'auto' must be the only operator";
  for (Op op : ops)
    if (!searchable(op))
      return "operator '" + std::string(op_info(op).name) + "' cannot be searched";
  return {};
}

constexpr double kNoLimit = std::numeric_limits<double>::infinity();

using O = SearchOptions;
using Role = OptionRole;

// The description. Help lines are the command line's (the CLI adds "(default ...)").
const SearchOptionField kFields[] = {
    {.name = "time_limit_s",
     .member = &O::time_limit_s,
     .role = Role::Budget,
     .help = "time budget in seconds",
     .check =
         [](const O& o) {
           return o.time_limit_s > 0 && std::isfinite(o.time_limit_s)
                      ? std::string()
                      : fmt::format("the time budget must be positive (got {})", o.time_limit_s);
         }},
    {.name = "max_candidates",
     .member = &O::max_candidates,
     .role = Role::Budget,
     .help = "budget of candidate formulas evaluated",
     .may_be_empty = true,
     .check =
         [](const O& o) {
           return !o.max_candidates || *o.max_candidates > 0
                      ? std::string()
                      : fmt::format("the evaluation budget must be positive (got {})",
                                    *o.max_candidates);
         }},
    {.name = "seed", .member = &O::seed, .role = Role::Search, .help = "seed of the search"},
    {.name = "threads",
     .member = &O::threads,
     .role = Role::Run,
     .help = "threads, 0 for all cores",
     .check =
         [](const O& o) {
           return o.threads >= 0 ? std::string() : "threads must be >= 0 (0: all cores)";
         }},
    {.name = "device",
     .member = &O::device,
     .role = Role::Run,
     .help = "cpu, cuda or auto: where the evolution scores its children",
     .default_note = ": the GPU when this build has CUDA and one is present",
     .choices = "auto, cpu, cuda"},
    {.name = "loss",
     .member = &O::loss,
     .role = Role::Search,
     .help = "mse, rmse, max_abs, max_rel, rel or log; or display, on a scene: the error of the "
             "displayed pixels (docs/scenes.md)",
     .choices = "mse, rmse, max_abs, max_rel, rel, log, display"},
    {.name = "precision",
     .member = &O::precision,
     .role = Role::Search,
     .help = "the arithmetic the shader runs the formula in: double, float or half; the front "
             "ranks each formula's error computed in it",
     .choices = "double, float, half"},
    {.name = "cost",
     .member = &O::cost,
     .role = Role::Search,
     .help = "what the front's cost counts: instructions (NVIDIA SASS), rdna2 or rdna3 (AMD "
             "RDNA 2 and 3 VALU instructions), or nodes",
     .choices = "instructions, rdna2, rdna3, nodes"},
    {.name = "operators",
     .member = &O::operators,
     .role = Role::Search,
     .help =
         "operators, comma-separated: + - * / ^ sqrt rsqrt rcp exp2 log2 exp log abs saturate sin "
         "cos min max pow sign copysign select asin acos atan atan2 tanh erf; or auto: chosen "
         "from the data",
     .check =
         [](const O& o) {
           return o.operators.empty() ? "no operators given" : searchable_ops(o.operators);
         }},
    {.name = "evolution_operators",
     .member = &O::evolution_operators,
     .role = Role::Search,
     .help = "more operators for the evolution only, 'none', or 'auto'",
     .may_be_empty = true,
     .check = [](const O& o) { return searchable_ops(o.evolution_operators); }},
    {.name = "literals",
     .member = &O::literals,
     .role = Role::Search,
     .help = "literal constants, comma-separated",
     .check =
         [](const O& o) {
           if (o.literals.size() > 100) return std::string("at most 100 literal constants");
           for (double v : o.literals)
             if (!std::isfinite(v)) return std::string("literal constants must be finite");
           return std::string();
         }},
    {.name = "start",
     .member = &O::start,
     .role = Role::Search,
     .help = "start from this formula (repeatable): it joins the front as written and with its "
             "number literals refitted, and seeds the evolution",
     .may_be_empty = true,
     .check =
         [](const O& o) {
           return o.start.size() <= 100 ? std::string() : std::string("at most 100 formulas");
         }},
    {.name = "symmetry",
     .member = &O::symmetry,
     .role = Role::Search,
     .help = "when the data is even, odd or point-symmetric in an input, search the half where "
             "it is >= 0 and add the reflection"},
    {.name = "uniform",
     .member = &O::uniform,
     .role = Role::Search,
     .help = "inputs constant per material (comma-separated): what reads only them is computed "
             "once per material, and the cost is per pixel",
     .may_be_empty = true,
     .names = true,
     .check =
         [](const O& o) {
           for (std::size_t k = 0; k < o.uniform.size(); ++k)
             if (std::find(o.uniform.begin(), o.uniform.begin() + static_cast<std::ptrdiff_t>(k),
                           o.uniform[k]) != o.uniform.begin() + static_cast<std::ptrdiff_t>(k))
               return "uniform input '" + o.uniform[k] + "' is given twice";
           return std::string();
         }},
    {.name = "max_power",
     .member = &O::max_power,
     .role = Role::Search,
     .help = "largest integer power x^k",
     .check = [](const O& o) { return in_range<&O::max_power>(o, 2, kMaxIntegerPower); }},
    {.name = "max_nodes",
     .member = &O::max_nodes,
     .role = Role::Search,
     .help = "largest formula of the evolution, in nodes",
     .check = [](const O& o) { return in_range<&O::max_nodes>(o, 1, kNoLimit); }},
    {.name = "population",
     .member = &O::population,
     .role = Role::Search,
     .help = "formulas per island of the evolution",
     .check = [](const O& o) { return in_range<&O::population>(o, 4, kNoLimit); }},
    {.name = "max_classes",
     .member = &O::max_classes,
     .role = Role::Search,
     .help = "distinct formulas the enumeration keeps; bounds the memory, about 500 bytes each",
     .check = [](const O& o) { return in_range<&O::max_classes>(o, 1024, kNoLimit); }},
    {.name = "enumerate",
     .member = &O::enumerate,
     .role = Role::Search,
     .help = "run the exhaustive enumeration"},
    {.name = "evolve", .member = &O::evolve, .role = Role::Search, .help = "run the evolution"},
    {.name = "stop_at",
     .member = &O::stop_at,
     .role = Role::Budget,
     .help = "stop once a formula has at most this loss and this cost",
     .may_be_empty = true},
    {.name = "screen_rows",
     .member = &O::screen_rows,
     .role = Role::Search,
     .help = "rows cached per distinct formula of the enumeration, to deduplicate and screen",
     .check =
         [](const O& o) {
           return o.screen_rows >= 16 && o.screen_rows % 8 == 0
                      ? std::string()
                      : std::string("must be a multiple of 8, at least 16");
         }},
    {.name = "max_enumeration_share",
     .member = &O::max_enumeration_share,
     .role = Role::Search,
     .help = "fraction of the time budget the enumeration may use",
     .check = [](const O& o) { return in_range<&O::max_enumeration_share>(o, 0, 1); }},
    {.name = "max_enumeration_cost",
     .member = &O::max_enumeration_cost,
     .role = Role::Search,
     .help = "highest cost level the enumeration reaches",
     .check = [](const O& o) { return in_range<&O::max_enumeration_cost>(o, 0, 60); }},
    {.name = "islands",
     .member = &O::islands,
     .role = Role::Search,
     .help = "sub-populations of the evolution",
     .check = [](const O& o) { return in_range<&O::islands>(o, 1, kNoLimit); }},
    {.name = "migration_interval",
     .member = &O::migration_interval,
     .role = Role::Search,
     .help = "generations between migrations of the evolution",
     .check = [](const O& o) { return in_range<&O::migration_interval>(o, 1, kNoLimit); }},
    {.name = "max_parameters",
     .member = &O::max_parameters,
     .role = Role::Search,
     .help = "free constants per formula of the evolution",
     .check = [](const O& o) { return in_range<&O::max_parameters>(o, 0, 8); }},
    {.name = "fit_rows",
     .member = &O::fit_rows,
     .role = Role::Search,
     .help = "rows the evolution fits constants and ranks formulas on",
     .check = [](const O& o) { return in_range<&O::fit_rows>(o, 8, kNoLimit); }},
    {.name = "linear_scaling",
     .member = &O::linear_scaling,
     .role = Role::Search,
     .help = "also try a * f + b for each formula of the evolution"},
    {.name = "min_step",
     .member = &O::min_step,
     .role = Role::Run,
     .help = "a costlier front member is shown only where it lowers the loss by at least this "
             "fraction of the cheaper member's shown before it (0: every step)",
     .check = [](const O& o) { return in_range<&O::min_step>(o, 0, 0.5); }},
    {.name = "progress_interval_s",
     .member = &O::progress_interval_s,
     .role = Role::Run,
     .help = "seconds between progress reports",
     .check =
         [](const O& o) {
           return o.progress_interval_s > 0 ? std::string() : std::string("must be positive");
         }},
    {.name = "checkpoint_path",
     .member = &O::checkpoint_path,
     .role = Role::Run,
     .help =
         "write the search's state to this file (atomically) every checkpoint_interval_s seconds "
         "and when it stops",
     .may_be_empty = true},
    {.name = "checkpoint_interval_s",
     .member = &O::checkpoint_interval_s,
     .role = Role::Run,
     .help = "seconds between checkpoints",
     .default_note = "; 0: every generation",
     .check =
         [](const O& o) {
           return o.checkpoint_interval_s >= 0 && std::isfinite(o.checkpoint_interval_s)
                      ? std::string()
                      : std::string("the checkpoint interval must be a number of seconds >= 0");
         }},
    {.name = "certify",
     .member = &O::certify,
     .role = Role::Run,
     .help = "with a reference: a rigorous bound of each front member's error over the whole "
             "domain (interval arithmetic)"},
    {.name = "certify_time_limit_s",
     .member = &O::certify_time_limit_s,
     .role = Role::Run,
     .help = "seconds per member for the certified bound (a looser bound when they run out)",
     .check =
         [](const O& o) {
           return o.certify_time_limit_s > 0 && std::isfinite(o.certify_time_limit_s)
                      ? std::string()
                      : std::string("must be a positive number of seconds");
         }},
    {.name = "resume_path",
     .member = &O::resume_path,
     .role = Role::Run,
     .help = "continue the search a checkpoint recorded (same data and options; the budgets may "
             "differ)",
     .may_be_empty = true},
};

std::string number_text(double v) { return fmt::format("{}", v); }

[[noreturn]] void bad_text(const SearchOptionField& f, const std::string& why) {
  throw Error(why, {search_option_location(f)});
}

double number_from(const SearchOptionField& f, std::string_view text) {
  const std::string s(text);
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.empty() || used != s.size()) bad_text(f, "not a number: '" + s + "'");
  return v;
}

template <class T>
T integer_from(const SearchOptionField& f, std::string_view text) {
  T v{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    bad_text(f, "not an integer in range: '" + std::string(text) + "'");
  return v;
}

std::vector<std::string_view> split(std::string_view list, char separator = ',') {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    std::size_t end = list.find(separator, pos);
    if (end == std::string_view::npos) end = list.size();
    std::string_view item = list.substr(pos, end - pos);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (!item.empty()) out.push_back(item);
    pos = end + 1;
  }
  return out;
}

template <class E, class FromName>
E choice_from(const SearchOptionField& f, std::string_view text, FromName from_name) {
  const auto v = from_name(text);
  if (!v)
    bad_text(f, "unknown " + std::string(f.name) + " '" + std::string(text) +
                    "' (known: " + std::string(f.choices) + ")");
  return *v;
}

}  // namespace

SearchOptions::SearchOptions() = default;

std::span<const SearchOptionField> search_option_fields() { return kFields; }

const SearchOptionField* find_search_option(std::string_view name) {
  for (const SearchOptionField& f : kFields)
    if (f.name == name) return &f;
  return nullptr;
}

OptionKind search_option_kind(const SearchOptionField& field) {
  if (field.names) return OptionKind::Names;
  return std::visit(
      Overloaded{[](double O::*) { return OptionKind::Real; },
                 [](bool O::*) { return OptionKind::Bool; },
                 [](std::string O::*) { return OptionKind::Text; },
                 [](std::optional<SearchTarget> O::*) { return OptionKind::StopTarget; },
                 [](std::vector<double> O::*) { return OptionKind::Reals; },
                 [](std::vector<std::string> O::*) { return OptionKind::Formulas; },
                 [](std::vector<Op> O::*) { return OptionKind::Operators; },
                 [](Loss O::*) { return OptionKind::Choice; },
                 [](CostTarget O::*) { return OptionKind::Choice; },
                 [](ComputeDevice O::*) { return OptionKind::Choice; },
                 [](Precision O::*) { return OptionKind::Choice; },
                 [](auto) { return OptionKind::Integer; }},
      field.member);
}

std::string_view option_kind_name(OptionKind kind) {
  switch (kind) {
    case OptionKind::Real: return "real";
    case OptionKind::Integer: return "integer";
    case OptionKind::Bool: return "bool";
    case OptionKind::Text: return "text";
    case OptionKind::StopTarget: return "stop target";
    case OptionKind::Reals: return "reals";
    case OptionKind::Formulas: return "formulas";
    case OptionKind::Names: return "names";
    case OptionKind::Operators: return "operators";
    case OptionKind::Choice: return "choice";
  }
  return "?";
}

std::string search_option_location(const SearchOptionField& field) {
  return "SearchOptions::" + std::string(field.name);
}

std::string search_option_text(const SearchOptions& o, const SearchOptionField& field) {
  return std::visit(
      Overloaded{[&](double O::*m) { return number_text(o.*m); },
                 [&](bool O::*m) { return std::string(o.*m ? "true" : "false"); },
                 [&](std::string O::*m) { return o.*m; },
                 [&](std::optional<std::int64_t> O::*m) {
                   return o.*m ? std::to_string(*(o.*m)) : std::string();
                 },
                 [&](std::optional<SearchTarget> O::*m) {
                   return o.*m ? number_text((o.*m)->max_loss) + "," + number_text((o.*m)->max_cost)
                               : std::string();
                 },
                 [&](std::vector<double> O::*m) {
                   std::string s;
                   for (double v : o.*m) s += (s.empty() ? "" : ",") + number_text(v);
                   return s;
                 },
                 [&](std::vector<std::string> O::*m) {
                   std::string s;
                   for (const std::string& f : o.*m)
                     s += (s.empty() ? "" : (field.names ? "," : "; ")) + f;
                   return s;
                 },
                 [&](std::vector<Op> O::*m) { return operator_list_name(o.*m); },
                 [&](Loss O::*m) { return std::string(loss_name(o.*m)); },
                 [&](CostTarget O::*m) { return std::string(cost_target_name(o.*m)); },
                 [&](ComputeDevice O::*m) { return std::string(device_name(o.*m)); },
                 [&](Precision O::*m) { return std::string(precision_name(o.*m)); },
                 [&](auto m) { return std::to_string(o.*m); }},
      field.member);
}

void set_search_option(SearchOptions& o, const SearchOptionField& f, std::string_view text) {
  std::visit(
      Overloaded{
          [&](double O::*m) { o.*m = number_from(f, text); },
          [&](bool O::*m) {
            if (text != "true" && text != "false")
              bad_text(f, "expected true or false, got '" + std::string(text) + "'");
            o.*m = text == "true";
          },
          [&](std::string O::*m) { o.*m = std::string(text); },
          [&](std::optional<std::int64_t> O::*m) {
            if (text.empty())
              o.*m = std::nullopt;
            else
              o.*m = integer_from<std::int64_t>(f, text);
          },
          [&](std::optional<SearchTarget> O::*m) {
            const auto parts = split(text);
            if (parts.empty()) {
              o.*m = std::nullopt;
              return;
            }
            if (parts.size() != 2) bad_text(f, "expected MAX_LOSS,MAX_COST");
            o.*m = SearchTarget{number_from(f, parts[0]), number_from(f, parts[1])};
          },
          [&](std::vector<double> O::*m) {
            std::vector<double> v;
            for (std::string_view s : split(text)) {
              const double x = number_from(f, s);
              if (!std::isfinite(x)) bad_text(f, "not a number: '" + std::string(s) + "'");
              v.push_back(x);
            }
            o.*m = std::move(v);
          },
          [&](std::vector<std::string> O::*m) {
            std::vector<std::string> v;
            for (std::string_view s : split(text, f.names ? ',' : ';')) v.emplace_back(s);
            o.*m = std::move(v);
          },
          [&](std::vector<Op> O::*m) {
            if (f.may_be_empty && (text.empty() || text == "none"))
              (o.*m).clear();
            else if (text == "auto")
              o.*m = kAutoOperators;
            else
              o.*m = parse_operator_list(text, {search_option_location(f)});
          },
          [&](Loss O::*m) { o.*m = choice_from<Loss>(f, text, loss_from_name); },
          [&](CostTarget O::*m) { o.*m = choice_from<CostTarget>(f, text, cost_target_from_name); },
          [&](ComputeDevice O::*m) {
            o.*m = choice_from<ComputeDevice>(f, text, device_from_name);
          },
          [&](Precision O::*m) { o.*m = choice_from<Precision>(f, text, precision_from_name); },
          [&](auto m) { o.*m = integer_from<std::remove_reference_t<decltype(o.*m)>>(f, text); }},
      f.member);
}

void set_search_option(SearchOptions& o, std::string_view name, std::string_view text) {
  const SearchOptionField* f = find_search_option(name);
  if (f == nullptr) throw Error("no search option '" + std::string(name) + "'", {"SearchOptions"});
  set_search_option(o, *f, text);
}

void SearchOptions::validate() const {
  for (const SearchOptionField& f : kFields) {
    if (f.check == nullptr) continue;
    std::string why = f.check(*this);
    if (!why.empty()) throw Error(why, {search_option_location(f)});
  }
}

bool SearchOptions::is_valid(std::string* why) const {
  try {
    validate();
    return true;
  } catch (const Error& e) {
    if (why != nullptr) *why = e.what();
    return false;
  }
}

std::vector<Op> parse_operator_list(std::string_view list, const SourceLocation& where) {
  std::vector<Op> ops;
  for (std::string_view name : split(list)) {
    Op op = Op::Count_;
    if (name == "^" || name == "ipow")
      op = Op::IPow;
    else if (name == "add")
      op = Op::Add;
    else if (name == "sub")
      op = Op::Sub;
    else if (name == "mul")
      op = Op::Mul;
    else if (name == "div")
      op = Op::Div;
    else
      op = op_from_name(name);
    if (!searchable(op))
      throw Error("unknown operator '" + std::string(name) + "' (known: " + known_operators() + ")",
                  where);
    if (std::find(ops.begin(), ops.end(), op) == ops.end()) ops.push_back(op);
  }
  if (ops.empty()) throw Error("no operators given (known: " + known_operators() + ")", where);
  return ops;
}

std::string operator_list_name(const std::vector<Op>& ops) {
  if (is_auto_operators(ops)) return "auto";
  std::string s;
  for (Op op : ops) {
    if (!s.empty()) s += ',';
    s += list_name(op);
  }
  return s;
}

}  // namespace shaderfit
