// A self-contained HTML page: styles inline, images embedded as data URIs, no network.
//
//   HtmlReport r("shaderfit search: fresnel-seed");
//   r.heading("Pareto front");
//   r.table({"cost", "MSE", "formula"}, rows);
//   r.image("front.png", "Pareto front of MSE against SASS instructions");
//   r.code("GLSL", glsl_source);
//   r.write("report.html");
//
// Each embedded image carries its pixel size; a small script in the page checks on load that
// every image decoded at that size and records the result on <body> (data-images-ok,
// data-images-total, data-errors), with each image's box on the page (data-plot-boxes:
// "x,y,width,height;..." in CSS pixels) and the page's height (data-page-height), which the
// headless-browser test reads.
#pragma once

#include <string>
#include <vector>

namespace shaderfit {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text);  // plain text, escaped
  // A table; cells are plain text (escaped). `numeric` columns are right-aligned.
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows,
             const std::vector<bool>& numeric = {});
  // Key/value pairs as a two-column table.
  void settings(const std::vector<std::pair<std::string, std::string>>& items);
  // Embeds a PNG file. Throws shaderfit::Error if it cannot be read or is not a PNG.
  void image(const std::string& png_path, const std::string& caption);
  void code(const std::string& language, const std::string& source);

  [[nodiscard]] std::string html() const;
  // Throws shaderfit::Error when the file cannot be written.
  void write(const std::string& path) const;

 private:
  std::string title_;
  std::string body_;
};

std::string html_escape(const std::string& text);
std::string base64_encode(const std::string& bytes);

}  // namespace shaderfit
