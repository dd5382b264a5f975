// A small XML well-formedness checker for the report tests: parses a document
// (an optional <!DOCTYPE ...> first) into a tree, and fails on unclosed or
// mismatched tags, unquoted or repeated attributes, raw '<' in text and
// unknown entities.
#ifndef ROCKCAL_TESTS_REPORTS_XML_CHECK_H_
#define ROCKCAL_TESTS_REPORTS_XML_CHECK_H_

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rockcal::reports::testing {

struct XmlNode {
  std::string name;
  std::map<std::string, std::string> attributes;  // raw values (entities kept)
  std::string text;                               // direct text, raw
  std::vector<std::unique_ptr<XmlNode>> children;
  std::vector<std::size_t> child_at;  // where in `text` each child appears

  std::string Attribute(const std::string& key) const {
    const auto it = attributes.find(key);
    return it == attributes.end() ? std::string() : it->second;
  }
  bool Has(const std::string& key) const { return attributes.count(key) > 0; }
  // All text below this node, in document order.
  std::string AllText() const {
    std::string out;
    std::size_t from = 0;
    for (std::size_t k = 0; k < children.size(); ++k) {
      const std::size_t at = k < child_at.size() ? child_at[k] : text.size();
      out += text.substr(from, at - from) + children[k]->AllText();
      from = at;
    }
    return out + text.substr(std::min(from, text.size()));
  }
  // Every node below (and including) this one, depth first.
  void Visit(const std::function<void(const XmlNode&)>& f) const {
    f(*this);
    for (const auto& c : children) c->Visit(f);
  }
};

namespace xml_detail {

inline bool NameStart(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':';
}
inline bool NameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' ||
         c == '.';
}

// Checks the entity references of `s` ("&amp;", "&#179;", "&#x2192;").
inline bool CheckEntities(const std::string& s, std::string* error) {
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k] != '&') continue;
    const std::size_t end = s.find(';', k);
    if (end == std::string::npos || end - k > 10) {
      *error = "bare '&' near: " + s.substr(k, 20);
      return false;
    }
    const std::string e = s.substr(k + 1, end - k - 1);
    bool ok = e == "amp" || e == "lt" || e == "gt" || e == "quot" || e == "apos";
    if (!ok && e.size() > 1 && e[0] == '#') {
      ok = true;
      const bool hex = e[1] == 'x';
      for (std::size_t i = hex ? 2 : 1; i < e.size(); ++i)
        ok = ok && (hex ? std::isxdigit(static_cast<unsigned char>(e[i]))
                        : std::isdigit(static_cast<unsigned char>(e[i])));
    }
    if (!ok) {
      *error = "unknown entity &" + e + ";";
      return false;
    }
  }
  return true;
}

}  // namespace xml_detail

