// Fuzz target: a search checkpoint, as `shaderfit search --resume FILE` reads it. An input that
// starts with the checkpoint's first line is read as a whole file (header checks, checksum);
// any other input is taken as the JSON body and given a header with a matching checksum, so that
// the fuzzer reaches the body's reader instead of stopping at the checksum; in a body, the string
// "@rng" stands for a generator's state (some 6 KB of text, too long for the fuzzer to carry
// about). parse_checkpoint must
// read it or throw shaderfit::Error; a checkpoint it read must write back to text that reads
// again and writes the same text (the round trip a resumed run relies on), and must pass or be
// refused by the check against a search's data and options.
#include <fmt/format.h>

#include <locale>
#include <sstream>
#include <string>

#include "fuzz_targets.hpp"
#include "core/hash.hpp"
#include "search/checkpoint.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"

namespace shaderfit::fuzz {

namespace {

// The body with each "@rng" replaced by the state of a freshly seeded generator, as JSON text.
std::string expand_rng(std::string_view body) {
  static const std::string state = [] {
    std::ostringstream out;
    out.imbue(std::locale::classic());
    out << Rng(1);
    return '"' + out.str() + '"';
  }();
  std::string out;
  constexpr std::string_view token = "\"@rng\"";
  std::size_t at = 0;
  while (true) {
    const std::size_t next = body.find(token, at);
    out += body.substr(at, next - at);
    if (next == std::string_view::npos) return out;
    out += state;
    at = next + token.size();
  }
}

std::string with_header(std::string_view text) {
  const std::string body = expand_rng(text);
  const std::string head =
      fmt::format("shaderfit checkpoint\nformat {}\nshaderfit {}\n",
                  search_detail::kCheckpointFormat, search_detail::checkpoint_writer_version());
  return head +
         fmt::format("fnv1a64 {:016x}\n",
                     core_detail::fnv1a64(body, core_detail::fnv1a64(head))) +
         body;
}

}  // namespace

void checkpoint(const std::uint8_t* data, std::size_t size) {
  using namespace search_detail;
  const std::string_view text = as_text(data, size);
  const std::string file =
      text.starts_with("shaderfit checkpoint\n") ? std::string(text) : with_header(text);
  Checkpoint c;
  try {
    c = parse_checkpoint(file, "fuzz.ckpt");
  } catch (const Error&) {
    return;  // the expected outcome for bad input
  }
  const std::string written = checkpoint_text(c);
  Checkpoint again;
  try {
    again = parse_checkpoint(written, "written.ckpt");
  } catch (const Error& e) {
    throw FuzzFailure(std::string("a checkpoint that was read does not read back: ") + e.what());
  }
  if (checkpoint_text(again) != written)
    throw FuzzFailure("a checkpoint read back writes other text:\n" + written);
  // A small search problem over the checkpoint's inputs: the check compares data and options and
  // must refuse a mismatch with an Error, whatever the checkpoint holds.
  SearchProblem problem;
  problem.input_names = c.input_names;
  problem.inputs.assign(c.input_names.size(), {0.0, 0.5, 1.0});
  problem.target = {0.0, 0.25, 1.0};
  try {
    check_checkpoint_matches(c, SearchOptions{}, problem, "fuzz.ckpt");
  } catch (const Error&) {
  }
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(checkpoint)
