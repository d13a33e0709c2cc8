#include "shaderfit/report/html.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace {

// Clicking a header of a sortable table sorts its rows by that column, the next click the other
// way: by data-sort or the text, as numbers in numeric columns (NaN last either way).
constexpr const char* kSortScript =
    "<script>\n(function(){function key(r,c,num){var e=r.cells[c];if(!e)return num?NaN:'';"
    "var t=e.hasAttribute('data-sort')?e.getAttribute('data-sort'):e.textContent;"
    "return num?parseFloat(t):t;}\n"
    "function sort(){var th=this,t=th.closest('table'),b=t.tBodies[0],c=th.cellIndex,"
    "num=th.classList.contains('num'),d=th.getAttribute('data-order')==='up'?-1:1,"
    "hs=t.tHead.rows[0].cells,rows=Array.prototype.slice.call(b.rows);"
    "for(var k=0;k<hs.length;k++)hs[k].removeAttribute('data-order');"
    "th.setAttribute('data-order',d>0?'up':'down');"
    "rows.sort(function(x,y){var p=key(x,c,num),q=key(y,c,num);if(!num)return "
    "d*p.localeCompare(q,undefined,{numeric:true});if(isNaN(p)||isNaN(q))return "
    "isNaN(p)-isNaN(q);return p===q?0:d*(p<q?-1:1);});"
    "for(var i=0;i<rows.length;i++)b.appendChild(rows[i]);}\n"
    "var ts=document.querySelectorAll('table.sortable');for(var i=0;i<ts.length;i++){"
    "var hs=ts[i].tHead.rows[0].cells;for(var j=0;j<hs.length;j++)"
    "hs[j].addEventListener('click',sort);}})();\n</script>\n";

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string base64_encode(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  const std::string tag = "h" + std::to_string(level < 1 ? 1 : level > 4 ? 4 : level);
  body_ += "<" + tag + ">" + html_escape(text) + "</" + tag + ">\n";
}

void HtmlReport::paragraph(const std::string& text) {
  body_ += "<p>" + html_escape(text) + "</p>\n";
}

void HtmlReport::heading(const std::string& text, int level, const std::string& id) {
  const std::string tag = "h" + std::to_string(level < 1 ? 1 : level > 4 ? 4 : level);
  body_ += "<" + tag + " id=\"" + html_escape(id) + "\">" + html_escape(text) + "</" + tag + ">\n";
}

void HtmlReport::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows,
                       const std::vector<bool>& numeric) {
  HtmlTable t{header, {}, numeric, false};
  t.rows.reserve(rows.size());
  for (const auto& row : rows) {
    std::vector<HtmlCell> cells;
    cells.reserve(row.size());
    for (const std::string& text : row) cells.push_back({text, {}, std::nullopt});
    t.rows.push_back(std::move(cells));
  }
  table(t);
}

void HtmlReport::table(const HtmlTable& t) {
  auto cls = [&](std::size_t c) {
    return c < t.numeric.size() && t.numeric[c] ? " class=\"num\"" : "";
  };
  // The sort key as JavaScript's parseFloat reads it.
  auto sort_text = [](double v) -> std::string {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    return fmt::format("{:.17g}", v);
  };
  std::ostringstream s;
  s << (t.sortable ? "<table class=\"sortable\">\n" : "<table>\n") << "<thead><tr>";
  for (std::size_t c = 0; c < t.header.size(); ++c)
    s << "<th" << cls(c) << ">" << html_escape(t.header[c]) << "</th>";
  s << "</tr></thead>\n<tbody>\n";
  for (const auto& row : t.rows) {
    s << "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c) {
      const HtmlCell& cell = row[c];
      s << "<td" << cls(c);
      if (cell.sort_value) s << " data-sort=\"" << sort_text(*cell.sort_value) << "\"";
      s << ">";
      if (cell.href.empty())
        s << html_escape(cell.text);
      else
        s << "<a href=\"" << html_escape(cell.href) << "\">" << html_escape(cell.text) << "</a>";
      s << "</td>";
    }
    s << "</tr>\n";
  }
  s << "</tbody></table>\n";
  body_ += s.str();
  sortable_ = sortable_ || t.sortable;
}

