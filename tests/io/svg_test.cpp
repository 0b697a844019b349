#include "fairspline/io/svg.hpp"

#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::io {
namespace {

using nlohmann::json;

const std::vector<Point> kExample = {{1, 90},  {3, 105},  {6, 120}, {10, 100},
                                     {12, 85}, {15, 104}, {17, 80}};

FitResult example_fit(bool closed = false, ReportLevel level = ReportLevel::kFull) {
  FitInput in;
  in.points = kExample;
  in.closed = closed;
  return fit("li-combined", in, json::object(), level);
}

/// Minimal XML well-formedness check: declarations/comments skipped, tags balanced and
/// properly nested, attribute values quoted, no raw '<' or bare '&' in text or attributes.
/// Returns an empty string when fine, else a description of the first problem.
std::string xml_problem(const std::string& s, std::string* root = nullptr) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  bool seen_root = false;
  const std::regex entity("^&(amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);");
  auto check_text = [&](std::size_t b, std::size_t e) -> std::string {
    for (std::size_t k = b; k < e; ++k) {
      if (s[k] == '<') return "raw '<' at " + std::to_string(k);
      if (s[k] == '&' && !std::regex_search(s.substr(k, 12), entity)) {
        return "bare '&' at " + std::to_string(k);
      }
    }
    return "";
  };
  while (i < s.size()) {
    const auto lt = s.find('<', i);
    const std::string text_problem = check_text(i, lt == std::string::npos ? s.size() : lt);
    if (!text_problem.empty()) return text_problem;
    if (lt == std::string::npos) break;
    if (s.compare(lt, 2, "<?") == 0) {
      const auto end = s.find("?>", lt);
      if (end == std::string::npos) return "unterminated <?";
      i = end + 2;
      continue;
    }
    if (s.compare(lt, 4, "<!--") == 0) {
      const auto end = s.find("-->", lt);
      if (end == std::string::npos) return "unterminated comment";
      i = end + 3;
      continue;
    }
    // Find the end of the tag, honoring quotes.
    std::size_t k = lt + 1;
    char quote = 0;
    while (k < s.size() && (quote || s[k] != '>')) {
      if (quote && s[k] == quote) {
        quote = 0;
      } else if (!quote && (s[k] == '"' || s[k] == '\'')) {
        quote = s[k];
      } else if (quote && s[k] == '<') {
        return "raw '<' in attribute at " + std::to_string(k);
      }
      ++k;
    }
    if (k >= s.size()) return "unterminated tag at " + std::to_string(lt);
    const std::string tag = s.substr(lt + 1, k - lt - 1);
    i = k + 1;
    if (tag.empty()) return "empty tag";
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name) return "unbalanced </" + name + ">";
      stack.pop_back();
      continue;
    }
    const bool self_closing = tag.back() == '/';
    const std::string name = tag.substr(0, tag.find_first_of(" \t\n/"));
    if (!std::regex_match(name, std::regex("[A-Za-z_][A-Za-z0-9_.:-]*"))) {
      return "bad tag name '" + name + "'";
    }
    // Attributes: name="value" pairs only.
    std::string attrs = tag.substr(name.size(), tag.size() - name.size() - (self_closing ? 1 : 0));
    static const std::regex attr_re(R"re(^\s*([A-Za-z_:][A-Za-z0-9_.:-]*)="([^"]*)")re");
    std::smatch m;
    while (std::regex_search(attrs, m, attr_re)) {
      const std::string value = m[2];
      for (std::size_t q = 0; q < value.size(); ++q) {
        if (value[q] == '&' && !std::regex_search(value.substr(q, 12), entity)) {
          return "bare '&' in attribute of <" + name + ">";
        }
      }
      attrs = m.suffix();
    }
    if (attrs.find_first_not_of(" \t\n") != std::string::npos) {
      return "malformed attributes in <" + name + ">: '" + attrs + "'";
    }
    if (stack.empty()) {
      if (seen_root) return "second root element <" + name + ">";
      seen_root = true;
      if (root) *root = tag;
    }
    if (!self_closing) stack.push_back(name);
  }
  if (!stack.empty()) return "unclosed <" + stack.back() + ">";
  if (!seen_root) return "no root element";
  return "";
}

