#include "shaderfit/data/csv.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

#include "shaderfit/core/random.hpp"

namespace shaderfit {
namespace {

// Runs `f`, which must throw Error with this message at this location.
void expect_error(const std::function<void()>& f, const std::string& message,
                  const std::string& source, int line, int column) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), message);
    EXPECT_EQ(e.where().source, source);
    EXPECT_EQ(e.where().line, line) << message;
    EXPECT_EQ(e.where().column, column) << message;
  }
}

void expect_parse_error(const std::string& text, const std::string& message, int line, int column) {
  expect_error([&] { (void)parse_csv(text, "t.csv"); }, message, "t.csv", line, column);
}

// A fresh path in the temporary directory, removed at the end of the test.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("shaderfit_csv_test_" +
               std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + name)) {}
  ~TempFile() { std::filesystem::remove_all(path_); }
  [[nodiscard]] std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(DataCsv, ParsesNumericAndTextColumns) {
  Dataset d = parse_csv("r0,x,material\n0.04,0.5,glass\n1e-3,-2,gold\n", "t.csv");
  EXPECT_EQ(d.source, "t.csv");
  EXPECT_EQ(d.header_line, 1);
  EXPECT_EQ(d.rows(), 2u);
  EXPECT_EQ(d.names(), (std::vector<std::string>{"r0", "x", "material"}));
  EXPECT_EQ(d.numeric("r0").values, (std::vector<double>{0.04, 1e-3}));
  EXPECT_EQ(d.numeric("x").values, (std::vector<double>{0.5, -2}));
  EXPECT_EQ(d.column("material").labels, (std::vector<std::string>{"glass", "gold"}));
}

TEST(DataCsv, QuotesWhitespaceCrlfBomAndBlankLines) {
  std::string text =
      "\xEF\xBB\xBF"
      " a , \"b, quoted\" ,c\r\n"
      "  1 ,\"2\", \"say \"\"hi\"\"\" \r\n"
      "+3,\t4\t,\"two\nlines\"\r\n"
      "\r\n\n   \n";
  Dataset d = parse_csv(text, "t.csv");
  EXPECT_EQ(d.names(), (std::vector<std::string>{"a", "b, quoted", "c"}));
  EXPECT_EQ(d.numeric("a").values, (std::vector<double>{1, 3}));
  EXPECT_EQ(d.numeric("b, quoted").values, (std::vector<double>{2, 4}));
  EXPECT_EQ(d.column("c").labels, (std::vector<std::string>{"say \"hi\"", "two\nlines"}));
}

TEST(DataCsv, NoFinalNewlineAndLeadingBlankLines) {
  Dataset d = parse_csv("\n\nx\n5", "t.csv");
  EXPECT_EQ(d.header_line, 3);
  EXPECT_EQ(d.numeric("x").values, (std::vector<double>{5}));
}

TEST(DataCsv, NonNumberIsReportedWhenAskedForNumbers) {
  Dataset d = parse_csv("x,R\n1,0.5\n2, abc\n3,\n", "t.csv");
  EXPECT_FALSE(d.column("R").numeric());
  EXPECT_EQ(d.column("R").labels, (std::vector<std::string>{"0.5", "abc", ""}));
  expect_error([&] { (void)d.numeric("R"); }, "column 'R' is not numeric: 'abc' in row 2", "t.csv",
               3, 4);
  expect_error([&] { (void)d.numeric("Q"); }, "no column 'Q' in t.csv (columns: x, R)", "t.csv", 1,
               0);
  // Partial numbers are not numbers.
  EXPECT_FALSE(parse_csv("x\n1.5x\n", "t.csv").column("x").numeric());
  EXPECT_FALSE(parse_csv("x\n0x10\n", "t.csv").column("x").numeric());
}

// A column of numbers never becomes text for a few cells: an empty cell or a stray word in it is
// an error at that cell, or its row is dropped and counted.
TEST(DataCsv, AGapInAColumnOfNumbersIsAnError) {
  const char* drop = " (fix them, or drop their rows: CsvOptions::drop_missing_rows)";
  expect_error([] { (void)parse_csv("a,b,c\n1,2,3\n4,,5\n", "t.csv"); },
               std::string("column 'b' is numbers but for 1 cell: this one is empty") + drop,
               "t.csv", 3, 3);
  expect_error([] { (void)parse_csv("a,b\n1,2\n3,oops\n5,6\n7,n/a\n", "t.csv"); },
               std::string("column 'b' is numbers but for 2 cells: this one is 'oops'") + drop,
               "t.csv", 3, 3);
  // Fewer numbers than other cells: a text column, as a column of labels is.
  EXPECT_FALSE(parse_csv("a,kind\n1,2\n3,gold\n4,glass\n", "t.csv").column("kind").numeric());
}