void HtmlReport::settings(const std::vector<std::pair<std::string, std::string>>& items) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& [k, v] : items) rows.push_back({k, v});
  table({"setting", "value"}, rows);
}

void HtmlReport::image(const std::string& png_path, const std::string& caption) {
  std::ifstream f(png_path, std::ios::binary);
  if (!f) throw Error("cannot read image '" + png_path + "'", SourceLocation{png_path});
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (bytes.size() < 24 || bytes.compare(1, 3, "PNG") != 0 || bytes.compare(12, 4, "IHDR") != 0) {
    throw Error("'" + png_path + "' is not a PNG image", SourceLocation{png_path});
  }
  auto be32 = [&](std::size_t o) {
    return (static_cast<unsigned char>(bytes[o]) << 24) |
           (static_cast<unsigned char>(bytes[o + 1]) << 16) |
           (static_cast<unsigned char>(bytes[o + 2]) << 8) |
           static_cast<unsigned char>(bytes[o + 3]);
  };
  const unsigned w = be32(16), h = be32(20);
  body_ += "<figure><img class=\"plot\" alt=\"" + html_escape(caption) + "\" width=\"" +
           std::to_string(w) + "\" height=\"" + std::to_string(h) + "\" data-width=\"" +
           std::to_string(w) + "\" data-height=\"" + std::to_string(h) +
           "\" src=\"data:image/png;base64," + base64_encode(bytes) + "\"><figcaption>" +
           html_escape(caption) + "</figcaption></figure>\n";
}

void HtmlReport::code(const std::string& language, const std::string& source) {
  body_ += "<div class=\"code\"><div class=\"lang\">" + html_escape(language) +
           "</div><pre><code>" + html_escape(source) + "</code></pre></div>\n";
}

void HtmlReport::code_tabs(const std::vector<std::pair<std::string, std::string>>& sources) {
  if (sources.empty()) return;
  if (sources.size() > 6) throw Error("at most 6 code tabs, not " + std::to_string(sources.size()));
  // Radio buttons and labels, then the panels: the checked button shows its panel (CSS below).
  // Unique on the page (parts made apart are appended) and the same from run to run.
  const std::string group =
      "tabs" + std::to_string(std::hash<std::string>{}(sources.front().second) % 1000000007u);
  body_ += "<div class=\"tabs\">";
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::string id = group + "-" + std::to_string(k);
    body_ += "<input type=\"radio\" name=\"" + group + "\" id=\"" + id + "\"" +
             (k == 0 ? " checked" : "") + "><label for=\"" + id + "\">" +
             html_escape(sources[k].first) + "</label>";
  }
  for (const auto& [language, source] : sources)
    body_ += "<div class=\"tab\"><pre><code>" + html_escape(source) + "</code></pre></div>";
  body_ += "</div>\n";
}

void HtmlReport::answer(const std::string& text) {
  body_ += "<p class=\"answer\">" + html_escape(text) + "</p>\n";
}

void HtmlReport::folded(const std::string& summary, const HtmlReport& content) {
  body_ += "<details><summary>" + html_escape(summary) + "</summary>\n" + content.body_ +
           "</details>\n";
  sortable_ = sortable_ || content.sortable_;
}

void HtmlReport::append(const HtmlReport& other) {
  body_ += other.body_;
  sortable_ = sortable_ || other.sortable_;
}

