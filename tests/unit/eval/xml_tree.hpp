#pragma once
// A strict little XML reader for the plot tests: enough of XML 1.0 to read what
// lab/eval/svg_document writes (declaration, comments, elements, attributes, text, the five
// named entities and character references), rejecting anything not well-formed instead of
// guessing. No DTDs, no CDATA: the writer never emits them, so here they are errors too.
#include <cctype>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace probeless::testing {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  // values with entities decoded
  std::vector<XmlElement> children;
  std::string text;  // the element's own character data, entities decoded

  // Every element named `n` below this one (depth first, document order).
  std::vector<const XmlElement*> find_all(std::string_view n) const {
    std::vector<const XmlElement*> out;
    collect(n, out);
    return out;
  }
  const std::string& attr(const std::string& key) const {
    const auto it = attributes.find(key);
    if (it == attributes.end()) throw std::out_of_range("<" + name + "> has no " + key);
    return it->second;
  }

 private:
  void collect(std::string_view n, std::vector<const XmlElement*>& out) const {
    for (const auto& c : children) {
      if (c.name == n) out.push_back(&c);
      c.collect(n, out);
    }
  }
};

class XmlReader {
 public:
  // The root element; throws std::runtime_error naming the offset of the first fault.
  static XmlElement parse(std::string_view doc) {
    XmlReader r(doc);
    if (r.starts("<?xml")) r.skip_past("?>");
    r.skip_misc();
    XmlElement root = r.element();
    r.skip_misc();
    if (r.pos_ != doc.size()) r.fail("content after the root element");
    return root;
  }

 private:
  explicit XmlReader(std::string_view doc) : doc_(doc) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("XML offset " + std::to_string(pos_) + ": " + what);
  }
  bool starts(std::string_view s) const { return doc_.substr(pos_).starts_with(s); }
  char peek() const { return pos_ < doc_.size() ? doc_[pos_] : '\0'; }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++pos_;
  }
  void skip_space() {
    while (pos_ < doc_.size() && std::isspace(static_cast<unsigned char>(doc_[pos_]))) ++pos_;
  }
  void skip_past(std::string_view end) {
    const auto at = doc_.find(end, pos_);
    if (at == std::string_view::npos) fail("unterminated " + std::string(end));
    pos_ = at + end.size();
  }
  void skip_misc() {  // whitespace and comments around the root
    for (skip_space(); starts("<!--"); skip_space()) skip_past("-->");
  }

  std::string name() {
    const auto first = pos_;
    const auto is_start = [](char c) {
      return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':';
    };
    if (!is_start(peek())) fail("expected a name");
    while (is_start(peek()) || std::isdigit(static_cast<unsigned char>(peek())) || peek() == '-' ||
           peek() == '.')
      ++pos_;
    return std::string(doc_.substr(first, pos_ - first));
  }

  // Character data up to `stop` (exclusive), entities decoded; '<' is never allowed in it.
  std::string chars(char stop) {
    std::string out;
    while (pos_ < doc_.size() && doc_[pos_] != stop) {
      const char c = doc_[pos_];
      if (c == '<') fail("raw '<' in character data");
      if (c == '&') {
        out += entity();
        continue;
      }
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
        fail("control character");
      out += c;
      ++pos_;
    }
    return out;
  }

  std::string entity() {
    const auto end = doc_.find(';', pos_);
    if (end == std::string_view::npos || end - pos_ > 10) fail("'&' that starts no entity");
    const auto e = doc_.substr(pos_ + 1, end - pos_ - 1);
    pos_ = end + 1;
    static const std::map<std::string_view, std::string> named = {
        {"amp", "&"}, {"lt", "<"}, {"gt", ">"}, {"quot", "\""}, {"apos", "'"}};
    if (const auto it = named.find(e); it != named.end()) return it->second;
    if (e.size() > 1 && e[0] == '#') {
      const bool hex = e[1] == 'x';
      const unsigned long code =
          std::stoul(std::string(e.substr(hex ? 2 : 1)), nullptr, hex ? 16 : 10);
      if (code < 0x80 && code >= 0x20) return std::string(1, static_cast<char>(code));
      return "?";  // the tests only look at ASCII
    }
    fail("unknown entity &" + std::string(e) + ";");
  }

  XmlElement element() {
    expect('<');
    XmlElement el;
    el.name = name();
    for (;;) {
      const bool spaced = std::isspace(static_cast<unsigned char>(peek()));
      skip_space();
      if (starts("/>")) {
        pos_ += 2;
        return el;
      }
      if (peek() == '>') break;
      if (!spaced) fail("attributes must be separated by white space");
      std::string key = name();
      skip_space();
      expect('=');
      skip_space();
      const char quote = peek();
      if (quote != '"' && quote != '\'') fail("unquoted attribute value");
      ++pos_;
      std::string value = chars(quote);
      expect(quote);
      if (!el.attributes.emplace(std::move(key), std::move(value)).second)
        fail("attribute given twice");
    }
    expect('>');
    for (;;) {
      el.text += chars('<');
      if (pos_ >= doc_.size()) fail("<" + el.name + "> is never closed");
      if (starts("<!--")) {
        skip_past("-->");
      } else if (starts("</")) {
        pos_ += 2;
        if (name() != el.name) fail("</...> does not close <" + el.name + ">");
        skip_space();
        expect('>');
        return el;
      } else if (starts("<!") || starts("<?")) {
        fail("DTD, CDATA and processing instructions are not expected");
      } else {
        el.children.push_back(element());
      }
    }
  }

  std::string_view doc_;
  std::size_t pos_ = 0;
};

}  // namespace probeless::testing