TEST(DataCsv, RowsWithGapsAreDroppedWhenAsked) {
  const Dataset d = parse_csv("a,b,label\n1,2,x\n4,,y\n5,6,z\n7,oops,w\n8,9,\n", "t.csv",
                              {.drop_missing_rows = true});
  EXPECT_EQ(d.numeric("a").values, (std::vector<double>{1, 5, 8}));
  EXPECT_EQ(d.numeric("b").values, (std::vector<double>{2, 6, 9}));
  EXPECT_EQ(d.column("label").labels, (std::vector<std::string>{"x", "z", ""}));
  EXPECT_EQ(d.dropped_rows, 2u);
  EXPECT_EQ(d.first_dropped_line, 3);
  const Dataset whole = parse_csv("a,b\n1,2\n3,4\n", "t.csv", {.drop_missing_rows = true});
  EXPECT_EQ(whole.dropped_rows, 0u);
  EXPECT_EQ(whole.first_dropped_line, 0);
  expect_error(
      [] { (void)parse_csv("a,b,c\n1,,3\n,5,6\n7,8,\n", "t.csv", {.drop_missing_rows = true}); },
      "every data row has an empty or non-number cell in a column of numbers", "t.csv", 1, 0);
}

TEST(DataCsv, ColumnsCountCharactersNotBytes) {
  Dataset d = parse_csv("name,v\n\xC3\xA9t\xC3\xA9,abc\n", "t.csv");  // "été"
  expect_error([&] { (void)d.numeric("v"); }, "column 'v' is not numeric: 'abc' in row 1", "t.csv",
               2, 5);
}

TEST(DataCsv, MissingFile) {
  TempFile missing("missing.csv");
  expect_error([&] { (void)read_csv(missing.path()); },
               "cannot open '" + missing.path() + "': No such file or directory", missing.path(), 0,
               0);
}

TEST(DataCsv, DirectoryIsNotReadable) {
  TempFile dir("dir");
  std::filesystem::create_directory(dir.path());
  try {
    (void)read_csv(dir.path());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("'" + dir.path() + "': Is a directory"), std::string::npos)
        << e.message();
    EXPECT_EQ(e.where().source, dir.path());
  }
}

TEST(DataCsv, EmptyFile) {
  expect_parse_error("", "empty file: no header row", 1, 0);
  expect_parse_error(" \n\r\n\n", "empty file: no header row", 1, 0);
}

TEST(DataCsv, BadHeaderNames) {
  expect_parse_error("a,,c\n1,2,3\n", "empty column name in the header (column 2)", 1, 3);
  expect_parse_error("a, \"\" ,c\n1,2,3\n", "empty column name in the header (column 2)", 1, 4);
  expect_parse_error("x,y,x\n1,2,3\n", "duplicate column name 'x'", 1, 5);
}

TEST(DataCsv, RaggedRows) {
  expect_parse_error("a,b,c,d,e\n1,2,3\n", "row has 3 cells, the header has 5", 2, 1);
  expect_parse_error("a,b\n1,2\n1,2, 3\n", "row has 3 cells, the header has 2", 3, 6);
  expect_parse_error("a,b\n1,2\n\n3,4\n", "row has 1 cell, the header has 2", 3, 1);
}