std::string HtmlReport::html() const {
  std::ostringstream s;
  s << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<title>" << html_escape(title_) << "</title>\n<style>\n"
    << "body{font-family:'DejaVu Sans',system-ui,sans-serif;max-width:1100px;margin:2em "
       "auto;padding:0 1em;"
       "color:#1a1a1a;line-height:1.45}\n"
    << "h1{font-size:1.6em;border-bottom:2px solid "
       "#0072B2;padding-bottom:.2em}h2{margin-top:1.8em}\n"
    << "table{border-collapse:collapse;margin:.8em 0;font-size:.92em}th,td{border:1px solid "
       "#ccc;padding:.25em .6em;"
       "text-align:left;vertical-align:top}th{background:#eef3f8}td.num,th.num{text-align:right;"
       "font-variant-numeric:tabular-nums}tbody tr:nth-child(even){background:#fafafa}\n"
    << "figure{margin:1em 0}img.plot{max-width:100%;height:auto;border:1px solid #ddd}"
       "figcaption{font-size:.9em;color:#555}\n"
    << ".code{margin:.8em "
       "0}.lang{font-size:.8em;color:#555;text-transform:uppercase;letter-spacing:.05em}"
       "pre{background:#f6f8fa;border:1px solid #ddd;padding:.7em;overflow-x:auto}\n"
    << ".tabs>input{position:absolute;opacity:0}.tabs>label{display:inline-block;padding:.25em "
       ".9em;border:1px solid #ccc;border-bottom:none;font-size:.85em;cursor:pointer;"
       "background:#eef3f8;margin-right:.2em;text-transform:uppercase}.tabs>.tab{display:none}.tabs>.tab pre{margin-top:0}"
       ".tabs>input:checked+label{background:#fff;font-weight:bold}"
       ".tabs>input:nth-of-type(1):checked~.tab:nth-of-type(1),"
       ".tabs>input:nth-of-type(2):checked~.tab:nth-of-type(2),"
       ".tabs>input:nth-of-type(3):checked~.tab:nth-of-type(3),"
       ".tabs>input:nth-of-type(4):checked~.tab:nth-of-type(4),"
       ".tabs>input:nth-of-type(5):checked~.tab:nth-of-type(5),"
       ".tabs>input:nth-of-type(6):checked~.tab:nth-of-type(6){display:block}\n"
    << "details{margin:1.5em 0;border-top:1px solid #ddd;padding-top:.5em}"
       "summary{cursor:pointer;color:#0072B2;font-weight:bold}\n"
    << ".answer{font-size:1.25em;font-family:'DejaVu Sans Mono',monospace;background:#f6f8fa;"
       "padding:.4em .6em;border-left:4px solid #0072B2}\n"
    << (sortable_ ? "table.sortable th{cursor:pointer;user-select:none}"
                    "th[data-order=up]::after{content:' \\25B2'}"
                    "th[data-order=down]::after{content:' \\25BC'}\n"
                  : "")
    << "</style>\n</head>\n<body>\n<h1>" << html_escape(title_) << "</h1>\n"
    << body_
    // Self-check for the headless-browser test (and harmless for people): count the images that
    // decoded at their recorded size, and any script errors.
    << "<script>\n(function(){var errors=0;window.addEventListener('error',function(){errors++;"
       "document.body.setAttribute('data-errors',String(errors));});\n"
       "window.addEventListener('load',function(){var "
       "imgs=document.querySelectorAll('img.plot'),ok=0;"
       "for(var i=0;i<imgs.length;i++){var m=imgs[i];if(m.complete&&m.naturalWidth>0&&"
       "String(m.naturalWidth)===m.getAttribute('data-width')&&String(m.naturalHeight)===m."
       "getAttribute('data-height'))"
       "ok++;}document.body.setAttribute('data-images-ok',String(ok));"
       "document.body.setAttribute('data-images-total',String(imgs.length));"
       "document.body.setAttribute('data-errors',String(errors));"
       // Where each image's pixels are on the page, and the page's height, so that a test can
       // find the plots in a screenshot of the whole page.
       "var boxes=[];for(var k=0;k<imgs.length;k++){var b=imgs[k].getBoundingClientRect();"
       "boxes.push([Math.round(b.left+imgs[k].clientLeft+window.scrollX),"
       "Math.round(b.top+imgs[k].clientTop+window.scrollY),imgs[k].clientWidth,imgs[k]."
       "clientHeight].join(','));}"
       "document.body.setAttribute('data-plot-boxes',boxes.join(';'));"
       "document.body.setAttribute('data-page-height',String(document.documentElement."
       "scrollHeight)"
       ");"
       "});})();\n</script>\n";
  if (sortable_) s << kSortScript;  // after the self-check, which counts its errors
  s << "</body>\n</html>\n";
  return s.str();
}

void HtmlReport::write(const std::string& path) const {
  std::ofstream f(path, std::ios::binary);
  f << html();
  if (!f) throw Error("cannot write '" + path + "'", SourceLocation{path});
}

}  // namespace shaderfit