/// The d attribute of the first element with the given class.
std::string path_data(const std::string& svg, const std::string& cls) {
  const auto at = svg.find("class=\"" + cls + "\"");
  if (at == std::string::npos) return "";
  const auto tag_end = svg.find('>', at);
  const auto d = svg.find(" d=\"", at);
  if (d == std::string::npos || d > tag_end) return "";
  return svg.substr(d + 4, svg.find('"', d + 4) - d - 4);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size())) ++n;
  return n;
}

TEST(SvgWrite, WellFormedWithNamespaceAndOneCubicPerSegment) {
  const FitResult r = example_fit();
  const std::string svg = write_svg(r);
  std::string root;
  EXPECT_EQ(xml_problem(svg, &root), "") << svg;
  EXPECT_EQ(root.rfind("svg ", 0), 0u);
  EXPECT_NE(root.find("xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_NE(root.find("version=\"1.1\""), std::string::npos);
  EXPECT_NE(root.find("width=\"800\""), std::string::npos);
  EXPECT_NE(root.find("height=\"600\""), std::string::npos);
  const std::string d = path_data(svg, "curve");
  ASSERT_FALSE(d.empty());
  EXPECT_EQ(d[0], 'M');
  EXPECT_EQ(count(d, "C"), r.spline.segments.size());
  EXPECT_EQ(count(d, "Z"), 0u);
  EXPECT_EQ(count(svg, "<circle"), r.points.size());
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  EXPECT_EQ(svg.find("class=\"comb"), std::string::npos);
  EXPECT_EQ(svg.find("class=\"control-polygon"), std::string::npos);
  // The caption names the method and says whether the curve is regular.
  EXPECT_NE(svg.find("<text class=\"caption\""), std::string::npos);
  EXPECT_NE(svg.find("li-combined"), std::string::npos);
  EXPECT_NE(svg.find("regular"), std::string::npos);
  EXPECT_NE(svg.find("bending"), std::string::npos);
}

TEST(SvgWrite, YAxisPointsUp) {
  // The highest input point (6, 120) must be drawn nearest the top of the image.
  const std::string svg = write_svg(example_fit());
  std::smatch m;
  std::string rest = svg.substr(svg.find("class=\"points\""));
  std::vector<double> ys;
  static const std::regex cy(R"re(cy="([-0-9.]+)")re");
  while (std::regex_search(rest, m, cy)) {
    ys.push_back(std::stod(m[1]));
    rest = m.suffix();
  }
  ASSERT_EQ(ys.size(), kExample.size());
  EXPECT_EQ(std::min_element(ys.begin(), ys.end()) - ys.begin(), 2);
  EXPECT_EQ(std::max_element(ys.begin(), ys.end()) - ys.begin(), 6);
}

TEST(SvgWrite, CombAndControlPolygonOnlyWhenAsked) {
  const FitResult r = example_fit(true);
  SvgOptions o;
  o.comb = true;
  o.control_polygon = true;
  o.comb_samples_per_segment = 8;
  const std::string svg = write_svg(r, o);
  EXPECT_EQ(xml_problem(svg), "");
  const std::string teeth = path_data(svg, "comb-teeth");
  const std::string envelope = path_data(svg, "comb-envelope");
  EXPECT_EQ(count(teeth, "M"), r.spline.segments.size() * 9);
  EXPECT_EQ(count(envelope, "L") + count(envelope, "M"), r.spline.segments.size() * 9);
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
  EXPECT_EQ(count(path_data(svg, "curve"), "Z"), 1u);
  // Inner control points + input points.
  EXPECT_EQ(count(svg, "<circle"), 2 * r.spline.segments.size() + r.points.size());
}

TEST(SvgWrite, DataBallsAreDrawnAsDiscsAroundTheirCentres) {
  FitInput in;
  in.points = {{0, 0}, {3, 1.5}, {6, -0.5}, {9, 1}, {12, 0}};
  in.radii = {0, 0.6, 0, 0.4, 0};
  const FitResult r = fit("quasi-elastic", in, json::object(), ReportLevel::kBasic);
  const std::string svg = write_svg(r);
  EXPECT_EQ(xml_problem(svg), "");
  const std::string balls = svg.substr(svg.find("class=\"balls\""));
  static const std::regex radius(R"re(<circle cx="[-0-9.]+" cy="[-0-9.]+" r="([-0-9.]+)")re");
  std::vector<double> radii;
  std::string rest = balls.substr(0, balls.find("</g>"));
  std::smatch m;
  while (std::regex_search(rest, m, radius)) {
    radii.push_back(std::stod(m[1]));
    rest = m.suffix();
  }
  ASSERT_EQ(radii.size(), 2u);  // one disc per positive radius
  EXPECT_NEAR(radii[0] / radii[1], 1.5, 1e-3);
  // Without balls there is no such group.
  in.radii.clear();
  EXPECT_EQ(write_svg(fit("quasi-elastic", in)).find("class=\"balls\""), std::string::npos);
}

