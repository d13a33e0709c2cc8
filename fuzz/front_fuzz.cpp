// Fuzz target: a search front's JSON, as `shaderfit codegen --front FILE.json` reads it (the file
// `shaderfit search --json` writes, possibly edited by hand). parse_front_file must read it or
// throw shaderfit::Error; each member then goes through what the command does: its cost in every
// target and its code in one language.
#include "fuzz_targets.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit::fuzz {

void front(const std::uint8_t* data, std::size_t size) {
  std::vector<ReadFrontMember> members;
  try {
    // The command passes --params names to every member; `s` stands for them here.
    members = parse_front_file(as_text(data, size), "front.json", {{}, {"s"}}).front;
  } catch (const Error&) {
    return;  // the expected outcome for bad input
  }
  CodegenOptions o;
  o.language = static_cast<Language>(size % 5);
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Expression& e = members[i].member.expression;
    o.name = "f_" + std::to_string(i);
    o.bake_parameters = members[i].parameters_have_values;
    o.comment = {to_infix(e)};
    for (InstructionTarget t :
         {InstructionTarget::Sass, InstructionTarget::Ptx, InstructionTarget::Generic})
      (void)instruction_count(e, t);
    try {
      (void)generate_function(e, o);
    } catch (const Error&) {
      // names the language reserves, parameter values that are not finite in float32: documented
    }
  }
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(front)