// Parses `doc`; on success returns the root element, else nullptr and *error
// (with the byte offset).
inline std::unique_ptr<XmlNode> ParseXml(const std::string& doc, std::string* error) {
  using namespace xml_detail;
  std::size_t pos = 0;
  auto fail = [&](const std::string& m) {
    *error = m + " at byte " + std::to_string(pos) + ": " + doc.substr(pos, 60);
    return nullptr;
  };
  auto skip_space = [&] {
    while (pos < doc.size() && std::isspace(static_cast<unsigned char>(doc[pos]))) ++pos;
  };
  skip_space();
  if (doc.compare(pos, 9, "<!DOCTYPE") == 0) {
    pos = doc.find('>', pos);
    if (pos == std::string::npos) return fail("unterminated doctype");
    ++pos;
  }
  auto document = std::make_unique<XmlNode>();
  std::vector<XmlNode*> stack = {document.get()};
  while (pos < doc.size()) {
    if (doc[pos] != '<') {
      const std::size_t end = doc.find('<', pos);
      const std::string text =
          doc.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
      if (stack.size() == 1 && text.find_first_not_of(" \t\r\n") != std::string::npos)
        return fail("text outside the root element");
      if (!CheckEntities(text, error)) return fail(*error);
      stack.back()->text += text;
      pos = end == std::string::npos ? doc.size() : end;
      continue;
    }
    if (doc.compare(pos, 4, "<!--") == 0) {
      const std::size_t end = doc.find("-->", pos);
      if (end == std::string::npos) return fail("unterminated comment");
      pos = end + 3;
      continue;
    }
    if (doc.compare(pos, 2, "</") == 0) {
      pos += 2;
      const std::size_t start = pos;
      while (pos < doc.size() && NameChar(doc[pos])) ++pos;
      const std::string name = doc.substr(start, pos - start);
      skip_space();
      if (pos >= doc.size() || doc[pos] != '>') return fail("bad closing tag </" + name);
      ++pos;
      if (stack.size() < 2 || stack.back()->name != name)
        return fail("closing </" + name + "> does not match <" +
                    (stack.size() > 1 ? stack.back()->name : "") + ">");
      stack.pop_back();
      continue;
    }
    ++pos;
    if (pos >= doc.size() || !NameStart(doc[pos])) return fail("bad tag name");
    const std::size_t start = pos;
    while (pos < doc.size() && NameChar(doc[pos])) ++pos;
    auto node = std::make_unique<XmlNode>();
    node->name = doc.substr(start, pos - start);
    bool self_closing = false;
    for (;;) {
      const std::size_t before = pos;
      skip_space();
      if (pos >= doc.size()) return fail("unterminated tag <" + node->name);
      if (doc[pos] == '>') {
        ++pos;
        break;
      }
      if (doc.compare(pos, 2, "/>") == 0) {
        pos += 2;
        self_closing = true;
        break;
      }
      if (pos == before) return fail("no space before attribute in <" + node->name);
      if (!NameStart(doc[pos])) return fail("bad attribute name in <" + node->name);
      const std::size_t a = pos;
      while (pos < doc.size() && NameChar(doc[pos])) ++pos;
      const std::string key = doc.substr(a, pos - a);
      if (pos >= doc.size() || doc[pos] != '=')
        return fail("attribute " + key + " without a value");
      ++pos;
      if (pos >= doc.size() || (doc[pos] != '"' && doc[pos] != '\''))
        return fail("unquoted attribute " + key);
      const char quote = doc[pos++];
      const std::size_t end = doc.find(quote, pos);
      if (end == std::string::npos) return fail("unterminated attribute " + key);
      const std::string value = doc.substr(pos, end - pos);
      if (value.find('<') != std::string::npos) return fail("'<' in attribute " + key);
      if (!CheckEntities(value, error)) return fail(*error);
      if (!node->attributes.emplace(key, value).second) return fail("repeated attribute " + key);
      pos = end + 1;
    }
    XmlNode* raw = node.get();
    if (stack.size() == 1 && !stack.back()->children.empty()) return fail("a second root element");
    stack.back()->child_at.push_back(stack.back()->text.size());
    stack.back()->children.push_back(std::move(node));
    if (!self_closing) stack.push_back(raw);
  }
  if (stack.size() != 1) {
    *error = "unclosed <" + stack.back()->name + "> at the end";
    return nullptr;
  }
  if (document->children.size() != 1) {
    *error = "no root element";
    return nullptr;
  }
  return std::move(document->children.front());
}

// Replaces the five XML entities and numeric references by their characters
// (numeric ones by '?', enough to compare ASCII values).
inline std::string Unescape(const std::string& s) {
  std::string out;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k] != '&') {
      out += s[k];
      continue;
    }
    const std::size_t end = s.find(';', k);
    const std::string e = s.substr(k + 1, end - k - 1);
    out += e == "amp"    ? "&"
           : e == "lt"   ? "<"
           : e == "gt"   ? ">"
           : e == "quot" ? "\""
           : e == "apos" ? "'"
                         : "?";
    if (e == "#39") out.back() = '\'';
    k = end;
  }
  return out;
}

}  // namespace rockcal::reports::testing

#endif  // ROCKCAL_TESTS_REPORTS_XML_CHECK_H_