TEST(SvgWrite, OptionsTurnThingsOff) {
  SvgOptions o;
  o.points = false;
  o.caption = false;
  o.height = 0;  // automatic
  const std::string svg = write_svg(example_fit(), o);
  EXPECT_EQ(xml_problem(svg), "");
  EXPECT_EQ(svg.find("<circle"), std::string::npos);
  EXPECT_EQ(svg.find("<text"), std::string::npos);
  // The example is taller than wide: the automatic height exceeds the width.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(svg, m, std::regex(R"re(<svg [^>]*height="([0-9.]+)")re")));
  EXPECT_GT(std::stod(m[1]), 800.0);
}

TEST(SvgWrite, EscapesTextAndHandlesDegenerateData) {
  FitResult r;
  r.method = "a<b & \"c\"";
  r.points = {{2, 2}};
  const std::string svg = write_svg(r);
  EXPECT_EQ(xml_problem(svg), "") << svg;
  EXPECT_NE(svg.find("a&lt;b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_NE(svg.find("no report"), std::string::npos);
  // A straight horizontal line: zero height, zero curvature, comb of zero teeth length.
  FitInput in;
  in.points = {{0, 0}, {1, 0}, {2, 0}};
  SvgOptions o;
  o.comb = true;
  const std::string line = write_svg(fit("li-strain", in), o);
  EXPECT_EQ(xml_problem(line), "");
  EXPECT_EQ(line.find("nan"), std::string::npos);
}

TEST(SvgOptionsFromKeys, ParsesAndValidates) {
  const SvgOptions o = svg_options_from_json({{"svg.comb", 1},
                                              {"svg.control_polygon", true},
                                              {"svg.width", 1000},
                                              {"height", 0},
                                              {"svg.caption", "false"},
                                              {"svg.comb_samples_per_segment", 4},
                                              {"svg.comb_scale", 2.5}});
  EXPECT_TRUE(o.comb);
  EXPECT_TRUE(o.control_polygon);
  EXPECT_EQ(o.width, 1000);
  EXPECT_EQ(o.height, 0);
  EXPECT_FALSE(o.caption);
  EXPECT_EQ(o.comb_samples_per_segment, 4);
  EXPECT_EQ(o.comb_scale, 2.5);
  SvgOptions p;
  try {
    set_svg_option(p, "svg.cmob", true);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnknownOption);
    EXPECT_NE(std::string(e.what()).find("svg.cmob"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("svg.comb"), std::string::npos);
  }
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, json>>{{"svg.width", -1},
                                                 {"svg.width", "wide"},
                                                 {"svg.height", -5},
                                                 {"svg.comb", 2},
                                                 {"svg.comb", "yes"},
                                                 {"svg.comb_samples_per_segment", 0},
                                                 {"svg.comb_samples_per_segment", 2.5},
                                                 {"svg.margin", nullptr}}) {
    try {
      set_svg_option(p, key, value);
      ADD_FAILURE() << key << " = " << value;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kBadOption) << key;
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(svg_options_from_json(json::array()), Error);
}

TEST(SvgRender, RsvgConvertProducesPng) {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "rsvg-convert not installed";
  }
  const auto dir = std::filesystem::temp_directory_path() /
                   ("fairspline-svg-render-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  SvgOptions o;
  o.comb = true;
  o.control_polygon = true;
  {
    std::ofstream f(dir / "fit.svg");
    f << write_svg(example_fit(), o);
  }
  const std::string cmd = "rsvg-convert '" + (dir / "fit.svg").string() + "' -o '" +
                          (dir / "fit.png").string() + "' 2>'" + (dir / "err.txt").string() + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream png(dir / "fit.png", std::ios::binary);
  std::string magic(8, '\0');
  png.read(magic.data(), 8);
  EXPECT_EQ(magic, std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_GT(std::filesystem::file_size(dir / "fit.png"), 1000u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fairspline::io
