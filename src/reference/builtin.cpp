#include "shaderfit/reference/builtin.hpp"

#include <array>
#include <numbers>

#include "shaderfit/reference/builtin_evaluate.hpp"

namespace shaderfit::reference {

namespace {

using Names = std::span<const std::string_view>;

constexpr std::string_view kSchlick[] = {"cos_theta", "r0"};
constexpr std::string_view kSchlickSymbols[] = {"cos", "F0"};
constexpr std::string_view kDielectric[] = {"cos_theta", "ior"};
constexpr std::string_view kDielectricSymbols[] = {"cos", "ior"};
constexpr std::string_view kDielectricF0[] = {"cos", "F0"};
constexpr std::string_view kConductor[] = {"cos_theta", "ior_n", "ior_k"};
constexpr std::string_view kConductorSymbols[] = {"cos", "eta", "kappa"};
constexpr std::string_view kFv[] = {"dot_lh", "f0", "roughness"};
constexpr std::string_view kFvConductor[] = {"dot_lh", "ior_n", "ior_k", "roughness"};
constexpr std::string_view kSmithG1[] = {"v", "alpha"};
constexpr std::string_view kGgxD[] = {"cos", "alpha"};
constexpr std::string_view kX[] = {"x"};

constexpr unsigned kFit = FitReference, kRational = RationalTarget, kBoth = kFit | kRational;
constexpr double kHalfPi = std::numbers::pi / 2;

const std::array<BuiltinFunction, 22> kTable = {{
    {BuiltinId::FresnelSchlick,
     "fresnel-schlick",
     "F0 + (1 - F0)(1 - cos)^5",
     kSchlick,
     kSchlickSymbols,
     {0, 1},
     kBoth},
    {BuiltinId::FresnelSeed,
     "fresnel-seed",
     "seed 001: r0 + (x - r0) x^4, x = 1 - cos",
     kSchlick,
     {},
     {0, 1},
     kFit},
    {BuiltinId::FresnelDielectric,
     "fresnel-dielectric",
     "exact unpolarized dielectric reflectance, relative index ior",
     kDielectric,
     kDielectricSymbols,
     {0, 1},
     kBoth},
    {BuiltinId::FresnelDielectricF0,
     "fresnel-dielectric-f0",
     "exact dielectric reflectance for the index with normal reflectance F0",
     kDielectricF0,
     {},
     {0, 1},
     kRational},
    {BuiltinId::FresnelConductor,
     "fresnel-conductor",
     "exact conductor reflectance, complex index eta + i kappa",
     kConductor,
     kConductorSymbols,
     {0, 1},
     kBoth},
    {BuiltinId::FresnelExact,
     "fresnel-exact",
     "exact Fresnel: dielectric where ior_k = 0, else conductor",
     kConductor,
     {},
     {0, 1},
     kFit},
    {BuiltinId::FvSchlickSmithLh,
     "fv-schlick-smith-lh",
     "seed 002: Schlick F x Schlick-Smith V in dot(L,H) (Hable)",
     kFv,
     {},
     {0, 1},
     kFit},
    {BuiltinId::FvSchlickSmith,
     "fv-schlick-smith",
     "Schlick F x Schlick-Smith V at n = h",
     kFv,
     {},
     {0, 1},
     kFit},
    {BuiltinId::FvExact,
     "fv-exact",
     "exact dielectric F (IOR from f0) x exact Smith GGX V at n = h",
     kFv,
     {},
     {0, 1},
     kFit},
    {BuiltinId::FvExactConductor,
     "fv-exact-conductor",
     "exact conductor F (n + ik) x exact Smith GGX V at n = h",
     kFvConductor,
     {},
     {0, 1},
     kFit},
    {BuiltinId::SmithGgxG1,
     "smith-ggx-g1",
     "Smith GGX masking 2v / (v + sqrt(alpha^2 + (1 - alpha^2) v^2))",
     kSmithG1,
     {},
     {0, 1},
     kRational},
    {BuiltinId::GgxDistribution,
     "ggx-d",
     "GGX distribution alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2)",
     kGgxD,
     {},
     {0, 1},
     kRational},
    {BuiltinId::Exp, "exp", "e^x", kX, {}, {-1, 1}, kRational},
    {BuiltinId::Exp2, "exp2", "2^x", kX, {}, {0, 1}, kRational},
    {BuiltinId::Log, "log", "natural logarithm", kX, {}, {1, 2}, kRational},
    {BuiltinId::Log2, "log2", "base-2 logarithm", kX, {}, {1, 2}, kRational},
    {BuiltinId::Atan, "atan", "arc tangent", kX, {}, {-1, 1}, kRational},
    {BuiltinId::Sin, "sin", "sine", kX, {}, {0, kHalfPi}, kRational},
    {BuiltinId::Cos, "cos", "cosine", kX, {}, {0, kHalfPi}, kRational},
    {BuiltinId::Sqrt, "sqrt", "square root", kX, {}, {0.25, 1}, kRational},
    {BuiltinId::Rsqrt, "rsqrt", "reciprocal square root", kX, {}, {0.25, 1}, kRational},
    {BuiltinId::Rcp, "rcp", "reciprocal", kX, {}, {1, 2}, kRational},
}};

}  // namespace

std::span<const BuiltinFunction> builtin_functions() { return kTable; }

const BuiltinFunction* find_builtin(std::string_view name, BuiltinList list) {
  for (const BuiltinFunction& f : kTable)
    if (f.name == name && f.listed_in(list)) return &f;
  return nullptr;
}

double evaluate_builtin(const BuiltinFunction& f, std::span<const double> args) {
  return evaluate_builtin<double>(f.id, args);
}

}  // namespace shaderfit::reference
