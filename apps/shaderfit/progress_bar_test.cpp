#include "progress_bar.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "cli.hpp"
#include "cli_test_util.hpp"

namespace shaderfit::cli::testing {
namespace {

TEST(ProgressBar, FormatsTheLine) {
  EXPECT_EQ(format_progress_line("lut", 0.25, "16384/65536 cells", 0.84, 80),
            "lut [#####---------------]  25%  16384/65536 cells  0.8 s");
  EXPECT_EQ(format_progress_line("fit", 0.0, "", 0, 80), "fit [--------------------]   0%  0.0 s");
  EXPECT_EQ(format_progress_line("fit", 1.0, "9/9 blocks", 12.34, 80),
            "fit [####################] 100%  9/9 blocks  12.3 s");
  // Out of range is clamped; unknown (negative) shows no bar.
  EXPECT_EQ(format_progress_line("x", 1.5, "", 1, 80), "x [####################] 100%  1.0 s");
  EXPECT_EQ(format_progress_line("search", -1, "front 3", 2, 80), "search  front 3  2.0 s");
  // Narrow terminals: the detail is cut first, then the line; never the full width.
  EXPECT_EQ(format_progress_line("lut", 0.5, "16384/65536 cells", 1, 50),
            "lut [##########----------]  50%  16384/655  1.0 s");
  EXPECT_EQ(format_progress_line("lut", 0.5, "16384/65536 cells", 1, 50).size(), 49u);
  EXPECT_EQ(format_progress_line("lut", 0.5, "16384/65536 cells", 1, 40),
            "lut [##########----------]  50%  1.0 s");
  EXPECT_EQ(format_progress_line("lut", 0.5, "cells", 1, 20), "lut [##########----");
  EXPECT_EQ(format_progress_line("lut", 0.5, "cells", 1, 0), "");
}

TEST(ProgressBar, PrintsNothingWhenNotATerminal) {
  std::ostringstream out, err;
  Context ctx{out, err, false};
  {
    ProgressBar bar(ctx, "lut", 0.0);
    EXPECT_FALSE(bar.active());
    EXPECT_FALSE(bar.callback());  // the library is given no callback
    for (std::size_t i = 0; i <= 100; ++i) bar.update(Progress{i, 100, "cells"});
    bar.update(0.5, "half");
    bar.clear();
  }
  EXPECT_EQ(err.str(), "");
  EXPECT_EQ(out.str(), "");
}

TEST(ProgressBar, DrawsOnATerminalAtMostTenTimesASecondAndClears) {
  std::ostringstream out, err;
  Context ctx{out, err, true};
  {
    ProgressBar bar(ctx, "lut", 0.0);
    ASSERT_TRUE(bar.active());
    const ProgressCallback report = bar.callback();
    ASSERT_TRUE(report);
    report(Progress{1, 4, "cells"});
    report(Progress{2, 4, "cells"});  // within 0.1 s of the first: not drawn
    EXPECT_EQ(err.str().rfind("\rlut [#####---------------]  25%  1/4 cells  0.0 s\033[K", 0), 0u)
        << err.str();
    EXPECT_EQ(err.str().find("2/4"), std::string::npos) << err.str();
    bar.clear();
    EXPECT_EQ(err.str().substr(err.str().size() - 4), "\r\033[K");
  }
  // Cleared once: the destructor has nothing left to erase.
  EXPECT_EQ(err.str().find("\r\033[K\r\033[K"), std::string::npos);
  EXPECT_EQ(out.str(), "");
}

TEST(ProgressBar, WaitsBeforeTheFirstDraw) {
  std::ostringstream out, err;
  Context ctx{out, err, true};
  ProgressBar bar(ctx, "fit");  // the default delay: a command that ends sooner shows no bar
  bar.update(0.5, "");
  EXPECT_EQ(err.str(), "");
}

// The commands in a test (not a terminal) print no progress.
TEST(ProgressBar, CommandsPrintNoProgressOutsideATerminal) {
  const CliResult lut = run({"lut", "--size", "4", "--no-files"});
  ASSERT_EQ(lut.status, 0) << lut.err;
  const CliResult fit = run({"fit", "--domain", "x=0:1:16", "--grid", "g=0:1:8", "--per-cell", "a",
                             "--param", "a=1", "--reference", "g * x", "a * x"});
  ASSERT_EQ(fit.status, 0) << fit.err;
  const CliResult search =
      run({"search", "--dataset", "fresnel-seed", "--time", "0.3", "--threads", "1", "--quiet"});
  ASSERT_EQ(search.status, 0) << search.err;
  for (const CliResult* r : {&lut, &fit, &search}) {
    EXPECT_EQ(r->err.find('\r'), std::string::npos) << r->err;
    EXPECT_EQ(r->out.find('\r'), std::string::npos) << r->out;
  }
}

}  // namespace
}  // namespace shaderfit::cli::testing
