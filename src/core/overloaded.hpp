// Overloaded{f, g, ...}: one callable from several lambdas, for std::visit over a variant whose
// alternatives each need their own code.
#pragma once

namespace shaderfit {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace shaderfit
