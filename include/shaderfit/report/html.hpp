// A self-contained HTML page: styles inline, images embedded as data URIs, no network.
//
//   HtmlReport r("shaderfit search: fresnel-seed");
//   r.heading("Pareto front");
//   r.table({"cost", "MSE", "formula"}, rows);
//   r.image("front.png", "Pareto front of MSE against SASS instructions");
//   r.code("GLSL", glsl_source);
//   r.write("report.html");
//
// Sections can carry an id (heading(text, level, id)) that table cells link to ("#id"); a table
// built as an HtmlTable may be sortable: clicking a header sorts its rows by that column (again:
// the other way), with a small inline script that the page holds only when it has such a table.
//
// Each embedded image carries its pixel size; a small script in the page checks on load that
// every image decoded at that size and records the result on <body> (data-images-ok,
// data-images-total, data-errors), with each image's box on the page (data-plot-boxes:
// "x,y,width,height;..." in CSS pixels) and the page's height (data-page-height), which the
// headless-browser test reads.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace shaderfit {

// A table cell: its text (escaped), a link when `href` is not empty (a place on the page: "#id"),
// and what a sortable table sorts it by: `sort_value` where set (NaN sorts last either way), else
// its text, read as a number in a numeric column.
struct HtmlCell {
  std::string text;
  std::string href;
  std::optional<double> sort_value;
};

struct HtmlTable {
  std::vector<std::string> header;
  std::vector<std::vector<HtmlCell>> rows;
  std::vector<bool> numeric;  // right-aligned, and sorted as numbers
  bool sortable = false;      // clicking a header sorts the rows by that column
};

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  // A heading that "#id" links reach; `id` should be unique on the page (it is escaped, not
  // checked).
  void heading(const std::string& text, int level, const std::string& id);
  void paragraph(const std::string& text);  // plain text, escaped
  void answer(const std::string& text);     // the page's answer (a formula), set apart
  // A table; cells are plain text (escaped). `numeric` columns are right-aligned.
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows,
             const std::vector<bool>& numeric = {});
  void table(const HtmlTable& table);
  // Key/value pairs as a two-column table.
  void settings(const std::vector<std::pair<std::string, std::string>>& items);
  // Embeds a PNG file. Throws shaderfit::Error if it cannot be read or is not a PNG.
  void image(const std::string& png_path, const std::string& caption);
  void code(const std::string& language, const std::string& source);
  // The same code in several languages as tabs (the first shown; no script needed): pairs of
  // language and source, at most 6.
  void code_tabs(const std::vector<std::pair<std::string, std::string>>& sources);
  // Everything `content` holds, folded under a line that says what it is (closed at first).
  void folded(const std::string& summary, const HtmlReport& content);
  // Everything `other` holds, after what this holds (sections made apart, on other threads).
  void append(const HtmlReport& other);

  [[nodiscard]] std::string html() const;
  // Throws shaderfit::Error when the file cannot be written.
  void write(const std::string& path) const;

 private:
  std::string title_;
  std::string body_;
  bool sortable_ = false;  // a sortable table was added: the page carries the sorting script
};

std::string html_escape(const std::string& text);
std::string base64_encode(const std::string& bytes);

}  // namespace shaderfit
