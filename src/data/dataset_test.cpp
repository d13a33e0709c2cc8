#include "shaderfit/data/dataset.hpp"

#include <gtest/gtest.h>

#include <string>

namespace shaderfit {
namespace {

Dataset small() {
  Dataset d;
  d.source = "data.csv";
  d.header_line = 1;
  d.add_numeric("r0", {0.04, 0.5});
  d.add_numeric("x", {0.1, 0.2});
  d.add_text("material", {"glass", "gold"});
  return d;
}

TEST(DataDataset, AddFindAndNames) {
  Dataset d = small();
  EXPECT_EQ(d.rows(), 2u);
  EXPECT_EQ(d.names(), (std::vector<std::string>{"r0", "x", "material"}));
  ASSERT_NE(d.find("x"), nullptr);
  EXPECT_EQ(d.find("x")->values[1], 0.2);
  EXPECT_EQ(d.find("nope"), nullptr);
  EXPECT_TRUE(d.column("r0").numeric());
  EXPECT_FALSE(d.column("material").numeric());
  EXPECT_EQ(d.column("material").size(), 2u);
  EXPECT_EQ(d.numeric("r0").values[0], 0.04);
  EXPECT_EQ(Dataset{}.rows(), 0u);
}

TEST(DataDataset, MissingColumnListsTheColumns) {
  Dataset d = small();
  try {
    (void)d.column("R");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "no column 'R' in data.csv (columns: r0, x, material)");
    EXPECT_EQ(e.where().source, "data.csv");
    EXPECT_EQ(e.where().line, 1);
    EXPECT_STREQ(e.what(), "data.csv:1: no column 'R' in data.csv (columns: r0, x, material)");
  }
  EXPECT_THROW((void)d.numeric("R"), Error);
}

TEST(DataDataset, TextColumnIsNotNumeric) {
  Dataset d = small();
  d.add_text("id", {"7", "seven"});
  try {
    (void)d.numeric("id");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "column 'id' is not numeric: 'seven' in row 2");
    EXPECT_EQ(e.where().source, "data.csv");  // built in code: no cell location
  }
}

TEST(DataDataset, AddRejectsBadColumns) {
  Dataset d = small();
  EXPECT_THROW(d.add_numeric("x", {1, 2}), Error);
  EXPECT_THROW(d.add_numeric("", {1, 2}), Error);
  EXPECT_THROW(d.add_text("y", {"a"}), Error);
  try {
    d.add_numeric("y", {1, 2, 3});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "column 'y' has 3 rows, the data set has 2");
  }
  EXPECT_EQ(d.columns.size(), 3u);
}

}  // namespace
}  // namespace shaderfit
