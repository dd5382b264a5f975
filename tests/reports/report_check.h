// Checks shared by the tests of the HTML reports (html_report_test.cc,
// study_report_test.cc, html_page_test.cc): parse a report, check that it is
// self-contained, and compare every number marked with data-json against the
// JSON files it comes from (reports/README.md, "Numbers a machine can check").
#ifndef ROCKCAL_TESTS_REPORTS_REPORT_CHECK_H_
#define ROCKCAL_TESTS_REPORTS_REPORT_CHECK_H_

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "xml_check.h"

namespace rockcal::reports::testing {

struct Parsed {
  std::string html;
  std::unique_ptr<XmlNode> root;
  std::vector<std::string> sections;  // <section id> in order
};

// Parses `html` (a failure is a test failure) and lists its sections.
inline Parsed ParseReport(std::string html) {
  Parsed p;
  p.html = std::move(html);
  std::string error;
  p.root = ParseXml(p.html, &error);
  EXPECT_NE(p.root, nullptr) << "not well-formed: " << error;
  if (p.root)
    p.root->Visit([&](const XmlNode& n) {
      if (n.name == "section") p.sections.push_back(n.Attribute("id"));
    });
  return p;
}

inline bool HasSection(const Parsed& p, const std::string& id) {
  for (const auto& s : p.sections)
    if (s == id) return true;
  return false;
}

inline const XmlNode* FindSection(const Parsed& p, const std::string& id) {
  const XmlNode* found = nullptr;
  p.root->Visit([&](const XmlNode& n) {
    if (n.name == "section" && n.Attribute("id") == id) found = &n;
  });
  return found;
}

// Self-contained and script-free: no <script>, no external resources, links
// only within the file, unique ids, and every link target present.
inline void ExpectSelfContained(const Parsed& p) {
  ASSERT_NE(p.root, nullptr);
  EXPECT_EQ(p.root->name, "html");
  std::set<std::string> ids, targets;
  p.root->Visit([&](const XmlNode& n) {
    EXPECT_NE(n.name, "script");
    EXPECT_NE(n.name, "img");
    EXPECT_NE(n.name, "link");
    EXPECT_NE(n.name, "iframe");
    EXPECT_FALSE(n.Has("src")) << "<" << n.name << " src=...>";
    for (const auto& [k, v] : n.attributes)
      EXPECT_NE(k.rfind("on", 0), 0u) << "event handler " << k;
    if (n.Has("href")) {
      const std::string href = n.Attribute("href");
      ASSERT_FALSE(href.empty());
      EXPECT_EQ(href[0], '#') << "external link " << href;
      targets.insert(href.substr(1));
    }
    if (n.Has("id")) {
      EXPECT_TRUE(ids.insert(n.Attribute("id")).second) << "duplicate id " << n.Attribute("id");
    }
  });
  for (const auto& t : targets) EXPECT_TRUE(ids.count(t)) << "link to missing #" << t;
  EXPECT_EQ(p.html.find("<script"), std::string::npos);
  EXPECT_EQ(p.html.find("url("), std::string::npos);
}

// The shown number of a cell: its text parsed as a double; a number shown
// in percent ("12.5 %") is divided by 100.
inline bool ShownNumber(const std::string& text, double* v) {
  char* end = nullptr;
  const std::string t = Unescape(text);
  *v = std::strtod(t.c_str(), &end);
  if (end == t.c_str()) return false;
  const std::size_t rest = t.find_first_not_of(' ', static_cast<std::size_t>(end - t.c_str()));
  if (rest != std::string::npos && t[rest] == '%') *v /= 100.0;
  return true;
}

// Every element with data-json="FILE#POINTER": its data-value equals
// json[FILE] at POINTER (to 1e-9 relative), and its shown text rounds to it.
// Returns the pointers seen per file.
inline std::map<std::string, std::set<std::string>> CheckNumbers(
    const Parsed& p, const std::map<std::string, nlohmann::json>& files) {
  std::map<std::string, std::set<std::string>> seen;
  p.root->Visit([&](const XmlNode& n) {
    if (!n.Has("data-json")) return;
    const std::string ref = Unescape(n.Attribute("data-json"));
    const std::size_t hash = ref.find('#');
    ASSERT_NE(hash, std::string::npos) << ref;
    const std::string file = ref.substr(0, hash), pointer = ref.substr(hash + 1);
    const auto it = files.find(file);
    if (it == files.end()) return;
    seen[file].insert(pointer);
    const nlohmann::json::json_pointer ptr(pointer);
    ASSERT_TRUE(it->second.contains(ptr)) << ref << " not in " << file;
    const nlohmann::json& expected = it->second.at(ptr);
    const std::string value = Unescape(n.Attribute("data-value"));
    if (expected.is_string()) {
      EXPECT_EQ(value, expected.get<std::string>()) << ref;
      EXPECT_EQ(Unescape(n.AllText()), expected.get<std::string>()) << ref;
      return;
    }
    ASSERT_TRUE(expected.is_number()) << ref;
    const double want = expected.get<double>();
    const double got = std::strtod(value.c_str(), nullptr);
    EXPECT_NEAR(got, want, 1e-9 * std::fabs(want) + 1e-300) << ref;
    double shown = 0;
    ASSERT_TRUE(ShownNumber(n.AllText(), &shown)) << ref << " shows '" << n.AllText() << "'";
    EXPECT_NEAR(shown, want, 0.006 * std::fabs(want) + 1e-12)
        << ref << " shows '" << n.AllText() << "'";
  });
  return seen;
}

// The pointers of every number (and string) leaf of `j`.
inline std::set<std::string> Leaves(const nlohmann::json& j) {
  std::set<std::string> out;
  const nlohmann::json flat = j.flatten();
  for (const auto& item : flat.items()) out.insert(item.key());
  return out;
}

}  // namespace rockcal::reports::testing

#endif  // ROCKCAL_TESTS_REPORTS_REPORT_CHECK_H_
