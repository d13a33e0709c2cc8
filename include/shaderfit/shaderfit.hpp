// Everything public in shaderfit, for programs that do not mind the compile time. Libraries and
// shaderfit's own sources include the one header per concept they use instead.
#pragma once

#include "shaderfit/core.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/data/csv.hpp"
#include "shaderfit/data/dataset.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/dataset_eval.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/expr/op.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"