TEST(DataCsv, NaNAndInfinityAreRejectedAtLoad) {
  expect_parse_error("x,R\n1,2\n3,nan\n", "NaN in column 'R'", 3, 3);
  expect_parse_error("x,R\n1,NaN\n", "NaN in column 'R'", 2, 3);
  expect_parse_error("x,R\n1,-nan\n", "NaN in column 'R'", 2, 3);
  expect_parse_error("x,R\n1,  inf\n", "infinite value 'inf' in column 'R'", 2, 5);
  expect_parse_error("x,R\n1,-INF\n", "infinite value '-INF' in column 'R'", 2, 3);
  expect_parse_error("x,R\n1,Infinity\n", "infinite value 'Infinity' in column 'R'", 2, 3);
  expect_parse_error("x,R\n1,\"inf\"\n", "infinite value 'inf' in column 'R'", 2, 3);
  expect_parse_error("x,R\n1,1e999\n", "number out of range '1e999' in column 'R'", 2, 3);
  // Rejected even in a column that is otherwise text.
  expect_parse_error("m\nglass\nnan\n", "NaN in column 'm'", 3, 1);
}

TEST(DataCsv, NoDataRows) {
  expect_parse_error("a,b\n", "no data rows (only a header)", 1, 0);
  expect_parse_error("a,b\n\n  \n", "no data rows (only a header)", 1, 0);
}

TEST(DataCsv, BadQuotes) {
  expect_parse_error("a,b\n1,\"abc\n", "unterminated quoted cell", 2, 3);
  expect_parse_error("a,b\n1,\"abc\"d\n", "unexpected text after a closing quote", 2, 8);
}

TEST(DataCsv, RoundTripIsExact) {
  Rng rng(7);
  std::vector<double> values = {0.0,
                                -0.0,
                                1.0,
                                0.1,
                                1.0 / 3.0,
                                -2.5e-300,
                                std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::max(),
                                -std::numeric_limits<double>::max(),
                                123456789012345678.0};
  for (int i = 0; i < 2000; ++i) {
    double v = std::bit_cast<double>(rng());
    if (std::isfinite(v)) values.push_back(v);
    values.push_back(uniform(rng, -1, 1));
  }
  Dataset d;
  d.add_numeric("v", values);
  d.add_text("label", std::vector<std::string>(values.size(), " a, \"b\"\nc "));
  d.columns[1].labels[0] = "";
  Dataset back = parse_csv(to_csv(d), "t.csv");
  const std::vector<double>& got = back.numeric("v").values;
  ASSERT_EQ(got.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got[i]), std::bit_cast<std::uint64_t>(values[i])) << i;
  }
  EXPECT_EQ(back.column("label").labels, d.columns[1].labels);
}

// Found by fuzzing (fuzz/regressions/csv/header_starting_with_bom): a first column name that
// starts with the byte-order mark was written bare, and read back as a BOM and an empty name.
TEST(DataCsv, NameStartingWithByteOrderMarkRoundTrips) {
  Dataset d;
  d.add_numeric("\xEF\xBB\xBFx", {1.0});
  d.add_text("y", {"\xEF\xBB\xBF"});
  const Dataset back = parse_csv(to_csv(d), "t.csv");
  EXPECT_EQ(back.names(), d.names());
  EXPECT_EQ(back.column("y").labels, d.columns[1].labels);
}

TEST(DataCsv, ShortestNumberText) {
  Dataset d;
  d.add_numeric("a", {0.1, 1.0, -0.0, 1e21, 2.5e-7});
  EXPECT_EQ(to_csv(d), "a\n0.1\n1\n-0\n1e+21\n2.5e-07\n");
}

TEST(DataCsv, WriteAndReadFile) {
  TempFile file("data.csv");
  Dataset d;
  d.add_numeric("x", {1.5, 2.25});
  d.add_text("kind", {"metal", "dielectric"});
  write_csv(d, file.path());
  Dataset back = read_csv(file.path());
  EXPECT_EQ(back.source, file.path());
  EXPECT_EQ(back.numeric("x").values, d.columns[0].values);
  EXPECT_EQ(back.column("kind").labels, d.columns[1].labels);
}

TEST(DataCsv, WriteErrors) {
  Dataset d;
  d.source = "mem";
  d.add_numeric("R", {1.0, std::numeric_limits<double>::quiet_NaN()});
  expect_error([&] { (void)to_csv(d); }, "cannot write NaN in column 'R' (row 2)", "mem", 0, 0);
  TempFile dir("no_such_dir");
  std::string path = dir.path() + "/x.csv";
  Dataset ok;
  ok.add_numeric("x", {1});
  expect_error([&] { write_csv(ok, path); },
               "cannot write '" + path + "': No such file or directory", path, 0, 0);
}

}  // namespace
}  // namespace shaderfit
