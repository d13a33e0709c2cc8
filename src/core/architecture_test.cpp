// docs/architecture.md lists each area and the areas it may include; this test holds the code to
// that list, so the map and the code cannot drift apart: every area of src/ and include/shaderfit/
// is listed, the listed arrows form no cycle, and no library file (tests and their helpers aside)
// includes an area its own may not. A folder inside an area is a wing of it, an area of its own
// named "area/wing" (search/enumeration): the files at the area's root are the area itself.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using Arrows = std::map<std::string, std::set<std::string>>;

const fs::path kRoot = SHADERFIT_SOURCE_DIR;

// The first fenced block after the heading "## Areas": lines "area: other other ...".
Arrows read_arrows() {
  std::ifstream doc(kRoot / "docs" / "architecture.md");
  Arrows arrows;
  std::string line;
  bool in_section = false, in_block = false;
  while (std::getline(doc, line)) {
    if (!in_section) {
      in_section = line.rfind("## Areas", 0) == 0;
      continue;
    }
    if (line.rfind("```", 0) == 0) {
      if (in_block) break;
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream names(line.substr(colon + 1));
    auto& to = arrows[line.substr(0, colon)];
    for (std::string n; names >> n;) to.insert(n);
  }
  return arrows;
}

// The areas ("expr") and their wings ("search/front"); a testdata folder holds files, not code.
std::set<std::string> area_folders() {
  std::set<std::string> out;
  for (const fs::path& dir : {kRoot / "src", kRoot / "include" / "shaderfit"})
    for (const auto& e : fs::directory_iterator(dir)) {
      if (!e.is_directory()) continue;
      const std::string area = e.path().filename().string();
      out.insert(area);
      for (const auto& w : fs::directory_iterator(e.path()))  // testdata: tests' files, no wing
        if (w.is_directory() && w.path().filename() != "testdata")
          out.insert(area + "/" + w.path().filename().string());
    }
  return out;
}

// The area or wing of a path relative to src/ or include/shaderfit/ whose first part is an area:
// "search/front/tidy.hpp" is in search/front, "search/options.hpp" in search.
std::string area_of(const fs::path& rel, const std::set<std::string>& areas) {
  auto part = rel.begin();
  const std::string area = part->string();
  if (++part == rel.end() || std::next(part) == rel.end()) return area;
  const std::string wing = area + "/" + part->string();
  return areas.count(wing) ? wing : area;
}

bool is_test_code(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.find("_test.") != std::string::npos || name.find("test_") != std::string::npos;
}

// The area (or wing) of `#include "shaderfit/<area>/..."` (public) or `#include "<area>/..."`
// (internal, under src/); "" for any other line.
std::string included_area(const std::string& line, const std::set<std::string>& areas) {
  std::size_t at = line.find_first_not_of(" \t");
  if (at == std::string::npos || line[at] != '#') return {};
  at = line.find_first_not_of(" \t", at + 1);
  if (at == std::string::npos || line.compare(at, 7, "include") != 0) return {};
  const std::size_t open = line.find('"', at);
  if (open == std::string::npos) return {};
  std::string path = line.substr(open + 1, line.find('"', open + 1) - open - 1);
  if (path.rfind("shaderfit/", 0) == 0) path.erase(0, 10);
  if (path.find('/') == std::string::npos) return {};
  return area_of(fs::path(path), areas);
}

TEST(Architecture, EveryAreaIsOnTheMap) {
  const Arrows arrows = read_arrows();
  ASSERT_FALSE(arrows.empty()) << "no area list in docs/architecture.md (## Areas, first block)";
  for (const std::string& a : area_folders())
    EXPECT_TRUE(arrows.count(a)) << "area '" << a << "' is not in docs/architecture.md";
  for (const auto& [from, to] : arrows) {
    EXPECT_TRUE(area_folders().count(from)) << "docs/architecture.md lists no such area: " << from;
    for (const std::string& t : to)
      EXPECT_TRUE(arrows.count(t)) << from << " may include '" << t << "', which is not listed";
  }
}

TEST(Architecture, TheMapHasNoCycle) {
  const Arrows arrows = read_arrows();
  std::map<std::string, int> state;  // 1: on the current path, 2: done
  std::vector<std::string> path;
  std::function<void(const std::string&)> visit = [&](const std::string& a) {
    if (state[a] == 2) return;
    path.push_back(a);
    if (state[a] == 1) {
      std::string cycle;
      for (const auto& p : path) cycle += (cycle.empty() ? "" : " -> ") + p;
      ADD_FAILURE() << "cycle between areas: " << cycle;
      path.pop_back();
      return;
    }
    state[a] = 1;
    if (auto it = arrows.find(a); it != arrows.end())
      for (const std::string& b : it->second) visit(b);
    state[a] = 2;
    path.pop_back();
  };
  for (const auto& [a, to] : arrows) visit(a);
}

TEST(Architecture, LibraryIncludesFollowTheMap) {
  const Arrows arrows = read_arrows();
  const std::set<std::string> areas = area_folders();
  int checked = 0;
  for (const fs::path& dir : {kRoot / "src", kRoot / "include" / "shaderfit"}) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (!e.is_regular_file() || is_test_code(e.path())) continue;
      const fs::path rel = e.path().lexically_relative(dir);
      if (rel.begin() == rel.end() || std::next(rel.begin()) == rel.end()) continue;  // top level
      const std::string from = area_of(rel, areas);
      const auto allowed = arrows.find(from);
      std::ifstream f(e.path());
      std::string line;
      for (int n = 1; std::getline(f, line); ++n) {
        const std::string to = included_area(line, areas);
        if (to == from || !areas.count(to)) continue;
        ++checked;
        EXPECT_TRUE(allowed != arrows.end() && allowed->second.count(to))
            << e.path().lexically_relative(kRoot).string() << ":" << n << ": " << from
            << " includes " << to << ", which docs/architecture.md does not allow";
      }
    }
  }
  EXPECT_GT(checked, 0);
}

}  // namespace
